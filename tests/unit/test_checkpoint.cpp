// Restart checkpoints (docs/checkpoints.md) of a process plugin that keeps no restart state: the
// core refuses to write checkpoints for it (they could not be continued) and refuses to restart it.
// The restarts themselves are tested end to end in tests/integration/test_cli.cpp.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "engine/simulation.hpp"
#include "sphforge/case_file.hpp"
#include "sphforge/errors.hpp"

namespace {

using namespace sphforge;
namespace fs = std::filesystem;

fs::path write_block_case(const std::string& run_section) {
  const fs::path dir = fs::temp_directory_path() / ("sphforge_checkpoint_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "block.json";
  std::ofstream(file) << R"({
    "case": {"name": "free_block"},
    "process": {"plugin": "test_free_block", "n": 4, "spacing": "1 mm", "v0": "0.02 m/s"},
    "material": {"plugin": "elastoplastic", "density": "1e8 kg/m^3", "youngs_modulus": "57 MPa",
                 "poisson_ratio": 0.47, "yield_stress": "1 GPa"},
    "contact": {"law": {"plugin": "coulomb", "friction_coefficient": 0}},
    "run": )" + run_section + "}";
  return file;
}

TEST(Checkpoint, AProcessWithoutRestartStateIsNotCheckpointed) {
  const fs::path file = write_block_case(R"({"end_time": "1 ms", "checkpoint_interval": "0.1 ms"})");
  PluginLoader loader({SPHFORGE_PLUGIN_BUILD_DIR, SPHFORGE_TEST_PLUGIN_DIR});
  try {
    Simulation sim(load_case(file.string()), loader);
    FAIL() << "a case whose process keeps no restart state was accepted with run.checkpoint_interval";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/run/checkpoint_interval"), std::string::npos) << what;
    EXPECT_NE(what.find("process 'test_free_block'"), std::string::npos) << what;
  }
  // Without checkpoints the same case is valid, and a restart of it is refused before any file is read.
  Simulation sim(load_case(write_block_case(R"({"end_time": "1 ms"})").string()), loader);
  try {
    sim.restore(file.parent_path() / "does_not_matter.h5");
    FAIL() << "a process without restart state was restarted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot restart: process 'test_free_block'"), std::string::npos) << e.what();
  }
  fs::remove_all(file.parent_path());
}

}  // namespace
