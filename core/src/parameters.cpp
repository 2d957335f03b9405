// Declarative parameter validation: one ParamSpecs table per plugin drives validation of its
// case section, default filling, and its self-documentation.

#include "sphforge/parameters.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "sphforge/errors.hpp"
#include "sphforge/units.hpp"

namespace sphforge {

namespace {

const char* type_name(ParamType type) {
  switch (type) {
    case ParamType::Number: return "number";
    case ParamType::Integer: return "integer";
    case ParamType::Boolean: return "boolean";
    case ParamType::String: return "string";
    case ParamType::Object: return "object";
    case ParamType::Array: return "array";
    case ParamType::Quantity: return "quantity";
  }
  return "?";
}

/// Shortest text that reads back as the same double, so a range error never shows two values
/// that print identically ("1e+06 is out of range [0, 1e+06]").
std::string format_number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  if (ec != std::errc()) return std::to_string(v);
  return std::string(buf, end);
}

/// " Pa" for a dimensional unit, "" for dimensionless, to append after a number.
std::string unit_suffix(const std::string& unit) {
  return (unit.empty() || unit == "1") ? std::string() : " " + unit;
}

/// A short rendering of a user's JSON value for error messages; long values are cut so that
/// a wrongly-typed object does not flood the terminal.
std::string show(const json& value) {
  std::string text = value.dump();
  constexpr std::size_t kMax = 60;
  if (text.size() > kMax) text = text.substr(0, kMax) + "...";
  return value.type_name() + std::string(" ") + text;
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) {
    if (!out.empty()) out += ", ";
    out += item;
  }
  return out;
}

void check_range(double value, const ParamSpec& spec, const std::string& unit, const std::string& file,
                 const std::string& pointer) {
  if (value >= spec.min && value <= spec.max) return;
  throw InputError(file, pointer,
                   "value " + format_number(value) + unit_suffix(unit) + " is out of range [" +
                       format_number(spec.min) + ", " + format_number(spec.max) + "]" +
                       unit_suffix(unit));
}

/// Checks one given value against its spec; returns it converted (numbers to SI).
json validate_value(const json& value, const ParamSpec& spec, const std::string& file,
                    const std::string& pointer) {
  switch (spec.type) {
    case ParamType::Number: {
      double si = 0.0;
      if (value.is_number()) {
        si = value.get<double>();
      } else if (value.is_string()) {
        try {
          si = parse_quantity(value.get_ref<const std::string&>(), spec.unit);
        } catch (const std::invalid_argument& e) {
          throw InputError(file, pointer, e.what());
        }
      } else {
        const std::string example = spec.unit == "1" ? "" : " or a string such as \"1 " + spec.unit + "\"";
        throw InputError(file, pointer,
                         "expected a number in " + spec.unit + example + ", got " + show(value));
      }
      if (!std::isfinite(si)) throw InputError(file, pointer, "expected a finite number, got " + show(value));
      // The range is checked in SI, and reported in the spec's (SI) unit, since the user may
      // have written any compatible unit.
      check_range(si, spec, spec.unit, file, pointer);
      return si;
    }
    case ParamType::Integer: {
      long long n = 0;
      if (value.is_number_integer() && !value.is_number_unsigned()) {
        n = value.get<long long>();
      } else if (value.is_number_unsigned()) {
        const auto u = value.get<unsigned long long>();
        if (u > static_cast<unsigned long long>(std::numeric_limits<long long>::max()))
          throw InputError(file, pointer, "expected an integer, got " + show(value) + " (too large)");
        n = static_cast<long long>(u);
      } else if (value.is_number_float()) {
        // 3.0 is integral; 2.5 is not. Bounds keep the cast to long long defined.
        const double d = value.get<double>();
        if (!(std::trunc(d) == d && std::abs(d) < 9.2e18))
          throw InputError(file, pointer, "expected an integer, got " + show(value));
        n = static_cast<long long>(d);
      } else {
        throw InputError(file, pointer, "expected an integer, got " + show(value));
      }
      check_range(static_cast<double>(n), spec, "1", file, pointer);
      return n;
    }
    case ParamType::Boolean:
      if (!value.is_boolean())
        throw InputError(file, pointer, "expected true or false, got " + show(value));
      return value;
    case ParamType::String: {
      if (!value.is_string()) throw InputError(file, pointer, "expected a string, got " + show(value));
      const auto& s = value.get_ref<const std::string&>();
      if (!spec.choices.empty() &&
          std::find(spec.choices.begin(), spec.choices.end(), s) == spec.choices.end())
        throw InputError(file, pointer,
                         "expected one of: " + join(spec.choices) + "; got \"" + s + "\"");
      return value;
    }
    case ParamType::Object:
      if (!value.is_object()) throw InputError(file, pointer, "expected an object, got " + show(value));
      return value;
    case ParamType::Array:
      if (!value.is_array()) throw InputError(file, pointer, "expected an array, got " + show(value));
      return value;
    case ParamType::Quantity:
      if (!value.is_number() && !value.is_string())
        throw InputError(file, pointer, "expected a number or a quantity string such as \"1 mm/s\", got " + show(value));
      return value;
  }
  throw std::logic_error("unhandled ParamType");
}

