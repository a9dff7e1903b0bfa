#include <assistive_sim/eval/map_score.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace assistive_sim
{
namespace eval
{
MapScore scoreMap(const Grid& gt, const Grid& est, const Eigen::Vector2d& wearer_gt, const MapScoreParams& p,
                  const Eigen::Isometry2d& T_est_gt)
{
  MapScore s;
  s.radius_m = p.radius_m;
  if (gt.width <= 0 || gt.height <= 0 || gt.data.size() != static_cast<size_t>(gt.width) * gt.height)
    return s;
  const double r2 = p.radius_m * p.radius_m;
  for (int cy = 0; cy < gt.height; ++cy)
    for (int cx = 0; cx < gt.width; ++cx)
    {
      const int8_t g = gt.at(cx, cy);
      if (g == CELL_UNKNOWN)
        continue;
      const Eigen::Vector2d c = gt.cellCenter(cx, cy);
      if ((c - wearer_gt).squaredNorm() > r2)
        continue;
      ++s.gt_known;
      const Eigen::Vector2d ce = T_est_gt * c;
      const int8_t e = est.atWorld(ce.x(), ce.y());
      if (e == CELL_UNKNOWN)
      {
        ++s.est_unknown;
        continue;
      }
      ++s.scored;
      const bool go = isObstacle(g), eo = isObstacle(e);
      if (go && eo)
        ++s.tp;
      else if (!go && eo)
        ++s.fp;
      else if (go && !eo)
        ++s.fn;
      else
        ++s.tn;
      if (go && e == CELL_FREE)
      {
        ++s.free_where_obstacle;
        s.free_where_obstacle_cells.push_back(static_cast<size_t>(cy) * gt.width + cx);
      }
    }
  if (s.tp + s.fp > 0)
    s.precision = static_cast<double>(s.tp) / static_cast<double>(s.tp + s.fp);
  if (s.tp + s.fn > 0)
    s.recall = static_cast<double>(s.tp) / static_cast<double>(s.tp + s.fn);
  if (s.scored > 0)
    s.misclassified = static_cast<double>(s.fp + s.fn) / static_cast<double>(s.scored);
  if (s.gt_known > 0)
    s.coverage = static_cast<double>(s.scored) / static_cast<double>(s.gt_known);
  return s;
}

void MapScoreAccumulator::add(const MapScore& s)
{
  sum_.radius_m = s.radius_m;
  sum_.gt_known += s.gt_known;
  sum_.scored += s.scored;
  sum_.est_unknown += s.est_unknown;
  sum_.tp += s.tp;
  sum_.fp += s.fp;
  sum_.fn += s.fn;
  sum_.tn += s.tn;
  sum_.free_where_obstacle += s.free_where_obstacle;
  if (!s.free_where_obstacle_cells.empty())
  {
    std::vector<size_t> add = s.free_where_obstacle_cells, merged;
    std::sort(add.begin(), add.end());
    std::set_union(fwo_cells_.begin(), fwo_cells_.end(), add.begin(), add.end(), std::back_inserter(merged));
    fwo_cells_.swap(merged);
  }
  ++grids_;
}

MapScore MapScoreAccumulator::total() const
{
  MapScore t = sum_;
  t.free_where_obstacle_cells = fwo_cells_;
  if (t.tp + t.fp > 0)
    t.precision = static_cast<double>(t.tp) / static_cast<double>(t.tp + t.fp);
  if (t.tp + t.fn > 0)
    t.recall = static_cast<double>(t.tp) / static_cast<double>(t.tp + t.fn);
  if (t.scored > 0)
    t.misclassified = static_cast<double>(t.fp + t.fn) / static_cast<double>(t.scored);
  if (t.gt_known > 0)
    t.coverage = static_cast<double>(t.scored) / static_cast<double>(t.gt_known);
  return t;
}

Eigen::Isometry2d planarPose(const Eigen::Isometry3d& pose, const Eigen::Vector3d& forward)
{
  const Eigen::Vector3d f = pose.linear() * forward;
  return Eigen::Translation2d(pose.translation().x(), pose.translation().y()) *
         Eigen::Rotation2Dd(std::atan2(f.y(), f.x()));
}

}  // namespace eval
}  // namespace assistive_sim
