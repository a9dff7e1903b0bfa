// Motion refinement over points and lines (pointline_refine.h): exact synthetic data.
#include <gtest/gtest.h>
#include <cmath>
#include "assistive_vo/pointline_refine.h"
#include "synthetic.h"

using namespace assistive_vo;

namespace
{
/// A line segment of the image of 3D points A, B (left or right camera).
LineSegment segmentOf(const StereoCamera& cam, const Eigen::Vector3d& A, const Eigen::Vector3d& B, bool right)
{
  LineSegment s;
  s.p = cam.projectLeft(A);
  s.q = cam.projectLeft(B);
  if (right)
  {
    s.p.x() = cam.projectRightU(A);
    s.q.x() = cam.projectRightU(B);
  }
  return s;
}

/// A 3D line through C with direction D, seen in the reference pair and (T_ref_cur) the current
/// one: the reference segments from C -/+ 0.5 D, the current ones from other parts of the line.
StereoLineObservation lineObs(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur, const Eigen::Vector3d& C,
                              const Eigen::Vector3d& D)
{
  const LineSegment l = segmentOf(cam, C - 0.5 * D, C + 0.5 * D, false);
  const LineSegment r = segmentOf(cam, C - 0.4 * D, C + 0.6 * D, true);
  StereoLineObservation o;
  EXPECT_TRUE(triangulateStereoSegment(cam, l, r, 0.5, o.P, o.Q));
  const Eigen::Isometry3d T_cur_ref = T_ref_cur.inverse();
  const LineSegment cl = segmentOf(cam, T_cur_ref * (C - 0.3 * D), T_cur_ref * (C + 0.45 * D), false);
  const LineSegment cr = segmentOf(cam, T_cur_ref * (C - 0.45 * D), T_cur_ref * (C + 0.3 * D), true);
  o.left_p = cl.p, o.left_q = cl.q, o.right_p = cr.p, o.right_q = cr.q;
  return o;
}

double rotErr(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

/// Points of `X` seen in the current frame (exact).
std::vector<StereoObservation> observe(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur, const Vec3List& X)
{
  std::vector<StereoObservation> o;
  for (const auto& x : X)
  {
    const Eigen::Vector3d Xc = T_ref_cur.inverse() * x;
    o.push_back({cam.projectLeft(Xc).x(), cam.projectLeft(Xc).y(), cam.projectRightU(Xc)});
  }
  return o;
}

StereoLineObservations slantedLines(const StereoCamera& cam, const Eigen::Isometry3d& T)
{
  StereoLineObservations L;
  const double dirs[6][3] = {{0.1, 1, 0.05}, {-0.4, 1, 0.1}, {0.5, 1, -0.2}, {1, 0.6, 0.1}, {-1, 0.8, 0.3}, {0.2, 1, 0.6}};
  const double pos[6][3] = {{-1, 0, 4}, {1, 0.2, 5}, {0, -0.3, 3}, {0.5, 0.8, 6}, {-0.8, -0.5, 4.5}, {0.3, 0.1, 3.5}};
  for (int i = 0; i < 6; ++i)
    L.push_back(lineObs(cam, T, Eigen::Vector3d(pos[i][0], pos[i][1], pos[i][2]),
                        Eigen::Vector3d(dirs[i][0], dirs[i][1], dirs[i][2])));
  return L;
}
}  // namespace

TEST(PointLineRefine, TriangulatesAStereoSegmentOnTheLine)
{
  const StereoCamera cam = test::makeCamera();
  const Eigen::Vector3d C(0.4, -0.2, 3.0), D(0.3, 1.0, 0.4);
  const LineSegment l = segmentOf(cam, C - 0.5 * D, C + 0.5 * D, false);
  const LineSegment r = segmentOf(cam, C - 0.2 * D, C + 0.7 * D, true);  // another part of the line
  Eigen::Vector3d P, Q;
  ASSERT_TRUE(triangulateStereoSegment(cam, l, r, 0.5, P, Q));
  // the left end points' 3D points, exactly
  EXPECT_LT((P - (C - 0.5 * D)).norm(), 1e-9);
  EXPECT_LT((Q - (C + 0.5 * D)).norm(), 1e-9);
  // a horizontal right segment has no row-wise match; a negative disparity none either
  LineSegment flat = r;
  flat.q.y() = flat.p.y();
  EXPECT_FALSE(triangulateStereoSegment(cam, l, flat, 0.5, P, Q));
  LineSegment behind = r;
  behind.p.x() += 400, behind.q.x() += 400;
  EXPECT_FALSE(triangulateStereoSegment(cam, l, behind, 0.5, P, Q));
}

TEST(PointLineRefine, RecoversTheMotionFromPointsAndLinesExactly)
{
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(0.02, -0.05, 0.01, 0.08, -0.03, 0.25);
  std::mt19937 rng(3);
  const Vec3List X = test::randomVisiblePoints(cam, T, 3, rng);
  const StereoLineObservations L = slantedLines(cam, T);
  // started 3 deg and 10 cm away
  const Eigen::Isometry3d init = T * test::makePose(0.03, 0.04, -0.02, 0.06, -0.05, 0.06);
  const BundleAdjustmentResult r = refineMotionPointsLines(cam, init, X, observe(cam, T, X), L, PointLineRefineOptions());
  ASSERT_TRUE(r.ok);
  EXPECT_LT((r.T_ref_cur.translation() - T.translation()).norm(), 1e-8);
  EXPECT_LT(rotErr(r.T_ref_cur, T), 1e-8);
  EXPECT_LT(r.final_cost, 1e-12);
  EXPECT_TRUE(r.covariance.allFinite());
}

TEST(PointLineRefine, RecoversTheMotionFromLinesAlone)
{
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(-0.03, 0.04, 0.02, -0.05, 0.02, 0.3);
  const StereoLineObservations L = slantedLines(cam, T);
  const Eigen::Isometry3d init = T * test::makePose(-0.02, 0.02, 0.03, 0.05, 0.04, -0.05);
  const BundleAdjustmentResult r =
      refineMotionPointsLines(cam, init, Vec3List(), std::vector<StereoObservation>(), L, PointLineRefineOptions());
  ASSERT_TRUE(r.ok);
  EXPECT_LT((r.T_ref_cur.translation() - T.translation()).norm(), 1e-8);
  EXPECT_LT(rotErr(r.T_ref_cur, T), 1e-8);
}

TEST(PointLineRefine, ParallelLinesAloneAreRefusedWithoutNaN)
{
  // all lines vertical, no point: the motion along them is free
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(0.0, 0.02, 0.0, 0.05, 0.0, 0.2);
  StereoLineObservations L;
  for (int i = 0; i < 6; ++i)
    L.push_back(lineObs(cam, T, Eigen::Vector3d(-1.2 + 0.5 * i, 0.0, 3.0 + 0.4 * i), Eigen::Vector3d(0, 1, 0)));
  const BundleAdjustmentResult r =
      refineMotionPointsLines(cam, T * test::makePose(0, 0.01, 0, 0.02, 0.03, 0.0), Vec3List(),
                              std::vector<StereoObservation>(), L, PointLineRefineOptions());
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.T_ref_cur.matrix().allFinite());
  // a point with them fixes the free direction
  std::mt19937 rng(5);
  const Vec3List X = test::randomVisiblePoints(cam, T, 2, rng);
  const BundleAdjustmentResult r2 = refineMotionPointsLines(cam, T * test::makePose(0, 0.01, 0, 0.02, 0.03, 0.0), X,
                                                            observe(cam, T, X), L, PointLineRefineOptions());
  ASSERT_TRUE(r2.ok);
  EXPECT_LT((r2.T_ref_cur.translation() - T.translation()).norm(), 1e-8);
  EXPECT_LT(rotErr(r2.T_ref_cur, T), 1e-8);
}