std::string missing_message(const ParamSpec& spec) {
  std::string what = spec.type == ParamType::Number
                         ? (spec.unit == "1" ? std::string("dimensionless number") : spec.unit)
                         : std::string(type_name(spec.type));
  if (!spec.doc.empty()) what += ", " + spec.doc;
  return "missing required value '" + spec.name + "' (" + what + ")";
}

}  // namespace

// --- ParamSpec builders -------------------------------------------------------------------

ParamSpec ParamSpec::quantity(std::string name, std::string doc) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::Quantity;
  s.unit = "";
  s.doc = std::move(doc);
  return s;
}

ParamSpec ParamSpec::number(std::string name, std::string unit, std::optional<double> def,
                            std::string doc, double min, double max) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::Number;
  s.unit = std::move(unit);
  if (def) s.default_value = *def;
  s.doc = std::move(doc);
  s.min = min;
  s.max = max;
  return s;
}

ParamSpec ParamSpec::integer(std::string name, std::optional<long long> def, std::string doc,
                             double min, double max) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::Integer;
  if (def) s.default_value = *def;
  s.doc = std::move(doc);
  s.min = min;
  s.max = max;
  return s;
}

ParamSpec ParamSpec::boolean(std::string name, std::optional<bool> def, std::string doc) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::Boolean;
  if (def) s.default_value = *def;
  s.doc = std::move(doc);
  return s;
}

ParamSpec ParamSpec::string(std::string name, std::optional<std::string> def, std::string doc,
                            std::vector<std::string> choices) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::String;
  if (def) s.default_value = *def;
  s.doc = std::move(doc);
  s.choices = std::move(choices);
  return s;
}

// An optional Object/Array defaults to an empty one, so that sub()/element() on an absent
// section still works and fills the nested defaults.
ParamSpec ParamSpec::object(std::string name, std::string doc, bool required) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::Object;
  if (!required) s.default_value = json::object();
  s.doc = std::move(doc);
  return s;
}

ParamSpec ParamSpec::array(std::string name, std::string doc, bool required) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = ParamType::Array;
  if (!required) s.default_value = json::array();
  s.doc = std::move(doc);
  return s;
}

json ParamSpec::describe() const {
  json d = json::object();
  d["name"] = name;
  d["type"] = type_name(type);
  // Every parameter carries "unit": SI unit of numbers, null where it has none (strings,
  // objects) or where it follows another parameter (a Quantity takes its command's unit).
  d["unit"] = (type == ParamType::Number || type == ParamType::Integer) ? json(unit) : json(nullptr);
  if (type == ParamType::Number || type == ParamType::Integer) {
    if (std::isfinite(min)) d["min"] = min;
    if (std::isfinite(max)) d["max"] = max;
  }
  if (default_value) d["default"] = *default_value;
  if (!choices.empty()) d["choices"] = choices;
  d["doc"] = doc;
  d["required"] = !default_value.has_value();
  return d;
}

// --- validation ---------------------------------------------------------------------------

