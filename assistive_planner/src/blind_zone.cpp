#include "assistive_planner/blind_zone.h"

#include <algorithm>
#include <cmath>

namespace assistive_planner
{
int vouchBlindZone(Grid& grid, const Point2& wearer, double facing, const RangerReading& ranger, double zone_m,
                   double half_angle, double view_m)
{
  if (grid.empty() || !(zone_m > 0.0) || !ranger.valid() || !(half_angle > 0.0) || !std::isfinite(facing) ||
      !std::isfinite(wearer.x) || !std::isfinite(wearer.y))
    return 0;
  const double res = grid.resolution;
  const double reach = std::min(zone_m, ranger.clearDistance() - res);  // the ranger's echo is never vouched past
  const bool echo_near = std::isfinite(ranger.range) && ranger.range <= zone_m + res;
  const double cone_half =
      ranger.field_of_view > 0.0 && ranger.field_of_view < M_PI ? 0.5 * ranger.field_of_view : 0.0;
  if (!(reach > 0.0))
    return 0;
  const Grid seen = grid;  // judged on the grid as given
  int cx, cy;
  seen.worldToCell(wearer.x, wearer.y, cx, cy);
  const int r = int(std::ceil(zone_m / res)) + 1;
  const double step = 0.25 * res, beyond = zone_m + std::max(res, view_m);
  int changed = 0;
  for (int y = cy - r; y <= cy + r; ++y)
    for (int x = cx - r; x <= cx + r; ++x)
    {
      if (!seen.inside(x, y) || !isUnknownCode(seen.at(x, y)))
        continue;
      const double dx = seen.cellX(x) - wearer.x, dy = seen.cellY(y) - wearer.y;
      const double d = std::hypot(dx, dy);
      if (d < 1e-9)
        continue;
      // a cell counts as inside a sector when any part of it is (its half-diagonal seen from the
      // wearer): the cells next to the body subtend tens of degrees, and a ray along the facing
      // crosses cells whose centres lie well off it
      const double bearing = std::atan2(dy, dx);
      const double spread = std::asin(std::min(1.0, 0.7072 * res / d));
      if (echo_near && std::fabs(d - ranger.range) <= 0.5 * res &&
          std::fabs(wrapAngle(bearing - ranger.yaw)) <= cone_half + spread)
      {
        // the ranger's echo: a solid on its arc, as the obstacle stage fuses it (unknown cells only)
        grid.data[size_t(grid.index(x, y))] = CELL_OBSTACLE;
        ++changed;
        continue;
      }
      if (d > reach)
        continue;
      if (std::fabs(wrapAngle(bearing - facing)) > half_angle + spread)
        continue;
      const double ux = dx / d, uy = dy / d;
      bool blocked = false;
      // the ranger's echo past the cell, within its cone: a solid there, nothing nearer
      bool seen_past = echo_near && std::fabs(wrapAngle(bearing - ranger.yaw)) <= cone_half + spread;
      for (double s = step; s <= beyond + 1e-9; s += step)
      {
        int px, py;
        if (!seen.worldToCell(wearer.x + s * ux, wearer.y + s * uy, px, py))
          break;  // the window's edge: nothing seen past the zone
        if (s >= d && seen_past)
          break;
        const int8_t code = seen.at(px, py);
        if (px == x && py == y)
          continue;
        if (s < d)
        {
          if (!isUnknownCode(code) && code != CELL_FREE)
          {
            blocked = true;
            break;
          }
        }
        else if (!seen_past && !isUnknownCode(code))
        {
          seen_past = true;
          break;
        }
      }
      if (blocked || !seen_past)
        continue;
      grid.data[size_t(grid.index(x, y))] = CELL_FREE;
      ++changed;
    }
  return changed;
}
}  // namespace assistive_planner
