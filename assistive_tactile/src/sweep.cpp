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

}  // namespace assistive_tactile
