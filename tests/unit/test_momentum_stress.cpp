// The per-particle half of the momentum equation, A_i (corrected_stress, theory eqs. 7, 7a, 7b), for
// the three values of numerics.momentum_correction: full A = sigma C, none A = sigma, deviatoric
// A = S C - p I. Checked entry by entry against the products formed here with Eigen from a
// symmetric correction C with off-diagonal entries and a general stress, for several particles, so a
// mode that corrected the wrong part (or dropped the pressure) fails. Tolerance 1e-12 relative: the
// same products in a different summation order.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <vector>

#include "engine/sph_operators.hpp"

namespace {

using namespace sphforge;

struct Sample {
  std::vector<double> p, S, C;
  std::size_t n = 3;
};

Sample sample() {
  Sample s;
  s.p = {2.5e6, -1.0e5, 0.0};
  s.S = {1.0e5, -3.0e5, 2.0e5, 4.0e4, -7.0e4, 1.1e5,  // xx yy zz xy yz xz
         -2.0e5, 1.5e5, 5.0e4, 0.0, 3.0e4, -6.0e4,
         0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  s.C = {1.2, 0.9, 1.05, 0.1, -0.05, 0.2,  // xx yy zz xy yz xz
         1.0, 1.0, 1.0, 0.0, 0.0, 0.0,
         1.4, 0.8, 1.1, -0.2, 0.15, 0.05};
  return s;
}

Eigen::Matrix3d symmetric(const double* v) {
  Eigen::Matrix3d m;
  m << v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2];
  return m;
}

void expect_equal(const double* a, const Eigen::Matrix3d& expected, const char* mode, std::size_t i) {
  const double scale = std::max(expected.cwiseAbs().maxCoeff(), 1.0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(a[3 * r + c], expected(r, c), 1e-12 * scale) << mode << ", particle " << i << ", entry " << r << c;
}

TEST(MomentumStress, FullCorrectsTheWholeStress) {
  const Sample s = sample();
  std::vector<double> A(9 * s.n);
  corrected_stress(s.p.data(), s.S.data(), s.C.data(), true, A.data(), s.n);
  for (std::size_t i = 0; i < s.n; ++i) {
    const Eigen::Matrix3d sigma = symmetric(&s.S[6 * i]) - s.p[i] * Eigen::Matrix3d::Identity();
    expect_equal(&A[9 * i], sigma * symmetric(&s.C[6 * i]), "full", i);
  }
}

TEST(MomentumStress, NoneIsThePlainStress) {
  const Sample s = sample();
  for (bool correct_pressure : {true, false}) {  // without C the flag changes nothing
    std::vector<double> A(9 * s.n);
    corrected_stress(s.p.data(), s.S.data(), nullptr, correct_pressure, A.data(), s.n);
    for (std::size_t i = 0; i < s.n; ++i)
      expect_equal(&A[9 * i], symmetric(&s.S[6 * i]) - s.p[i] * Eigen::Matrix3d::Identity(), "none", i);
  }
}

TEST(MomentumStress, DeviatoricCorrectsOnlyTheDeviator) {
  const Sample s = sample();
  std::vector<double> A(9 * s.n);
  corrected_stress(s.p.data(), s.S.data(), s.C.data(), false, A.data(), s.n);
  for (std::size_t i = 0; i < s.n; ++i)
    expect_equal(&A[9 * i],
                 symmetric(&s.S[6 * i]) * symmetric(&s.C[6 * i]) - s.p[i] * Eigen::Matrix3d::Identity(),
                 "deviatoric", i);
}

}  // namespace
