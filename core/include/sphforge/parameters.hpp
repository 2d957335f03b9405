// Parameters of the core and of every plugin are declared as ParamSpec lists. The same list
// validates a case section (unknown keys, types, units, ranges -> InputError with the JSON
// pointer), fills defaults, and documents the plugin in `sphforge plugins`.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace sphforge {

using json = nlohmann::json;

/// Quantity: a number (SI) or a "value unit" string whose unit is only known later, e.g. a
/// controller's value takes the unit of the command it drives; read it with ParamValues::quantity().
enum class ParamType { Number, Integer, Boolean, String, Object, Array, Quantity };

struct ParamSpec {
  std::string name;            ///< JSON key
  ParamType type = ParamType::Number;
  std::string unit = "1";      ///< SI unit of a Number ("m", "Pa", "rad/s", "1" = dimensionless)
  std::optional<json> default_value;  ///< absent: the key is required
  double min = -std::numeric_limits<double>::infinity();  ///< inclusive, in SI
  double max = std::numeric_limits<double>::infinity();   ///< inclusive, in SI
  std::vector<std::string> choices;  ///< allowed values of a String (empty: any)
  std::string doc;                   ///< one line

  // Builders, so plugin code reads like a table.
  static ParamSpec number(std::string name, std::string unit, std::optional<double> def,
                          std::string doc, double min = -std::numeric_limits<double>::infinity(),
                          double max = std::numeric_limits<double>::infinity());
  static ParamSpec integer(std::string name, std::optional<long long> def, std::string doc,
                           double min = -std::numeric_limits<double>::infinity(),
                           double max = std::numeric_limits<double>::infinity());
  static ParamSpec boolean(std::string name, std::optional<bool> def, std::string doc);
  static ParamSpec string(std::string name, std::optional<std::string> def, std::string doc,
                          std::vector<std::string> choices = {});
  static ParamSpec object(std::string name, std::string doc, bool required = false);
  static ParamSpec quantity(std::string name, std::string doc);  ///< required
  static ParamSpec array(std::string name, std::string doc, bool required = false);

  json describe() const;  ///< for `sphforge plugins --json`
};

using ParamSpecs = std::vector<ParamSpec>;

/// A validated section of a case: numbers in SI, defaults filled in. Remembers the file and
/// JSON pointer of every value so later checks (by plugins) can report precise errors.
class ParamValues {
 public:
  ParamValues() = default;
  ParamValues(json values, std::string file, std::string pointer);

  double number(const std::string& name) const;
  long long integer(const std::string& name) const;
  bool boolean(const std::string& name) const;
  const std::string& string(const std::string& name) const;
  const json& raw(const std::string& name) const;  ///< Object/Array values as given
  /// A Quantity parameter converted to SI in `unit`; a wrong unit throws InputError at its pointer.
  double quantity(const std::string& name, const std::string& unit) const;
  bool has(const std::string& name) const;          ///< present (given or defaulted)
  /// An Array parameter of exactly `count` values, each a number (SI) or a "value unit" string,
  /// converted to SI in `unit` (e.g. a vector ["5 mm", 0, "1 cm"] in "m"); anything else throws
  /// InputError at its pointer.
  std::vector<double> quantities(const std::string& name, std::size_t count, const std::string& unit) const;
  /// An Array parameter of pairs [[a, b], ...] (at least one), a in `unit_a` and b in `unit_b`, each a
  /// number (SI) or a "value unit" string, e.g. a schedule [["0 s", "1 mm/s"], ["5 s", "2 mm/s"]].
  std::vector<std::pair<double, double>> pairs(const std::string& name, const std::string& unit_a,
                                               const std::string& unit_b) const;

  /// Validates the Object parameter `name` (or element `index` of an Array) against `specs`.
  ParamValues sub(const std::string& name, const ParamSpecs& specs) const;
  ParamValues element(const std::string& name, std::size_t index, const ParamSpecs& specs) const;

  /// Throws InputError pointing at `name` (or at the section when empty).
  [[noreturn]] void fail(const std::string& name, const std::string& message) const;

  const std::string& file() const { return file_; }
  const std::string& pointer() const { return pointer_; }
  std::string pointer_of(const std::string& name) const;
  const json& values() const { return values_; }

 private:
  json values_;
  std::string file_;
  std::string pointer_;
};

/// Validates `section` (a JSON object found at `pointer` in `file`) against `specs`.
/// `ignore` lists keys handled elsewhere (e.g. "plugin"). Throws InputError.
ParamValues validate_parameters(const json& section, const ParamSpecs& specs,
                                const std::string& file, const std::string& pointer,
                                const std::vector<std::string>& ignore = {});

/// Escapes a key for use in a JSON pointer (RFC 6901: "~" -> "~0", "/" -> "~1").
std::string json_pointer_escape(const std::string& key);

}  // namespace sphforge
