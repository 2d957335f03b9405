// `sphforge bench`: one case at several particle spacings, run time against error
// (DESIGN.md "Performance vocabulary"). Each spacing runs as a child `sphforge run` so that its
// peak memory can be measured on its own; the results go to bench.csv, bench.json and bench.png.
// The columns and the error definition are documented in docs/bench.md.
#pragma once

#include <string>
#include <vector>

namespace sphforge::cli {

struct BenchOptions {
  std::string case_path;                       ///< the case file (already resolved to the default case when none was given)
  std::string spacing_list;                    ///< --spacing "0.5 mm,0.25 mm" or "5e-4,2.5e-4"
  std::string parameter = "process.particle_spacing";  ///< --parameter: dotted key or JSON pointer set to each spacing
  std::string reference;                       ///< --reference FILE: {"metrics": {"name": value or "value unit"}}
  std::string out;                             ///< --out DIR (default runs/<case>-bench)
  std::vector<std::string> overrides;          ///< --set, passed to every run before the spacing
  bool force = false;
  bool quiet = false;                          ///< no table on stdout
};

/// Runs the benchmark. Returns the exit code: 0 at least one run finished, 3 every run was
/// unstable, 2 every run was rejected as invalid input, 1 every run failed otherwise.
/// Invalid options, case or reference file throw InputError (exit 2) before anything is written.
int run_bench(const BenchOptions& options);

/// Parses "--spacing" ("0.5 mm, 0.25 mm", "5e-4,2.5e-4") into metres, coarsest first.
/// Throws InputError at the pointer "--spacing" for an empty list, a bad or non-positive item or a
/// repeated spacing.
std::vector<double> parse_spacing_list(const std::string& text);

/// "process.particle_spacing" or "/process/particle_spacing" -> the dotted key of `--set`.
/// Throws InputError at "--parameter" when it cannot be expressed as one.
std::string parameter_key(const std::string& parameter);

}  // namespace sphforge::cli
