// Compiled with -ffast-math (see the plugins' CMakeLists.txt): only then does GCC map std::log and
// std::exp in a simd loop onto libmvec's vector functions. Nothing else lives in this file, so the
// flag changes no other arithmetic; the arguments are finite and positive (log) by contract, so
// the finite-math assumptions it makes hold.
#include "vector_math.hpp"

#include <cmath>

namespace sphforge::vmath {

__attribute__((target_clones("avx2", "default"))) void log(int count, const double* __restrict x,
                                                             double* __restrict y) {
#pragma omp simd
  for (int i = 0; i < count; ++i) y[i] = std::log(x[i]);
}

__attribute__((target_clones("avx2", "default"))) void exp(int count, const double* __restrict x,
                                                             double* __restrict y) {
#pragma omp simd
  for (int i = 0; i < count; ++i) y[i] = std::exp(x[i]);
}

}  // namespace sphforge::vmath
