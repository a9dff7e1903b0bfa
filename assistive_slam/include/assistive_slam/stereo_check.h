#pragma once
// Geometric check of a keyframe pair (placeholder for helper "loop"'s loop_verifier.h until it
// lands): ORB matches (ratio test), P3P RANSAC of the current keyframe's view against the
// candidate's 3D points, then the inliers' 3D points must agree in both stereo frames.
#include <optional>
#include <utility>
#include <vector>
#include <Eigen/Geometry>
#include "assistive_slam/keyframe.h"

namespace assistive_slam
{
struct StereoCheckResult
{
  bool accepted = false;
  int matches = 0, inliers = 0;
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  ///< pose of keyframe b's camera in a's
  /// The inliers that agree in both stereo views: (keyframe: 0, or the index into localMapCheck's
  /// list; its feature a; b's feature).
  struct Inlier
  {
    int keyframe = 0, a = 0, b = 0;
  };
  std::vector<Inlier> inlier_matches;
};

struct StereoCheckOptions
{
  int min_inliers = 40;
  double min_inlier_ratio = 0.35;
  double inlier_px = 2.0;
  double ratio = 0.8;            ///< Lowe's ratio test on the Hamming distances
  int max_hamming = 64;
  /// b's rotation in the reference frame when it is known (after a VO loss the gyro carried it:
  /// 0.1 deg off in the vision corridor trial): b's position alone is solved, two matches a
  /// hypothesis. P3P's free rotation traded 5 deg of yaw for 0.7 m of position on a corridor's
  /// far points, where 15-20 matches fit either.
  std::optional<Eigen::Matrix3d> R_ref_b;
};

StereoCheckResult stereoCheck(const Keyframe& a, const Keyframe& b, const StereoModel& cam,
                              const StereoCheckOptions& o);

/// The same check of query b against a local map: several keyframes, each with its pose in one
/// reference frame (the map); one match per query feature (its nearest descriptor over them all).
/// T_a_b: b's camera in the reference frame.
StereoCheckResult localMapCheck(const std::vector<std::pair<const Keyframe*, Eigen::Isometry3d>>& local, const Keyframe& b,
                                const StereoModel& cam, const StereoCheckOptions& o);

}  // namespace assistive_slam
