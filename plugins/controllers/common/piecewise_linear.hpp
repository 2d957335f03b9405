// Piecewise-linear function of time (docs/theory.md eq. 60), read from a case as a list of
// [time, value] pairs with units: [["0 s", "300 rpm"], ["26 s", "300 rpm"], ["36 s", "90 rpm"]].
// Before the first point it holds the first value, after the last point the last value; two points
// at the same time make a jump (the later one applies from that instant on).
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "sphforge/parameters.hpp"
#include "sphforge/units.hpp"

namespace sphforge::control {

class PiecewiseLinear {
 public:
  PiecewiseLinear() = default;
  /// times in s, non-decreasing; values in SI. At least one point.
  PiecewiseLinear(std::vector<double> times, std::vector<double> values)
      : times_(std::move(times)), values_(std::move(values)) {}

  double operator()(double t) const {
    if (t < times_.front()) return values_.front();
    if (t >= times_.back()) return values_.back();
    // First point strictly after t: the segment [k-1, k] contains t (k >= 1 because t >= times_[0]).
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
    const double t0 = times_[k - 1], t1 = times_[k];
    const double w = (t - t0) / (t1 - t0);  // t1 > t0: upper_bound skipped equal times
    return (1.0 - w) * values_[k - 1] + w * values_[k];
  }
  const std::vector<double>& times() const { return times_; }
  const std::vector<double>& values() const { return values_; }

 private:
  std::vector<double> times_, values_;
};

/// Reads the Array parameter `name` of `p` as [[time, value], ...] with `value_unit` (SI unit
/// expression of the quantity it drives). Errors name the element's JSON pointer.
inline PiecewiseLinear read_piecewise_linear(const ParamValues& p, const std::string& name,
                                             const std::string& value_unit) {
  const json& points = p.raw(name);
  if (!points.is_array() || points.empty())
    p.fail(name, "expected a non-empty array of [time, value] pairs, e.g. [[\"0 s\", \"1 mm/s\"], [\"5 s\", \"2 mm/s\"]]");
  std::vector<double> times, values;
  auto as_si = [&](const json& v, const std::string& unit, const std::string& where) -> double {
    try {
      if (v.is_number()) return v.get<double>();
      if (v.is_string()) return parse_quantity(v.get<std::string>(), unit);
    } catch (const std::exception& e) {
      p.fail(name, where + ": " + e.what());
    }
    p.fail(name, where + ": expected a number (SI) or a \"value unit\" string in " + unit);
  };
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::string where = "point " + std::to_string(k);
    if (!points[k].is_array() || points[k].size() != 2) p.fail(name, where + ": expected a [time, value] pair");
    times.push_back(as_si(points[k][0], "s", where + " time"));
    values.push_back(as_si(points[k][1], value_unit, where + " value"));
    if (k > 0 && times[k] < times[k - 1]) p.fail(name, where + ": times must not decrease");
  }
  return PiecewiseLinear(std::move(times), std::move(values));
}

}  // namespace sphforge::control
