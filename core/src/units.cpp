// Unit expressions and quantities ("14 mm", "0.015 mm/s/kN", "22 degC") converted to SI.
//
// Grammar (whitespace is allowed around tokens, but two factors must be joined by '*' or '/':
// "N m" is rejected rather than guessed at):
//   expression := power (('*' | '/') power)*          left-associative: "mm/s/kN" = (mm/s)/kN
//   power      := primary ('^' ['+'|'-'] digits)?
//   primary    := '(' expression ')' | '1' | name
//   name       := exact unit name | SI prefix + prefixable unit name
//
// Temperatures: "degC" and "degF" carry an offset and therefore always denote an *absolute*
// temperature; they are accepted only as the whole unit ("22 degC", never "degC/s"). A
// temperature *difference* or any compound unit involving temperature must use "K"
// ("5 K", "W/(m*K)"), because "1 degC/s" would be ambiguous between an offset and a scale.

#include "sphforge/units.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace sphforge {

namespace {

struct NamedUnit {
  std::string_view name;
  Dimension dimension;
  double scale;
  double offset;
  bool prefixable;  // e.g. "mm", "kN", "MPa"; not "kmin" or "kdegC"
};

// Dimension exponents: {m, kg, s, K}. Mass is based on kg, so "g" has scale 1e-3 and "kg" is
// found as prefix "k" + "g", exactly like any other prefixed unit.
constexpr double kPi = std::numbers::pi;
const NamedUnit kUnits[] = {
    {"m", {{1, 0, 0, 0}}, 1.0, 0.0, true},
    {"g", {{0, 1, 0, 0}}, 1e-3, 0.0, true},
    {"s", {{0, 0, 1, 0}}, 1.0, 0.0, true},
    {"K", {{0, 0, 0, 1}}, 1.0, 0.0, true},
    {"N", {{1, 1, -2, 0}}, 1.0, 0.0, true},
    {"Pa", {{-1, 1, -2, 0}}, 1.0, 0.0, true},
    {"J", {{2, 1, -2, 0}}, 1.0, 0.0, true},
    {"W", {{2, 1, -3, 0}}, 1.0, 0.0, true},
    {"Hz", {{0, 0, -1, 0}}, 1.0, 0.0, true},
    {"rad", {{0, 0, 0, 0}}, 1.0, 0.0, true},
    {"deg", {{0, 0, 0, 0}}, kPi / 180.0, 0.0, false},
    {"rpm", {{0, 0, -1, 0}}, 2.0 * kPi / 60.0, 0.0, false},
    {"min", {{0, 0, 1, 0}}, 60.0, 0.0, false},
    {"h", {{0, 0, 1, 0}}, 3600.0, 0.0, false},
    {"bar", {{-1, 1, -2, 0}}, 1e5, 0.0, true},
    {"L", {{3, 0, 0, 0}}, 1e-3, 0.0, true},
    {"degC", {{0, 0, 0, 1}}, 1.0, 273.15, false},
    {"degF", {{0, 0, 0, 1}}, 5.0 / 9.0, 273.15 - 32.0 * 5.0 / 9.0, false},
};

struct Prefix {
  std::string_view text;
  double factor;
};

// Both MICRO SIGN (U+00B5) and GREEK SMALL LETTER MU (U+03BC) are accepted for micro, since
// they look identical and users cannot tell which one their editor produced.
const Prefix kPrefixes[] = {
    {"n", 1e-9}, {"u", 1e-6},  {"\xC2\xB5", 1e-6}, {"\xCE\xBC", 1e-6}, {"m", 1e-3},
    {"c", 1e-2}, {"k", 1e3},   {"M", 1e6},         {"G", 1e9},
};

// Bounds that keep malicious or accidental input ("((m^99)^99)^99", thousands of nested
// parentheses) from overflowing exponents or the stack.
constexpr long kMaxExponent = 1000;
constexpr int kMaxDepth = 64;

std::string known_units_hint() {
  std::string all, prefixable, prefixes;
  for (const auto& u : kUnits) {
    all += (all.empty() ? "" : ", ") + std::string(u.name);
    if (u.prefixable) prefixable += (prefixable.empty() ? "" : ", ") + std::string(u.name);
  }
  for (const auto& p : kPrefixes)
    if (p.text != "\xCE\xBC") prefixes += (prefixes.empty() ? "" : ", ") + std::string(p.text);
  return "known units: " + all + " (" + prefixable + " take SI prefixes " + prefixes + ")";
}

bool is_temperature_with_offset(const NamedUnit& u) { return u.offset != 0.0; }

const NamedUnit* find_exact(std::string_view name) {
  for (const auto& u : kUnits)
    if (u.name == name) return &u;
  return nullptr;
}

/// Recursive-descent parser over one unit expression. Errors quote the whole expression so the
/// user can see which part was meant.
class UnitParser {
 public:
  explicit UnitParser(std::string_view text) : text_(text) {}

