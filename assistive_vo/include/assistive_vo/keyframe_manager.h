#pragma once
// VisualOdometry's keyframes (issue 32): when a new keyframe is due (too few tracks left, too
// little image covered, turned too far), what one starts with (the tracks carried on plus fresh
// FAST corners with stereo depth, FeatureTracker's line tracks) and the keyframe's store: its
// pose, covariance, the pose of the previous frame and the gyro's rotation since it. Motion is
// always estimated against the keyframe. ROS-free.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include "assistive_vo/feature_detector.h"
#include "assistive_vo/feature_tracker.h"
#include "assistive_vo/frame_stats.h"
#include "assistive_vo/params.h"
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
/// The current keyframe (w = the first optical frame of the run).
struct VoKeyframe
{
  Eigen::Isometry3d T_w_kf = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_kf_prev = Eigen::Isometry3d::Identity();  ///< the previous frame in the keyframe
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  ///< of T_w_kf
  double stamp = 0.0;
  // gyro since the keyframe (bias-corrected, optical axes)
  Eigen::Matrix3d R_gyro = Eigen::Matrix3d::Identity();
  bool gyro_since = false;  ///< every frame since the keyframe had the gyro
  Eigen::Matrix3d R_prev_vision = Eigen::Matrix3d::Identity();  ///< vision-only, keyframe -> previous frame
  Eigen::Vector3d gyro_rate = Eigen::Vector3d::Zero();  ///< the gyro's rate over the keyframe's frame (optical, rad/s)
  int tracks_started = 0;
  int cells_started = 0;  ///< grid cells holding a track when the keyframe started
};

class KeyframeManager
{
public:
  explicit KeyframeManager(const VoParams& p = VoParams(), const StereoCamera& cam = StereoCamera());
  void setParams(const VoParams& p);
  void setCamera(const StereoCamera& cam) { cam_ = cam; }
  /// Forgets the keyframe (the detector's threshold stays).
  void reset();
  /// The keyframe is no longer tracked (failure, new camera): a new one must be started.
  void invalidate() { valid_ = false; }
  /// A keyframe with enough features is being tracked.
  bool valid() const { return valid_; }
  const VoKeyframe& current() const { return kf_; }
  /// The FAST threshold the next detection starts from.
  int detectorThreshold() const { return detector_.threshold(); }

  /// A new keyframe at the current pose `T_w_cur` (covariance `cov_cur`, time `stamp`): the
  /// current tracks with a stereo match carried on (`from_current_tracks`), fresh corners with
  /// stereo depth up to target_features; the tracker's lines with them. valid() tells whether
  /// enough features were found.
  void start(const cv::Mat& left, const cv::Mat& right, bool from_current_tracks, FeatureTracker& tracker,
             const Eigen::Isometry3d& T_w_cur, const Eigen::Matrix<double, 6, 6>& cov_cur, double stamp,
             FrameStats& st);
  /// Time for a new keyframe: too few tracks left, too little image covered, turned too far.
  bool needed(const Eigen::Isometry3d& T_kf_cur, const FeatureTracker& tracker) const;

  /// The frame's motion was accepted: it is the previous frame of the next.
  void setPrevious(const Eigen::Isometry3d& T_kf_cur) { kf_.T_kf_prev = T_kf_cur; }
  /// The frame's vision-only rotation keyframe -> frame (the gyro check of the next frame).
  void setPreviousVisionRotation(const Eigen::Matrix3d& R) { kf_.R_prev_vision = R; }
  /// The gyro's rate over the keyframe's own frame interval (bias-corrected, optical axes, rad/s).
  void setGyroRate(const Eigen::Vector3d& w) { kf_.gyro_rate = w; }
  /// The gyro's rotation of this frame joins the keyframe's (none: the span has no gyro prior).
  void addGyro(bool have_gyro, const Eigen::Matrix3d& R_gyro_opt);

private:
  /// A keyframe track of a new corner with disparity `disp` (its pixel noise `sigma_scale` x
  /// pixel_sigma); false when its depth is out of range.
  bool newTrack(const FeatureTracker& tracker, const cv::Point2f& corner, float disp, double max_depth,
                double sigma_scale, PointTrack& n) const;
  /// Coarse corners (coarse_min_ratio) of the smoothed pair with stereo depth up to `max_depth`,
  /// appended to `kept` up to target_features; how many.
  int addCoarseCorners(const cv::Mat& left, const cv::Mat& right, FeatureTracker& tracker, double max_depth,
                       std::vector<PointTrack>& kept, FrameStats& st);

  VoParams p_;
  StereoCamera cam_;
  FeatureDetector detector_;
  bool valid_ = false;  ///< the tracker's tracks and pyramids are meaningful
  VoKeyframe kf_;
};
}  // namespace assistive_vo
