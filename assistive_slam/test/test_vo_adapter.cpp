// VoAdapter: the VO's output into SlamFrames, the one path of the nodelet and slam_benchmark
// (issue 32), against hand-computed answers.
#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include "assistive_slam/vo_adapter.h"

namespace vo_adapter_test  // named: the core's tests are one unity build
{
using namespace assistive_slam;

/// camera_link <- left optical frame (x_link = z_opt, y_link = -x_opt, z_link = -y_opt), as the URDF.
Eigen::Isometry3d linkOptical()
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return T;
}

VoOdometry odom(double stamp, double variance)
{
  VoOdometry o;
  o.stamp = stamp;
  o.T_odom_link = Eigen::Translation3d(1.0, 2.0, 1.6) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ());
  o.position_variance = variance;
  o.twist_covariance = Eigen::Matrix<double, 6, 1>(1, 2, 3, 4, 5, 6).asDiagonal();
  return o;
}

TEST(VoAdapter, PoseTrustAndTheOpticalFrame)
{
  VoAdapter a(1000.0, linkOptical());
  const cv::Mat img(4, 4, CV_8U, cv::Scalar(7));
  SlamFrame f = a.frame(odom(10.0, 0.01), img, img);
  EXPECT_EQ(f.stamp, 10.0);
  EXPECT_TRUE(f.pose_trusted);
  EXPECT_TRUE(f.vo_replenished);  // vo/odom does not say: keyframes by distance / angle
  EXPECT_EQ(f.left.data, img.data);  // not copied here
  EXPECT_TRUE(f.T_odom_cam.isApprox(odom(10.0, 0.01).T_odom_link * linkOptical(), 1e-15));
  // the optical z axis is camera_link's x: forward
  EXPECT_TRUE((f.T_odom_cam.linear() * Eigen::Vector3d::UnitZ())
                  .isApprox(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX(), 1e-15));
  EXPECT_FALSE(a.frame(odom(10.1, 9999.0), img, img).pose_trusted);  // assistive_vo's untrusted variance
  EXPECT_FALSE(a.frame(odom(10.2, 1000.0), img, img).pose_trusted);  // the threshold itself
  VoOdometry nan = odom(10.3, 0.01);
  nan.T_odom_link.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(a.frame(nan, img, img).pose_trusted);
}

TEST(VoAdapter, TwistCovarianceOverTheFrameIntervalInOpticalAxes)
{
  VoAdapter a(1000.0, linkOptical());
  const cv::Mat img;
  SlamFrame f = a.frame(odom(5.0, 0.01), img, img);
  EXPECT_TRUE(f.vo_covariance.isZero(0.0)) << "no interval before the first frame";
  f = a.frame(odom(5.1, 0.01), img, img);
  // link (vx vy vz wx wy wz) variances 1..6 -> optical x = -y_link, y = -z_link, z = x_link; times dt^2
  const Eigen::Matrix<double, 6, 1> expect = 0.01 * Eigen::Matrix<double, 6, 1>(2, 3, 1, 5, 6, 4);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      EXPECT_NEAR(f.vo_covariance(i, j), i == j ? expect(i) : 0.0, 1e-15) << i << "," << j;
  EXPECT_TRUE(a.frame(odom(4.0, 0.01), img, img).vo_covariance.isZero(0.0)) << "time went back";
  VoOdometry inf = odom(4.1, 0.01);
  inf.twist_covariance(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(a.frame(inf, img, img).vo_covariance.isZero(0.0)) << "not finite";
  f = a.frame(odom(4.3, 0.01), img, img);
  EXPECT_NEAR(f.vo_covariance(2, 2), 0.04, 1e-15);  // from the previous frame given, whatever it was
}
}  // namespace vo_adapter_test
