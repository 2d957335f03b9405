// The sampled PID law of the `pid` controller (docs/theory.md eqs. 61-64), free of any plugin or
// SPH machinery so that it can be verified against closed-form plant responses
// (tests/unit/test_pid_law.cpp).
//
// At each sampling instant t_k (every `sample_interval`, or every call when it is 0), with
// h = t_k - t_{k-1} the time since the previous sample (0 at the first):
//   e_k = target - measured                                                        (eq. 61)
//   P = Kp e_k,  D = Kd (e_k - e_{k-1}) / h   (or -Kd (y_k - y_{k-1}) / h on the measurement)
//   I_k = I_{k-1} + e_k h, then the anti-windup rule                                (eq. 62)
//   u = sat(P + Ki I_k + D, u_min, u_max)                                           (eq. 63)
// Between samples the command is held (zero-order hold). The integral is advanced with the
// elapsed time h rather than the nominal interval, so a sampling instant that falls a fraction
// of a step late does not bias the integral.
//
// Diagnostic: reversals() counts the consecutive samples, up to the last, whose command change
// reversed the direction of the previous change. A loop sampled faster than its plant can answer
// is unstable beyond k_c (Kp dt_pid + 2 Kd) = 2 (eq. 109a) and then runs a period-2 cycle, which
// raises the count by one every sample; a stable loop's oscillation dies out and the count stays
// small (the AA7075 quick case: at most 2 at contact stiffness factor 0.05; 263 at the end of its
// 300 samples at factor 1). A change that does not reverse, or none (within 1e-9 of the command's
// size), resets it; a cycle clipped by the limits is not exactly periodic and may reset it now and
// then, but it climbs into the hundreds in between.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace sphforge::control {

enum class AntiWindup {
  none,              ///< plain integral (for comparison: winds up while saturated)
  clamp,             ///< paper eq. 16: the integral contribution Ki I is clamped to [i_min, i_max]
  conditional,       ///< the integral is frozen while the output saturates in the error's direction
  back_calculation,  ///< dI/dt = e + (u_sat - u_unsat) / (Ki Tt)   (eq. 64)
};

enum class DerivativeOn { error, measurement };

struct PidSettings {
  double kp = 0.0, ki = 0.0, kd = 0.0;  ///< SI: command/measured, command/(measured s), command s/measured
  double command_min = -std::numeric_limits<double>::infinity();
  double command_max = std::numeric_limits<double>::infinity();
  /// Limits of the integral contribution Ki I in command units (AntiWindup::clamp).
  double integral_min = -std::numeric_limits<double>::infinity();
  double integral_max = std::numeric_limits<double>::infinity();
  AntiWindup anti_windup = AntiWindup::clamp;
  double tracking_time = 0.0;  ///< s, Tt of back-calculation (> 0 when used)
  DerivativeOn derivative_on = DerivativeOn::error;
  double sample_interval = 0.0;  ///< s; 0: sample at every call
};

/// Contributions of the last sample, in command units (error in measured units).
struct PidTerms {
  double error = 0.0, proportional = 0.0, integral = 0.0, derivative = 0.0, command = 0.0;
};

class PidLaw {
 public:
  explicit PidLaw(const PidSettings& s) : s_(s) {}

