// Natural logarithm and exponential of short arrays, vectorized (docs/theory.md eq. 36b). The
// Johnson-Cook return evaluates a handful of them per particle; one at a time (libm's scalar log
// and exp) they were half of the return's time, in blocks they run 2-4 at once through glibc's
// vector math library (libmvec, the SSE2 or, where the CPU has it, AVX2 variant; results within
// 4 ulp of the scalar ones, far below the return's 1e-10).
#pragma once

namespace sphforge::vmath {

/// Callers pass counts that are multiples of this (padding with harmless arguments such as 1.0), so
/// that every element goes through the same vector code whatever the count: the results of a
/// particle do not depend on how many others share its block.
inline constexpr int kPadding = 8;

inline constexpr int padded(int count) { return (count + kPadding - 1) / kPadding * kPadding; }

/// y[i] = ln x[i] for x[i] > 0 (finite), count a multiple of kPadding.
void log(int count, const double* x, double* y);
/// y[i] = exp x[i] for finite x[i], count a multiple of kPadding.
void exp(int count, const double* x, double* y);

}  // namespace sphforge::vmath
