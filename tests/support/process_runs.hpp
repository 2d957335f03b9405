// Helpers of the integration tests that run a bundled process case with the sphforge executable
// (SPHFORGE_EXECUTABLE, defined for the integration test target): one run in a scratch folder, and
// the particle frame it wrote, read back with VTK.
#pragma once

#include "command_line.hpp"

#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace sphforge_test {

/// Runs sphforge with `args` from the folder `dir` (created), one OpenMP thread, the plugins of the
/// build (SPHFORGE_PLUGIN_PATH unset), at most 300 s; stdout and stderr captured to files there.
inline Result run_sphforge(const std::vector<std::string>& args, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  std::string cmd = "cd " + shell_quote(dir.string()) +
                    " && env -u SPHFORGE_PLUGIN_PATH OMP_WAIT_POLICY=PASSIVE OMP_NUM_THREADS=1 timeout -k 10 300 " +
                    shell_quote(SPHFORGE_EXECUTABLE);
  for (const auto& a : args) cmd += " " + shell_quote(a);
  cmd += " >" + shell_quote((dir / "stdout.txt").string()) + " 2>" + shell_quote((dir / "stderr.txt").string());
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = status == -1 ? -1 : WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = slurp(dir / "stdout.txt");
  r.err = slurp(dir / "stderr.txt");
  return r;
}

/// An empty folder `<tmp>/sphforge_<prefix>_<pid>_<name>` (removed first if it exists).
inline std::filesystem::path scratch_folder(const std::string& prefix, const std::string& name) {
  const std::filesystem::path p =
      std::filesystem::temp_directory_path() / ("sphforge_" + prefix + "_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(p);
  return p;
}

/// A particles_NNNNNN.vtu frame of a run: positions and every point array.
inline vtkSmartPointer<vtkUnstructuredGrid> read_particle_frame(const std::filesystem::path& file) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  return reader->GetOutput();
}

}  // namespace sphforge_test
