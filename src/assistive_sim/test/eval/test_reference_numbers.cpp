// Reproduces the published reference numbers of the real-data README, items 9 and 10
// (evo / TUM evaluate_ate.py), to 1e-5 m. Skips when the data folder is absent.
#include <assistive_sim/eval/metrics.h>
#include <assistive_sim/eval/trajectory.h>

#include <gtest/gtest.h>

#include "real_data.h"

using namespace assistive_sim::eval;

namespace
{
const char* KITTI00 = "trajectories/evo_kitti00_orb_sptam";
const char* FR2 = "trajectories/evo_tum_fr2_desk_orb";
constexpr double TOL = 1e-5;  // published figures are rounded to 1e-6
}  // namespace

TEST(ReferenceNumbers, Kitti00OrbApeSe3)
{
  REQUIRE_REAL_DATA(KITTI00);
  const std::string d = realDataDir() + "/" + KITTI00;
  const Trajectory gt = readKitti(d + "/KITTI_00_gt.txt"), est = readKitti(d + "/KITTI_00_ORB.txt");
  ASSERT_EQ(gt.size(), 4541u);
  ASSERT_EQ(est.size(), 4541u);
  const ErrorStats s = ape(gt, est, AlignMode::SE3);
  EXPECT_EQ(s.n, 4541u);
  EXPECT_NEAR(s.rmse, 1.303450, TOL);
  EXPECT_NEAR(s.mean, 1.156997, TOL);
  EXPECT_NEAR(s.median, 1.065625, TOL);
  EXPECT_NEAR(s.std, 0.600282, TOL);
  EXPECT_NEAR(s.min, 0.069313, TOL);
  EXPECT_NEAR(s.max, 3.587949, TOL);
  EXPECT_NEAR(s.sse, 7715.0734, 1e-4);
}

TEST(ReferenceNumbers, Kitti00SptamApeSe3)
{
  REQUIRE_REAL_DATA(KITTI00);
  const std::string d = realDataDir() + "/" + KITTI00;
  const ErrorStats s = ape(readKitti(d + "/KITTI_00_gt.txt"), readKitti(d + "/KITTI_00_SPTAM.txt"), AlignMode::SE3);
  EXPECT_NEAR(s.rmse, 3.738488, TOL);
  EXPECT_NEAR(s.mean, 3.490977, TOL);
  EXPECT_NEAR(s.median, 3.642585, TOL);
  EXPECT_NEAR(s.std, 1.337675, TOL);
  EXPECT_NEAR(s.min, 0.694787, TOL);
  EXPECT_NEAR(s.max, 7.768977, TOL);
}

TEST(ReferenceNumbers, Kitti00Rpe10m)
{
  REQUIRE_REAL_DATA(KITTI00);
  const std::string d = realDataDir() + "/" + KITTI00;
  const Trajectory gt = readKitti(d + "/KITTI_00_gt.txt");
  const ErrorStats orb = computeStats(rpeTranslationErrors(gt, readKitti(d + "/KITTI_00_ORB.txt"), 10.0));
  EXPECT_EQ(orb.n, 353u);
  EXPECT_NEAR(orb.rmse, 0.226261, TOL);
  EXPECT_NEAR(orb.mean, 0.169017, TOL);
  EXPECT_NEAR(orb.median, 0.138484, TOL);
  EXPECT_NEAR(orb.max, 1.272209, TOL);
  EXPECT_NEAR(orb.min, 0.025323, TOL);
  const ErrorStats sp = computeStats(rpeTranslationErrors(gt, readKitti(d + "/KITTI_00_SPTAM.txt"), 10.0));
  EXPECT_EQ(sp.n, 355u);
  EXPECT_NEAR(sp.rmse, 0.276071, TOL);
  EXPECT_NEAR(sp.mean, 0.222848, TOL);
  EXPECT_NEAR(sp.median, 0.178334, TOL);
  EXPECT_NEAR(sp.max, 1.206594, TOL);
}

TEST(ReferenceNumbers, Fr2DeskTumEvaluateAte)
{
  REQUIRE_REAL_DATA(FR2);
  const std::string d = realDataDir() + "/" + FR2;
  const Trajectory gt = readTum(d + "/fr2_desk_groundtruth.txt"), est = readTum(d + "/fr2_desk_ORB.txt");
  ASSERT_EQ(gt.size(), 20957u);
  ASSERT_EQ(est.size(), 2893u);
  const MatchedTrajectories m = match(gt, est, 0.02, AssociationMethod::TUM_GREEDY);
  ASSERT_EQ(m.gt.size(), 2223u);
  const ErrorStats s = ape(m.gt, m.est, AlignMode::SE3);
  EXPECT_NEAR(s.rmse, 0.008144, TOL);
  EXPECT_NEAR(s.mean, 0.007514, TOL);
  EXPECT_NEAR(s.median, 0.007432, TOL);
  EXPECT_NEAR(s.std, 0.003140, TOL);
  EXPECT_NEAR(s.min, 0.000332, TOL);
  EXPECT_NEAR(s.max, 0.024329, TOL);
}

TEST(ReferenceNumbers, Fr2DeskEvoApeAlign)
{
  REQUIRE_REAL_DATA(FR2);
  const std::string d = realDataDir() + "/" + FR2;
  const Trajectory gt = readTum(d + "/fr2_desk_groundtruth.txt"), est = readTum(d + "/fr2_desk_ORB.txt");
  const MatchedTrajectories m = match(gt, est, 0.01, AssociationMethod::EVO_NEAREST);
  ASSERT_EQ(m.gt.size(), 2174u);
  const ErrorStats s = ape(m.gt, m.est, AlignMode::SE3);
  EXPECT_NEAR(s.rmse, 0.008119, TOL);
  EXPECT_NEAR(s.mean, 0.007492, TOL);
  EXPECT_NEAR(s.median, 0.007415, TOL);
  EXPECT_NEAR(s.std, 0.003129, TOL);
  EXPECT_NEAR(s.min, 0.000350, TOL);
  EXPECT_NEAR(s.max, 0.024300, TOL);
  EXPECT_NEAR(s.sse, 0.143305, TOL);
}
