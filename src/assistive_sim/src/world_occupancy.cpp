// World geometry queries and the ground-truth occupancy grid of a world (README "Grid cell
// codes"): floor height, footprint tests, computeOccupancy. The YAML parsing is world_parse.cpp.
#include <assistive_sim/world.h>

#include <algorithm>
#include <cmath>

namespace assistive_sim
{
double World::floorHeight(double x, double y) const
{
  double h = 0.0;
  for (const Solid& s : solids)
    if (s.walkable && s.containsXY(x, y)) h = std::max(h, s.z1);
  return h;
}

bool Solid::containsXY(double x, double y, double inflate) const
{
  const double dx = x - center.x(), dy = y - center.y();
  if (shape == CYLINDER) return dx * dx + dy * dy <= (radius + inflate) * (radius + inflate);
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
  return std::abs(lx) <= half.x() + inflate && std::abs(ly) <= half.y() + inflate;
}

bool Solid::overlapsRect(double x0, double y0, double x1, double y1) const
{
  // Touching is not overlapping (a curb edge on a cell border belongs to one side only).
  constexpr double EPS = 1e-6;
  x0 += EPS;
  y0 += EPS;
  x1 -= EPS;
  y1 -= EPS;
  if (shape == CYLINDER)
  {
    const double px = std::clamp(center.x(), x0, x1), py = std::clamp(center.y(), y0, y1);
    const double dx = px - center.x(), dy = py - center.y();
    return dx * dx + dy * dy <= radius * radius;
  }
  // Separating axis test: rectangle axes (x, y) and the box's two axes.
  const double c = std::cos(yaw), s = std::sin(yaw);
  const Eigen::Vector2d ax(c, s), ay(-s, c);
  const Eigen::Vector2d corners[4] = {center + ax * half.x() + ay * half.y(), center + ax * half.x() - ay * half.y(),
                                      center - ax * half.x() + ay * half.y(), center - ax * half.x() - ay * half.y()};
  double bx0 = 1e18, bx1 = -1e18, by0 = 1e18, by1 = -1e18;
  for (const auto& p : corners)
  {
    bx0 = std::min(bx0, p.x());
    bx1 = std::max(bx1, p.x());
    by0 = std::min(by0, p.y());
    by1 = std::max(by1, p.y());
  }
  if (bx1 < x0 || bx0 > x1 || by1 < y0 || by0 > y1) return false;
  const Eigen::Vector2d rc[4] = {{x0, y0}, {x0, y1}, {x1, y0}, {x1, y1}};
  for (const Eigen::Vector2d& axis : {ax, ay})
  {
    const double hb = (axis == ax ? half.x() : half.y());
    const double cc = axis.dot(center);
    double r0 = 1e18, r1 = -1e18;
    for (const auto& p : rc)
    {
      r0 = std::min(r0, axis.dot(p));
      r1 = std::max(r1, axis.dot(p));
    }
    if (r1 < cc - hb || r0 > cc + hb) return false;
  }
  return true;
}

OccupancyGrid computeOccupancy(const World& w, const OccupancyParams& p)
{
  OccupancyGrid g;
  g.resolution = p.resolution;
  g.origin_x = std::floor((w.floor_min.x() - p.border) / p.resolution) * p.resolution;
  g.origin_y = std::floor((w.floor_min.y() - p.border) / p.resolution) * p.resolution;
  g.width = static_cast<int>(std::ceil((w.floor_max.x() + p.border - g.origin_x) / p.resolution));
  g.height = static_cast<int>(std::ceil((w.floor_max.y() + p.border - g.origin_y) / p.resolution));
  g.data.assign(static_cast<size_t>(g.width) * g.height, CELL_UNKNOWN);
  const double top_rel = w.trajectory.eye_height + p.head_above_eye + p.head_margin;

  // Floor height per cell (max over the cell: sample 3x3 points).
  std::vector<double> fh(g.data.size(), 0.0);
  std::vector<char> on_floor(g.data.size(), 0);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix)
    {
      const double x0 = g.origin_x + ix * p.resolution, y0 = g.origin_y + iy * p.resolution;
      const double x1 = x0 + p.resolution, y1 = y0 + p.resolution;
      const size_t i = static_cast<size_t>(iy) * g.width + ix;
      on_floor[i] = x1 > w.floor_min.x() && x0 < w.floor_max.x() && y1 > w.floor_min.y() && y0 < w.floor_max.y();
      if (!on_floor[i]) continue;
      double h = 0.0;
      for (const Solid& s : w.solids)
        if (s.walkable && s.overlapsRect(x0, y0, x1, y1)) h = std::max(h, s.z1);
      fh[i] = h;
      g.data[i] = CELL_FREE;
    }
  // Steps: floor height differs from an 8-neighbour's by more than the threshold. Mark the
  // higher cell and the lower one (both border the edge).
  std::vector<int8_t> out = g.data;
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix)
    {
      const size_t i = static_cast<size_t>(iy) * g.width + ix;
      if (!on_floor[i]) continue;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
        {
          if (!g.inside(ix + dx, iy + dy)) continue;
          const size_t j = static_cast<size_t>(iy + dy) * g.width + ix + dx;
          if (on_floor[j] && std::abs(fh[j] - fh[i]) > p.step_threshold) out[i] = CELL_STEP;
        }
    }
  // A walkable solid's cells are steps too when the cell contains its edge (partial cover).
  // Obstacles: any non-walkable solid in the cell between floor and head height + margin.
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix)
    {
      const size_t i = static_cast<size_t>(iy) * g.width + ix;
      const double x0 = g.origin_x + ix * p.resolution, y0 = g.origin_y + iy * p.resolution;
      const double x1 = x0 + p.resolution, y1 = y0 + p.resolution;
      const double lo = (on_floor[i] ? fh[i] : 0.0) + p.min_obstacle_height;
      const double hi = (on_floor[i] ? fh[i] : 0.0) + top_rel;
      for (const Solid& s : w.solids)
      {
        if (s.walkable) continue;
        if (s.z1 <= lo || s.z0 >= hi) continue;
        if (s.overlapsRect(x0, y0, x1, y1))
        {
          out[i] = CELL_OBSTACLE;
          break;
        }
      }
    }
  g.data.swap(out);
  return g;
}

