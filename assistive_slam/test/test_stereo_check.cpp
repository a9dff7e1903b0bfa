// The geometric check of a query keyframe against keyframes with 3D points (stereo_check.h):
// exact synthetic keyframes (points, their pixels and right columns, one random ORB descriptor per
// point shared by both views), with the query's rotation free (P3P) or known (after a VO loss).
#include <random>
#include <gtest/gtest.h>
#include "assistive_slam/stereo_check.h"
#include "synthetic_camera.h"

using namespace assistive_slam;
using slam_test::camera;

namespace stereo_check_test
{
Eigen::Isometry3d pose(double yaw_deg, const Eigen::Vector3d& t)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();  // optical y: down
  T.translation() = t;
  return T;
}

/// The view of `world` points from a camera at T_world_cam: those in front and inside the image.
/// `outliers` of the query's features get a descriptor of another point (a wrong match).
Keyframe view(const std::vector<Eigen::Vector3d>& world, const cv::Mat& desc, const Eigen::Isometry3d& T_world_cam,
              int outliers = 0)
{
  const StereoModel c = camera();
  Keyframe k;
  k.T_map_cam = k.T_odom_cam = T_world_cam;
  for (size_t i = 0; i < world.size(); ++i)
  {
    const Eigen::Vector3d X = T_world_cam.inverse() * world[i];
    if (X.z() < 0.5)
      continue;
    const Eigen::Vector3d uvr = c.project(X);
    if (uvr.x() < 0 || uvr.x() >= 640 || uvr.y() < 0 || uvr.y() >= 480)
      continue;
    k.keypoints.emplace_back(cv::Point2f(float(uvr.x()), float(uvr.y())), 31.f);
    k.u_right.push_back(float(uvr.z()));
    k.points.push_back(X);
    k.landmark.push_back(-1);
    k.descriptors.push_back(desc.row(int(i)));
  }
  for (int j = 0; j < outliers && j + 1 < k.descriptors.rows; j += 1)
  {
    cv::Mat a = k.descriptors.row(2 * j % k.descriptors.rows).clone();
    k.descriptors.row((2 * j + 1) % k.descriptors.rows).copyTo(k.descriptors.row(2 * j % k.descriptors.rows));
    a.copyTo(k.descriptors.row((2 * j + 1) % k.descriptors.rows));
  }
  return k;
}

struct Scene
{
  std::vector<Eigen::Vector3d> world;
  cv::Mat desc;
  explicit Scene(int n, uint32_t seed)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> x(-3.0, 3.0), y(-1.5, 1.0), z(2.0, 15.0);
    std::uniform_int_distribution<int> byte(0, 255);
    desc.create(n, 32, CV_8U);
    for (int i = 0; i < n; ++i)
    {
      world.emplace_back(x(rng), y(rng), z(rng));
      for (int b = 0; b < 32; ++b)
        desc.at<uint8_t>(i, b) = uint8_t(byte(rng));
    }
  }
};
}  // namespace stereo_check_test
using namespace stereo_check_test;

TEST(StereoCheck, KnownRotationGivesTheExactPosition)
{
  const Scene s(80, 3);
  const Eigen::Isometry3d Ta = pose(0, Eigen::Vector3d::Zero()), Tb = pose(12, Eigen::Vector3d(0.4, 0.05, 0.9));
  const Keyframe a = view(s.world, s.desc, Ta), b = view(s.world, s.desc, Tb, 10);  // 10 swapped pairs: 20 wrong
  ASSERT_GE(b.keypoints.size(), 40u);
  StereoCheckOptions o;
  o.min_inliers = 15;
  o.R_ref_b = Tb.linear();
  const StereoCheckResult r = localMapCheck({ { &a, Ta } }, b, camera(), o);
  ASSERT_TRUE(r.accepted);
  EXPECT_NEAR((r.T_a_b.translation() - Tb.translation()).norm(), 0.0, 1e-6);
  EXPECT_NEAR(angleDeg(r.T_a_b.inverse() * Tb), 0.0, 1e-9);  // the rotation given is kept
  EXPECT_EQ(r.inliers, static_cast<int>(b.keypoints.size()) - 20);
  // The free check (P3P) finds the same pose on exact data.
  o.R_ref_b.reset();
  const StereoCheckResult p = localMapCheck({ { &a, Ta } }, b, camera(), o);
  ASSERT_TRUE(p.accepted);
  EXPECT_NEAR((p.T_a_b.translation() - Tb.translation()).norm(), 0.0, 1e-3);
}

TEST(StereoCheck, AWrongKnownRotationIsRejected)
{
  // The position alone cannot make up for a rotation 5 deg off: no pose fits the matches, so
  // nothing is accepted (the gyro's rotation is trusted, not bent to a look-alike).
  const Scene s(80, 4);
  const Eigen::Isometry3d Ta = pose(0, Eigen::Vector3d::Zero()), Tb = pose(-8, Eigen::Vector3d(-0.3, 0.0, 1.2));
  const Keyframe a = view(s.world, s.desc, Ta), b = view(s.world, s.desc, Tb);
  StereoCheckOptions o;
  o.min_inliers = 15;
  o.R_ref_b = pose(-3, Eigen::Vector3d::Zero()).linear();
  EXPECT_FALSE(localMapCheck({ { &a, Ta } }, b, camera(), o).accepted);
  o.R_ref_b = Tb.linear();
  EXPECT_TRUE(localMapCheck({ { &a, Ta } }, b, camera(), o).accepted);
}
