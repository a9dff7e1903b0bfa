// CI scores a few small generated worlds (issue 17): three worlds (seeds 1-3, kinds office, lobby,
// hall, 150 frames = 10 s of walk each) made by generate_world and render_bag, scored by the set
// runs of obstacles_benchmark and vo_benchmark. The bounds are loose but meaningful: they hold for
// the code of the issue-17 baseline (figures in the README "Benchmarks over a set") and fail on a
// real regression (an obstacle reported free where none was, VO drift or jumps growing).
// The stage benchmarks are other packages' executables (devel/lib/<package>/); the test says
// plainly when one is not built and skips.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <assistive_eval/bench_set.h>

using namespace assistive_eval;

namespace
{
// Bounds: the baseline code (main at issue 17's start, dedbf51) gives, on these three worlds,
// free_where_obstacle_cells 3 / 3 / 0, recall_3m 0.948 / 0.933 / 1.000, precision_3m 0.837 /
// 0.915 / 0.891, VO drift null (office: 0.46 m walked) / 0.20 / 0.89 %, max jump <= 2.7 mm,
// ATE <= 4.0 mm. No more obstacle cells reported free than that code; recall and precision with
// margin; VO drift at the targets (mean 1 %, worst 2 %), jumps and ATE with margin.
constexpr double FREE_WHERE_OBSTACLE_MAX = 3;
constexpr double RECALL_3M_WORST_MIN = 0.85, RECALL_3M_MEAN_MIN = 0.90, PRECISION_3M_WORST_MIN = 0.75;
constexpr double DRIFT_PCT_WORST_MAX = 2.0, DRIFT_PCT_MEAN_MAX = 1.0, MAX_JUMP_M_WORST_MAX = 0.05,
                 ATE_RMSE_M_WORST_MAX = 0.03;

std::string libDir()
{
  const std::string self = selfExecutable();
  return std::filesystem::path(self).parent_path().parent_path().string();
}
std::map<std::string, double> runSet(const std::vector<std::string>& argv, std::string* out)
{
  std::map<std::string, double> v;
  const int rc = runCapture(argv, out);
  EXPECT_EQ(rc, 0) << *out;
  EXPECT_TRUE(parseJsonNumbers(lastJsonLine(*out), &v)) << *out;
  return v;
}
double at(const std::map<std::string, double>& v, const std::string& k)
{
  const auto it = v.find(k);
  return it == v.end() ? NAN : it->second;
}
}  // namespace

TEST(GeneratedSet, ThreeSmallWorldsScoreWithinBounds)
{
  const std::string lib = libDir();
  const std::string vo = lib + "/assistive_vo/vo_benchmark", ob = lib + "/assistive_obstacles/obstacles_benchmark";
  for (const std::string& e : {vo, ob, lib + "/assistive_sim/render_bag", lib + "/assistive_sim/generate_world"})
    if (!std::filesystem::exists(e))
      GTEST_SKIP() << "SKIPPED: " << e << " is not built";
  const std::string dir = testing::TempDir() + "/generated_set_" + std::to_string(::getpid());
  const std::vector<std::string> set{"--generated", "3", "--kinds", "office,lobby,hall", "--frames", "150",
                                     "--keep", dir};

  std::string out;
  std::vector<std::string> a{ob};
  a.insert(a.end(), set.begin(), set.end());
  a.insert(a.end(), {"--png", dir + "/png"});
  const auto obs = runSet(a, &out);
  std::printf("%s", out.c_str());
  ASSERT_EQ(at(obs, "bags"), 3) << out;
  EXPECT_EQ(at(obs, "bags_failed"), 0) << out;
  // Obstacles (truth poses): no more obstacle cells reported free than the baseline code
  // (BOUNDS below), recall and precision not collapsing.
  EXPECT_LE(at(obs, "free_where_obstacle_cells_max"), FREE_WHERE_OBSTACLE_MAX) << out;
  EXPECT_GE(at(obs, "recall_3m_worst"), RECALL_3M_WORST_MIN) << out;
  EXPECT_GE(at(obs, "precision_3m_worst"), PRECISION_3M_WORST_MIN) << out;
  EXPECT_GE(at(obs, "recall_3m_mean"), RECALL_3M_MEAN_MIN) << out;

  std::vector<std::string> b{vo};
  b.insert(b.end(), set.begin(), set.end());  // the same bags, reused from dir
  b.insert(b.end(), {"--no-peer", "--plot", dir + "/png"});
  const auto v = runSet(b, &out);
  std::printf("%s", out.c_str());
  ASSERT_EQ(at(v, "bags"), 3) << out;
  EXPECT_EQ(at(v, "bags_failed"), 0) << out;
  EXPECT_LE(at(v, "drift_pct_worst"), DRIFT_PCT_WORST_MAX) << out;
  EXPECT_LE(at(v, "drift_pct_mean"), DRIFT_PCT_MEAN_MAX) << out;
  EXPECT_LE(at(v, "max_jump_m_worst"), MAX_JUMP_M_WORST_MAX) << out;
  EXPECT_LE(at(v, "ate_rmse_m_worst"), ATE_RMSE_M_WORST_MAX) << out;
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}
