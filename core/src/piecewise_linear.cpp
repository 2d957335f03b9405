#include "sphforge/piecewise_linear.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace sphforge {

PiecewiseLinear::PiecewiseLinear(std::vector<std::pair<double, double>> points) {
  if (points.empty()) throw std::invalid_argument("a schedule needs at least one (time, value) pair");
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (k > 0 && !(points[k].first >= points[k - 1].first))
      throw std::invalid_argument("schedule times must not decrease (entry " + std::to_string(k) + ")");
    t_.push_back(points[k].first);
    v_.push_back(points[k].second);
  }
  cumulative_.assign(t_.size(), 0.0);
  for (std::size_t k = 1; k < t_.size(); ++k)
    cumulative_[k] = cumulative_[k - 1] + 0.5 * (v_[k] + v_[k - 1]) * (t_[k] - t_[k - 1]);
}

double PiecewiseLinear::value(double t) const {
  if (t < t_.front()) return v_.front();
  if (t >= t_.back()) return v_.back();
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
  return v_[k] + (v_[k + 1] - v_[k]) * (t - t_[k]) / (t_[k + 1] - t_[k]);
}

double PiecewiseLinear::antiderivative(double t) const {
  // Eq. (45): piecewise-linear v integrates exactly by the trapezoid rule between knots.
  if (t <= t_.front()) return v_.front() * (t - t_.front());
  if (t >= t_.back()) return cumulative_.back() + v_.back() * (t - t_.back());
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
  return cumulative_[k] + 0.5 * (v_[k] + value(t)) * (t - t_[k]);
}

double PiecewiseLinear::integral(double t0, double t1) const { return antiderivative(t1) - antiderivative(t0); }

}  // namespace sphforge
