#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "assistive_tactile/vest_gyro.h"

using assistive_tactile::VestGyro;

// A vest worn leaning 20 deg forward (the IMU's z axis is not the vertical) on a torso turning
// left at 1 rad/s about the vertical, sampled at 100 Hz: the yaw rate is the rate along the
// measured up, 1 rad/s (the z axis alone would read cos 20 = 0.94).
TEST(VestGyro, YawRateIsTheTurnAboutTheMeasuredUp)
{
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  // vectors of the world (z up) seen in the vest's frame
  const Eigen::Vector3d up_in_vest = tilt.transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d rate = 1.0 * up_in_vest, accel = 9.81 * up_in_vest;
  VestGyro g;
  for (int i = 0; i <= 100; ++i) g.add(0.01 * i, rate, accel);
  EXPECT_TRUE(std::isnan(g.take(1.0)));  // the first take: no interval to divide by
  for (int i = 101; i <= 150; ++i) g.add(0.01 * i, rate, accel);
  EXPECT_NEAR(g.take(1.5), 1.0, 0.01);
  EXPECT_NEAR(rate.z(), std::cos(20.0 * M_PI / 180.0), 1e-9);
  // still: zero
  for (int i = 151; i <= 200; ++i) g.add(0.01 * i, Eigen::Vector3d::Zero(), accel);
  EXPECT_NEAR(g.take(2.0), 0.0, 1e-9);
}

// A vest whose IMU stops (link lost, unplugged) gives no rate: the cue logic then estimates the
// facing from the head again. The same after a gap in the samples, once: the turn in the gap is
// unknown.
TEST(VestGyro, NoSamplesNoRate)
{
  VestGyro g;
  const Eigen::Vector3d up(0.0, 0.0, 9.81), rate(0.0, 0.0, 0.5);
  for (int i = 0; i <= 50; ++i) g.add(0.02 * i, rate, up);
  g.take(1.0);
  for (int i = 51; i <= 75; ++i) g.add(0.02 * i, rate, up);
  EXPECT_NEAR(g.take(1.5), 0.5, 1e-9);
  EXPECT_TRUE(std::isnan(g.take(2.5)));  // nothing for a second
  for (int i = 0; i <= 25; ++i) g.add(3.0 + 0.02 * i, rate, up);  // back after a 2 s gap
  EXPECT_TRUE(std::isnan(g.take(3.5)));
  for (int i = 26; i <= 50; ++i) g.add(3.0 + 0.02 * i, rate, up);
  EXPECT_NEAR(g.take(4.0), 0.5, 1e-9);
  // broken samples are ignored
  g.add(4.02, Eigen::Vector3d(NAN, 0.0, 0.0), up);
  g.add(4.04, rate, Eigen::Vector3d::Zero());
  for (int i = 1; i <= 25; ++i) g.add(4.0 + 0.02 * i, rate, up);
  EXPECT_NEAR(g.take(4.5), 0.5, 0.03);
}

