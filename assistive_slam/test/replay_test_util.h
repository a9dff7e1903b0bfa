// Helpers of the SLAM rostests that replay a rendered bag (test_slam_places, test_slam_fastslam):
// the bag's truth, truth lookup by stamp, SE3-aligned ATE, spinning on the wall clock.
#pragma once
#include <cmath>
#include <map>
#include <string>
#include <vector>
#include <Eigen/Geometry>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2_eigen/tf2_eigen.h>

namespace replay_test
{
inline Eigen::Isometry3d toEigen(const geometry_msgs::Pose& p)
{
  Eigen::Isometry3d T;
  tf2::fromMsg(p, T);
  return T;
}

/// The bag's /ground_truth/odom poses (left optical frame in world) by stamp.
inline std::map<double, Eigen::Isometry3d> readTruth(const std::string& bag_path)
{
  std::map<double, Eigen::Isometry3d> truth;
  rosbag::Bag bag(bag_path);
  for (const auto& m : rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{"/ground_truth/odom"})))
  {
    auto o = m.instantiate<nav_msgs::Odometry>();
    truth[o->header.stamp.toSec()] = toEigen(o->pose.pose);
  }
  return truth;
}

/// The pose at stamp t (the frames' own stamps), or false.
inline bool truthAt(const std::map<double, Eigen::Isometry3d>& truth, double t, Eigen::Isometry3d* T)
{
  auto it = truth.lower_bound(t - 1e-4);
  if (it == truth.end() || std::abs(it->first - t) > 1e-3)
    return false;
  *T = it->second;
  return true;
}

/// SE3 fit (no scale) of est onto truth; RMS of the residual positions.
inline double ate(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt, Eigen::Isometry3d* A)
{
  Eigen::Matrix3Xd a(3, est.size()), b(3, gt.size());
  for (size_t i = 0; i < est.size(); ++i)
  {
    a.col(static_cast<long>(i)) = est[i];
    b.col(static_cast<long>(i)) = gt[i];
  }
  A->matrix() = Eigen::umeyama(a, b, false);
  double s = 0;
  for (size_t i = 0; i < est.size(); ++i)
    s += ((*A) * est[i] - gt[i]).squaredNorm();
  return std::sqrt(s / static_cast<double>(est.size()));
}

inline void spinFor(double wall_s)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(wall_s);
  while (ros::ok() && ros::WallTime::now() < end)
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
}
}  // namespace replay_test
