#pragma once
// Keyframes (seed 3.2.3.3): one rectified stereo pair reduced to features with descriptors and
// their 3D points, with the VO's pose at the time and the pose the map gives it.
#include <cstdint>
#include <memory>
#include <vector>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include "assistive_slam/params.h"

namespace assistive_slam
{
/// Rectified stereo pair: left intrinsics and baseline (right camera at +baseline along x).
struct StereoModel
{
  double fx = 0, fy = 0, cx = 0, cy = 0, baseline = 0;
  bool valid() const { return fx > 0 && fy > 0 && baseline > 0; }
  /// Left pixel (u, v) and right column of a point in the left optical frame.
  Eigen::Vector3d project(const Eigen::Vector3d& X) const
  {
    return {fx * X.x() / X.z() + cx, fy * X.y() / X.z() + cy, fx * (X.x() - baseline) / X.z() + cx};
  }
};

struct Keyframe
{
  uint32_t id = 0;
  uint32_t submap = 0;
  double stamp = 0;
  Eigen::Isometry3d T_odom_cam = Eigen::Isometry3d::Identity();  ///< VO pose (optical frame in odom)
  Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();   ///< pose in the map (BA, pose graph)
  double path_m = 0;                      ///< distance walked (odom) at this keyframe
  std::vector<cv::KeyPoint> keypoints;    ///< left image
  std::vector<float> u_right;             ///< column of the stereo match in the right image
  cv::Mat descriptors;                    ///< one row per keypoint (ORB: CV_8U x 32)
  std::vector<Eigen::Vector3d> points;    ///< 3D point per keypoint, left optical frame
  std::vector<int64_t> landmark;          ///< landmark id per keypoint of the local BA (-1: none)
};
using KeyframePtr = std::shared_ptr<Keyframe>;

/// ORB in both images, matched along the rectified rows; only features with a stereo match and a
/// depth in [min_depth, max_depth] are kept (every keyframe feature has a 3D point).
class StereoFeatureExtractor
{
public:
  explicit StereoFeatureExtractor(const SlamParams& p = SlamParams());
  void extract(const cv::Mat& left, const cv::Mat& right, const StereoModel& cam, Keyframe& kf) const;

private:
  SlamParams p_;
  cv::Ptr<cv::ORB> orb_;
};

/// Decides when a frame becomes a keyframe: on a VO replenishment at least min distance / angle
/// from the last keyframe, or regardless once max distance / angle is exceeded.
class KeyframePolicy
{
public:
  explicit KeyframePolicy(const SlamParams& p = SlamParams()) : p_(p) {}
  bool take(const Eigen::Isometry3d& T_odom_cam, bool vo_replenished);
  void reset() { have_last_ = false; }

private:
  SlamParams p_;
  bool have_last_ = false;
  Eigen::Isometry3d last_ = Eigen::Isometry3d::Identity();
};

/// Rotation angle of a relative pose, degrees.
double angleDeg(const Eigen::Isometry3d& T);

}  // namespace assistive_slam