  Unit parse() {
    skip_space();
    if (at_end()) return Unit{};  // "" is dimensionless, as documented in the header
    Unit u = expression(0);
    skip_space();
    if (!at_end()) {
      if (is_name_char(text_[pos_]))
        fail("unexpected \"" + std::string(text_.substr(pos_)) +
             "\"; join units with '*' or '/' (e.g. \"N*m\")");
      fail("unexpected \"" + std::string(text_.substr(pos_)) + "\"");
    }
    return u;
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const {
    throw std::invalid_argument("invalid unit \"" + std::string(text_) + "\": " + reason);
  }

  bool at_end() const { return pos_ >= text_.size(); }
  void skip_space() {
    while (!at_end() && (text_[pos_] == ' ' || text_[pos_] == '\t')) ++pos_;
  }
  // Non-ASCII bytes are taken as part of a name so that "µm" is one token (and an unknown
  // non-ASCII name is reported whole, not byte by byte).
  static bool is_name_char(char c) {
    auto uc = static_cast<unsigned char>(c);
    return (uc >= 'a' && uc <= 'z') || (uc >= 'A' && uc <= 'Z') || uc >= 0x80;
  }

  static Unit combine(const Unit& a, const Unit& b, int sign) {
    Unit r;
    for (std::size_t i = 0; i < 4; ++i)
      r.dimension.exponents[i] = a.dimension.exponents[i] + sign * b.dimension.exponents[i];
    r.scale = sign > 0 ? a.scale * b.scale : a.scale / b.scale;
    return r;
  }

  Unit expression(int depth) {
    if (depth > kMaxDepth) fail("parentheses nested too deeply");
    Unit result = power(depth);
    for (;;) {
      skip_space();
      if (at_end()) break;
      const char op = text_[pos_];
      if (op != '*' && op != '/') break;
      ++pos_;
      const Unit rhs = power(depth);
      result = combine(result, rhs, op == '*' ? +1 : -1);
      check_bounds(result);
    }
    return result;
  }

  Unit power(int depth) {
    Unit base = primary(depth);
    skip_space();
    if (at_end() || text_[pos_] != '^') return base;
    ++pos_;
    skip_space();
    const std::size_t start = pos_;
    if (!at_end() && (text_[pos_] == '-' || text_[pos_] == '+')) ++pos_;
    while (!at_end() && text_[pos_] >= '0' && text_[pos_] <= '9') ++pos_;
    std::string_view digits = text_.substr(start, pos_ - start);
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    long exponent = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), exponent);
    if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size())
      fail("expected an integer exponent after '^' at position " + std::to_string(start + 1));
    if (!at_end() && (text_[pos_] == '.' || is_name_char(text_[pos_])))
      fail("expected an integer exponent after '^' at position " + std::to_string(start + 1));
    if (std::labs(exponent) > kMaxExponent) fail("exponent " + std::to_string(exponent) + " is too large");
    Unit r;
    for (std::size_t i = 0; i < 4; ++i) r.dimension.exponents[i] = base.dimension.exponents[i] * static_cast<int>(exponent);
    r.scale = std::pow(base.scale, static_cast<double>(exponent));
    check_bounds(r);
    return r;
  }

  Unit primary(int depth) {
    skip_space();
    if (at_end()) fail("expected a unit name, '1' or '(' at the end");
    const char c = text_[pos_];
    if (c == '(') {
      ++pos_;
      Unit inner = expression(depth + 1);
      skip_space();
      if (at_end() || text_[pos_] != ')') fail("missing ')'");
      ++pos_;
      return inner;
    }
    if (c == '1') {
      ++pos_;
      // "1" is the only number allowed in a unit; "10" or "1.5" is not a unit.
      if (!at_end() && ((text_[pos_] >= '0' && text_[pos_] <= '9') || text_[pos_] == '.'))
        fail("numbers other than '1' are not allowed in a unit");
      return Unit{};
    }
    if (!is_name_char(c))
      fail("expected a unit name, '1' or '(' at position " + std::to_string(pos_ + 1) +
           ", got '" + std::string(1, c) + "'");
    const std::size_t start = pos_;
    while (!at_end() && is_name_char(text_[pos_])) ++pos_;
    return lookup(text_.substr(start, pos_ - start));
  }

  Unit lookup(std::string_view name) const {
    const NamedUnit* named = find_exact(name);
    double factor = 1.0;
    if (named == nullptr) {
      for (const auto& p : kPrefixes) {
        if (name.size() <= p.text.size() || name.substr(0, p.text.size()) != p.text) continue;
        const NamedUnit* base = find_exact(name.substr(p.text.size()));
        if (base == nullptr) continue;
        if (!base->prefixable)
          fail("the unit \"" + std::string(base->name) + "\" does not take an SI prefix (got \"" +
               std::string(name) + "\")");
        named = base;
        factor = p.factor;
        break;
      }
    }
    if (named == nullptr) fail("unknown unit \"" + std::string(name) + "\"; " + known_units_hint());
    if (is_temperature_with_offset(*named))
      fail("\"" + std::string(named->name) +
           "\" is an absolute temperature and must be the whole unit; use \"K\" in compound "
           "units and for temperature differences");
    Unit u;
    u.dimension = named->dimension;
    u.scale = named->scale * factor;
    return u;
  }

  void check_bounds(const Unit& u) const {
    for (int e : u.dimension.exponents)
      if (std::abs(e) > kMaxExponent) fail("exponent is too large");
    if (!std::isfinite(u.scale) || u.scale == 0.0) fail("scale factor out of range");
  }

  std::string_view text_;
  std::size_t pos_ = 0;
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\n' || s.front() == '\r'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\n' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

}  // namespace

