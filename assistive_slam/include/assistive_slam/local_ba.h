#pragma once
// Local bundle adjustment over a sliding window of keyframes (Ceres): keyframe poses and the
// landmarks they share, stereo reprojection residuals (left u, v and right u), Huber loss;
// relative-pose priors from the VO between consecutive keyframes keep weakly linked windows stable.
#include <cstdint>
#include <map>
#include <vector>
#include <Eigen/Geometry>
#include "assistive_slam/keyframe.h"
#include "assistive_slam/pose_graph.h"

namespace assistive_slam
{
struct BaObservation
{
  int frame = 0;          ///< index into BaProblem::poses
  int64_t landmark = 0;   ///< key into BaProblem::landmarks
  Eigen::Vector3d uvr;    ///< left u, left v, right u (px)
  double scale = 1.0;     ///< noise relative to pixel_sigma (ORB: 1.2^pyramid level)
};

struct BaProblem
{
  std::vector<Eigen::Isometry3d> poses;      ///< T_world_cam per keyframe (refined in place)
  std::vector<bool> fixed;                   ///< held constant (gauge); same size as poses
  std::map<int64_t, Eigen::Vector3d> landmarks;  ///< world coordinates (refined in place)
  std::vector<BaObservation> observations;
  /// Optional priors on consecutive poses (i, i+1): measured T_i_i+1 with information.
  std::vector<PoseGraphEdge> priors;         ///< from / to are indices into poses
};

struct BaOptions
{
  int max_iterations = 10;
  double huber_px = 1.5;
  double pixel_sigma_px = 0.7;
};

struct BaResult
{
  bool solved = false;
  int iterations = 0;
  double initial_rms_px = 0, final_rms_px = 0;  ///< RMS reprojection error (all observations)
};

BaResult bundleAdjust(BaProblem& problem, const StereoModel& cam, const BaOptions& options);

/// RMS stereo reprojection error of all observations (px; points behind the camera count 1e3).
double reprojectionRms(const BaProblem& problem, const StereoModel& cam);

}  // namespace assistive_slam