  /// Called at every time step; samples when a sampling instant has been reached and returns
  /// true then. The command (terms().command) is held between samples.
  bool update(double time, double target, double measured) {
    // A relative slack of 1e-9 of the interval keeps round-off in the accumulated step times
    // from pushing a sample one step late.
    if (sampled_ && time < next_sample_ - 1e-9 * s_.sample_interval) return false;
    const double e = target - measured;
    const double h = sampled_ ? time - last_time_ : 0.0;

    PidTerms t;
    t.error = e;
    t.proportional = s_.kp * e;
    if (sampled_ && h > 0.0)
      t.derivative = s_.derivative_on == DerivativeOn::error ? s_.kd * (e - last_error_) / h
                                                             : -s_.kd * (measured - last_measured_) / h;
    double integral = integral_ + e * h;  // eq. 62
    switch (s_.anti_windup) {
      case AntiWindup::none:
        break;
      case AntiWindup::clamp:
        if (s_.ki != 0.0) {
          const double lo = s_.integral_min / s_.ki, hi = s_.integral_max / s_.ki;
          integral = std::clamp(integral, std::min(lo, hi), std::max(lo, hi));
        }
        break;
      case AntiWindup::conditional: {
        // Freeze when the output with the updated integral saturates and the error drives it
        // further into the limit; integrating out of saturation is always allowed.
        const double u = t.proportional + s_.ki * integral + t.derivative;
        const double push = s_.ki * e;
        if ((u > s_.command_max && push > 0.0) || (u < s_.command_min && push < 0.0)) integral = integral_;
        break;
      }
      case AntiWindup::back_calculation:
        // The saturation excess of the previous sample bleeds the integral off with time constant Tt.
        if (s_.ki != 0.0) integral += h * saturation_excess_ / (s_.ki * s_.tracking_time);
        break;
    }
    t.integral = s_.ki * integral;
    const double unsaturated = t.proportional + t.integral + t.derivative;
    t.command = std::clamp(unsaturated, s_.command_min, s_.command_max);  // eq. 63
    saturation_excess_ = t.command - unsaturated;

    // A change at the round-off level of the command is no change: a settled loop's last bits
    // alternate at random and must not read as a cycle.
    const double change = sampled_ ? t.command - terms_.command : 0.0;
    const double resolution = 1e-9 * std::max(std::abs(t.command), std::abs(terms_.command));
    if (std::abs(change) <= resolution) reversals_ = 0;
    else if (change * last_change_ < 0.0) ++reversals_;
    else reversals_ = 0;
    last_change_ = change;

    integral_ = integral;
    last_error_ = e;
    last_measured_ = measured;
    last_time_ = time;
    next_sample_ = sampled_ ? next_sample_ + s_.sample_interval : time + s_.sample_interval;
    // A step longer than the interval skips instants rather than sampling twice in a row.
    if (next_sample_ <= time) next_sample_ = time + s_.sample_interval;
    sampled_ = true;
    terms_ = t;
    return true;
  }

  const PidTerms& terms() const { return terms_; }
  double integral() const { return integral_; }  ///< I, in measured units times s
  /// Consecutive samples whose command change reversed the previous change (see the header).
  long reversals() const { return reversals_; }

  /// Everything update() remembers between calls: what a restart must give back
  /// (the `pid` plugin's save_state()).
  struct Memory {
    PidTerms terms;
    bool sampled = false;
    double integral = 0.0, last_error = 0.0, last_measured = 0.0, last_time = 0.0;
    double next_sample = 0.0, saturation_excess = 0.0;
    double last_change = 0.0;
    long reversals = 0;
  };
  Memory memory() const {
    return {terms_,       sampled_,           integral_,    last_error_, last_measured_, last_time_,
            next_sample_, saturation_excess_, last_change_, reversals_};
  }
  void restore(const Memory& m) {
    terms_ = m.terms;
    sampled_ = m.sampled;
    integral_ = m.integral;
    last_error_ = m.last_error;
    last_measured_ = m.last_measured;
    last_time_ = m.last_time;
    next_sample_ = m.next_sample;
    saturation_excess_ = m.saturation_excess;
    last_change_ = m.last_change;
    reversals_ = m.reversals;
  }

 private:
  PidSettings s_;
  PidTerms terms_;
  bool sampled_ = false;
  double integral_ = 0.0, last_error_ = 0.0, last_measured_ = 0.0, last_time_ = 0.0;
  double next_sample_ = 0.0, saturation_excess_ = 0.0;
  double last_change_ = 0.0;  ///< command change at the last sample (0 at the first)
  long reversals_ = 0;
};

}  // namespace sphforge::control
