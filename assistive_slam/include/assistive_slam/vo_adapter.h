#pragma once
// SLAM takes the VO's output through this one adapter (issue 32): the nodelet from vo/odom
// (nav_msgs/Odometry, the same stamp as the images), slam_benchmark from the VO front end in the
// same process; both get the same SlamFrame for the same VO output.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include "assistive_slam/slam_system.h"

namespace assistive_slam
{
/// What vo/odom carries for one frame (assistive_vo README "Published topics"): an untrusted pose
/// has a position variance of assistive_vo's kUntrustedVariance (9999) and the last trusted pose.
struct VoOdometry
{
  double stamp = 0;
  Eigen::Isometry3d T_odom_link = Eigen::Isometry3d::Identity();
  double position_variance = 0;                ///< the pose covariance's first diagonal (m^2)
  Matrix6d twist_covariance = Matrix6d::Zero();  ///< camera_link axes (vx vy vz wx wy wz)
};

class VoAdapter
{
public:
  /// `untrusted_variance`: a position variance this large marks the VO pose untrusted
  /// (SlamNodeParams::untrusted_variance); `T_link_optical`: the left optical frame in camera_link.
  VoAdapter(double untrusted_variance, const Eigen::Isometry3d& T_link_optical)
    : untrusted_variance_(untrusted_variance), T_link_optical_(T_link_optical)
  {
  }
  /// The SlamFrame of one VO output and its rectified mono8 pair. The odometry does not say when
  /// the VO replenished its tracks: every frame counts as replenished and keyframes come by
  /// distance / angle (KeyframePolicy). Q_t of the fastslam backend: the VO's twist covariance
  /// over the interval since the previous frame given here, in the optical frame's axes (zero on
  /// the first frame, after time went back, or when not finite).
  SlamFrame frame(const VoOdometry& o, const cv::Mat& left, const cv::Mat& right);
  const Eigen::Isometry3d& linkOptical() const { return T_link_optical_; }

private:
  double untrusted_variance_;
  Eigen::Isometry3d T_link_optical_;
  double prev_stamp_ = -1.0;
};
}  // namespace assistive_slam
