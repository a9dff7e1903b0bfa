// Reproduces the published reference numbers of the real-data README, items 9 and 10
// (evo / TUM evaluate_ate.py), to 1e-5 m. Skips when the data folder is absent.
#include <assistive_eval/metrics.h>
#include <assistive_eval/trajectory.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>

#include "real_data.h"

using namespace assistive_eval;

namespace
{
const char* KITTI00 = "trajectories/evo_kitti00_orb_sptam";
const char* FR2 = "trajectories/evo_tum_fr2_desk_orb";
constexpr double TOL = 1e-5;  // published figures are rounded to 1e-6
const double SKIP = std::numeric_limits<double>::quiet_NaN();

/// The published statistics of one run (SKIP: not published for it).
struct Published
{
  double rmse, mean, median, std, min, max;
};
/// A trajectory file of item 9 (KITTI 00: "gt", "ORB", "SPTAM").
Trajectory kitti00(const std::string& which) { return readKitti(realDataDir() + "/" + KITTI00 + "/KITTI_00_" + which + ".txt"); }
/// Item 10: the fr2/desk truth and the ORB estimate.
std::pair<Trajectory, Trajectory> fr2Desk()
{
  const std::string d = realDataDir() + "/" + FR2;
  return {readTum(d + "/fr2_desk_groundtruth.txt"), readTum(d + "/fr2_desk_ORB.txt")};
}

void expectStats(const ErrorStats& s, const Published& p)
{
  const std::pair<double, double> pairs[] = {{s.rmse, p.rmse}, {s.mean, p.mean}, {s.median, p.median},
                                             {s.std, p.std},   {s.min, p.min},   {s.max, p.max}};
  const char* names[] = {"rmse", "mean", "median", "std", "min", "max"};
  for (int i = 0; i < 6; ++i)
    if (!std::isnan(pairs[i].second))
    {
      EXPECT_NEAR(pairs[i].first, pairs[i].second, TOL) << names[i];
    }
}
}  // namespace

TEST(ReferenceNumbers, Kitti00OrbApeSe3)
{
  REQUIRE_REAL_DATA(KITTI00);
  const Trajectory gt = kitti00("gt"), est = kitti00("ORB");
  ASSERT_EQ(gt.size(), 4541u);
  ASSERT_EQ(est.size(), 4541u);
  const ErrorStats s = ape(gt, est, AlignMode::SE3);
  EXPECT_EQ(s.n, 4541u);
  expectStats(s, {1.303450, 1.156997, 1.065625, 0.600282, 0.069313, 3.587949});
  EXPECT_NEAR(s.sse, 7715.0734, 1e-4);
}

TEST(ReferenceNumbers, Kitti00SptamApeSe3)
{
  REQUIRE_REAL_DATA(KITTI00);
  const ErrorStats s = ape(kitti00("gt"), kitti00("SPTAM"), AlignMode::SE3);
  expectStats(s, {3.738488, 3.490977, 3.642585, 1.337675, 0.694787, 7.768977});
}

TEST(ReferenceNumbers, Kitti00Rpe10m)
{
  REQUIRE_REAL_DATA(KITTI00);
  const Trajectory gt = kitti00("gt");
  const ErrorStats orb = computeStats(rpeTranslationErrors(gt, kitti00("ORB"), 10.0));
  EXPECT_EQ(orb.n, 353u);
  expectStats(orb, {0.226261, 0.169017, 0.138484, SKIP, 0.025323, 1.272209});
  const ErrorStats sp = computeStats(rpeTranslationErrors(gt, kitti00("SPTAM"), 10.0));
  EXPECT_EQ(sp.n, 355u);
  expectStats(sp, {0.276071, 0.222848, 0.178334, SKIP, SKIP, 1.206594});
}

TEST(ReferenceNumbers, Fr2DeskTumEvaluateAte)
{
  REQUIRE_REAL_DATA(FR2);
  const auto [gt, est] = fr2Desk();
  ASSERT_EQ(gt.size(), 20957u);
  ASSERT_EQ(est.size(), 2893u);
  const MatchedTrajectories m = match(gt, est, 0.02, AssociationMethod::TUM_GREEDY);
  ASSERT_EQ(m.gt.size(), 2223u);
  const ErrorStats s = ape(m.gt, m.est, AlignMode::SE3);
  expectStats(s, {0.008144, 0.007514, 0.007432, 0.003140, 0.000332, 0.024329});
}

TEST(ReferenceNumbers, Fr2DeskEvoApeAlign)
{
  REQUIRE_REAL_DATA(FR2);
  const auto [gt, est] = fr2Desk();
  const MatchedTrajectories m = match(gt, est, 0.01, AssociationMethod::EVO_NEAREST);
  ASSERT_EQ(m.gt.size(), 2174u);
  const ErrorStats s = ape(m.gt, m.est, AlignMode::SE3);
  expectStats(s, {0.008119, 0.007492, 0.007415, 0.003129, 0.000350, 0.024300});
  EXPECT_NEAR(s.sse, 0.143305, TOL);
}
