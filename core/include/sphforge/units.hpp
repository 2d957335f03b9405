// Physical quantities written as strings in case files ("14 mm", "300 kN", "90 rpm", "22 degC",
// "0.015 mm/s/kN") are converted to SI here. Bare numbers are already SI.
#pragma once

#include <array>
#include <string>
#include <string_view>

namespace sphforge {

/// Exponents of the SI base dimensions a quantity carries: length, mass, time, temperature.
/// Angles are dimensionless (SI), so "rpm" is 1/s and matches "rad/s".
struct Dimension {
  std::array<int, 4> exponents{0, 0, 0, 0};  // m, kg, s, K
  bool operator==(const Dimension&) const = default;
  bool dimensionless() const { return exponents == std::array<int, 4>{0, 0, 0, 0}; }
  std::string to_string() const;  // e.g. "m kg s^-2"
};

/// A unit expression resolved to SI: value_SI = scale * value + offset.
/// offset is non-zero only for degC and degF, which are allowed only on their own.
struct Unit {
  Dimension dimension;
  double scale = 1.0;
  double offset = 0.0;
};

/// Parses a unit expression: names with SI prefixes (m, g, s, K, N, Pa, J, W, Hz, rad, deg,
/// rpm, min, h, bar, degC, ...), '*', '/', '^' with an integer exponent and parentheses,
/// e.g. "kg/m^3", "W/(m*K)", "mm/s/kN". "1" or "" is dimensionless.
/// Throws std::invalid_argument with a human-readable reason on failure.
Unit parse_unit(std::string_view text);

/// Converts "NUMBER [UNIT]" to SI and checks that its dimension is that of `expected_unit`
/// (itself a unit expression, e.g. "Pa" or "m/s"). The result is expressed in the SI
/// coherent unit of that dimension (so expected "mm" still yields metres).
/// Throws std::invalid_argument naming what was expected on failure.
double parse_quantity(std::string_view text, std::string_view expected_unit);

}  // namespace sphforge