std::string json_pointer_escape(const std::string& key) {
  std::string out;
  out.reserve(key.size());
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

ParamValues validate_parameters(const json& section, const ParamSpecs& specs,
                                const std::string& file, const std::string& pointer,
                                const std::vector<std::string>& ignore) {
  if (!section.is_object()) throw InputError(file, pointer, "expected an object, got " + show(section));

  auto find_spec = [&](const std::string& key) -> const ParamSpec* {
    for (const auto& s : specs)
      if (s.name == key) return &s;
    return nullptr;
  };

  // Unknown keys first: a misspelt optional key would otherwise be silently replaced by its
  // default, and a misspelt required key is better reported as the typo than as "missing".
  for (const auto& [key, value] : section.items()) {
    if (find_spec(key) != nullptr) continue;
    if (std::find(ignore.begin(), ignore.end(), key) != ignore.end()) continue;
    std::vector<std::string> names;
    for (const auto& s : specs) names.push_back(s.name);
    const std::string expected =
        names.empty() ? std::string("this section takes no parameters") : "expected one of: " + join(names);
    throw InputError(file, pointer + "/" + json_pointer_escape(key), "unknown key '" + key + "'; " + expected);
  }

  // Ignored keys are kept as given: they belong to whoever handles them elsewhere.
  json result = json::object();
  for (const auto& key : ignore)
    if (section.contains(key) && find_spec(key) == nullptr) result[key] = section[key];

  for (const auto& spec : specs) {
    const std::string item_pointer = pointer + "/" + json_pointer_escape(spec.name);
    if (auto it = section.find(spec.name); it != section.end())
      result[spec.name] = validate_value(*it, spec, file, item_pointer);
    else if (spec.default_value)
      result[spec.name] = *spec.default_value;
    else
      throw InputError(file, item_pointer, missing_message(spec));
  }
  return ParamValues(std::move(result), file, pointer);
}

// --- ParamValues --------------------------------------------------------------------------

ParamValues::ParamValues(json values, std::string file, std::string pointer)
    : values_(std::move(values)), file_(std::move(file)), pointer_(std::move(pointer)) {}

const json& ParamValues::raw(const std::string& name) const {
  if (!values_.is_object() || !values_.contains(name))
    throw std::logic_error("parameter '" + name + "' is not declared in the section at '" + pointer_ +
                           "' (missing from its ParamSpecs?)");
  return values_.at(name);
}

double ParamValues::quantity(const std::string& name, const std::string& unit) const {
  const json& value = raw(name);
  if (value.is_number()) return value.get<double>();
  try {
    return parse_quantity(value.get<std::string>(), unit);
  } catch (const std::invalid_argument& e) {
    fail(name, e.what());
  }
}

bool ParamValues::has(const std::string& name) const {
  return values_.is_object() && values_.contains(name);
}

// Type mismatches below are programming errors too (the spec declared another type), so they
// are logic_errors rather than InputErrors.
double ParamValues::number(const std::string& name) const {
  const json& v = raw(name);
  if (!v.is_number()) throw std::logic_error("parameter '" + name + "' is not a number");
  return v.get<double>();
}

long long ParamValues::integer(const std::string& name) const {
  const json& v = raw(name);
  if (!v.is_number_integer()) throw std::logic_error("parameter '" + name + "' is not an integer");
  return v.get<long long>();
}

bool ParamValues::boolean(const std::string& name) const {
  const json& v = raw(name);
  if (!v.is_boolean()) throw std::logic_error("parameter '" + name + "' is not a boolean");
  return v.get<bool>();
}

const std::string& ParamValues::string(const std::string& name) const {
  const json& v = raw(name);
  if (!v.is_string()) throw std::logic_error("parameter '" + name + "' is not a string");
  return v.get_ref<const std::string&>();
}

namespace {
/// One array entry `e` of parameter `name` as a number (SI) or a "value unit" string in `unit`; errors
/// name the parameter and the entry (`where`).
double quantity_entry(const ParamValues& p, const std::string& name, const json& e, const std::string& where,
                      const std::string& unit) {
  if (e.is_number()) return e.get<double>();
  if (e.is_string()) {
    try {
      return parse_quantity(e.get<std::string>(), unit);
    } catch (const std::invalid_argument& ex) {
      p.fail(name, where + ": " + ex.what());
    }
  }
  p.fail(name, where + ": expected a number or a \"value unit\" string in " + unit);
}
}  // namespace

std::vector<double> ParamValues::quantities(const std::string& name, std::size_t count, const std::string& unit) const {
  const json& value = raw(name);
  if (!value.is_array() || value.size() != count)
    fail(name, "expected an array of " + std::to_string(count) + " values in " + unit);
  std::vector<double> out(count);
  for (std::size_t c = 0; c < count; ++c) out[c] = quantity_entry(*this, name, value[c], "component " + std::to_string(c), unit);
  return out;
}

std::vector<std::pair<double, double>> ParamValues::pairs(const std::string& name, const std::string& unit_a,
                                                          const std::string& unit_b) const {
  const json& v = raw(name);
  if (!v.is_array() || v.empty()) fail(name, "expected a non-empty array of [" + unit_a + ", " + unit_b + "] pairs");
  std::vector<std::pair<double, double>> out;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const std::string at = "entry " + std::to_string(k);
    if (!v[k].is_array() || v[k].size() != 2) fail(name, at + ": expected a pair [" + unit_a + ", " + unit_b + "]");
    out.emplace_back(quantity_entry(*this, name, v[k][0], at + " [0]", unit_a),
                     quantity_entry(*this, name, v[k][1], at + " [1]", unit_b));
  }
  return out;
}

ParamValues ParamValues::sub(const std::string& name, const ParamSpecs& specs) const {
  return validate_parameters(raw(name), specs, file_, pointer_of(name));
}

ParamValues ParamValues::element(const std::string& name, std::size_t index,
                                 const ParamSpecs& specs) const {
  const json& array = raw(name);
  if (!array.is_array()) throw std::logic_error("parameter '" + name + "' is not an array");
  if (index >= array.size())
    throw std::logic_error("parameter '" + name + "' has " + std::to_string(array.size()) +
                           " elements; index " + std::to_string(index) + " is out of range");
  return validate_parameters(array[index], specs, file_, pointer_of(name) + "/" + std::to_string(index));
}

void ParamValues::fail(const std::string& name, const std::string& message) const {
  throw InputError(file_, name.empty() ? pointer_ : pointer_of(name), message);
}

std::string ParamValues::pointer_of(const std::string& name) const {
  return pointer_ + "/" + json_pointer_escape(name);
}

}  // namespace sphforge
