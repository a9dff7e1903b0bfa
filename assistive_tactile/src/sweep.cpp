#include "assistive_tactile/sweep.h"

#include <algorithm>
#include <cmath>

namespace assistive_tactile
{
double obstacleClearance(const ObstacleGrid& g, double x, double y, double reach)
{
  if (g.empty() || !(g.resolution > 0.0))
    return reach;
  const int cx = int(std::floor((x - g.origin_x) / g.resolution));
  const int cy = int(std::floor((y - g.origin_y) / g.resolution));
  const int k = int(std::ceil(reach / g.resolution)) + 1;
  double best2 = reach * reach;
  for (int j = std::max(0, cy - k); j <= std::min(g.height - 1, cy + k); ++j)
    for (int i = std::max(0, cx - k); i <= std::min(g.width - 1, cx + k); ++i)
    {
      if (g.data[size_t(j) * size_t(g.width) + size_t(i)] <= 50)
        continue;
      const double dx = g.cellX(i) - x;
      const double dy = g.cellY(j) - y;
      best2 = std::min(best2, dx * dx + dy * dy);
    }
  return std::sqrt(best2);
}

double alongRayUntil(const ObstacleGrid& g, double x, double y, double yaw, double max, double step,
                     bool (*stop)(int8_t))
{
  for (double d = 0.0; d <= max; d += step)
    if (stop(g.atWorld(x + d * std::cos(yaw), y + d * std::sin(yaw))))
      return d;
  return max;
}

double sideFree(const ObstacleGrid& g, double x, double y, double yaw, int side, double max)
{
  return alongRayUntil(g, x, y, yaw + (side > 0 ? 0.5 : -0.5) * M_PI, max, 0.02, [](int8_t c) { return c > 50; });
}

SweepResult sweepWalk(const ObstacleGrid& g, double x, double y, double yaw, const WalkModel& m, double radius,
                      double dt)
{
  SweepResult r;
  const double reach = radius + 0.5;
  const double c0 = obstacleClearance(g, x, y, reach);
  const double limit = std::min(radius, c0 - 0.03);
  double v = std::max(0.0, m.v0);
  double turned = 0.0;
  r.min_clear = c0;
  for (double t = 0.0; t < m.horizon_s; t += dt)
  {
    // speed: up towards the pace until the stop begins, then down at its stop
    if (t >= m.stop_at_s)
    {
      v = std::max(0.0, v - m.decel * dt);
      if (v <= 0.0)
        break;
    }
    else if (m.accel > 0.0 && v < m.pace)
      v = std::min(m.pace, v + m.accel * dt);
    // heading: the veer turns the walk from turn_start_s at turn_rate until done (a stop cancels
    // what is left of it)
    if (t >= m.turn_start_s && (m.turn_while_stopping || t < m.stop_at_s) && std::fabs(turned) < std::fabs(m.turn))
    {
      const double d = std::min(std::fabs(m.turn) - std::fabs(turned), m.turn_rate * dt);
      const double s = m.turn > 0.0 ? 1.0 : -1.0;
      turned += s * d;
      yaw += s * d;
    }
    x += v * dt * std::cos(yaw);
    y += v * dt * std::sin(yaw);
    r.walked += v * dt;
    const double c = obstacleClearance(g, x, y, reach);
    r.min_clear = std::min(r.min_clear, c);
    // (the further the walk, the less sure where it is: the clearance it needs grows, up to
    // what the body has now less 3 cm, so that a walk along an aisle's shelf stays allowed)
    const double need = std::max(limit, std::min(radius + m.spread_per_m * r.walked, c0 - 0.03));
    if (c < need)
    {
      r.hit = true;
      r.hit_t = t + dt;
      r.hit_along = r.walked;
      break;
    }
  }
  r.end_x = x;
  r.end_y = y;
  r.end_yaw = yaw;
  return r;
}

namespace
{
/// Douglas-Peucker: marks in `keep` the points of pts[i0..i1] the simplified polyline keeps.
void simplify(const std::vector<GroundPoint>& pts, size_t i0, size_t i1, double tol, std::vector<bool>& keep)
{
  if (i1 <= i0 + 1)
    return;
  const double ax = pts[i0][0], ay = pts[i0][1], dx = pts[i1][0] - ax, dy = pts[i1][1] - ay;
  const double len = std::hypot(dx, dy);
  double worst = -1.0;
  size_t at = i0;
  for (size_t i = i0 + 1; i < i1; ++i)
  {
    const double px = pts[i][0] - ax, py = pts[i][1] - ay;
    const double d = len > 1e-9 ? std::fabs(px * dy - py * dx) / len : std::hypot(px, py);
    if (d > worst)
    {
      worst = d;
      at = i;
    }
  }
  if (worst <= tol)
    return;
  keep[at] = true;
  simplify(pts, i0, at, tol, keep);
  simplify(pts, at, i1, tol, keep);
}
}  // namespace

PathCorner nextCorner(const std::vector<GroundPoint>& path, double x, double y, double tolerance, double max_m,
                      double merge_m, double search_m)
{
  PathCorner c;
  if (path.size() < 2)
    return c;
  // the nearest point within the path's first stretch (a path folding back must not jump ahead)
  size_t near = 0;
  double best = 1e300, along = 0.0;
  for (size_t i = 0; i < path.size(); ++i)
  {
    if (i > 0)
      along += std::hypot(path[i][0] - path[i - 1][0], path[i][1] - path[i - 1][1]);
    if (along > search_m)
      break;
    const double d = std::hypot(path[i][0] - x, path[i][1] - y);
    if (d < best)
    {
      best = d;
      near = i;
    }
  }
  std::vector<GroundPoint> pts{ { x, y } };
  double run = 0.0;
  for (size_t i = near + 1; i < path.size() && run < max_m; ++i)
  {
    run += std::hypot(path[i][0] - pts.back()[0], path[i][1] - pts.back()[1]);
    pts.push_back(path[i]);
  }
  if (pts.size() < 3)
    return c;
  std::vector<bool> keep(pts.size(), false);
  keep.front() = keep.back() = true;
  simplify(pts, 0, pts.size() - 1, tolerance, keep);
  std::vector<size_t> idx;
  for (size_t i = 0; i < pts.size(); ++i)
    if (keep[i])
      idx.push_back(i);
  if (idx.size() < 3)
    return c;
  const GroundPoint &a = pts[idx[0]], &b = pts[idx[1]];
  // corners joined by a leg shorter than `merge_m` are one (a turn into a side hall the path
  // rounds in two): where the leg in and the last leg out meet
  size_t k = 1;
  while (k + 2 < idx.size() && std::hypot(pts[idx[k + 1]][0] - pts[idx[k]][0], pts[idx[k + 1]][1] - pts[idx[k]][1]) < merge_m)
    ++k;
  const GroundPoint &o = pts[idx[k]], &n = pts[idx[k + 1]];
  c.found = true;
  c.heading_in = std::atan2(b[1] - a[1], b[0] - a[0]);
  c.heading_out = std::atan2(n[1] - o[1], n[0] - o[0]);
  c.leg_out = std::hypot(n[0] - o[0], n[1] - o[1]);
  const double ux = std::cos(c.heading_in), uy = std::sin(c.heading_in);
  const double wx = std::cos(c.heading_out), wy = std::sin(c.heading_out);
  const double cross = ux * wy - uy * wx;
  c.x = b[0];
  c.y = b[1];
  if (k > 1 && std::fabs(cross) > 0.2)
  {
    const double t = ((o[0] - a[0]) * wy - (o[1] - a[1]) * wx) / cross;
    c.x = a[0] + t * ux;
    c.y = a[1] + t * uy;
  }
  return c;
}

}  // namespace assistive_tactile
