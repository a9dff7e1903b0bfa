#pragma once
#include <Eigen/Geometry>

namespace assistive_vo
{
/// Rotation camera_link <- optical frame (x_link = z_opt, y_link = -x_opt, z_link = -y_opt).
inline Eigen::Matrix3d R_link_optical()
{
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return R;
}

/// Start pose of camera_link in odom (REP-105, README "Interfaces"): gravity-aligned, yaw 0,
/// origin on the floor under the camera. `up_link` is the measured "up" direction in camera_link
/// (the accelerometer's specific force at rest), any length.
inline Eigen::Isometry3d startPoseFromUp(const Eigen::Vector3d& up_link, double height)
{
  const Eigen::Vector3d u = up_link.normalized();
  const double roll = std::atan2(u.y(), u.z());
  const double pitch = std::atan2(-u.x(), std::hypot(u.y(), u.z()));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX())).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0, 0, height);
  return T;
}

inline Eigen::Isometry3d startPoseFromRollPitch(double roll, double pitch, double height)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX())).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0, 0, height);
  return T;
}
}  // namespace assistive_vo
