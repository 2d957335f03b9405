// Unit expressions and quantity strings -> SI.

#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>
#include <string>

#include "sphforge/units.hpp"

namespace sphforge {
namespace {

using Exps = std::array<int, 4>;  // m, kg, s, K

/// The message of the std::invalid_argument thrown by f(); fails the test if none is thrown.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected std::invalid_argument";
  return {};
}

TEST(Dimension, ToString) {
  EXPECT_EQ(Dimension{}.to_string(), "1");
  EXPECT_EQ((Dimension{{1, 0, 0, 0}}).to_string(), "m");
  EXPECT_EQ((Dimension{{1, 1, -2, 0}}).to_string(), "m kg s^-2");
  EXPECT_EQ((Dimension{{0, 0, 0, 1}}).to_string(), "K");
  EXPECT_EQ((Dimension{{-3, 1, 0, 0}}).to_string(), "m^-3 kg");
  EXPECT_TRUE(Dimension{}.dimensionless());
}

TEST(ParseUnit, BaseAndDerivedNames) {
  EXPECT_EQ(parse_unit("m").dimension.exponents, (Exps{1, 0, 0, 0}));
  EXPECT_DOUBLE_EQ(parse_unit("g").scale, 1e-3);
  EXPECT_EQ(parse_unit("g").dimension.exponents, (Exps{0, 1, 0, 0}));
  EXPECT_EQ(parse_unit("N").dimension.exponents, (Exps{1, 1, -2, 0}));
  EXPECT_EQ(parse_unit("Pa").dimension.exponents, (Exps{-1, 1, -2, 0}));
  EXPECT_EQ(parse_unit("J").dimension.exponents, (Exps{2, 1, -2, 0}));
  EXPECT_EQ(parse_unit("W").dimension.exponents, (Exps{2, 1, -3, 0}));
  EXPECT_EQ(parse_unit("Hz").dimension.exponents, (Exps{0, 0, -1, 0}));
  EXPECT_TRUE(parse_unit("rad").dimension.dimensionless());
  EXPECT_DOUBLE_EQ(parse_unit("deg").scale, std::numbers::pi / 180.0);
  EXPECT_DOUBLE_EQ(parse_unit("rpm").scale, 2.0 * std::numbers::pi / 60.0);
  EXPECT_EQ(parse_unit("rpm").dimension, parse_unit("rad/s").dimension);
  EXPECT_DOUBLE_EQ(parse_unit("bar").scale, 1e5);
  EXPECT_DOUBLE_EQ(parse_unit("L").scale, 1e-3);
  EXPECT_EQ(parse_unit("L").dimension.exponents, (Exps{3, 0, 0, 0}));
  EXPECT_EQ(parse_unit("K").dimension.exponents, (Exps{0, 0, 0, 1}));
}

TEST(ParseUnit, ExactNameBeforePrefix) {
  // "min" is minutes (not milli-inch), "mm" millimetres, "ms" milliseconds, "Pa" pascal.
  EXPECT_DOUBLE_EQ(parse_unit("min").scale, 60.0);
  EXPECT_EQ(parse_unit("min").dimension.exponents, (Exps{0, 0, 1, 0}));
  EXPECT_DOUBLE_EQ(parse_unit("h").scale, 3600.0);
  EXPECT_DOUBLE_EQ(parse_unit("mm").scale, 1e-3);
  EXPECT_EQ(parse_unit("mm").dimension.exponents, (Exps{1, 0, 0, 0}));
  EXPECT_DOUBLE_EQ(parse_unit("ms").scale, 1e-3);
  EXPECT_EQ(parse_unit("ms").dimension.exponents, (Exps{0, 0, 1, 0}));
  EXPECT_DOUBLE_EQ(parse_unit("Pa").scale, 1.0);
}

TEST(ParseUnit, Prefixes) {
  EXPECT_DOUBLE_EQ(parse_unit("kg").scale, 1.0);
  EXPECT_EQ(parse_unit("kg").dimension.exponents, (Exps{0, 1, 0, 0}));
  EXPECT_DOUBLE_EQ(parse_unit("kN").scale, 1e3);
  EXPECT_DOUBLE_EQ(parse_unit("MPa").scale, 1e6);
  EXPECT_DOUBLE_EQ(parse_unit("GPa").scale, 1e9);
  EXPECT_DOUBLE_EQ(parse_unit("nm").scale, 1e-9);
  EXPECT_DOUBLE_EQ(parse_unit("um").scale, 1e-6);
  EXPECT_DOUBLE_EQ(parse_unit("\xC2\xB5m").scale, 1e-6);  // micro sign
  EXPECT_DOUBLE_EQ(parse_unit("\xCE\xBCm").scale, 1e-6);  // greek mu
  EXPECT_DOUBLE_EQ(parse_unit("cm").scale, 1e-2);
  EXPECT_DOUBLE_EQ(parse_unit("kHz").scale, 1e3);
  EXPECT_DOUBLE_EQ(parse_unit("mbar").scale, 100.0);
  EXPECT_DOUBLE_EQ(parse_unit("mL").scale, 1e-6);
}

TEST(ParseUnit, Expressions) {
  const Unit density = parse_unit("kg/m^3");
  EXPECT_EQ(density.dimension.exponents, (Exps{-3, 1, 0, 0}));
  EXPECT_DOUBLE_EQ(density.scale, 1.0);

  const Unit conductivity = parse_unit("W/(m*K)");
  EXPECT_EQ(conductivity.dimension.exponents, (Exps{1, 1, -3, -1}));

  // Left-associative: (mm/s)/kN.
  const Unit feed = parse_unit("mm/s/kN");
  EXPECT_EQ(feed.dimension.exponents, (Exps{0, -1, 1, 0}));
  EXPECT_DOUBLE_EQ(feed.scale, 1e-6);

  EXPECT_DOUBLE_EQ(parse_unit("g/cm^3").scale, 1e3);
  EXPECT_EQ(parse_unit("m*s^-2").dimension.exponents, (Exps{1, 0, -2, 0}));
  EXPECT_EQ(parse_unit("1/s").dimension.exponents, (Exps{0, 0, -1, 0}));
  EXPECT_EQ(parse_unit("(mm/s)^2").dimension.exponents, (Exps{2, 0, -2, 0}));
  EXPECT_DOUBLE_EQ(parse_unit("(mm/s)^2").scale, 1e-6);
  EXPECT_DOUBLE_EQ(parse_unit("km^+2").scale, 1e6);
  EXPECT_EQ(parse_unit(" kg / m ^ 3 ").dimension.exponents, (Exps{-3, 1, 0, 0}));
  EXPECT_TRUE(parse_unit("1").dimension.dimensionless());
  EXPECT_TRUE(parse_unit("").dimension.dimensionless());
  EXPECT_DOUBLE_EQ(parse_unit("").scale, 1.0);
}

TEST(ParseUnit, TemperatureOffsets) {
  const Unit c = parse_unit("degC");
  EXPECT_EQ(c.dimension.exponents, (Exps{0, 0, 0, 1}));
  EXPECT_DOUBLE_EQ(c.scale, 1.0);
  EXPECT_DOUBLE_EQ(c.offset, 273.15);
  const Unit f = parse_unit("degF");
  EXPECT_DOUBLE_EQ(f.scale, 5.0 / 9.0);
  EXPECT_NEAR(32.0 * f.scale + f.offset, 273.15, 1e-12);
  EXPECT_NEAR(212.0 * f.scale + f.offset, 373.15, 1e-12);
}

TEST(ParseUnit, Errors) {
  EXPECT_NE(error_of([] { parse_unit("furlong"); }).find("unknown unit \"furlong\""), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("m/xs"); }).find("unknown unit \"xs\""), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("degC/s"); }).find("absolute temperature"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("W/degC"); }).find("use \"K\""), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("kdegC"); }).find("does not take an SI prefix"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("krpm"); }).find("\"rpm\" does not take an SI prefix"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("kmin"); }).find("\"min\" does not take an SI prefix"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("kh"); }).find("\"h\" does not take an SI prefix"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("m^2.5"); }).find("integer exponent"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("m^"); }).find("integer exponent"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("(m/s"); }).find("missing ')'"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("m/"); }).find("expected a unit name"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("N m"); }).find("join units with '*' or '/'"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("m)"); }).find("unexpected \")\""), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("10/s"); }).find("numbers other than '1'"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit("m^99999"); }).find("too large"), std::string::npos);
  EXPECT_NE(error_of([] { parse_unit(std::string(200, '(') + "m" + std::string(200, ')')); })
                .find("nested too deeply"),
            std::string::npos);
}

