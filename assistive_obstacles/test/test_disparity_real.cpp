// Issue 9 check on real camera data (skipped, with a message, when the folder is absent): the
// stage's default disparity configuration against full-resolution OpenCV SGBM on the same pairs.
// Accuracy only; speed is measured by disparity_benchmark.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include <assistive_obstacles/disparity.h>
#include <assistive_eval/disparity_eval.h>

#ifndef ASSISTIVE_REAL_DATA_DIR
#define ASSISTIVE_REAL_DATA_DIR "../shared/data/real"
#endif

using namespace assistive_obstacles;
using namespace assistive_eval;

TEST(DisparityReal, DefaultNoWorseThanOneAndAHalfTimesFullResSgbm)
{
  // $ASSISTIVE_REAL_DATA, else the CMake default (the folder beside the workspace)
  const char* env = std::getenv("ASSISTIVE_REAL_DATA");
  const std::string root = (env && *env) ? std::string(env) : std::string(ASSISTIVE_REAL_DATA_DIR);
  const std::string dir = root + "/stereo_disparity";
  const auto pairs = loadRealPairs(dir);
  if (pairs.empty())
    GTEST_SKIP() << "SKIPPED: real data not found at " << dir << " (set ASSISTIVE_REAL_DATA)";
  const ObstaclesParams defaults;
  DisparityEstimator est(defaults);
  for (const RealPair& p : pairs)
  {
    cv::Mat ours;
    ASSERT_TRUE(est.computeFullRes(p.left, p.right, ours)) << p.name;
    const cv::Mat peer = peerSgbm(p.left, p.right, defaults.max_disparity);
    const DisparityScore a = scoreDisparity(ours, p.gt), b = scoreDisparity(peer, p.gt);
    ASSERT_GT(a.valid, 1000u) << p.name;
    if (p.metric == "d1")
      EXPECT_LE(a.d1_pct, 1.5 * b.d1_pct) << p.name;
    else
      EXPECT_LE(a.bad2_pct, 1.5 * b.bad2_pct) << p.name;
    std::printf("%s: D1 %.2f %% (peer %.2f), bad-2.0 %.2f %% (peer %.2f)\n", p.name.c_str(), a.d1_pct, b.d1_pct,
                a.bad2_pct, b.bad2_pct);
  }
}
