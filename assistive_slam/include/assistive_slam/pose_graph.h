#pragma once
// Pose-graph optimisation (Ceres): nodes are poses in one frame, edges relative poses with an
// information matrix. Used on the submap graph after an accepted loop closure (seed 3.2.3.2).
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>
#include <Eigen/Geometry>

namespace assistive_slam
{
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// The pose of node `to` in node `from` (T_from_to), information in the order x y z, then the
/// rotation vector (small-angle roll pitch yaw).
struct PoseGraphEdge
{
  uint32_t from = 0, to = 0;
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  Matrix6d information = Matrix6d::Identity();
};

struct PoseGraphResult
{
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;
};

class PoseGraph
{
public:
  void addNode(uint32_t id, const Eigen::Isometry3d& T_world_node);
  /// Both nodes must exist (std::invalid_argument otherwise).
  void addEdge(const PoseGraphEdge& e);
  /// Fixed nodes define the gauge; with none, the node of the smallest id is held fixed.
  void setFixed(uint32_t id) { fixed_.insert(id); }
  PoseGraphResult optimise(int max_iterations = 50);
  const Eigen::Isometry3d& pose(uint32_t id) const { return nodes_.at(id); }
  const std::map<uint32_t, Eigen::Isometry3d>& poses() const { return nodes_; }
  const std::vector<PoseGraphEdge>& edges() const { return edges_; }

private:
  std::map<uint32_t, Eigen::Isometry3d> nodes_;
  std::vector<PoseGraphEdge> edges_;
  std::set<uint32_t> fixed_;
};

/// Information of a relative pose with independent noise: sigma_t (m) per axis, sigma_r (rad).
Matrix6d isotropicInformation(double sigma_t, double sigma_r);

}  // namespace assistive_slam
