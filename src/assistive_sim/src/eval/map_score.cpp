#include <assistive_sim/eval/map_score.h>

#include <cmath>

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

}  // namespace eval
}  // namespace assistive_sim
