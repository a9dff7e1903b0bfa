#pragma once
// Motion refinement over points and lines together (motion_solver points_lines): the point+line
// RANSAC's hypothesis (an algebraic, trifocal solution) refined by Gauss-Newton / Levenberg-
// Marquardt on the geometric error of all its inliers: stereo reprojection of the points (left u,
// v, right u) and, for each line, the distance of the current left and right segment ends to the
// projection of the 3D line triangulated in the reference (keyframe) pair. The structure stays
// fixed (6 unknowns): the bundle adjustment refines points only, and with few points it was
// the lines' information that it dropped. ROS-free (Eigen).
#include <vector>
#include <Eigen/Geometry>
#include "assistive_vo/bundle_adjustment.h"
#include "assistive_vo/line_detector.h"
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
/// A line of the reference pair (two 3D points on it, reference optical frame) and its segment
/// in the current left and right images (px).
struct StereoLineObservation
{
  Eigen::Vector3d P = Eigen::Vector3d::Zero(), Q = Eigen::Vector3d::Zero();
  Eigen::Vector2d left_p = Eigen::Vector2d::Zero(), left_q = Eigen::Vector2d::Zero();
  Eigen::Vector2d right_p = Eigen::Vector2d::Zero(), right_q = Eigen::Vector2d::Zero();
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
using StereoLineObservations = std::vector<StereoLineObservation, Eigen::aligned_allocator<StereoLineObservation>>;

/// The 3D line of a stereo segment pair of a rectified rig: each left end point at the disparity
/// of the right segment's line on its row. False when a disparity is below `min_disparity` (or the
/// right segment is horizontal: no row-wise correspondence).
bool triangulateStereoSegment(const StereoCamera& cam, const LineSegment& left, const LineSegment& right,
                              double min_disparity, Eigen::Vector3d& P, Eigen::Vector3d& Q);

struct PointLineRefineOptions
{
  int iterations = 10;
  double huber_px = 1.0;
  double pixel_sigma_px = 0.5;  ///< for the covariance
  /// Optional rotation prior (the integrated gyro): R_ref_cur ~ rotation_prior, information
  /// rotation_prior_weight (px^2 / rad^2), as TwoFrameBundleAdjuster::Options.
  bool use_rotation_prior = false;
  Eigen::Matrix3d rotation_prior = Eigen::Matrix3d::Identity();
  double rotation_prior_weight = 0.0;
  /// Optional translation prior (a motion model's prediction): the translation of T_ref_cur ~
  /// translation_prior, information translation_prior_weight (px^2 / m^2). Lines of one plane
  /// leave directions free (vertical lines: the motion along them); the prior holds those.
  bool use_translation_prior = false;
  Eigen::Vector3d translation_prior = Eigen::Vector3d::Zero();
  double translation_prior_weight = 0.0;
};

/// Refines T_ref_cur from `points_ref` (reference frame) seen at `obs_cur` (ur < 0: no right
/// observation) and `lines`. The result's covariance has BundleAdjustmentResult's convention.
/// !ok (and the initial motion) when the system is degenerate or the inputs not finite.
BundleAdjustmentResult refineMotionPointsLines(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur_init,
                                               const Vec3List& points_ref,
                                               const std::vector<StereoObservation>& obs_cur,
                                               const StereoLineObservations& lines,
                                               const PointLineRefineOptions& opt);
}  // namespace assistive_vo
