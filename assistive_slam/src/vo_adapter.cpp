#include "assistive_slam/vo_adapter.h"

namespace assistive_slam
{
SlamFrame VoAdapter::frame(const VoOdometry& o, const cv::Mat& left, const cv::Mat& right)
{
  SlamFrame f;
  f.stamp = o.stamp;
  f.left = left;
  f.right = right;
  f.T_odom_cam = o.T_odom_link * T_link_optical_;
  // The VO marks an untrusted pose by a huge covariance: no keyframe from it.
  f.pose_trusted = o.position_variance < untrusted_variance_ && o.T_odom_link.matrix().allFinite();
  f.vo_replenished = true;
  const double dt = f.stamp - prev_stamp_;
  if (prev_stamp_ > 0 && dt > 0)
  {
    Matrix6d A = Matrix6d::Zero();
    A.topLeftCorner<3, 3>() = T_link_optical_.linear().transpose();
    A.bottomRightCorner<3, 3>() = T_link_optical_.linear().transpose();
    f.vo_covariance = A * o.twist_covariance * A.transpose() * (dt * dt);
    if (!f.vo_covariance.allFinite())
      f.vo_covariance.setZero();
  }
  prev_stamp_ = f.stamp;
  return f;
}
}  // namespace assistive_slam
