#pragma once
// Geometric check of a keyframe pair (placeholder for helper "loop"'s loop_verifier.h until it
// lands): ORB matches (ratio test), P3P RANSAC of the current keyframe's view against the
// candidate's 3D points, then the inliers' 3D points must agree in both stereo frames.
#include <Eigen/Geometry>
#include "assistive_slam/keyframe.h"

namespace assistive_slam
{
struct StereoCheckResult
{
  bool accepted = false;
  int matches = 0, inliers = 0;
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  ///< pose of keyframe b's camera in a's
};

struct StereoCheckOptions
{
  int min_inliers = 40;
  double min_inlier_ratio = 0.35;
  double inlier_px = 2.0;
  double ratio = 0.8;            ///< Lowe's ratio test on the Hamming distances
  int max_hamming = 64;
};

StereoCheckResult stereoCheck(const Keyframe& a, const Keyframe& b, const StereoModel& cam,
                              const StereoCheckOptions& o);

}  // namespace assistive_slam
