#pragma once
// What vo/odom carries for one VoOutput, ROS-free: the nodelet's message (conversions.h,
// toOdometryMsg) and slam_benchmark's input to SLAM (assistive_slam/vo_adapter.h) both come from
// here, so SLAM sees the same VO output in the benchmark as on the device.
#include <Eigen/Geometry>
#include "assistive_vo/visual_odometry.h"

namespace assistive_vo
{
/// Variance (diagonal of pose.covariance and twist.covariance, off-diagonals 0) of a vo/odom
/// message whose pose is not trusted (VoOutput::pose_trusted false): rtabmap's "null odometry"
/// convention. Consumers must not guide on such a pose (README "Topics").
constexpr double kUntrustedVariance = 9999.0;

struct PublishedOdometry
{
  Eigen::Isometry3d T_odom_link = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> pose_covariance = Eigen::Matrix<double, 6, 6>::Zero();   ///< odom axes
  Eigen::Matrix<double, 6, 6> twist_covariance = Eigen::Matrix<double, 6, 6>::Zero();  ///< camera_link axes
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero(), angular_velocity = Eigen::Vector3d::Zero();
};

/// An untrusted output keeps its pose (the last trusted one) with kUntrustedVariance diagonals and
/// zero twist; a trusted one is published as it is.
inline PublishedOdometry published(const VoOutput& o)
{
  PublishedOdometry p;
  p.T_odom_link = o.T_odom_link;
  if (!o.pose_trusted)
  {
    p.pose_covariance.diagonal().setConstant(kUntrustedVariance);
    p.twist_covariance.diagonal().setConstant(kUntrustedVariance);
    return p;
  }
  p.pose_covariance = o.pose_covariance;
  p.twist_covariance = o.twist_covariance;
  p.linear_velocity = o.linear_velocity;
  p.angular_velocity = o.angular_velocity;
  return p;
}
}  // namespace assistive_vo