std::vector<uint8_t> computeOccupancyDetail(const World& w, const OccupancyParams& p, double partial_depth)
{
  const OccupancyGrid g = computeOccupancy(w, p);
  std::vector<uint8_t> flags(g.data.size(), 0);
  const double top_rel = w.trajectory.eye_height + p.head_above_eye + p.head_margin;
  const double d = std::max(0.0, std::min(partial_depth, 0.49 * p.resolution));
  // Cells whose obstacle code comes from a solid that reaches deeper than d into them ("core").
  std::vector<char> core(g.data.size(), 0);
  std::vector<double> fh(g.data.size(), 0.0);  // floor height per cell, as computeOccupancy takes it
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix)
    {
      const double x0 = g.origin_x + ix * p.resolution, y0 = g.origin_y + iy * p.resolution;
      for (const Solid& s : w.solids)
        if (s.walkable && s.overlapsRect(x0, y0, x0 + p.resolution, y0 + p.resolution))
          fh[static_cast<size_t>(iy) * g.width + ix] = std::max(fh[static_cast<size_t>(iy) * g.width + ix], s.z1);
    }
  for (const Solid& s : w.solids)
  {
    if (s.walkable) continue;
    std::vector<size_t> touched;
    bool any_core = false;
    for (int iy = 0; iy < g.height; ++iy)
      for (int ix = 0; ix < g.width; ++ix)
      {
        const size_t i = static_cast<size_t>(iy) * g.width + ix;
        const double x0 = g.origin_x + ix * p.resolution, y0 = g.origin_y + iy * p.resolution;
        const double x1 = x0 + p.resolution, y1 = y0 + p.resolution;
        const double floor = g.data[i] == CELL_UNKNOWN ? 0.0 : fh[i];
        if (s.z1 <= floor + p.min_obstacle_height || s.z0 >= floor + top_rel) continue;
        if (s.overlapsRect(x0, y0, x1, y1))
        {
          if (s.glass) flags[i] |= DETAIL_GLASS;
          touched.push_back(i);
          if (s.overlapsRect(x0 + d, y0 + d, x1 - d, y1 - d))
          {
            core[i] = 1;
            any_core = true;
          }
        }
        else if (d > 0.0 && g.data[i] != CELL_OBSTACLE && g.data[i] != CELL_UNKNOWN &&
                 s.overlapsRect(x0 - d, y0 - d, x1 + d, y1 + d))
          flags[i] |= DETAIL_NEAR;
      }
    if (!any_core)  // a thin solid: every cell it touches must be found
      for (const size_t i : touched) core[i] = 1;
  }
  for (size_t i = 0; i < flags.size(); ++i)
    if (g.data[i] == CELL_OBSTACLE && !core[i]) flags[i] |= DETAIL_PARTIAL;
  return flags;
}
}  // namespace assistive_sim
