#pragma once
// A 3D OctoMap of everything seen (for inspection in rviz / octovis), kept beside the 2D grid.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <assistive_obstacles/params.h>

namespace octomap
{
class OcTree;
}

namespace assistive_obstacles
{
class SeenOctree
{
public:
  explicit SeenOctree(const ObstaclesParams& p = ObstaclesParams());
  ~SeenOctree();
  /// Inserts every octomap_point_stride-th world point as a ray from `origin` (max range clipped).
  void insert(const std::vector<Eigen::Vector3f>& world_points, const Eigen::Vector3f& origin);
  /// Writes the tree as a binary .bt file; false on failure.
  bool save(const std::string& path) const;
  /// Centres of the occupied leaves (and their size, m), for markers.
  void occupiedCenters(std::vector<Eigen::Vector3f>& centers, std::vector<float>& sizes) const;
  size_t leafCount() const;
  const octomap::OcTree& tree() const { return *tree_; }

private:
  ObstaclesParams params_;
  std::unique_ptr<octomap::OcTree> tree_;
};
}  // namespace assistive_obstacles
