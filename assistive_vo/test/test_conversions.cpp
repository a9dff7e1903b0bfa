#include <gtest/gtest.h>
#include "assistive_vo/conversions.h"
#include "assistive_vo/frames.h"

using namespace assistive_vo;

TEST(Conversions, CameraInfoRoundTrip)
{
  StereoCamera c;
  c.fx = 510.5; c.fy = 509.0; c.cx = 320.2; c.cy = 241.7; c.baseline = 0.12; c.width = 640; c.height = 480;
  sensor_msgs::CameraInfo l, r;
  toMsg(c, l, r);
  EXPECT_DOUBLE_EQ(r.P[3], -510.5 * 0.12);
  StereoCamera d;
  std::string err;
  ASSERT_TRUE(fromMsg(l, r, d, &err)) << err;
  EXPECT_DOUBLE_EQ(d.fx, c.fx);
  EXPECT_DOUBLE_EQ(d.fy, c.fy);
  EXPECT_DOUBLE_EQ(d.cx, c.cx);
  EXPECT_DOUBLE_EQ(d.cy, c.cy);
  EXPECT_NEAR(d.baseline, c.baseline, 1e-15);
  EXPECT_EQ(d.width, 640);
  EXPECT_EQ(d.height, 480);
}

TEST(Conversions, RejectsBadCameraInfo)
{
  StereoCamera c;
  c.fx = c.fy = 500; c.cx = 319.5; c.cy = 239.5; c.baseline = 0.12; c.width = 640; c.height = 480;
  sensor_msgs::CameraInfo l, r;
  StereoCamera d;
  std::string err;
  EXPECT_FALSE(fromMsg(l, r, d, &err));  // empty (missing) camera_info
  EXPECT_FALSE(err.empty());
  toMsg(c, l, r);
  r.P[3] = 0;  // no baseline
  EXPECT_FALSE(fromMsg(l, r, d, &err));
  toMsg(c, l, r);
  r.width = 320;  // size mismatch
  EXPECT_FALSE(fromMsg(l, r, d, &err));
  toMsg(c, l, r);
  l.P[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(fromMsg(l, r, d, &err));
}

TEST(Conversions, OdometryRoundTrip)
{
  VoOutput o;
  o.pose_valid = o.pose_trusted = true;
  o.T_odom_link = Eigen::Translation3d(1.0, -2.0, 1.6) * Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 0.1, 1).normalized());
  o.linear_velocity = Eigen::Vector3d(0.9, 0.0, 0.1);
  o.angular_velocity = Eigen::Vector3d(0.0, 0.0, 0.5);
  o.pose_covariance.setIdentity();
  o.pose_covariance(0, 5) = o.pose_covariance(5, 0) = 0.25;
  const nav_msgs::Odometry m = toOdometryMsg(o, ros::Time(12.5), "odom", "camera_link");
  EXPECT_EQ(m.header.frame_id, "odom");
  EXPECT_EQ(m.child_frame_id, "camera_link");
  EXPECT_DOUBLE_EQ(m.header.stamp.toSec(), 12.5);
  EXPECT_TRUE(poseFromMsg(m.pose.pose).isApprox(o.T_odom_link, 1e-12));
  EXPECT_DOUBLE_EQ(m.twist.twist.linear.x, 0.9);
  EXPECT_DOUBLE_EQ(m.twist.twist.angular.z, 0.5);
  EXPECT_DOUBLE_EQ(m.pose.covariance[5], 0.25);
  EXPECT_DOUBLE_EQ(m.pose.covariance[30], 0.25);
  EXPECT_DOUBLE_EQ(m.pose.covariance[7], 1.0);
  const geometry_msgs::TransformStamped t = toTransformMsg(o.T_odom_link, m.header.stamp, "odom", "camera_link");
  EXPECT_DOUBLE_EQ(t.transform.translation.y, -2.0);
  EXPECT_EQ(t.child_frame_id, "camera_link");
}

TEST(Conversions, UntrustedOdometryHasNullCovarianceAndNoTwist)
{
  VoOutput o;
  o.pose_valid = true;
  o.pose_trusted = false;  // e.g. lost beyond the coast limit: the last trusted pose
  o.T_odom_link = Eigen::Translation3d(1.0, -2.0, 1.6) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ());
  o.linear_velocity = Eigen::Vector3d(0.9, 0.0, 0.1);
  o.pose_covariance.setConstant(0.5);
  o.twist_covariance.setConstant(0.5);
  const nav_msgs::Odometry m = toOdometryMsg(o, ros::Time(3.0), "odom", "camera_link");
  EXPECT_TRUE(poseFromMsg(m.pose.pose).isApprox(o.T_odom_link, 1e-12));
  EXPECT_EQ(m.twist.twist.linear.x, 0.0);
  EXPECT_EQ(m.twist.twist.angular.z, 0.0);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
    {
      const size_t k = static_cast<size_t>(i * 6 + j);
      EXPECT_EQ(m.pose.covariance[k], i == j ? kUntrustedVariance : 0.0) << i << "," << j;
      EXPECT_EQ(m.twist.covariance[k], i == j ? kUntrustedVariance : 0.0) << i << "," << j;
    }
  EXPECT_EQ(kUntrustedVariance, 9999.0);  // the chain's contract (README "Topics")
}
