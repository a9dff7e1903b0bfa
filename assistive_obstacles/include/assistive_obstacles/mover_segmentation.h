#pragma once
// Moving points (issue 22): 3D scene flow against the VO's ego-motion, clustered on the ground
// plane into mover detections. ROS-free; not wired into the nodelet yet.
//
// A point seen in two frames (stereo depth in each, matched by a tracked feature) is static when
// the ego-motion explains its motion: p_cur = T_cur_prev * p_prev. The residual
// r = p_cur - T_cur_prev * p_prev of a static point is stereo noise, which is anisotropic:
// along the current viewing ray it is the depth error, sigma_Z = Z^2 * disparity_sigma / (fx * B)
// in each frame (scaled by range / Z to the ray); across the ray it is the feature's pixel error,
// range * pixel_sigma / fx in each frame. A point is moving when |r| > min_residual and
//   (r_ray / s_ray)^2 + (|r_across| / s_across)^2 > sigma_scale^2,
// s_ray = sqrt(s_Z(prev)^2 + s_Z(cur)^2), s_across likewise. So a person crossing the view is
// found at any range from one frame to the next, but one walking along the ray only when the step
// between the two frames exceeds ~sigma_scale * sqrt(2) * sigma_Z (0.19 m at 3 m with the
// defaults): the caller may pair points over several frames (prev = k frames ago).
// Moving points are put into the world frame, binned into ground-plane cells, and 8-connected
// cells form one mover.
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

namespace assistive_obstacles
{
/// Defaults are the simulator's rig (500 px, 12 cm) and ObstaclesParams' disparity_sigma.
struct MoverSegmentationParams
{
  double fx = 500.0;              ///< px, full-resolution focal length
  double baseline = 0.12;         ///< m
  double disparity_sigma = 0.3;   ///< px, stereo disparity noise (as ObstaclesParams::disparity_sigma)
  double pixel_sigma = 0.5;       ///< px, a tracked feature's localisation error (across the ray)
  double sigma_scale = 3.0;       ///< moving when the residual exceeds this many sigmas (ellipsoid above) ...
  double min_residual = 0.05;     ///< m, ... and this (VO drift and feature localisation between frames)
  double cell_size = 0.2;         ///< m, ground-plane bins for clustering
  int min_cell_points = 1;        ///< bins with fewer moving points are ignored (isolated outliers)
  int min_cluster_points = 5;     ///< clusters with fewer moving points are no mover
  double footprint_margin = 0.1;  ///< m, added to a mover's radius for MoverDetection::radius
};

/// One point's scene flow: the same physical point in the previous and the current left optical
/// frame (m).
struct SceneFlowPoint
{
  Eigen::Vector3d prev = Eigen::Vector3d::Zero();
  Eigen::Vector3d cur = Eigen::Vector3d::Zero();
};

/// One mover in the world frame (ground plane x, y).
struct MoverDetection
{
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();     ///< m, mean of its points (world x, y)
  Eigen::Vector2d min = Eigen::Vector2d::Zero(), max = Eigen::Vector2d::Zero();  ///< m, extent
  double radius = 0.0;            ///< m, farthest point from the centroid + footprint_margin
  Eigen::Vector2d displacement = Eigen::Vector2d::Zero();  ///< m, mean world x, y residual since the previous frame
  double min_z = 0.0, max_z = 0.0;  ///< m, world heights of its points
  int points = 0;
};

/// Stereo depth sigma (m) at depth z: z^2 * disparity_sigma / (fx * B).
double stereoDepthSigma(const MoverSegmentationParams& p, double z);
/// The residual's normalised size: sqrt((r_ray / s_ray)^2 + (|r_across| / s_across)^2) (see above;
/// 0 for a perfectly explained point, and for a point not in front of both cameras).
double residualSigmas(const MoverSegmentationParams& p, const SceneFlowPoint& f, const Eigen::Isometry3d& T_cur_prev);

class MoverSegmentation
{
public:
  explicit MoverSegmentation(const MoverSegmentationParams& p = MoverSegmentationParams()) : params_(p) {}
  void setParams(const MoverSegmentationParams& p) { params_ = p; }
  const MoverSegmentationParams& params() const { return params_; }

  /// Whether one point's motion is not explained by the ego-motion `T_cur_prev` (maps
  /// previous-frame camera coordinates into the current camera frame).
  bool isMoving(const SceneFlowPoint& f, const Eigen::Isometry3d& T_cur_prev) const;
  /// The residual |cur - T_cur_prev * prev| (m).
  static double residual(const SceneFlowPoint& f, const Eigen::Isometry3d& T_cur_prev);

  /// One frame: marks the moving points (moving()) and clusters them into detections, sorted by
  /// point count (descending), then x, then y. `T_world_cur`: the current camera's pose in the
  /// world (z up).
  const std::vector<MoverDetection>& segment(const std::vector<SceneFlowPoint>& flow,
                                             const Eigen::Isometry3d& T_cur_prev,
                                             const Eigen::Isometry3d& T_world_cur);
  const std::vector<MoverDetection>& detections() const { return detections_; }
  /// Per input point of the last segment(): 1 = moving, 0 = static.
  const std::vector<uint8_t>& moving() const { return moving_; }
  /// Per input point: index into detections(), or -1 (static, or in a cluster too small).
  const std::vector<int>& cluster() const { return cluster_; }

private:
  MoverSegmentationParams params_;
  std::vector<uint8_t> moving_;
  std::vector<int> cluster_;
  std::vector<MoverDetection> detections_;
};

}  // namespace assistive_obstacles
