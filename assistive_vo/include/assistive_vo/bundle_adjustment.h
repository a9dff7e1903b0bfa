#pragma once
#include <vector>
#include <Eigen/Geometry>
#include "assistive_vo/p3p_ransac.h"
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
/// One point seen by two stereo frames: reference (fixed, defines the gauge) and current.
/// uR < 0 means "no right-image observation".
struct StereoObservation
{
  double u = 0, v = 0, ur = -1;
  double sigma_scale = 1.0;  ///< its pixel noise in units of Options::pixel_sigma_px
};

struct BundleAdjustmentResult
{
  bool ok = false;
  Eigen::Isometry3d T_ref_cur = Eigen::Isometry3d::Identity();
  double initial_cost = 0, final_cost = 0;  ///< robust cost, px^2
  int iterations = 0;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();  ///< of the
  ///< current pose as a left perturbation of T_cur_ref, order (tx ty tz rx ry rz), in the current frame
};

/// Two-frame sparse bundle adjustment (seed 2.1.4.2): Levenberg-Marquardt over the 6-dof motion
/// and the 3D points, stereo reprojection residuals (left u, v and right u) in both frames,
/// Huber weights, the point blocks eliminated by the Schur complement (3x3 per point, 6x6 reduced).
class TwoFrameBundleAdjuster
{
public:
  struct Options
  {
    int iterations = 8;
    double huber_px = 1.0;
    double pixel_sigma_px = 0.5;
    bool refine_points = true;
    /// Optional rotation prior (e.g. the integrated gyro): R_ref_cur ~ rotation_prior with
    /// information rotation_prior_weight (px^2 / rad^2, i.e. pixel_sigma^2 / sigma_rot^2).
    bool use_rotation_prior = false;
    Eigen::Matrix3d rotation_prior = Eigen::Matrix3d::Identity();
    double rotation_prior_weight = 0.0;
  };

  /// points_ref are refined in place when refine_points.
  BundleAdjustmentResult optimize(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur_init,
                                  Vec3List& points_ref, const std::vector<StereoObservation>& obs_ref,
                                  const std::vector<StereoObservation>& obs_cur, const Options& opt) const;

  /// Robust cost of a solution (sum of Huber-weighted squared residuals, px^2).
  static double cost(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur, const Vec3List& points_ref,
                     const std::vector<StereoObservation>& obs_ref,
                     const std::vector<StereoObservation>& obs_cur, double huber_px);
};
}  // namespace assistive_vo
