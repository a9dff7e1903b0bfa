#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include "assistive_vo/plausibility.h"

using namespace assistive_vo;

namespace
{
Eigen::Isometry3d motion(double tz, double yaw_deg)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0, 0, tz);
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return T;
}
}  // namespace

TEST(PlausibilityMonitor, GapsAndTimeJumpsAreCounted)
{
  PlausibilityMonitor m;  // max_frame_gap_s 1.0
  EXPECT_EQ(m.checkTiming(1.0 / 15), "");
  EXPECT_EQ(m.checkTiming(1.0), "");  // exactly the limit is no gap
  EXPECT_NE(m.checkTiming(1.5).find("gap of 1.50 s"), std::string::npos);
  EXPECT_NE(m.checkTiming(-0.2).find("time went backwards"), std::string::npos);
  EXPECT_NE(m.checkTiming(0.0).find("repeated stamp"), std::string::npos);
  EXPECT_EQ(m.counters().gaps, 1);
  EXPECT_EQ(m.counters().time_jumps, 2);
  m.reset();
  EXPECT_EQ(m.counters().gaps, 0);
  EXPECT_EQ(m.counters().time_jumps, 0);
}

TEST(PlausibilityMonitor, FrozenCameraSkipsThenUntrustsOncePerEpisode)
{
  VoParams p;  // frozen_max_change 0.5, frozen_min_gyro_dps 1.5
  p.frozen_frames = 2;
  PlausibilityMonitor m(p);
  std::string why;
  bool untrusted = true;
  // changing image: nothing to do
  EXPECT_FALSE(m.frozen(3.0, true, 10.0, why, untrusted));
  EXPECT_FALSE(untrusted);
  // unchanged image with a still head: normal
  EXPECT_FALSE(m.frozen(0.0, true, 0.5, why, untrusted));
  EXPECT_FALSE(m.frozen(0.0, false, -1, why, untrusted));
  // unchanged while the gyro turns: skipped, then untrusted on the second frame
  EXPECT_TRUE(m.frozen(0.1, true, 10.0, why, untrusted));
  EXPECT_FALSE(untrusted);
  EXPECT_NE(why.find("frozen camera"), std::string::npos);
  EXPECT_TRUE(m.frozen(0.1, true, 10.0, why, untrusted));
  EXPECT_TRUE(untrusted);
  EXPECT_TRUE(m.frozen(0.1, true, 10.0, why, untrusted));
  EXPECT_TRUE(untrusted);
  EXPECT_EQ(m.counters().frozen, 1);
  // the image changes: the run ends; a new episode counts again
  EXPECT_FALSE(m.frozen(3.0, true, 10.0, why, untrusted));
  EXPECT_TRUE(m.frozen(0.1, true, 10.0, why, untrusted));
  EXPECT_FALSE(untrusted);
  EXPECT_TRUE(m.frozen(0.1, true, 10.0, why, untrusted));
  EXPECT_EQ(m.counters().frozen, 2);
  // frozen_frames 1: untrusted on the first frozen frame
  p.frozen_frames = 1;
  PlausibilityMonitor one(p);
  EXPECT_TRUE(one.frozen(0.1, true, 10.0, why, untrusted));
  EXPECT_TRUE(untrusted);
  EXPECT_EQ(one.counters().frozen, 1);
}

TEST(PlausibilityMonitor, MotionJumpsAreRejected)
{
  PlausibilityMonitor m;  // max_speed 4 m/s, max_angular_speed 400 deg/s
  const double dt = 1.0 / 15;  // bounds: 0.287 m, 26.7 deg + 0.02 rad
  const Eigen::Isometry3d pred = motion(0.05, 0);
  const Eigen::Isometry3d kf = Eigen::Isometry3d::Identity();
  EXPECT_EQ(m.checkMotion(kf, motion(0.06, 1), pred, dt, false, false), "");
  EXPECT_EQ(m.checkMotion(kf, motion(0.45, 0), pred, dt, false, false), "implausible translation");
  EXPECT_EQ(m.checkMotion(kf, motion(0.45, 0), pred, dt, true, false), "");  // a clear majority supports it
  EXPECT_EQ(m.checkMotion(kf, motion(0.05, 30), pred, dt, false, false), "implausible rotation");
  // 5 deg against a gyro that says 0: only checked with the gyro
  EXPECT_EQ(m.checkMotion(kf, motion(0.05, 5), pred, dt, false, false), "");
  EXPECT_EQ(m.checkMotion(kf, motion(0.05, 5), pred, dt, false, true), "rotation disagrees with the gyro");
  Eigen::Isometry3d nan = Eigen::Isometry3d::Identity();
  nan.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(m.checkMotion(nan, motion(0.05, 0), pred, dt, false, false), "non-finite motion");
}

TEST(PlausibilityMonitor, GyroContradictionNeedsARunAndAsManyAgreeingFrames)
{
  PlausibilityMonitor m;  // gyro_disagreement 1.5 deg on 3 frames
  EXPECT_EQ(m.checkGyroAgreement(2.0), "");
  EXPECT_EQ(m.checkGyroAgreement(2.0), "");
  EXPECT_NE(m.checkGyroAgreement(2.0).find("contradicts the gyro (2.0 deg on 3 frames)"), std::string::npos);
  EXPECT_NE(m.checkGyroAgreement(2.0), "");
  EXPECT_EQ(m.counters().gyro_disagreement, 1);
  EXPECT_NE(m.pendingReason().find("3 agreeing frames to go"), std::string::npos);
  EXPECT_EQ(m.checkGyroAgreement(0.2), "");
  EXPECT_NE(m.pendingReason().find("2 agreeing frames to go"), std::string::npos);
  m.noGyro();  // nothing to check against also runs the count down
  EXPECT_EQ(m.checkGyroAgreement(0.2), "");
  EXPECT_EQ(m.pendingReason(), "");
}

TEST(PlausibilityMonitor, StereoInconsistencyOverARunOrAtOnceWhenLarge)
{
  PlausibilityMonitor m;  // stereo_max_error 0.6 px, min matched 0.3, 3 frames
  EXPECT_EQ(m.checkStereo(0.1, 0.9), "");
  EXPECT_EQ(m.checkStereo(-1, 0.9), "");  // too few residuals: not measured
  EXPECT_EQ(m.checkStereo(1.0, 0.9), "");
  EXPECT_EQ(m.checkStereo(0.1, 0.1), "");  // few matched
  EXPECT_NE(m.checkStereo(1.0, 0.9), "");  // third in a row
  EXPECT_EQ(m.counters().stereo_inconsistent, 1);
  EXPECT_NE(m.pendingReason().find("3 consistent frames to go"), std::string::npos);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(m.checkStereo(0.1, 0.9), "");
  EXPECT_EQ(m.pendingReason(), "");
  // 5 x the threshold: at once, a new episode
  EXPECT_NE(m.checkStereo(4.0, 0.9).find("off by 4.0 px"), std::string::npos);
  EXPECT_EQ(m.counters().stereo_inconsistent, 2);
}