std::string Dimension::to_string() const {
  static constexpr std::string_view kSymbols[4] = {"m", "kg", "s", "K"};
  std::string out;
  for (std::size_t i = 0; i < 4; ++i) {
    const int e = exponents[i];
    if (e == 0) continue;
    if (!out.empty()) out += ' ';
    out += kSymbols[i];
    if (e != 1) out += "^" + std::to_string(e);
  }
  return out.empty() ? "1" : out;
}

Unit parse_unit(std::string_view text) {
  const std::string_view t = trim(text);
  // Offset units are matched as the whole string only; inside an expression they are an error
  // (see UnitParser::lookup), which is what "allowed only on their own" means.
  if (const NamedUnit* named = find_exact(t); named != nullptr && is_temperature_with_offset(*named))
    return Unit{named->dimension, named->scale, named->offset};
  return UnitParser(t).parse();
}

double parse_quantity(std::string_view text, std::string_view expected_unit) {
  // A malformed expected unit is a bug in the caller's ParamSpec, but it is still reported as
  // invalid_argument (the documented exception) with a message saying so.
  Unit expected;
  try {
    expected = parse_unit(expected_unit);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("invalid expected unit \"" + std::string(expected_unit) +
                                "\": " + e.what());
  }
  const std::string expectation = "expected a quantity in " + std::string(expected_unit) +
                                  " (dimension " + expected.dimension.to_string() + ")";
  const std::string got = "got \"" + std::string(text) + "\"";
  auto error = [&](const std::string& reason) {
    return std::invalid_argument(expectation + ", " + got + ": " + reason);
  };

  const std::string_view t = trim(text);
  if (t.empty()) throw error("the string is empty");

  // from_chars rejects a leading '+', which users do write ("+5 mm"); it also accepts
  // "inf"/"nan", which are never a meaningful input quantity.
  std::string_view number = t;
  if (number.front() == '+') number.remove_prefix(1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), value,
                                         std::chars_format::general);
  if (ec != std::errc() || !std::isfinite(value) || number.empty() ||
      !((number.front() >= '0' && number.front() <= '9') || number.front() == '.' ||
        number.front() == '-'))
    throw error("expected a number at the start (e.g. \"14 mm\")");
  const std::string_view unit_text = trim(number.substr(static_cast<std::size_t>(end - number.data())));

  if (unit_text.empty()) return value;  // a bare number is already in SI

  Unit unit;
  try {
    unit = parse_unit(unit_text);
  } catch (const std::invalid_argument& e) {
    throw error(e.what());
  }
  if (unit.dimension != expected.dimension)
    throw std::invalid_argument(expectation + ", " + got + " (dimension " +
                                unit.dimension.to_string() + ")");
  const double si = value * unit.scale + unit.offset;
  if (!std::isfinite(si)) throw error("the value overflows when converted to SI");
  return si;
}

}  // namespace sphforge
