// Validation (label `validation`, not run in CI: about 11 minutes on one thread): the Taylor bar
// of cases/verification/taylor_bar_copper.json at dx = 0.6, 0.4 and 0.3 mm through
// `sphforge bench`, errors against cases/verification/reference/taylor_bar_copper.json.
// Target (issue 4): the finest run within 3 % of the final length 21.4 mm and of the footprint
// radius 7.165 mm (middle of the literature's 7.11-7.22 mm). The 3 % is the accuracy
// target, not a tuned bound; docs/verification.md section 9 reports the measured numbers.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

TEST(TaylorBarValidation, FinestWithinThreePercent) {
  const fs::path out = output_dir("taylor_bar_bench");
  const std::string line = sphforge_env() + shell_quote(kExe) +
                           " bench " + shell_quote((kCases / "taylor_bar_copper.json").string()) +
                           " --spacing \"0.6 mm,0.4 mm,0.3 mm\" --reference " +
                           shell_quote((kCases / "reference" / "taylor_bar_copper.json").string()) + " --out " +
                           shell_quote(out.string()) + " --quiet >/dev/null 2>&1";
  ASSERT_EQ(std::system(line.c_str()), 0);
  const json bench = json::parse(slurp(out / "bench.json"));
  std::printf("%s\n", slurp(out / "bench.csv").c_str());
  const json& runs = bench["runs"];
  ASSERT_EQ(runs.size(), 3u);
  const json& finest = runs.back();
  const double length_error = finest["errors"]["bar_length_z_m"].get<double>();
  const double radius_error = finest["errors"]["bar_base_radius_m"].get<double>();
  char text[200];
  std::snprintf(text, sizeof text, "taylor bar finest: length error %.2f %%, footprint radius error %.2f %%\n",
                100 * length_error, 100 * radius_error);
  record("validation_results.txt", text);
  EXPECT_LT(length_error, 0.03) << text;
  EXPECT_LT(radius_error, 0.03) << text;
}

}  // namespace
