// The VO core on the real camera clips of issue 9 (../shared/data/real, items 1 and 2), read
// straight from the dataset folders with assistive_eval's readers. Skips with a message when the
// folder is absent (set ASSISTIVE_REAL_DATA to point elsewhere).
#include <assistive_eval/datasets.h>
#include <assistive_eval/metrics.h>
#include <assistive_vo/visual_odometry.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <string>
#include <sys/stat.h>

#ifndef ASSISTIVE_REAL_DATA_DIR
#define ASSISTIVE_REAL_DATA_DIR "../shared/data/real"
#endif

namespace ev = assistive_eval;
using namespace assistive_vo;

namespace
{
const char* const KITTI = "stereo_sequence/kitti_raw_2011_09_26_drive_0001_sync_f000-059";
const char* const EUROC = "stereo_sequence/euroc_v101_static_first20";

std::string clipDir(const char* rel)
{
  const char* e = std::getenv("ASSISTIVE_REAL_DATA");
  const std::string root = (e && *e) ? std::string(e) : std::string(ASSISTIVE_REAL_DATA_DIR);
  return root + "/" + rel;
}

bool exists(const std::string& p)
{
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

struct ClipRun
{
  ev::Trajectory gt, est;
  int resets = 0;
  int not_tracking = 0;
  bool finite = true;
};

/// Default parameters, no IMU (the clips carry none), every frame of the clip.
ClipRun runClip(const std::string& kind, const std::string& dir)
{
  const auto src = ev::openDataset(kind, dir);
  VisualOdometry vo{ VoParams() };
  ClipRun r;
  for (size_t i = 0; i < src->size(); ++i)
  {
    const assistive_eval::StereoFrame f = src->frame(i);
    if (i == 0)
      vo.setCamera(StereoCamera::from(f.calib));
    const VoOutput o = vo.process(f.left, f.right, f.stamp, nullptr);
    if (i > 0 && o.state != TrackingState::TRACKING)
      ++r.not_tracking;
    r.finite = r.finite && o.T_odom_optical.matrix().allFinite();
    r.est.push_back({ f.stamp, o.T_odom_optical });
    if (f.has_gt_pose)
      r.gt.push_back({ f.stamp, f.gt_pose });
  }
  r.resets = vo.resets();
  return r;
}
}  // namespace

// Issue 9: "VO on the still EuRoC clip: estimated motion under 1 cm and 0.5 deg over the 20
// frames, no reset" (the truth: 3.1 mm path, 0.09 deg).
TEST(VoRealData, EurocStillClipGivesNoFalseMotion)
{
  const std::string dir = clipDir(EUROC);
  if (!exists(dir))
    GTEST_SKIP() << "SKIPPED: real data not found at " << dir << " (set ASSISTIVE_REAL_DATA)";
  const ClipRun r = runClip("euroc", dir);
  ASSERT_EQ(r.est.size(), 20u);
  EXPECT_TRUE(r.finite);
  EXPECT_EQ(r.resets, 0);
  EXPECT_EQ(r.not_tracking, 0);
  double max_t = 0.0, max_deg = 0.0;
  for (const auto& p : r.est)
  {
    const Eigen::Isometry3d d = r.est.front().pose.inverse() * p.pose;
    max_t = std::max(max_t, d.translation().norm());
    max_deg = std::max(max_deg, Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI);
  }
  std::cout << "EuRoC still: largest estimated displacement " << max_t * 1000.0 << " mm, rotation " << max_deg
            << " deg\n";
  EXPECT_LT(max_t, 0.01);
  EXPECT_LT(max_deg, 0.5);
}

// Issue 9: VO on the KITTI clip (60 frames, 70 m, 1.2-1.4 m steps) with default parameters.
TEST(VoRealData, KittiClipTracksEveryFrameWithLowDrift)
{
  const std::string dir = clipDir(KITTI);
  if (!exists(dir))
    GTEST_SKIP() << "SKIPPED: real data not found at " << dir << " (set ASSISTIVE_REAL_DATA)";
  const ClipRun r = runClip("kitti", dir);
  ASSERT_EQ(r.est.size(), 60u);
  ASSERT_EQ(r.gt.size(), 60u);
  EXPECT_TRUE(r.finite);
  EXPECT_EQ(r.resets, 0);
  EXPECT_EQ(r.not_tracking, 0);
  const ev::TrajectoryReport rep = ev::evaluateTrajectory(r.gt, r.est);
  std::cout << "KITTI: drift " << rep.drift.drift_pct << " %, " << rep.drift.drift_deg_per_m << " deg/m, ATE "
            << rep.ate.rmse << " m\n";
  EXPECT_LE(rep.drift.drift_pct, KITTI_DRIFT_LIMIT_PCT);
}
