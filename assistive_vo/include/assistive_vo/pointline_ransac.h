#pragma once
// RANSAC over mixed point and line correspondences with the quaternion trifocal solver
// (seed 2.2.3; its real-data runs use quaternion-5): random samples of `sample_size` features
// (any mix; sets the solver refuses are skipped), every real solution scored by the four-view
// reprojection error of all features (inliers below the threshold), the trial count adapted by
// eq. 2.18 with n = sample_size; the best model re-solved from all its inliers (over-determined).
// ROS-free.
#include <random>
#include <vector>
#include "assistive_vo/trifocal_solver.h"

namespace assistive_vo
{
struct PointLineRansacOptions
{
  int sample_size = 5;         ///< features per hypothesis (3 minimal, 4-5 over-determined)
  double threshold_px = 1.5;   ///< four-view reprojection error of an inlier
  double focal_px = 500.0;     ///< converts normalised errors to px
  double probability = 0.99;   ///< p of eq. 2.18
  int max_trials = 300;
};

struct PointLineRansacResult
{
  bool ok = false;
  StereoMotion motion;
  std::vector<int> point_inliers, line_inliers;  ///< indices into the inputs
  int trials = 0;
};

class PointLineRansac
{
public:
  explicit PointLineRansac(unsigned seed = 42) : rng_(seed) {}
  PointLineRansacResult estimate(const StereoRig& rig, const PointQuads& points, const LineQuads& lines,
                                 const PointLineRansacOptions& opt);

private:
  std::mt19937 rng_;
};
}  // namespace assistive_vo
