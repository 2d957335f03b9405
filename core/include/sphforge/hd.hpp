// Host/device annotations for physics code shared by the CPU (OpenMP) and CUDA backends.
//
// The physics (kernels, operators, constitutive updates) is written once as small inline
// functions marked `SPH_HD SPH_INLINE`. Compiled by g++ they are ordinary inline functions; compiled
// by nvcc (where __CUDACC__ is defined) they become `__host__ __device__` and are force-inlined
// into the CUDA kernels of the thin launch layer. Such functions must therefore avoid anything a
// device cannot run: exceptions, std::vector/std::string, virtual calls, iostreams, and most of
// <cmath>'s std:: overloads (use the plain arithmetic or the global ::sqrt-style functions).
#pragma once

#if defined(__CUDACC__)
#define SPH_HD __host__ __device__
#define SPH_INLINE __forceinline__
#else
#define SPH_HD
#define SPH_INLINE inline
#endif
