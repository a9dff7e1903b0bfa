#pragma once
#include <random>
#include <vector>
#include <Eigen/Geometry>
#include <Eigen/StdVector>
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
using Vec3List = std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>;
using Vec2List = std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>;

struct RansacResult
{
  bool ok = false;
  Eigen::Isometry3d T_ref_cur = Eigen::Isometry3d::Identity();  ///< maps current-frame coords to reference-frame coords
  std::vector<int> inliers;       ///< indices into the input
  double median_sq_error = 0;     ///< LMedS score of the best model (px^2)
  double threshold_px = 0;        ///< inlier threshold derived from the LMedS score
  int trials = 0;
};

struct RansacOptions
{
  double probability = 0.99;
  int max_trials = 300;
  int min_trials = 10;
  double threshold_max_px = 2.0;
  double threshold_min_px = 0.7;
};

/// Three-point absolute pose (OpenGV's Kneip P3P) in RANSAC, each hypothesis scored by the median
/// of squared reprojection errors (LMedS), the trial count adapted by eq. 2.18:
/// k = log(1-p) / log(1-w^3), w re-estimated from the best model so far.
/// Points are 3D in the reference frame, pixels are observed in the current left image.
class P3PRansac
{
public:
  explicit P3PRansac(unsigned seed = 42) : rng_(seed) {}
  RansacResult estimate(const StereoCamera& cam, const Vec3List& points_ref, const Vec2List& pixels_cur,
                        const RansacOptions& opt,
                        const Eigen::Isometry3d* prior_T_ref_cur = nullptr);

  /// Squared reprojection error (px^2) of each point under T_ref_cur (huge when behind the camera).
  static void reprojectionErrors(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur,
                                 const Vec3List& points_ref, const Vec2List& pixels_cur,
                                 std::vector<double>& sq_err);
  /// eq. 2.18
  static int trialCount(double p, double w, int n, int max_trials);

private:
  std::mt19937 rng_;
  std::vector<double> err_, tmp_;
};
}  // namespace assistive_vo
