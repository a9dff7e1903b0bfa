#pragma once
// Trajectories (stamped SE(3) poses), text file I/O (TUM, KITTI), timestamp association and
// alignment (Umeyama SE(3) / Sim(3), first pose). ROS-free: Eigen only.
#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

namespace assistive_eval
{
/// One pose of a body frame in a world frame at time t (seconds).
struct StampedPose
{
  double t = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};
using Trajectory = std::vector<StampedPose>;

/// TUM format: "t tx ty tz qx qy qz qw" per line, '#' comments; ',' and tabs accepted as separators.
/// Throws std::runtime_error naming the file and line on malformed input or a missing file.
Trajectory readTum(const std::string& path);
void writeTum(const std::string& path, const Trajectory& traj);
/// KITTI odometry format: 12 numbers per line (row-major 3x4 [R|t]). Stamps from `times_path`
/// (one number per line) when given, else the line index (seconds).
Trajectory readKitti(const std::string& path, const std::string& times_path = "");
void writeKitti(const std::string& path, const Trajectory& traj);

enum class AssociationMethod
{
  TUM_GREEDY,   ///< TUM evaluate_ate.py: all pairs |t1 - (t2 + offset)| < max_diff, greedy by diff
  EVO_NEAREST,  ///< evo: each stamp of the shorter trajectory -> nearest in the longer, <= max_diff
  INDEX         ///< index i <-> i (KITTI files), up to the shorter length
};
/// Index pairs (i in `first`, j in `second`), sorted by i.
std::vector<std::pair<size_t, size_t>> associate(const Trajectory& first, const Trajectory& second,
                                                 double max_diff, AssociationMethod method,
                                                 double offset_second = 0.0);

/// Two index-aligned trajectories: gt[i] and est[i] belong together.
struct MatchedTrajectories
{
  Trajectory gt;
  Trajectory est;
};
MatchedTrajectories match(const Trajectory& gt, const Trajectory& est, double max_diff,
                          AssociationMethod method);

enum class AlignMode
{
  NONE,
  FIRST_POSE,  ///< est poses premultiplied so that est[0] == gt[0]
  SE3,         ///< Umeyama/Horn on positions, no scale
  SIM3         ///< Umeyama with scale
};
/// p_aligned = scale * (R * p) + t; orientations R_aligned = R * R_est.
struct Alignment
{
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  double scale = 1.0;
};
/// Alignment of `est` onto `gt` (index-aligned). Needs >= 3 poses for SE3/SIM3 (else identity).
Alignment computeAlignment(const Trajectory& gt, const Trajectory& est, AlignMode mode);
Trajectory applyAlignment(const Trajectory& est, const Alignment& a);

/// Cumulative path length (m) of the positions: d[0] = 0.
std::vector<double> pathDistances(const Trajectory& traj);
double pathLength(const Trajectory& traj);

/// Fixed transform between the conventions of the interface contract: camera_link (x forward,
/// y left, z up) -> optical frame (z forward, x right, y down). pose_optical = pose_link * this.
Eigen::Isometry3d linkToOptical();

}  // namespace assistive_eval
