#pragma once
// VisualOdometry's pose estimation (issue 32): the frame's motion against its keyframe from the
// tracked corners (P3P RANSAC with a least-median-of-squares score) or, where corners are few and
// stereo line tracks exist, from points and lines (the trifocal point+line RANSAC, seed 2.2.2).
// The glue between FeatureTracker's tracks and the minimal solvers. ROS-free.
#include <Eigen/Geometry>
#include "assistive_vo/bundle_adjustment.h"
#include "assistive_vo/feature_tracker.h"
#include "assistive_vo/frame_stats.h"
#include "assistive_vo/p3p_ransac.h"
#include "assistive_vo/params.h"
#include "assistive_vo/pointline_ransac.h"
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
/// Motion of the current frame against the keyframe (the RANSAC, then the refinement).
struct MotionEstimate
{
  RansacResult rr;
  BundleAdjustmentResult br;
  Vec3List X_in;  ///< the inliers' keyframe points, refined by the bundle adjustment
  Eigen::Matrix3d R_vision = Eigen::Matrix3d::Identity();  ///< vision-only rotation keyframe -> current
  Eigen::Matrix<double, 6, 6> cov_vision = Eigen::Matrix<double, 6, 6>::Identity();
  Eigen::Isometry3d T_kf_cur = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_prev_cur = Eigen::Isometry3d::Identity();
  double dt_kf = 0.0;  ///< time since the keyframe
  /// Variance (rad^2 per axis) of the gyro's rotation since the keyframe from its timing against
  /// the images (gyro_time_sigma x the rate change since the keyframe)
  double gyro_timing_var = 0.0;
  bool with_lines = false;  ///< from the point+line RANSAC (refined on points and lines)
  bool lines_only = false;  ///< refined on the lines (and the motion prior) alone: too few points to check
};

class MotionEstimator
{
public:
  explicit MotionEstimator(const VoParams& p = VoParams(), const StereoCamera& cam = StereoCamera());
  void setParams(const VoParams& p);
  void setCamera(const StereoCamera& cam) { cam_ = cam; }

  /// The frame's motion against the keyframe (`T_kf_pred`: predicted): P3P, or the point+line
  /// RANSAC where few corners and stereo line tracks are (with the IMU, `have_imu`: the points
  /// first, the lines where they fail); the point+line RANSAC keeps only its line inliers in
  /// `tracker`. False: too few inliers.
  bool estimate(const Eigen::Isometry3d& T_kf_pred, bool have_imu, FeatureTracker& tracker, FrameStats& st,
                MotionEstimate& m);

private:
  /// P3P RANSAC (LMedS) against the keyframe's 3D points; false: too few inliers.
  bool estimatePoints(const Eigen::Isometry3d& T_kf_pred, const FeatureTracker& tracker, FrameStats& st,
                      MotionEstimate& m);
  /// Trifocal point+line RANSAC over the tracks with a stereo match now and the stereo line
  /// tracks; tracks without one join the inliers by their left reprojection.
  bool estimatePointsLines(FeatureTracker& tracker, FrameStats& st, MotionEstimate& m);

  VoParams p_;
  StereoCamera cam_;
  bool pointline_ = false;  ///< motion_solver is pointline
  P3PRansac ransac_;
  PointLineRansac pl_ransac_;
};
}  // namespace assistive_vo
