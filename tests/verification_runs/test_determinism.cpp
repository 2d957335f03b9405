// Determinism (issue "SPH core", neighbour search): with a fixed thread count a run is repeated
// bit for bit, and because every neighbour sum runs in a fixed order per particle (theory
// section 7) the particle fields do not depend on the thread count either. Only global energy
// sums (OpenMP reductions, used for the history and the instability check) may differ in their
// last bits between thread counts, so those are compared for 2 vs 2 threads only.
#include <gtest/gtest.h>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

TEST(Determinism, RepeatedRunsAreIdenticalAndFieldsIndependentOfThreads) {
  const std::vector<std::string> sets = {"run.end_time=4 ms"};
  auto with_threads = [&](const std::string& tag, int threads) {
    std::vector<std::string> s = sets;
    s.push_back("run.threads=" + std::to_string(threads));
    const RunResult r = run_case("collision.json", tag, s);
    EXPECT_EQ(r.code, 0) << r.err;
    return r.out;
  };
  const fs::path a = with_threads("determinism_a", 2), b = with_threads("determinism_b", 2),
                 one = with_threads("determinism_one", 1);
  // Same thread count: the whole history, byte for byte.
  EXPECT_EQ(slurp(a / "history.csv"), slurp(b / "history.csv"));
  // 1 vs 2 threads: every particle field of the last frame, exactly.
  const Frame fa = read_frame(frames(a).back()), f1 = read_frame(frames(one).back());
  ASSERT_EQ(fa.count, f1.count);
  ASSERT_GT(fa.count, 0u);
  for (const auto& [name, values] : fa.arrays) {
    ASSERT_TRUE(f1.arrays.count(name)) << name;
    EXPECT_EQ(values, f1.arrays.at(name)) << "field " << name << " differs between 1 and 2 threads";
  }
}

}  // namespace