TEST(ParseQuantity, ConvertsToSI) {
  EXPECT_DOUBLE_EQ(parse_quantity("14 mm", "m"), 0.014);
  EXPECT_DOUBLE_EQ(parse_quantity("300 kN", "N"), 3e5);
  EXPECT_NEAR(parse_quantity("90 rpm", "rad/s"), 9.42477796, 1e-8);
  EXPECT_DOUBLE_EQ(parse_quantity("22 degC", "K"), 295.15);
  EXPECT_NEAR(parse_quantity("0.015 mm/s/kN", "m/s/N"), 1.5e-8, 1e-22);
  EXPECT_DOUBLE_EQ(parse_quantity("1e6 kg/m^3", "kg/m^3"), 1e6);
  EXPECT_DOUBLE_EQ(parse_quantity("7.8 g/cm^3", "kg/m^3"), 7800.0);
  EXPECT_DOUBLE_EQ(parse_quantity("0.4 MPa", "Pa"), 4e5);
  EXPECT_DOUBLE_EQ(parse_quantity("2 bar", "Pa"), 2e5);
  EXPECT_DOUBLE_EQ(parse_quantity("1.5 min", "s"), 90.0);
  EXPECT_DOUBLE_EQ(parse_quantity("180 deg", "rad"), std::numbers::pi);
  EXPECT_NEAR(parse_quantity("-40 degF", "K"), 233.15, 1e-9);
  EXPECT_DOUBLE_EQ(parse_quantity("5 K", "K"), 5.0);  // temperature difference in K
  EXPECT_DOUBLE_EQ(parse_quantity("+5 mm", "m"), 0.005);
  EXPECT_DOUBLE_EQ(parse_quantity("-3 mm", "m"), -0.003);
  EXPECT_DOUBLE_EQ(parse_quantity("  12mm ", "m"), 0.012);
}

