#include <assistive_eval/map_score.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace assistive_eval
{
namespace
{
/// precision, recall, misclassified and coverage from the counts (left NaN when undefined).
void setRatios(MapScore& s)
{
  auto ratio = [](size_t num, size_t den, double& out) {
    if (den > 0)
      out = static_cast<double>(num) / static_cast<double>(den);
  };
  ratio(s.tp, s.tp + s.fp, s.precision);
  ratio(s.tp, s.tp + s.fn, s.recall);
  ratio(s.fp + s.fn, s.scored, s.misclassified);
  ratio(s.scored, s.gt_known, s.coverage);
}
}  // namespace

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
      const Eigen::Vector2d ce = T_est_gt * c;
      const int8_t e = est.atWorld(ce.x(), ce.y());
      const size_t idx = static_cast<size_t>(cy) * gt.width + cx;
      if (p.exclude && idx < p.exclude->size() && (*p.exclude)[idx])
      {
        ++s.excluded;
        if (isObstacle(g) && e == CELL_FREE) s.free_where_partial_cells.push_back(idx);
        continue;
      }
      ++s.gt_known;
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
        s.free_where_obstacle_cells.push_back(idx);
        if (p.glass && idx < p.glass->size() && (*p.glass)[idx]) s.free_where_glass_cells.push_back(idx);
      }
    }
  setRatios(s);
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
  sum_.excluded += s.excluded;
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
  setRatios(t);
  return t;
}

Eigen::Isometry2d planarPose(const Eigen::Isometry3d& pose, const Eigen::Vector3d& forward)
{
  const Eigen::Vector3d f = pose.linear() * forward;
  return Eigen::Translation2d(pose.translation().x(), pose.translation().y()) *
         Eigen::Rotation2Dd(std::atan2(f.y(), f.x()));
}

}  // namespace assistive_eval
