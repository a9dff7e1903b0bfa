#include "assistive_planner/waypoint_selector.h"

#include <cmath>
#include <deque>

#include "assistive_planner/cost_grid.h"

namespace assistive_planner
{
namespace
{
/// 8-connected flood fill from cell `start` over the cells `passable` accepts, without cutting a
/// corner past a cell it refuses; `reached` gets one flag per grid cell.
template <class Passable>
void floodFrom(const Grid& grid, int start, const Passable& passable, std::vector<char>& reached)
{
  reached.assign(grid.data.size(), 0);
  std::deque<int> q;
  q.push_back(start);
  reached[size_t(start)] = 1;
  while (!q.empty())
  {
    const int u = q.front();
    q.pop_front();
    const int x = u % grid.width, y = u / grid.width;
    for (int k = 0; k < 8; ++k)
    {
      const int nx = x + NB_DX[k], ny = y + NB_DY[k];
      if (!passable(nx, ny) || reached[size_t(grid.index(nx, ny))])
        continue;
      if (k >= 4 && (!passable(nx, y) || !passable(x, ny)))
        continue;  // no corner cutting past obstacles or unknown
      reached[size_t(grid.index(nx, ny))] = 1;
      q.push_back(grid.index(nx, ny));
    }
  }
}
}  // namespace

TriangleSearch searchTriangle(const Grid& grid, const Point2& apex, double yaw, double length, double half_angle)
{
  TriangleSearch r;
  const double c = std::cos(yaw), s = std::sin(yaw), t = std::tan(half_angle);
  r.corners[0] = apex;
  r.corners[1] = { apex.x + length * c - length * t * s, apex.y + length * s + length * t * c };
  r.corners[2] = { apex.x + length * c + length * t * s, apex.y + length * s - length * t * c };
  int ax, ay;
  if (grid.empty() || !grid.worldToCell(apex.x, apex.y, ax, ay))
    return r;
  const double slack = 0.5 * grid.resolution;  // a cell counts if its centre is within half a cell
  auto inside = [&](int x, int y) {
    if (length <= 0.0)
      return true;
    const double vx = grid.cellX(x) - apex.x, vy = grid.cellY(y) - apex.y;
    const double along = vx * c + vy * s, perp = -vx * s + vy * c;
    return along >= -slack && along <= length + slack && std::abs(perp) <= along * t + slack;
  };
  auto passable = [&](int x, int y) { return grid.inside(x, y) && isTraversableCode(grid.at(x, y)); };
  auto passableOrUnknown = [&](int x, int y) {
    return grid.inside(x, y) && (isTraversableCode(grid.at(x, y)) || isUnknownCode(grid.at(x, y)));
  };
  // reachability over the whole window (a wall across the triangle can be walked around) ...
  const int a = grid.index(ax, ay);
  floodFrom(grid, a, passable, r.reached);
  // ... then the free area and the farthest free cell inside the triangle: farthest along the axis
  // (in whole cells), ties broken towards the axis
  long best_along = -1;
  double best_d = -1.0, best_perp = 0.0;
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x)
    {
      const int u = grid.index(x, y);
      if (!inside(x, y))
        continue;
      if (!r.reached[size_t(u)])
      {
        r.unreachable_free += grid.at(x, y) == CELL_FREE;
        continue;
      }
      if (isTraversableCode(grid.at(x, y)))
        ++r.cells;
      if (u == a || grid.at(x, y) != CELL_FREE)
        continue;
      const double vx = grid.cellX(x) - apex.x, vy = grid.cellY(y) - apex.y;
      const double along = vx * c + vy * s, perp = std::abs(-vx * s + vy * c);
      const long al = long(std::floor(along / grid.resolution + 1e-9));
      if (al > best_along || (al == best_along && perp < best_perp))
      {
        best_along = al;
        best_perp = perp;
        best_d = std::hypot(vx, vy);
        r.x = x;
        r.y = y;
      }
    }
  if (r.unreachable_free > 0)
  {
    // Free cells cut off only by unmapped floor (after a map reset the floor at the feet lies below
    // the camera's view) are not "no path": whether they can be reached cannot be told yet.
    std::vector<char> through_unknown;
    floodFrom(grid, a, passableOrUnknown, through_unknown);
    for (int y = 0; y < grid.height; ++y)
      for (int x = 0; x < grid.width; ++x)
      {
        const size_t u = size_t(grid.index(x, y));
        if (inside(x, y) && !r.reached[u] && through_unknown[u] && grid.at(x, y) == CELL_FREE)
          ++r.free_behind_unknown;
      }
    r.unreachable_free -= r.free_behind_unknown;
  }
  r.found = best_along >= 0 && best_d > 0.0;
  r.distance = std::max(0.0, best_d);
  r.area = double(r.cells) * grid.resolution * grid.resolution;
  return r;
}

double WaypointSelector::areaTo(const Grid& grid, const Point2& wearer, const Point2& target) const
{
  int tx, ty;
  if (!grid.worldToCell(target.x, target.y, tx, ty) || grid.at(tx, ty) != CELL_FREE)
    return -1.0;
  const double yaw = std::atan2(target.y - wearer.y, target.x - wearer.x);
  const double len = std::hypot(target.x - wearer.x, target.y - wearer.y);
  const TriangleSearch s = searchTriangle(grid, wearer, yaw, len, p_.triangle_half_angle * M_PI / 180.0);
  if (!s.reached.empty() && s.reached[size_t(grid.index(tx, ty))])
    return s.area;
  return -1.0;
}

bool WaypointSelector::update(const Grid& grid, const Point2& wearer, double heading, bool reconsider)
{
  switched_ = false;
  last_ = searchTriangle(grid, wearer, heading, p_.triangle_length, p_.triangle_half_angle * M_PI / 180.0);
  // is the current waypoint still good?
  double cur_area = -1.0;
  if (has_)
  {
    const double dx = waypoint_.x - wearer.x, dy = waypoint_.y - wearer.y;
    const double off = std::abs(wrapAngle(std::atan2(dy, dx) - heading));
    if (std::hypot(dx, dy) > p_.reached_distance && off <= p_.abandon_angle * M_PI / 180.0)
      cur_area = areaTo(grid, wearer, waypoint_);
  }
  if (cur_area >= 0.0 && !reconsider)
  {
    area_ = cur_area;
    return true;
  }
  double cand_area = -1.0;
  Point2 cand;
  if (last_.found)
  {
    cand = { grid.cellX(last_.x), grid.cellY(last_.y) };
    cand_area = areaTo(grid, wearer, cand);
  }
  if (cur_area < 0.0)
  {
    has_ = cand_area >= 0.0;
    if (has_)
    {
      waypoint_ = cand;
      area_ = cand_area;
      switched_ = true;
    }
    return has_;
  }
  area_ = cur_area;
  if (cand_area > p_.switch_area_ratio * cur_area)
  {
    waypoint_ = cand;
    area_ = cand_area;
    switched_ = true;
  }
  return true;
}
}  // namespace assistive_planner
