// The sheet beyond the friction-drilling disc (docs/theory.md eq. 121b;
// plugins/processes/friction_drilling/sheet_far_field.hpp): a thin annulus with radial conduction,
// fed by the disc's rim ring held at a given temperature.
//
// Tolerances:
// - energy: the heat taken from the ring equals the heat stored in the annulus to round-off (the
//   scheme is conservative by construction): 1e-10 relative to the stored heat;
// - the flow into a wide annulus against the semi-infinite solid, E(t) = 2 k A dT sqrt(t / (pi alpha)):
//   within 2 %. What separates them: the annulus starts dr/2 outside the ring's radius (a capacity
//   offset of dr / (2 sqrt(alpha t)) = 0.4 % here), the curvature (sqrt(alpha t) / R = 1.1 %, which
//   raises the flow) and the explicit scheme's resolution of the first steps' steep gradient.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "processes/friction_drilling/sheet_far_field.hpp"

namespace {

using sphforge::friction_drilling::SheetFarField;

constexpr double kConductivity = 50.0;     // W/(m K), HX220
constexpr double kHeatCapacity = 3.925e6;  // rho c, J/(m^3 K): 7850 kg/m^3 x 500 J/(kg K)
constexpr double kThickness = 1.2e-3;      // m
constexpr double kT0 = 293.15;             // K

TEST(FrictionDrillingFarField, HeatTakenFromTheRingIsTheHeatStored) {
  // The sheet of the bundled case's quarter: ring at 4.8 mm, disc edge 5 mm, far field to 35 mm.
  SheetFarField far(4.8e-3, 5e-3, 35e-3, kThickness, 0.5 * std::numbers::pi, kConductivity, kHeatCapacity, kT0, 0.2e-3);
  double taken = 0.0;
  for (int s = 0; s < 2000; ++s) {
    const double T_ring = kT0 + 800.0 * std::sin(1e-3 * s);  // a rim that heats and cools
    taken += far.advance(T_ring, 2e-3) * 2e-3;
  }
  EXPECT_NEAR(taken, far.stored_J(kT0), 1e-10 * std::abs(far.stored_J(kT0)));
  EXPECT_NEAR(taken, far.absorbed_J(), 1e-10 * std::abs(taken));
  EXPECT_GT(far.stored_J(kT0), 0.0);
}

TEST(FrictionDrillingFarField, LongAfterTheRimIsHeldTheAnnulusIsAtItsTemperature) {
  // Outer edge adiabatic: the steady state is uniform, and the annulus then holds C dT.
  const double R = 5e-3, R_far = 15e-3, angle = 2.0 * std::numbers::pi;
  SheetFarField far(4.8e-3, R, R_far, kThickness, angle, kConductivity, kHeatCapacity, kT0, 0.2e-3);
  // alpha = 1.27e-5 m^2/s: (10 mm)^2 / alpha = 7.9 s; 200 s is 25 times that.
  for (int s = 0; s < 2000; ++s) far.advance(kT0 + 100.0, 0.1);
  const double capacity = kHeatCapacity * kThickness * 0.5 * angle * (R_far * R_far - R * R);
  for (double T : far.temperatures()) EXPECT_NEAR(T, kT0 + 100.0, 1e-6);
  EXPECT_NEAR(far.absorbed_J(), capacity * 100.0, 1e-8 * capacity * 100.0);
}

TEST(FrictionDrillingFarField, WideAnnulusTakesTheHeatOfASemiInfiniteSolid) {
  // Ring held 100 K above the sheet from t = 0. At R = 1 m the annulus is nearly a plane wall;
  // 10 s reach sqrt(alpha t) = 11 mm, and the annulus (0.1 m) is semi-infinite for that time.
  const double R = 1.0, dr = 0.2e-3, angle = 2.0 * std::numbers::pi, dT = 100.0, t_end = 10.0;
  SheetFarField far(R - 0.5 * dr, R, R + 0.1, kThickness, angle, kConductivity, kHeatCapacity, kT0, dr);
  const int steps = 10000;
  for (int s = 0; s < steps; ++s) far.advance(kT0 + dT, t_end / steps);
  const double alpha = kConductivity / kHeatCapacity, area = kThickness * R * angle;
  const double expected = 2.0 * kConductivity * area * dT * std::sqrt(t_end / (std::numbers::pi * alpha));
  EXPECT_NEAR(far.absorbed_J() / expected, 1.0, 0.02);
  // The far edge has not warmed yet: the annulus is semi-infinite over this time.
  EXPECT_LT(far.temperatures().back() - kT0, 1e-6);
}

TEST(FrictionDrillingFarField, RejectsAnEmptyAnnulus) {
  EXPECT_THROW(SheetFarField(4.8e-3, 5e-3, 5e-3, kThickness, 1.0, kConductivity, kHeatCapacity, kT0, 0.2e-3),
               std::invalid_argument);
}

}  // namespace
