#pragma once
// VisualOdometry's refinement (issue 32): the RANSAC's motion refined over its inliers, the
// two-frame sparse bundle adjustment on the corners (TwoFrameBundleAdjuster) or, for a point+line
// motion, the points and lines together (refineMotionPointsLines) with the predicted motion as a
// prior; then again with the gyro's rotation since the keyframe as a rotation prior. ROS-free.
#include <Eigen/Geometry>
#include "assistive_vo/bundle_adjustment.h"
#include "assistive_vo/feature_tracker.h"
#include "assistive_vo/frame_stats.h"
#include "assistive_vo/motion_estimator.h"
#include "assistive_vo/params.h"
#include "assistive_vo/pointline_refine.h"
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
/// What the refinement knows of the motion besides the tracks.
struct MotionPrior
{
  Eigen::Isometry3d T_kf_pred = Eigen::Isometry3d::Identity();  ///< predicted motion keyframe -> current
  Eigen::Isometry3d T_kf_prev = Eigen::Isometry3d::Identity();  ///< the previous frame in the keyframe
  bool gyro = false;  ///< the second pass with the gyro's rotation as a prior
  Eigen::Matrix3d R_kf_gyro = Eigen::Matrix3d::Identity();  ///< the gyro's rotation keyframe -> current (optical)
  double gyro_variance = 1.0;  ///< its variance per axis (rad^2)
};

class MotionRefiner
{
public:
  explicit MotionRefiner(const VoParams& p = VoParams(), const StereoCamera& cam = StereoCamera());
  void setParams(const VoParams& p) { p_ = p; }
  void setCamera(const StereoCamera& cam) { cam_ = cam; }

  /// Refines `m` (its RANSAC result) over the inliers: sets X_in, br, R_vision (vision only),
  /// cov_vision, T_kf_cur and T_prev_cur (and lines_only for a point+line motion).
  void refine(const FeatureTracker& tracker, const MotionPrior& prior, FrameStats& st, MotionEstimate& m);

private:
  /// The point+line motion: refined on the point and the line inliers together (structure fixed).
  void refinePointsLines(const FeatureTracker& tracker, const MotionPrior& prior,
                         const std::vector<StereoObservation>& ocur, MotionEstimate& m) const;

  VoParams p_;
  StereoCamera cam_;
  TwoFrameBundleAdjuster ba_;
};
}  // namespace assistive_vo
