// GravityAligner on a synthetic walk with an exact accelerometer: it measures a known tilt of the
// odom frame, levels it, leaves yaw alone, and rejects windows that cannot be gravity.
#include "assistive_vo/gravity_alignment.h"
#include <gtest/gtest.h>
#include <cmath>

using namespace assistive_vo;

namespace
{
constexpr double G = 9.81, DEG = M_PI / 180.0, RATE = 15.0;

/// A walking head: 1.2 m/s forward with a 2 Hz bob and sway, pitching and scanning.
Eigen::Vector3d position(double t)
{
  return Eigen::Vector3d(1.2 * t, 0.03 * std::sin(2 * M_PI * 1.0 * t), 1.6 + 0.02 * std::sin(2 * M_PI * 2.0 * t));
}
Eigen::Matrix3d orientation(double t)
{
  return (Eigen::AngleAxisd(0.3 * std::sin(0.5 * t), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(0.25 + 0.05 * std::sin(2 * M_PI * 2.0 * t), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(0.03 * std::sin(2 * M_PI * 1.0 * t), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}
Eigen::Vector3d acceleration(double t)
{
  const double h = 1e-4;
  return (position(t + h) - 2 * position(t) + position(t - h)) / (h * h);
}
/// The accelerometer (specific force) integrated over (t0, t1] in the head axes at t0, as
/// ImuBuffer::integrate gives it from a 200 Hz IMU.
Eigen::Vector3d meanAccel(double t0, double t1, double scale = 1.0)
{
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  const int n = 40;
  for (int i = 0; i < n; ++i)
  {
    const double t = t0 + (i + 0.5) * (t1 - t0) / n;
    s += acceleration(t) + Eigen::Vector3d(0, 0, G);
  }
  return scale * orientation(t0).transpose() * s * (t1 - t0) / n;
}
Eigen::Isometry3d truePose(double t)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = orientation(t);
  T.translation() = position(t);
  return T;
}
/// The tilt between the odom frame and the true world: angle between their z axes.
double tiltDeg(const Eigen::Isometry3d& T_odom_world)
{
  return std::acos(std::clamp(T_odom_world.linear().col(2).z(), -1.0, 1.0)) / DEG;
}
}  // namespace

TEST(GravityAligner, MeasuresAKnownTiltAndLevelsTheFrame)
{
  GravityAligner::Options o;
  o.window_s = 3.7;  // not a multiple of the walk's periods: the windows end at different phases
  o.time_constant_s = 1e-3;  // apply the whole measured tilt at once
  GravityAligner g(o);
  // The odometry's world is tilted 0.5 deg about an axis in the floor plane, and turned 20 deg.
  Eigen::Isometry3d T_odom_world = Eigen::Isometry3d::Identity();
  T_odom_world.linear() = (Eigen::AngleAxisd(20 * DEG, Eigen::Vector3d::UnitZ()) *
                           Eigen::AngleAxisd(0.5 * DEG, Eigen::Vector3d(1, 2, 0).normalized()))
                              .toRotationMatrix();
  const double yaw0 = std::atan2(T_odom_world.linear()(1, 0), T_odom_world.linear()(0, 0));
  int windows = 0;
  for (int k = 0; k <= static_cast<int>(12.5 * RATE); ++k)
  {
    const double t = k / RATE;
    Eigen::Matrix3d C;
    if (g.add(t, T_odom_world * truePose(t), meanAccel(t - 1 / RATE, t), C))
    {
      ++windows;
      if (windows == 1)
        EXPECT_NEAR(g.lastTiltDeg(), 0.5, 0.001);
      else
        EXPECT_LT(g.lastTiltDeg(), 0.001);  // levelled by the first correction
      // apply about the current position, as the odometry does
      const Eigen::Vector3d p = (T_odom_world * truePose(t)).translation();
      Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
      M.linear() = C;
      M.translation() = p - C * p;
      T_odom_world = M * T_odom_world;
      EXPECT_LT(((T_odom_world * truePose(t)).translation() - p).norm(), 1e-12);  // no jump
    }
  }
  EXPECT_EQ(windows, 3);
  EXPECT_EQ(g.accepted(), 3);
  EXPECT_LT(tiltDeg(T_odom_world), 0.001);
  // yaw untouched
  const double yaw1 = std::atan2(T_odom_world.linear()(1, 0), T_odom_world.linear()(0, 0));
  EXPECT_NEAR(yaw1, yaw0, 0.01 * DEG);
}

TEST(GravityAligner, CorrectsAFractionPerWindowSetByTheTimeConstant)
{
  GravityAligner::Options o;
  o.window_s = 4.0;
  o.time_constant_s = 40.0;
  GravityAligner g(o);
  Eigen::Isometry3d T_odom_world = Eigen::Isometry3d::Identity();
  T_odom_world.linear() = Eigen::AngleAxisd(1.0 * DEG, Eigen::Vector3d::UnitX()).toRotationMatrix();
  Eigen::Matrix3d C = Eigen::Matrix3d::Identity();
  bool closed = false;
  for (int k = 0; k <= static_cast<int>(4.2 * RATE) && !closed; ++k)
  {
    const double t = k / RATE;
    closed = g.add(t, T_odom_world * truePose(t), meanAccel(t - 1 / RATE, t), C);
  }
  ASSERT_TRUE(closed);
  EXPECT_NEAR(g.lastTiltDeg(), 1.0, 0.005);
  // T runs between the middles of the first and last 4 intervals: 4 s less 4 frames, so the
  // correction is T / 40 s of the tilt
  EXPECT_NEAR(Eigen::AngleAxisd(C).angle() / DEG, 1.0 * (4.0 - 4 / RATE) / 40.0, 0.001);
  // ... and it turns the frame back (about the x axis, the other way)
  EXPECT_LT(Eigen::AngleAxisd(C).axis().x() * Eigen::AngleAxisd(T_odom_world.linear()).axis().x(), 0.0);
}

TEST(GravityAligner, RejectsWhatCannotBeGravityAndRestartsAfterGaps)
{
  GravityAligner::Options o;
  o.window_s = 2.0;
  GravityAligner g(o);
  Eigen::Matrix3d C;
  // A miscalibrated accelerometer (10 % scale): |g| is 1 m/s^2 off, the window is rejected.
  bool closed = false;
  for (int k = 0; k <= static_cast<int>(2.2 * RATE) && !closed; ++k)
  {
    const double t = k / RATE;
    closed = g.add(t, truePose(t), meanAccel(t - 1 / RATE, t, 1.1), C);
  }
  ASSERT_TRUE(closed);
  EXPECT_EQ(g.rejected(), 1);
  EXPECT_EQ(g.accepted(), 0);
  EXPECT_TRUE(C.isIdentity(1e-15));

  // A gap in the frames (0.5 s) restarts the window: none closes within 2 s after it.
  g.clear();
  double t = 10.0;
  for (int k = 0; k < 20; ++k, t += 1 / RATE)
    EXPECT_FALSE(g.add(t, truePose(t), meanAccel(t - 1 / RATE, t), C));
  t += 0.5;
  for (int k = 0; k < 29; ++k, t += 1 / RATE)
    EXPECT_FALSE(g.add(t, truePose(t), meanAccel(t - 1 / RATE, t), C));
  // NaN input clears too, and nothing is returned
  EXPECT_FALSE(g.add(t, truePose(t), Eigen::Vector3d::Constant(std::nan("")), C));
  EXPECT_TRUE(C.isIdentity(1e-15));
  // switched off: never a correction
  o.time_constant_s = 0.0;
  GravityAligner off(o);
  for (int k = 0; k < 100; ++k)
    EXPECT_FALSE(off.add(k / RATE, truePose(k / RATE), meanAccel((k - 1) / RATE, k / RATE), C));
}