TEST(PointLineRefine, AMotionPriorHoldsWhatParallelLinesLeaveFree)
{
  // Vertical lines alone (the corridor's end wall) say nothing of the motion along them: with the
  // motion prior (translation and rotation) the estimate is the data's where the lines decide and
  // the prior's along them.
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(0.0, 0.02, 0.0, 0.05, -0.03, 0.2);
  StereoLineObservations L;
  for (int i = 0; i < 6; ++i)
    L.push_back(lineObs(cam, T, Eigen::Vector3d(-1.2 + 0.5 * i, 0.0, 3.0 + 0.4 * i), Eigen::Vector3d(0, 1, 0)));
  PointLineRefineOptions o;
  o.use_translation_prior = true;
  o.use_rotation_prior = true;
  o.rotation_prior = T.linear();
  o.rotation_prior_weight = 0.25 / (0.01 * 0.01);  // 0.5 px, 0.01 rad
  o.translation_prior_weight = 0.25 / (0.02 * 0.02);  // 0.5 px, 2 cm
  // the prior exact: the motion exactly
  o.translation_prior = T.translation();
  const Eigen::Isometry3d init = T * test::makePose(0, 0.01, 0, 0.02, 0.03, 0.0);
  const BundleAdjustmentResult r =
      refineMotionPointsLines(cam, init, Vec3List(), std::vector<StereoObservation>(), L, o);
  ASSERT_TRUE(r.ok);
  EXPECT_LT((r.T_ref_cur.translation() - T.translation()).norm(), 1e-8);
  EXPECT_LT(rotErr(r.T_ref_cur, T), 1e-8);
  // a prior 3 cm off in y (along the lines) and 3 cm off in x, the rotation known (a gyro's
  // 0.001 rad): y follows the prior (the lines cannot tell), x and z stay the lines' (of the
  // 30 mm offset the prior pulls them by 2 mm at most against six lines)
  o.rotation_prior_weight = 0.25 / (0.001 * 0.001);
  o.translation_prior = T.translation() + Eigen::Vector3d(0.03, 0.03, 0.0);
  const BundleAdjustmentResult r2 =
      refineMotionPointsLines(cam, init, Vec3List(), std::vector<StereoObservation>(), L, o);
  ASSERT_TRUE(r2.ok);
  const Eigen::Vector3d e = r2.T_ref_cur.translation() - T.translation();
  EXPECT_NEAR(e.y(), 0.03, 1e-3);
  EXPECT_LT(std::abs(e.x()), 2e-3);
  EXPECT_LT(std::abs(e.z()), 2e-3);
  EXPECT_TRUE(r2.covariance.allFinite());
}

