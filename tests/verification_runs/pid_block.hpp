// Analysis shared by the PID force-control runs (docs/verification.md section 12b): a punch under a
// `pid` on its force presses an elastic block on a table; after settling, the force error and the
// block's shortening between its bottom and top particle layers against F (L - dx) / (E A).
#pragma once

#include <cmath>
#include <string>

#include "run_helpers.hpp"

namespace sphforge_verification {

struct PidBlockResult {
  double mean_abs_force_error = 0.0;  ///< mean |F - target| / target after settling
  double shortening_error = 0.0;      ///< shortening / (F (L - dx) / (E A)) - 1
  double mean_force = 0.0, shortening = 0.0, predicted = 0.0;
  int rows = 0;
  std::string line;  ///< what the test prints and records
};

inline PidBlockResult analyse_pid_block(const fs::path& out, const std::string& name, double target, double youngs_modulus,
                                        double area, double length, double spacing, double settled_after) {
  const History h = read_history(out / "history.csv");
  const auto& t = h["time_s"];
  const auto& force = h["punch_force_z_N"];
  const auto& top = h["top_displacement_z_m"];
  const auto& bottom = h["bottom_displacement_z_m"];
  PidBlockResult r;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < settled_after) continue;
    r.mean_abs_force_error += std::abs(force[k] - target);
    r.mean_force += force[k];
    r.shortening += bottom[k] - top[k];
    ++r.rows;
  }
  if (r.rows == 0) return r;
  r.mean_abs_force_error /= r.rows * target;
  r.mean_force /= r.rows;
  r.shortening /= r.rows;
  r.predicted = r.mean_force * (length - spacing) / (youngs_modulus * area);
  r.shortening_error = r.shortening / r.predicted - 1.0;
  r.line = name + ": mean |F - target| after settling " + std::to_string(100.0 * r.mean_abs_force_error) +
           " % of the target; shortening " + std::to_string(r.shortening) + " m vs F (L - dx)/(E A) " +
           std::to_string(r.predicted) + " m: " + std::to_string(100.0 * r.shortening_error) + " %";
  return r;
}

}  // namespace sphforge_verification