TEST(ParseQuantity, BareNumbersAreSI) {
  EXPECT_DOUBLE_EQ(parse_quantity("5", "m"), 5.0);
  EXPECT_DOUBLE_EQ(parse_quantity("2.5e-3", "m"), 2.5e-3);
  EXPECT_DOUBLE_EQ(parse_quantity("300", "K"), 300.0);  // not degC
  EXPECT_DOUBLE_EQ(parse_quantity("0.3", "1"), 0.3);
}

TEST(ParseQuantity, ResultIsCoherentSIEvenForPrefixedExpectedUnit) {
  EXPECT_DOUBLE_EQ(parse_quantity("14 mm", "mm"), 0.014);
  EXPECT_DOUBLE_EQ(parse_quantity("1 km", "mm"), 1000.0);
}

TEST(ParseQuantity, DimensionMismatchNamesBothDimensions) {
  EXPECT_EQ(error_of([] { parse_quantity("14 kN", "m"); }),
            "expected a quantity in m (dimension m), got \"14 kN\" (dimension m kg s^-2)");
  EXPECT_NE(error_of([] { parse_quantity("90 rpm", "rad"); }).find("(dimension s^-1)"), std::string::npos);
  EXPECT_NE(error_of([] { parse_quantity("3 N*m", "N"); }).find("expected a quantity in N"), std::string::npos);
}

TEST(ParseQuantity, ErrorsSayWhatWasExpected) {
  const std::string prefix = "expected a quantity in m (dimension m), got ";
  const std::string unknown = error_of([] { parse_quantity("14 furlong", "m"); });
  EXPECT_EQ(unknown.rfind(prefix + "\"14 furlong\"", 0), 0u) << unknown;
  EXPECT_NE(unknown.find("unknown unit \"furlong\""), std::string::npos);

  const std::string bad_number = error_of([] { parse_quantity("abc mm", "m"); });
  EXPECT_EQ(bad_number.rfind(prefix, 0), 0u) << bad_number;
  EXPECT_NE(bad_number.find("expected a number"), std::string::npos);
  EXPECT_NE(error_of([] { parse_quantity("mm", "m"); }).find("expected a number"), std::string::npos);
  EXPECT_NE(error_of([] { parse_quantity("inf m", "m"); }).find("expected a number"), std::string::npos);
  EXPECT_NE(error_of([] { parse_quantity("nan", "m"); }).find("expected a number"), std::string::npos);

  const std::string trailing = error_of([] { parse_quantity("14 mm xyz", "m"); });
  EXPECT_EQ(trailing.rfind(prefix, 0), 0u) << trailing;
  EXPECT_NE(trailing.find("unexpected \"xyz\""), std::string::npos);
  EXPECT_NE(error_of([] { parse_quantity("14 mm)", "m"); }).find("unexpected \")\""), std::string::npos);

  const std::string empty = error_of([] { parse_quantity("", "m"); });
  EXPECT_EQ(empty.rfind(prefix, 0), 0u) << empty;
  EXPECT_NE(empty.find("empty"), std::string::npos);
  EXPECT_NE(error_of([] { parse_quantity("   ", "m"); }).find("empty"), std::string::npos);

  const std::string combined = error_of([] { parse_quantity("2 degC/s", "K/s"); });
  EXPECT_NE(combined.find("expected a quantity in K/s"), std::string::npos);
  EXPECT_NE(combined.find("absolute temperature"), std::string::npos);

  const std::string overflow = error_of([] { parse_quantity("1e300 GPa^9", "Pa^9"); });
  EXPECT_NE(overflow.find("overflows"), std::string::npos) << overflow;

  EXPECT_NE(error_of([] { parse_quantity("1 m", "bogus"); }).find("invalid expected unit \"bogus\""),
            std::string::npos);
}

}  // namespace
}  // namespace sphforge
