#include <gtest/gtest.h>
#include "assistive_vo/p3p_ransac.h"
#include "synthetic.h"

using namespace assistive_vo;

TEST(P3PRansac, TrialCountFollowsEq218)
{
  // k = log(1-p)/log(1-w^n)
  EXPECT_EQ(P3PRansac::trialCount(0.99, 0.5, 3, 1000), 35);   // 34.49 -> 35
  EXPECT_EQ(P3PRansac::trialCount(0.99, 0.9, 3, 1000), 4);    // 3.53 -> 4
  EXPECT_EQ(P3PRansac::trialCount(0.99, 1.0, 3, 1000), 1);
  EXPECT_EQ(P3PRansac::trialCount(0.99, 0.0, 3, 1000), 1000);
  EXPECT_EQ(P3PRansac::trialCount(0.99, 0.1, 3, 300), 300);   // 4603 capped
}

TEST(P3PRansac, ExactPoseWithThirtyPercentOutliers)
{
  const StereoCamera cam = test::makeCamera();
  std::mt19937 rng(7);
  const Eigen::Isometry3d T = test::makePose(0.02, -0.09, 0.01, 0.15, -0.04, 0.35);
  const Vec3List X = test::randomVisiblePoints(cam, T, 100, rng);
  Vec2List x;
  std::vector<int> truth_in;
  std::uniform_real_distribution<double> off(20, 60), sgn(0, 1);
  for (size_t i = 0; i < X.size(); ++i)
  {
    Eigen::Vector2d q = cam.projectLeft(T.inverse() * X[i]);
    if (i % 10 < 3)  // 30 % gross outliers, displaced by 20..60 px
      q += Eigen::Vector2d(off(rng) * (sgn(rng) < 0.5 ? -1 : 1), off(rng) * (sgn(rng) < 0.5 ? -1 : 1));
    else
      truth_in.push_back(static_cast<int>(i));
    x.push_back(q);
  }
  P3PRansac r(3);
  RansacOptions opt;
  const RansacResult res = r.estimate(cam, X, x, opt);
  ASSERT_TRUE(res.ok);
  EXPECT_EQ(res.inliers, truth_in);
  EXPECT_LT((res.T_ref_cur.translation() - T.translation()).norm(), 1e-6);
  EXPECT_LT(Eigen::AngleAxisd(res.T_ref_cur.linear().transpose() * T.linear()).angle(), 1e-7);
  EXPECT_LT(res.median_sq_error, 1e-10);
  // Adaptive k: w = 0.7 gives 11 trials at p = 0.99, far below the cap.
  EXPECT_LE(res.trials, 30);
  EXPECT_GE(res.trials, opt.min_trials);
}

TEST(P3PRansac, ReprojectionErrorsZeroAtTruthAndHugeBehind)
{
  const StereoCamera cam = test::makeCamera();
  std::mt19937 rng(1);
  const Eigen::Isometry3d T = test::makePose(0, 0.1, 0, 0.1, 0, 0.2);
  Vec3List X = test::randomVisiblePoints(cam, T, 10, rng);
  Vec2List x;
  for (const auto& p : X)
    x.push_back(cam.projectLeft(T.inverse() * p));
  X.push_back(Eigen::Vector3d(0, 0, -5));
  x.push_back(Eigen::Vector2d(320, 240));
  std::vector<double> e;
  P3PRansac::reprojectionErrors(cam, T, X, x, e);
  for (size_t i = 0; i + 1 < e.size(); ++i)
    EXPECT_NEAR(e[i], 0.0, 1e-16);
  EXPECT_GT(e.back(), 1e6);
}

TEST(P3PRansac, RejectsTooFewPoints)
{
  const StereoCamera cam = test::makeCamera();
  P3PRansac r;
  Vec3List X{Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(1, 0, 5), Eigen::Vector3d(0, 1, 5)};
  Vec2List x{Eigen::Vector2d(320, 240), Eigen::Vector2d(420, 240), Eigen::Vector2d(320, 340)};
  EXPECT_FALSE(r.estimate(cam, X, x, RansacOptions()).ok);
  EXPECT_FALSE(r.estimate(StereoCamera(), X, x, RansacOptions()).ok);
}
