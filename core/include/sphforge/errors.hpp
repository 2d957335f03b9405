// Error types that map to the command-line exit codes of the output contract:
//   InputError       -> exit 2 (the user can fix it: file, JSON pointer, what was expected)
//   InstabilityError -> exit 3 (numerical blow-up: step, time, particle, field)
#pragma once

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

// The error types live in libsphforge_core (their destructors are its key functions, core/src/errors.cpp)
// and are exported from it: an error thrown inside a plugin then does not depend on the plugin's code,
// which may be unloaded while the error travels to main() (it used to crash `sphforge check`).
#define SPHFORGE_EXPORTED_TYPE __attribute__((visibility("default")))

namespace sphforge {

/// A problem in something the user supplied (case file, unit, plugin name, path).
/// `file` and `pointer` (RFC 6901 JSON pointer) locate it; `what()` gives the whole message.
class SPHFORGE_EXPORTED_TYPE InputError : public std::runtime_error {
 public:
  ~InputError() override;
  InputError(std::string file, std::string pointer, const std::string& message)
      : std::runtime_error(compose(file, pointer, message)),
        file_(std::move(file)),
        pointer_(std::move(pointer)),
        message_(message) {}

  const std::string& file() const { return file_; }
  const std::string& pointer() const { return pointer_; }
  const std::string& message() const { return message_; }

 private:
  static std::string compose(const std::string& file, const std::string& pointer,
                             const std::string& message) {
    std::string where = file.empty() ? std::string("<input>") : file;
    if (!pointer.empty()) where += " at " + pointer;
    return where + ": " + message;
  }
  std::string file_, pointer_, message_;
};

/// A numerical instability detected during a run.
class SPHFORGE_EXPORTED_TYPE InstabilityError : public std::runtime_error {
 public:
  ~InstabilityError() override;
  InstabilityError(std::int64_t step, double time_s, std::int64_t particle_id,
                   std::string field, const std::string& diagnosis)
      : std::runtime_error("numerical instability at step " + std::to_string(step) +
                           ", t = " + format_time(time_s) + " s, particle " +
                           std::to_string(particle_id) + ", field '" + field + "': " + diagnosis),
        step_(step), time_s_(time_s), particle_id_(particle_id), field_(std::move(field)) {}
  static std::string format_time(double t) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g", t);
    return buffer;
  }
  std::int64_t step() const { return step_; }
  double time_s() const { return time_s_; }
  std::int64_t particle_id() const { return particle_id_; }
  const std::string& field() const { return field_; }

 private:
  std::int64_t step_;
  double time_s_;
  std::int64_t particle_id_;
  std::string field_;
};

}  // namespace sphforge
