// A piecewise-linear function of time from (t_k, v_k) points: tool motion schedules (docs/theory.md
// eq. 45) and the `schedule` controller (eq. 60). Constant before the first point and after the last;
// two points at one time make a jump (the later value holds from that instant). Its integral is
// exact (trapezoids between the points), so a tool driven by a velocity schedule lands where the
// schedule says.
#pragma once

#include <utility>
#include <vector>

namespace sphforge {

class PiecewiseLinear {
 public:
  PiecewiseLinear() = default;
  /// At least one point, times non-decreasing; throws std::invalid_argument otherwise.
  explicit PiecewiseLinear(std::vector<std::pair<double, double>> points);
  double value(double t) const;
  double operator()(double t) const { return value(t); }
  /// Integral from t0 to t1 (exact).
  double integral(double t0, double t1) const;
  bool empty() const { return t_.empty(); }

 private:
  double antiderivative(double t) const;    // integral from t_0 to t
  std::vector<double> t_, v_, cumulative_;  // cumulative_[k] = integral from t_0 to t_k
};

}  // namespace sphforge