TEST(PointLineRefine, AnOutlierIsDownWeightedAndTheGyroPriorHolds)
{
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(0.01, 0.03, -0.01, 0.04, 0.01, 0.2);
  std::mt19937 rng(9);
  const Vec3List X = test::randomVisiblePoints(cam, T, 12, rng);
  std::vector<StereoObservation> obs = observe(cam, T, X);
  obs[4].u += 25.0;  // a mistracked point
  obs[4].ur += 25.0;
  PointLineRefineOptions o;
  o.iterations = 30;
  const BundleAdjustmentResult r = refineMotionPointsLines(cam, T, X, obs, slantedLines(cam, T), o);
  ASSERT_TRUE(r.ok);
  EXPECT_LT((r.T_ref_cur.translation() - T.translation()).norm(), 2e-3);
  EXPECT_LT(rotErr(r.T_ref_cur, T), 5e-4);
  // least squares (no Huber) is pulled several times further
  PointLineRefineOptions ls = o;
  ls.huber_px = 1e6;
  const BundleAdjustmentResult r_ls = refineMotionPointsLines(cam, T, X, obs, slantedLines(cam, T), ls);
  ASSERT_TRUE(r_ls.ok);
  EXPECT_GT((r_ls.T_ref_cur.translation() - T.translation()).norm(),
            3 * (r.T_ref_cur.translation() - T.translation()).norm());
  // exact data and a prior at the true rotation: still exact
  o.use_rotation_prior = true;
  o.rotation_prior = T.linear();
  o.rotation_prior_weight = 1e4;
  const BundleAdjustmentResult r2 = refineMotionPointsLines(cam, T * test::makePose(0.01, 0, 0, 0.02, 0, 0), X,
                                                            observe(cam, T, X), slantedLines(cam, T), o);
  ASSERT_TRUE(r2.ok);
  EXPECT_LT((r2.T_ref_cur.translation() - T.translation()).norm(), 1e-8);
  EXPECT_LT(rotErr(r2.T_ref_cur, T), 1e-8);
}

TEST(PointLineRefine, NonFiniteInputIsRefused)
{
  const StereoCamera cam = test::makeCamera();
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = std::nan("");
  const BundleAdjustmentResult r =
      refineMotionPointsLines(cam, bad, Vec3List(), std::vector<StereoObservation>(), StereoLineObservations(),
                              PointLineRefineOptions());
  EXPECT_FALSE(r.ok);
  // nothing to refine on: refused too
  const BundleAdjustmentResult r2 = refineMotionPointsLines(cam, Eigen::Isometry3d::Identity(), Vec3List(),
                                                            std::vector<StereoObservation>(), StereoLineObservations(),
                                                            PointLineRefineOptions());
  EXPECT_FALSE(r2.ok);
}
