#include <gtest/gtest.h>
#include "assistive_vo/startup_rule.h"

using namespace assistive_vo;
using D = StartupRule::Decision;

namespace
{
/// 200 Hz samples of a still head over [t0, t1] with the given specific force.
void fill(ImuBuffer& imu, double t0, double t1, const Eigen::Vector3d& a)
{
  for (double t = t0; t <= t1 + 1e-9; t += 0.005)
    imu.add(t, Eigen::Vector3d::Zero(), a);
}
}  // namespace

TEST(StartupRule, StartsWithGravityWhenTheImuIsThere)
{
  ImuBuffer imu(5.0);
  const Eigen::Vector3d g(0.5, 0.2, 9.78);  // camera_link, slightly tilted head
  fill(imu, 9.0, 10.0, g);
  StartupRule rule;
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  EXPECT_EQ(rule.decide(10.0, imu, up), D::START_WITH_GRAVITY);
  EXPECT_TRUE(up.isApprox(g, 1e-9));
}

TEST(StartupRule, WaitsForTheImuThenFallsBack)
{
  ImuBuffer imu;
  StartupRule rule;  // wait_s 1.0 of image time
  Eigen::Vector3d up;
  EXPECT_EQ(rule.decide(10.0, imu, up), D::WAIT_FOR_IMU);
  EXPECT_EQ(rule.decide(10.5, imu, up), D::WAIT_FOR_IMU);
  EXPECT_DOUBLE_EQ(rule.waited(10.5), 0.5);
  EXPECT_EQ(rule.decide(10.99, imu, up), D::WAIT_FOR_IMU);
  EXPECT_EQ(rule.decide(11.0, imu, up), D::START_WITHOUT_IMU);
  // the IMU coming late still wins while waiting
  StartupRule late;
  EXPECT_EQ(late.decide(10.0, imu, up), D::WAIT_FOR_IMU);
  fill(imu, 10.0, 10.3, Eigen::Vector3d(0, 0, 9.81));
  EXPECT_EQ(late.decide(10.3, imu, up), D::START_WITH_GRAVITY);
}

TEST(StartupRule, ASpecificForceFarFromGravityIsNoGravity)
{
  ImuBuffer imu;
  fill(imu, 9.0, 10.0, Eigen::Vector3d(0, 0, 2.0));  // falling, or a broken accelerometer
  StartupRule rule;
  Eigen::Vector3d up;
  EXPECT_EQ(rule.decide(10.0, imu, up), D::WAIT_FOR_IMU);
  ImuBuffer hard;
  fill(hard, 9.0, 10.0, Eigen::Vector3d(0, 0, 20.0));
  EXPECT_EQ(rule.decide(10.0, hard, up), D::WAIT_FOR_IMU);
}

TEST(StartupRule, NoImuExpectedStartsAtOnce)
{
  ImuBuffer imu;
  fill(imu, 9.0, 10.0, Eigen::Vector3d(0, 0, 9.81));
  StartupRule::Options o;
  o.expect_imu = false;
  StartupRule rule(o);
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  EXPECT_EQ(rule.decide(10.0, imu, up), D::START_WITHOUT_IMU);
  EXPECT_EQ(up, Eigen::Vector3d::Zero());
}

TEST(StartupRule, TimeGoingBackRestartsTheWait)
{
  ImuBuffer imu;
  StartupRule rule;
  Eigen::Vector3d up;
  EXPECT_EQ(rule.decide(10.0, imu, up), D::WAIT_FOR_IMU);
  EXPECT_EQ(rule.decide(5.0, imu, up), D::WAIT_FOR_IMU);  // bag loop: waits from 5.0 now
  EXPECT_EQ(rule.decide(5.9, imu, up), D::WAIT_FOR_IMU);
  EXPECT_EQ(rule.decide(6.0, imu, up), D::START_WITHOUT_IMU);
  rule.reset();
  EXPECT_EQ(rule.decide(7.0, imu, up), D::WAIT_FOR_IMU);
  EXPECT_DOUBLE_EQ(rule.waited(7.0), 0.0);
}
