#include <assistive_obstacles/seen_octree.h>

#include <algorithm>

#include <octomap/OcTree.h>

namespace assistive_obstacles
{
SeenOctree::SeenOctree(const ObstaclesParams& p) : params_(p), tree_(new octomap::OcTree(p.octomap_resolution)) {}
SeenOctree::~SeenOctree() = default;

void SeenOctree::insert(const std::vector<Eigen::Vector3f>& pts, const Eigen::Vector3f& origin)
{
  octomap::Pointcloud cloud;
  const size_t st = static_cast<size_t>(std::max(1, params_.octomap_point_stride));
  cloud.reserve(pts.size() / st + 1);
  for (size_t i = 0; i < pts.size(); i += st) cloud.push_back(pts[i].x(), pts[i].y(), pts[i].z());
  tree_->insertPointCloud(cloud, octomap::point3d(origin.x(), origin.y(), origin.z()),
                          params_.octomap_max_range, false, true);
}

bool SeenOctree::save(const std::string& path) const
{
  octomap::OcTree copy(*tree_);
  copy.toMaxLikelihood();
  copy.prune();
  return copy.writeBinary(path);
}

void SeenOctree::occupiedCenters(std::vector<Eigen::Vector3f>& centers, std::vector<float>& sizes) const
{
  centers.clear();
  sizes.clear();
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it)
    if (tree_->isNodeOccupied(*it))
    {
      centers.emplace_back(it.getX(), it.getY(), it.getZ());
      sizes.push_back(static_cast<float>(it.getSize()));
    }
}

size_t SeenOctree::leafCount() const { return tree_->getNumLeafNodes(); }

}  // namespace assistive_obstacles
