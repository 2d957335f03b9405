// In-process runs of a bundled verification case (cases/verification/), for the `verification` tests
// that read the Simulation's fields before and after the run (the *_runs tests go through the
// executable instead).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "sphforge/case_file.hpp"
#include "sphforge/plugin_loader.hpp"

namespace sphforge_test {

namespace fs = std::filesystem;

inline const fs::path kVerificationCases = fs::path(SPHFORGE_SOURCE_DIR) / "cases" / "verification";

/// A fresh folder for one run's outputs, unique per process.
inline fs::path scratch_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sphforge_verify_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

struct InProcessCase {
  std::unique_ptr<sphforge::PluginLoader> loader;
  std::unique_ptr<sphforge::Simulation> sim;
  fs::path out;
};

/// The case `file` of cases/verification/ with `overrides`, built (not run), output folder `tag`.
inline InProcessCase make_case(const std::string& file, const std::vector<std::string>& overrides, const std::string& tag) {
  InProcessCase r;
  r.loader = std::make_unique<sphforge::PluginLoader>(std::vector<fs::path>{SPHFORGE_PLUGIN_BUILD_DIR});
  r.sim = std::make_unique<sphforge::Simulation>(sphforge::load_case((kVerificationCases / file).string(), overrides),
                                                 *r.loader);
  r.out = scratch_dir(tag);
  return r;
}

}  // namespace sphforge_test
