#include <assistive_obstacles/mover_segmentation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace assistive_obstacles
{
double stereoDepthSigma(const MoverSegmentationParams& p, double z)
{
  const double fb = p.fx * p.baseline;
  if (!(fb > 0.0)) return 0.0;
  return z * z * p.disparity_sigma / fb;
}

double MoverSegmentation::residual(const SceneFlowPoint& f, const Eigen::Isometry3d& T_cur_prev)
{
  return (f.cur - T_cur_prev * f.prev).norm();
}

double residualSigmas(const MoverSegmentationParams& p, const SceneFlowPoint& f, const Eigen::Isometry3d& T_cur_prev)
{
  const Eigen::Vector3d r = f.cur - T_cur_prev * f.prev;
  const double range_c = f.cur.norm(), range_p = f.prev.norm();
  if (!(range_c > 1e-9) || !(range_p > 1e-9) || !(f.cur.z() > 1e-9) || !(f.prev.z() > 1e-9))
    return 0.0;  // not in front of both cameras: no stereo point, never a mover
  const Eigen::Vector3d ray = f.cur / range_c;
  const double r_ray = r.dot(ray);
  const double r_across = (r - r_ray * ray).norm();
  const double zp = stereoDepthSigma(p, f.prev.z()) * range_p / f.prev.z();
  const double zc = stereoDepthSigma(p, f.cur.z()) * range_c / f.cur.z();
  const double s_ray = std::sqrt(zp * zp + zc * zc);
  const double ap = range_p * p.pixel_sigma / p.fx, ac = range_c * p.pixel_sigma / p.fx;
  const double s_across = std::sqrt(ap * ap + ac * ac);
  const double a = s_ray > 0.0 ? r_ray / s_ray : (r_ray != 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  const double b = s_across > 0.0 ? r_across / s_across : (r_across != 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  return std::sqrt(a * a + b * b);
}

bool MoverSegmentation::isMoving(const SceneFlowPoint& f, const Eigen::Isometry3d& T_cur_prev) const
{
  return residual(f, T_cur_prev) > params_.min_residual && residualSigmas(params_, f, T_cur_prev) > params_.sigma_scale;
}

const std::vector<MoverDetection>& MoverSegmentation::segment(const std::vector<SceneFlowPoint>& flow,
                                                              const Eigen::Isometry3d& T_cur_prev,
                                                              const Eigen::Isometry3d& T_world_cur)
{
  moving_.assign(flow.size(), 0);
  cluster_.assign(flow.size(), -1);
  detections_.clear();
  const double cs = params_.cell_size > 0.0 ? params_.cell_size : 0.2;

  // Bin the moving points (world x, y) into ground cells; std::map keeps the order deterministic.
  std::vector<Eigen::Vector3d> world(flow.size());
  std::map<std::pair<int, int>, std::vector<int>> cells;
  for (size_t i = 0; i < flow.size(); ++i)
  {
    if (!isMoving(flow[i], T_cur_prev)) continue;
    moving_[i] = 1;
    world[i] = T_world_cur * flow[i].cur;
    cells[{static_cast<int>(std::floor(world[i].x() / cs)), static_cast<int>(std::floor(world[i].y() / cs))}]
        .push_back(static_cast<int>(i));
  }
  for (auto it = cells.begin(); it != cells.end();)
    it = static_cast<int>(it->second.size()) < params_.min_cell_points ? cells.erase(it) : std::next(it);

  // 8-connected components of the occupied cells.
  std::map<std::pair<int, int>, int> label;
  std::vector<std::vector<int>> members;
  for (const auto& kv : cells)
  {
    if (label.count(kv.first)) continue;
    const int id = static_cast<int>(members.size());
    members.emplace_back();
    std::vector<std::pair<int, int>> stack{kv.first};
    label[kv.first] = id;
    while (!stack.empty())
    {
      const std::pair<int, int> c = stack.back();
      stack.pop_back();
      const std::vector<int>& pts = cells.at(c);
      members[id].insert(members[id].end(), pts.begin(), pts.end());
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
        {
          const std::pair<int, int> nb{c.first + dx, c.second + dy};
          if ((dx || dy) && cells.count(nb) && !label.count(nb))
          {
            label[nb] = id;
            stack.push_back(nb);
          }
        }
    }
  }

  // Detections: centroid, extent, radius, mean world displacement.
  const Eigen::Matrix3d R_world_cur = T_world_cur.linear();
  std::vector<std::pair<MoverDetection, std::vector<int>>> found;
  for (const std::vector<int>& m : members)
  {
    if (static_cast<int>(m.size()) < params_.min_cluster_points) continue;
    MoverDetection d;
    d.points = static_cast<int>(m.size());
    d.min = d.max = world[m[0]].head<2>();
    d.min_z = d.max_z = world[m[0]].z();
    Eigen::Vector2d sum = Eigen::Vector2d::Zero(), disp = Eigen::Vector2d::Zero();
    for (const int i : m)
    {
      const Eigen::Vector3d& w = world[i];
      sum += w.head<2>();
      d.min = d.min.cwiseMin(w.head<2>());
      d.max = d.max.cwiseMax(w.head<2>());
      d.min_z = std::min(d.min_z, w.z());
      d.max_z = std::max(d.max_z, w.z());
      disp += (R_world_cur * (flow[i].cur - T_cur_prev * flow[i].prev)).head<2>();
    }
    d.centroid = sum / d.points;
    d.displacement = disp / d.points;
    double r2 = 0.0;
    for (const int i : m) r2 = std::max(r2, (world[i].head<2>() - d.centroid).squaredNorm());
    d.radius = std::sqrt(r2) + params_.footprint_margin;
    found.emplace_back(d, m);
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) {
    if (a.first.points != b.first.points) return a.first.points > b.first.points;
    if (a.first.centroid.x() != b.first.centroid.x()) return a.first.centroid.x() < b.first.centroid.x();
    return a.first.centroid.y() < b.first.centroid.y();
  });
  for (size_t k = 0; k < found.size(); ++k)
  {
    detections_.push_back(found[k].first);
    for (const int i : found[k].second) cluster_[i] = static_cast<int>(k);
  }
  return detections_;
}

}  // namespace assistive_obstacles