// The offset is captured while the vest is still: a gyro 10 deg/s off (an MPU-6050's may be 20 at
// power-up), on a wearer standing quietly (sway and sensor noise: 0.03 m/s^2, 0.2 deg/s) for 3 s
// at 50 Hz: taken out, the standing rate is within 0.2 deg/s of zero. Walking (the gait's 1.5 m/s^2
// RMS at 1.8 steps a second) on a steady 5 deg/s veer is not still: no capture, the veer stays.
// The window slides: a stop of 1.5 s anywhere in a walk gives its second.
TEST(VestGyro, OffsetCapturedStillNotWalking)
{
  const double deg = M_PI / 180.0, offset = 10.0 * deg;
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  auto still = [&](double t) {
    return std::make_pair(Eigen::Vector3d(0.2 * deg * n(rng), 0.2 * deg * n(rng), offset + 0.2 * deg * n(rng)),
                          Eigen::Vector3d(0.03 * n(rng), 0.03 * n(rng), 9.81 + 0.03 * n(rng)));
    (void)t;
  };
  auto walking = [&](double t) {
    return std::make_pair(Eigen::Vector3d(0.0, 0.0, offset + 5.0 * deg),
                          Eigen::Vector3d(0.0, 0.0, 9.81 + 1.5 * std::sqrt(2.0) * std::sin(2.0 * M_PI * 1.8 * t)));
  };
  VestGyro walker;
  for (int i = 0; i <= 250; ++i)
  {
    const auto s = walking(0.02 * i);
    walker.add(0.02 * i, s.first, s.second);
  }
  walker.take(5.0);
  for (int i = 251; i <= 300; ++i)
  {
    const auto s = walking(0.02 * i);
    walker.add(0.02 * i, s.first, s.second);
  }
  EXPECT_EQ(walker.offsetCaptures(), 0);
  EXPECT_NEAR(walker.take(6.0), offset + 5.0 * deg, 1e-6);  // the veer and the offset, untouched

  VestGyro g;
  for (int i = 0; i <= 150; ++i)
  {
    const auto s = still(0.02 * i);
    g.add(0.02 * i, s.first, s.second);
  }
  EXPECT_GE(g.offsetCaptures(), 1);
  EXPECT_NEAR(g.offset(), offset, 0.1 * deg);
  g.take(4.0);
  for (int i = 151; i <= 250; ++i)
  {
    const auto s = still(0.02 * i);
    g.add(0.02 * i, s.first, s.second);
  }
  EXPECT_NEAR(g.take(5.0), 0.0, 0.2 * deg);

  // A stop of 1.5 s between two walks (1.3 s into the samples: no whole second of the stop begins
  // on a whole second) is found.
  VestGyro stop;
  for (int i = 0; i <= 200; ++i)
  {
    const double t = 0.02 * i;
    const auto s = t > 1.3 && t < 2.8 ? still(t) : walking(t);
    stop.add(t, s.first, s.second);
  }
  EXPECT_GE(stop.offsetCaptures(), 1);
  EXPECT_NEAR(stop.offset(), offset, 0.1 * deg);
}

// The offset kept across runs: written and read back; no file, a file without the line, garbage
// and an offset beyond 25 deg/s are refused with a reason, and setOffset ignores what it cannot be.
TEST(VestGyro, OffsetKeptAcrossRuns)
{
  const std::string dir = ::testing::TempDir();
  const std::string path = dir + "/vest_gyro_offset_test.yaml";
  std::string why;
  double x = 0.0;
  ASSERT_TRUE(assistive_tactile::saveOffset(path, 0.1234567, &why)) << why;
  ASSERT_TRUE(assistive_tactile::loadOffset(path, &x, &why)) << why;
  EXPECT_NEAR(x, 0.1234567, 1e-9);
  EXPECT_FALSE(assistive_tactile::loadOffset(dir + "/no_such_offset.yaml", &x, &why));
  EXPECT_NE(why.find("no_such_offset"), std::string::npos);
  for (const char* text : { "offset: 0.1\n", "offset_rad_s: fast\n", "offset_rad_s: 0.5\n", "offset_rad_s: nan\n" })
  {
    {
      std::ofstream out(path, std::ios::trunc);
      out << text;
    }
    x = 7.0;
    EXPECT_FALSE(assistive_tactile::loadOffset(path, &x, &why)) << text;
    EXPECT_EQ(x, 7.0) << text;
  }
  std::remove(path.c_str());
  VestGyro g;
  g.setOffset(0.05);
  EXPECT_DOUBLE_EQ(g.offset(), 0.05);
  g.setOffset(0.5);  // 29 deg/s: no MPU-6050's
  g.setOffset(std::numeric_limits<double>::quiet_NaN());
  EXPECT_DOUBLE_EQ(g.offset(), 0.05);
  EXPECT_EQ(g.offsetCaptures(), 0);
}
