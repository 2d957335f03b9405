// The artificial stress (eq. 9) is computed in place in the step (engine/simulation.cpp): R
// overwrites sigma/rho^2, which saves six doubles per particle of scratch. In place and out of
// place must agree bit for bit (each particle's inputs are read before its outputs are written).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "engine/sph_operators.hpp"

using namespace sphforge;

TEST(ArtificialStress, InPlaceEqualsSeparateOutputBitForBit) {
  const std::size_t n = 2000;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> p(n), S(6 * n), rho(n);
  for (std::size_t i = 0; i < n; ++i) {
    p[i] = 1e6 * u(rng);
    for (int c = 0; c < 6; ++c) S[6 * i + c] = 1e6 * u(rng);
    rho[i] = 2700.0 * (1.0 + 0.1 * u(rng));
  }
  std::vector<double> t(6 * n), separate(6 * n);
  stress_over_density_squared(p.data(), S.data(), rho.data(), t.data(), n);
  artificial_stress(t.data(), 0.3, separate.data(), n);
  std::vector<double> in_place = t;
  artificial_stress(in_place.data(), 0.3, in_place.data(), n);
  std::size_t nonzero = 0;
  for (std::size_t k = 0; k < 6 * n; ++k) {
    ASSERT_EQ(in_place[k], separate[k]) << "entry " << k;  // exact: the same operations on the same inputs
    nonzero += separate[k] != 0.0 ? 1 : 0;
  }
  EXPECT_GT(nonzero, n);  // random stresses have tensile principal values: the test compares real numbers
}
