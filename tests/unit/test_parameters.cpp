// ParamSpec validation: every error class with its exact JSON pointer, defaults, sub-sections.

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "sphforge/errors.hpp"
#include "sphforge/parameters.hpp"

namespace sphforge {
namespace {

const std::string kFile = "case.json";
const std::string kSection = "/materials/0";

ParamSpecs material_specs() {
  return {
      ParamSpec::number("density", "kg/m^3", std::nullopt, "reference density", 0.0),
      ParamSpec::number("yield_stress", "Pa", 2.5e8, "initial yield stress", 0.0, 1e6 * 1e3),
      ParamSpec::number("poisson", "1", 0.3, "Poisson ratio", 0.0, 0.5),
      ParamSpec::integer("layers", 3, "number of layers", 1, 10),
      ParamSpec::boolean("thermal", false, "couple temperature"),
      ParamSpec::string("hardening", "linear", "hardening law", {"linear", "johnson_cook"}),
      ParamSpec::object("table", "optional table"),
      ParamSpec::array("points", "optional points"),
  };
}

/// Runs validation expecting an InputError; fails the test if none is thrown.
InputError validation_error(const json& section, const ParamSpecs& specs,
                            const std::vector<std::string>& ignore = {}) {
  try {
    validate_parameters(section, specs, kFile, kSection, ignore);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError for " << section.dump();
  return InputError("", "", "");
}

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

TEST(JsonPointer, Escape) {
  EXPECT_EQ(json_pointer_escape("plain"), "plain");
  EXPECT_EQ(json_pointer_escape("a/b"), "a~1b");
  EXPECT_EQ(json_pointer_escape("m~n"), "m~0n");
  EXPECT_EQ(json_pointer_escape("~/"), "~0~1");
}

TEST(ParamSpec, Builders) {
  const ParamSpec n = ParamSpec::number("h", "m", 0.01, "smoothing length", 0.0);
  EXPECT_EQ(n.type, ParamType::Number);
  EXPECT_EQ(n.unit, "m");
  ASSERT_TRUE(n.default_value.has_value());
  EXPECT_DOUBLE_EQ(n.default_value->get<double>(), 0.01);
  EXPECT_EQ(n.min, 0.0);
  EXPECT_TRUE(std::isinf(n.max));

  EXPECT_FALSE(ParamSpec::number("rho", "kg/m^3", std::nullopt, "").default_value.has_value());
  EXPECT_EQ(ParamSpec::integer("n", 4, "").default_value, json(4));
  EXPECT_EQ(ParamSpec::boolean("b", true, "").default_value, json(true));
  EXPECT_EQ(ParamSpec::string("s", "x", "", {"x", "y"}).choices.size(), 2u);
  EXPECT_EQ(ParamSpec::object("o", "").default_value, json::object());
  EXPECT_FALSE(ParamSpec::object("o", "", true).default_value.has_value());
  EXPECT_EQ(ParamSpec::array("a", "").default_value, json::array());
  EXPECT_FALSE(ParamSpec::array("a", "", true).default_value.has_value());
}

TEST(ParamSpec, Describe) {
  const json d = ParamSpec::number("yield_stress", "Pa", 2.5e8, "initial yield stress", 0.0).describe();
  EXPECT_EQ(d["name"], "yield_stress");
  EXPECT_EQ(d["type"], "number");
  EXPECT_EQ(d["unit"], "Pa");
  EXPECT_EQ(d["default"], 2.5e8);
  EXPECT_EQ(d["min"], 0.0);
  EXPECT_FALSE(d.contains("max"));  // infinite: omitted
  EXPECT_EQ(d["doc"], "initial yield stress");
  EXPECT_EQ(d["required"], false);

  const json r = ParamSpec::number("density", "kg/m^3", std::nullopt, "rho").describe();
  EXPECT_EQ(r["required"], true);
  EXPECT_FALSE(r.contains("default"));
  EXPECT_FALSE(r.contains("min"));

  const json s = ParamSpec::string("law", "a", "law", {"a", "b"}).describe();
  EXPECT_EQ(s["type"], "string");
  EXPECT_EQ(s["choices"], json({"a", "b"}));
  EXPECT_EQ(s["default"], "a");

  EXPECT_EQ(ParamSpec::integer("n", 2, "", 1, 8).describe()["max"], 8.0);
  EXPECT_EQ(ParamSpec::object("o", "", true).describe()["type"], "object");
  EXPECT_EQ(ParamSpec::array("a", "").describe()["default"], json::array());
}

TEST(ValidateParameters, ConvertsAndFillsDefaults) {
  const ParamValues v = validate_parameters(json{{"density", "7.8 g/cm^3"}, {"layers", 5}},
                                            material_specs(), kFile, kSection);
  EXPECT_DOUBLE_EQ(v.number("density"), 7800.0);
  EXPECT_TRUE(v.values()["density"].is_number());  // stored in SI, not as the string
  EXPECT_EQ(v.integer("layers"), 5);
  // Defaults:
  EXPECT_DOUBLE_EQ(v.number("yield_stress"), 2.5e8);
  EXPECT_DOUBLE_EQ(v.number("poisson"), 0.3);
  EXPECT_FALSE(v.boolean("thermal"));
  EXPECT_EQ(v.string("hardening"), "linear");
  EXPECT_EQ(v.raw("table"), json::object());
  EXPECT_EQ(v.raw("points"), json::array());
  EXPECT_TRUE(v.has("thermal"));
  EXPECT_FALSE(v.has("nonexistent"));
  EXPECT_EQ(v.file(), kFile);
  EXPECT_EQ(v.pointer(), kSection);
  EXPECT_EQ(v.pointer_of("density"), "/materials/0/density");
}

TEST(ValidateParameters, AcceptsSINumbersAndUnitStrings) {
  const ParamValues v = validate_parameters(
      json{{"density", 2700}, {"yield_stress", "0.4 MPa"}, {"thermal", true}, {"hardening", "johnson_cook"},
           {"layers", 2.0}, {"table", {{"x", 1}}}, {"points", {1, 2, 3}}},
      material_specs(), kFile, kSection);
  EXPECT_DOUBLE_EQ(v.number("density"), 2700.0);
  EXPECT_DOUBLE_EQ(v.number("yield_stress"), 4e5);
  EXPECT_TRUE(v.boolean("thermal"));
  EXPECT_EQ(v.string("hardening"), "johnson_cook");
  EXPECT_EQ(v.integer("layers"), 2);
  EXPECT_EQ(v.raw("table")["x"], 1);
  EXPECT_EQ(v.raw("points").size(), 3u);
}

TEST(ValidateParameters, BoundsAreInclusive) {
  const ParamValues v = validate_parameters(json{{"density", 0}, {"poisson", 0.5}, {"layers", 10}},
                                            material_specs(), kFile, kSection);
  EXPECT_DOUBLE_EQ(v.number("density"), 0.0);
  EXPECT_DOUBLE_EQ(v.number("poisson"), 0.5);
  EXPECT_EQ(v.integer("layers"), 10);
}

TEST(ValidateParameters, IgnoredKeysAreAllowedAndKept) {
  const ParamValues v = validate_parameters(json{{"plugin", "elastoplastic"}, {"density", 1000}},
                                            material_specs(), kFile, kSection, {"plugin"});
  EXPECT_EQ(v.raw("plugin"), "elastoplastic");
}

TEST(ValidateParameters, SectionMustBeAnObject) {
  const InputError e = validation_error(json::array({1, 2}), material_specs());
  EXPECT_EQ(e.file(), kFile);
  EXPECT_EQ(e.pointer(), kSection);
  EXPECT_TRUE(contains(e.message(), "expected an object")) << e.message();
}

TEST(ValidateParameters, UnknownKey) {
  const InputError e = validation_error(json{{"density", 1000}, {"densty", 1}}, material_specs());
  EXPECT_EQ(e.pointer(), "/materials/0/densty");
  EXPECT_EQ(e.message(),
            "unknown key 'densty'; expected one of: density, yield_stress, poisson, layers, thermal, "
            "hardening, table, points");
  EXPECT_EQ(std::string(e.what()), "case.json at /materials/0/densty: " + e.message());

  // Unknown keys are escaped in the pointer (RFC 6901).
  EXPECT_EQ(validation_error(json{{"density", 1}, {"a/b~c", 1}}, material_specs()).pointer(),
            "/materials/0/a~1b~0c");
  // "plugin" is unknown unless ignored.
  EXPECT_EQ(validation_error(json{{"density", 1}, {"plugin", "x"}}, material_specs()).pointer(),
            "/materials/0/plugin");
}

TEST(ValidateParameters, MissingRequiredValue) {
  const InputError e = validation_error(json::object(), material_specs());
  EXPECT_EQ(e.pointer(), "/materials/0/density");
  EXPECT_EQ(e.message(), "missing required value 'density' (kg/m^3, reference density)");

  const InputError obj = validation_error(json::object(), {ParamSpec::object("tool", "the tool", true)});
  EXPECT_EQ(obj.pointer(), "/materials/0/tool");
  EXPECT_TRUE(contains(obj.message(), "missing required value 'tool' (object, the tool)")) << obj.message();
}

TEST(ValidateParameters, WrongUnit) {
  const InputError e = validation_error(json{{"density", "14 kN"}}, material_specs());
  EXPECT_EQ(e.pointer(), "/materials/0/density");
  EXPECT_TRUE(contains(e.message(), "expected a quantity in kg/m^3 (dimension m^-3 kg), got \"14 kN\""))
      << e.message();

  const InputError bad = validation_error(json{{"density", "lots"}}, material_specs());
  EXPECT_EQ(bad.pointer(), "/materials/0/density");
  EXPECT_TRUE(contains(bad.message(), "expected a number")) << bad.message();

  const InputError unknown = validation_error(json{{"density", "3 blobs"}}, material_specs());
  EXPECT_TRUE(contains(unknown.message(), "unknown unit \"blobs\"")) << unknown.message();
}

TEST(ValidateParameters, OutOfRange) {
  const InputError e = validation_error(
      json{{"density", 1}, {"yield_stress", "1.2 GPa"}},
      {ParamSpec::number("density", "kg/m^3", std::nullopt, "", 0.0),
       ParamSpec::number("yield_stress", "Pa", std::nullopt, "", 0.0, 1e6)});
  EXPECT_EQ(e.pointer(), "/materials/0/yield_stress");
  EXPECT_EQ(e.message(), "value 1.2e+09 Pa is out of range [0, 1e+06] Pa");

  const InputError neg = validation_error(json{{"density", -1}}, material_specs());
  EXPECT_EQ(neg.pointer(), "/materials/0/density");
  EXPECT_EQ(neg.message(), "value -1 kg/m^3 is out of range [0, inf] kg/m^3");

  const InputError dimless = validation_error(json{{"density", 1}, {"poisson", 0.6}}, material_specs());
  EXPECT_EQ(dimless.pointer(), "/materials/0/poisson");
  EXPECT_EQ(dimless.message(), "value 0.6 is out of range [0, 0.5]");

  const InputError integer = validation_error(json{{"density", 1}, {"layers", 0}}, material_specs());
  EXPECT_EQ(integer.pointer(), "/materials/0/layers");
  EXPECT_EQ(integer.message(), "value 0 is out of range [1, 10]");
}

TEST(ValidateParameters, WrongType) {
  struct Case {
    json section;
    std::string pointer;
    std::string message_part;
  };
  const Case cases[] = {
      {{{"density", true}}, "/materials/0/density", "expected a number in kg/m^3 or a string such as \"1 kg/m^3\", got boolean true"},
      {{{"density", nullptr}}, "/materials/0/density", "got null"},
      {{{"density", 1}, {"layers", 2.5}}, "/materials/0/layers", "expected an integer, got number 2.5"},
      {{{"density", 1}, {"layers", "3"}}, "/materials/0/layers", "expected an integer, got string \"3\""},
      {{{"density", 1}, {"thermal", 1}}, "/materials/0/thermal", "expected true or false, got number 1"},
      {{{"density", 1}, {"thermal", "yes"}}, "/materials/0/thermal", "expected true or false"},
      {{{"density", 1}, {"hardening", 3}}, "/materials/0/hardening", "expected a string, got number 3"},
      {{{"density", 1}, {"table", {1, 2}}}, "/materials/0/table", "expected an object, got array [1,2]"},
      {{{"density", 1}, {"points", {{"x", 1}}}}, "/materials/0/points", "expected an array, got object"},
  };
  for (const auto& c : cases) {
    const InputError e = validation_error(c.section, material_specs());
    EXPECT_EQ(e.pointer(), c.pointer) << c.section.dump();
    EXPECT_TRUE(contains(e.message(), c.message_part)) << e.message();
  }
}

TEST(ValidateParameters, BadChoice) {
  const InputError e = validation_error(json{{"density", 1}, {"hardening", "voce"}}, material_specs());
  EXPECT_EQ(e.pointer(), "/materials/0/hardening");
  EXPECT_EQ(e.message(), "expected one of: linear, johnson_cook; got \"voce\"");
}

TEST(ParamValues, SubAndElementPointers) {
  const ParamSpecs outer = {ParamSpec::object("tool", "", true), ParamSpec::array("controllers", "", true)};
  const ParamSpecs inner = {ParamSpec::number("radius", "m", std::nullopt, "", 0.0),
                            ParamSpec::number("speed", "rad/s", 0.0, "")};
  const json section = {{"tool", {{"radius", "7 mm"}}},
                        {"controllers", json::array({{{"radius", 1}}, {{"radius", -2}}, {{"radus", 1}}})}};
  const ParamValues v = validate_parameters(section, outer, kFile, "");

  const ParamValues tool = v.sub("tool", inner);
  EXPECT_EQ(tool.pointer(), "/tool");
  EXPECT_EQ(tool.file(), kFile);
  EXPECT_DOUBLE_EQ(tool.number("radius"), 0.007);
  EXPECT_DOUBLE_EQ(tool.number("speed"), 0.0);  // nested default
  EXPECT_EQ(tool.pointer_of("radius"), "/tool/radius");

  const ParamValues first = v.element("controllers", 0, inner);
  EXPECT_EQ(first.pointer(), "/controllers/0");
  EXPECT_DOUBLE_EQ(first.number("radius"), 1.0);

  try {
    v.element("controllers", 1, inner);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/controllers/1/radius");
    EXPECT_TRUE(contains(e.message(), "out of range")) << e.message();
  }
  try {
    v.element("controllers", 2, inner);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/controllers/2/radus");
    EXPECT_TRUE(contains(e.message(), "unknown key 'radus'; expected one of: radius, speed")) << e.message();
  }
  EXPECT_THROW(v.element("controllers", 3, inner), std::logic_error);
}

TEST(ParamValues, SubOfOptionalAbsentObjectFillsDefaults) {
  const ParamValues v = validate_parameters(json::object(), {ParamSpec::object("opt", "")}, kFile, "/run");
  const ParamValues sub = v.sub("opt", {ParamSpec::integer("n", 7, "")});
  EXPECT_EQ(sub.pointer(), "/run/opt");
  EXPECT_EQ(sub.integer("n"), 7);
}

TEST(ParamValues, SubOfNonObjectIsInputError) {
  const ParamValues v(json{{"tool", 3}}, kFile, "/x");
  try {
    v.sub("tool", {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/x/tool");
    EXPECT_TRUE(contains(e.message(), "expected an object")) << e.message();
  }
}

TEST(ParamValues, FailPointsAtNameOrSection) {
  const ParamValues v(json{{"a/b", 1}}, kFile, "/plugins/2");
  try {
    v.fail("a/b", "must be less than c");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), kFile);
    EXPECT_EQ(e.pointer(), "/plugins/2/a~1b");
    EXPECT_EQ(e.message(), "must be less than c");
  }
  try {
    v.fail("", "inconsistent section");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/plugins/2");
  }
}

TEST(ParamValues, UnknownNameOrWrongTypeIsLogicError) {
  const ParamValues v = validate_parameters(json{{"density", 1}}, material_specs(), kFile, kSection);
  EXPECT_THROW(v.number("nope"), std::logic_error);
  EXPECT_THROW(v.integer("nope"), std::logic_error);
  EXPECT_THROW(v.boolean("nope"), std::logic_error);
  EXPECT_THROW(v.string("nope"), std::logic_error);
  EXPECT_THROW(v.raw("nope"), std::logic_error);
  EXPECT_THROW(v.sub("nope", {}), std::logic_error);
  EXPECT_THROW(v.string("density"), std::logic_error);
  EXPECT_THROW(v.integer("hardening"), std::logic_error);
  // An InputError is not a logic_error: the distinction matters to the CLI's exit codes.
  try {
    v.raw("nope");
  } catch (const InputError&) {
    FAIL() << "a programming error must not be reported as an input error";
  } catch (const std::logic_error&) {
  }
}

}  // namespace
}  // namespace sphforge

// ParamValues::quantities: arrays of numbers or quantity strings, converted to SI, with errors at
// the array's pointer.
TEST(ParamValuesQuantities, MixedNumbersAndUnitsConvertToSi) {
  using namespace sphforge;
  const ParamValues p(json{{"point", {"5 mm", 0.25, "1 cm"}}, {"bad", {"5 kg", 0, 0}}, {"short", {1, 2}}},
                      "case.json", "/process");
  const std::vector<double> v = p.quantities("point", 3, "m");
  ASSERT_EQ(v.size(), 3u);
  EXPECT_DOUBLE_EQ(v[0], 0.005);
  EXPECT_DOUBLE_EQ(v[1], 0.25);
  EXPECT_DOUBLE_EQ(v[2], 0.01);
  try {
    (void)p.quantities("bad", 3, "m");
    FAIL() << "a mass given for a length must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/process/bad"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("component 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)p.quantities("short", 3, "m"), InputError);
}
