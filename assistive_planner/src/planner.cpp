#include "assistive_planner/planner.h"

#include <cstdio>

#include <algorithm>
#include <cmath>

#include "assistive_planner/cost_model.h"

namespace assistive_planner
{
Planner::Planner(const PlannerParams& p) : p_(p), motion_(p), waypoints_(p), crossing_(p) {}

int markWalkedFloor(Grid& grid, const std::vector<Point2>& walked, double radius)
{
  if (grid.empty() || !(radius > 0.0))
    return 0;
  int changed = 0;
  const int r = int(std::ceil(radius / grid.resolution)) + 1;
  for (const Point2& p : walked)
  {
    int cx, cy;
    grid.worldToCell(p.x, p.y, cx, cy);  // may lie outside: its neighbours may not
    if (cx < -r || cy < -r || cx >= grid.width + r || cy >= grid.height + r)
      continue;
    for (int y = cy - r; y <= cy + r; ++y)
      for (int x = cx - r; x <= cx + r; ++x)
      {
        if (!grid.inside(x, y) || !isUnknownCode(grid.at(x, y)))
          continue;
        if (std::hypot(grid.cellX(x) - p.x, grid.cellY(y) - p.y) > radius + 1e-9)
          continue;
        grid.data[size_t(grid.index(x, y))] = CELL_FREE;
        ++changed;
      }
  }
  return changed;
}

void Planner::setGoal(const Point2& goal)
{
  has_goal_ = true;
  goal_ = goal;
}

double Planner::freeDistance(const Grid& grid, const Point2& from, double yaw, double max_range)
{
  bool ends_unknown;
  return freeDistance(grid, from, yaw, max_range, ends_unknown);
}

double Planner::freeDistance(const Grid& grid, const Point2& from, double yaw, double max_range, bool& ends_unknown)
{
  ends_unknown = false;
  int x0, y0;
  if (grid.empty() || !grid.worldToCell(from.x, from.y, x0, y0))
    return 0.0;
  const double step = 0.25 * grid.resolution, c = std::cos(yaw), s = std::sin(yaw);
  double d = 0.0;
  while (d + step <= max_range)
  {
    const double nd = d + step;
    int x, y;
    if (!grid.worldToCell(from.x + nd * c, from.y + nd * s, x, y))
      return d;
    if (!(x == x0 && y == y0) && grid.at(x, y) != CELL_FREE)
    {
      ends_unknown = isUnknownCode(grid.at(x, y));
      return d;
    }
    d = nd;
  }
  return d;
}

double Planner::freeStrip(const Grid& grid, const Point2& from, double yaw, double max_range, double half_width,
                          bool& ends_unknown)
{
  ends_unknown = false;
  if (!(half_width > 0.0))
    return freeDistance(grid, from, yaw, max_range, ends_unknown);
  // The centre line first (the window's edge and what lies straight ahead), then every cell that is
  // not free whose centre lies inside the strip AHEAD of the body's front arc: a cell beside the
  // body or under it is contact, not something the next steps run into (on 0.2 m cells the strip
  // would otherwise stop the wearer beside every piece of furniture it passes).
  double best = freeDistance(grid, from, yaw, max_range, ends_unknown);
  int x0, y0;
  if (grid.empty() || !grid.worldToCell(from.x, from.y, x0, y0))
    return best;
  const double c = std::cos(yaw), s = std::sin(yaw), res = grid.resolution;
  const int reach = int(std::ceil((best + half_width) / res)) + 1;
  for (int y = y0 - reach; y <= y0 + reach; ++y)
    for (int x = x0 - reach; x <= x0 + reach; ++x)
    {
      if (!grid.inside(x, y) || (x == x0 && y == y0) || grid.at(x, y) == CELL_FREE)
        continue;
      const double dx = grid.cellX(x) - from.x, dy = grid.cellY(y) - from.y;
      const double f = dx * c + dy * s, l = -dx * s + dy * c;
      if (std::abs(l) > half_width || f <= std::sqrt(half_width * half_width - l * l))
        continue;  // outside the strip, or beside / under the body
      const double d = std::max(0.0, f - 0.5 * res);
      if (d < best)
      {
        best = d;
        ends_unknown = isUnknownCode(grid.at(x, y));
      }
    }
  return best;
}

void Planner::syncCosts(const Grid& grid, PlanOutput& out)
{
  const std::vector<double> w = cellWeights(grid, p_);
  const bool same_shape = have_grid_ && grid.width == last_grid_.width && grid.height == last_grid_.height &&
                          std::abs(grid.resolution - last_grid_.resolution) < 1e-9;
  int dx = 0, dy = 0;
  bool aligned = false;
  if (same_shape)
  {
    const double fx = (grid.origin_x - last_grid_.origin_x) / grid.resolution;
    const double fy = (grid.origin_y - last_grid_.origin_y) / grid.resolution;
    dx = int(std::lround(fx));
    dy = int(std::lround(fy));
    aligned = std::abs(fx - dx) < 1e-3 && std::abs(fy - dy) < 1e-3 && std::abs(dx) < grid.width &&
              std::abs(dy) < grid.height;
  }
  if (!aligned)
  {
    CostGrid cg(grid.width, grid.height);
    cg.w = w;
    dstar_.reset(cg);
    out.changed_cells = w.size();
  }
  else if (dx != 0 || dy != 0)
  {
    dstar_.scroll(dx, dy, w);  // new cell (x, y) = old (x + dx, y + dy)
    out.scrolled = true;
  }
  else
  {
    out.changed_cells = dstar_.setCosts(w);
  }
  have_grid_ = true;
  last_grid_.width = grid.width;
  last_grid_.height = grid.height;
  last_grid_.resolution = grid.resolution;
  last_grid_.origin_x = grid.origin_x;
  last_grid_.origin_y = grid.origin_y;
}

PlanOutput Planner::update(const Grid& input, const Point2& wearer, double head_yaw, double t)
{
  PlanOutput out;
  out.wearer = wearer;
  out.head_yaw = wrapAngle(head_yaw);
  if (input.empty() || !(input.resolution > 0.0) || !std::isfinite(wearer.x) || !std::isfinite(wearer.y) ||
      !std::isfinite(head_yaw))
  {
    out.status = input.empty() ? PlanStatus::NO_MAP : PlanStatus::NO_POSE;
    out.message = input.empty() ? "no traversability grid" : "invalid wearer pose";
    return out;
  }
  // The wearer stands on the floor under its feet even before the camera has seen it (at the start
  // it lies below the view): the footprint, and every place stood on since, is free floor. Only
  // places the body has been; unseen floor ahead stays unknown.
  if (walked_.empty() || std::hypot(wearer.x - walked_.back().x, wearer.y - walked_.back().y) >= 0.05)
  {
    walked_.push_back(wearer);
    if (walked_.size() > 20000)
      walked_.erase(walked_.begin(), walked_.begin() + 10000);
  }
  work_ = input;
  markWalkedFloor(work_, walked_, p_.footprint_radius_m);
  const Grid& grid = work_;
  syncCosts(grid, out);
  const bool motion_changed = motion_.update(wearer, head_yaw);
  out.heading = motion_.heading();
  out.motion_anchor = motion_.anchor();
  const double h = out.heading;
  bool ahead_unknown = false;
  out.free_ahead = freeStrip(grid, wearer, h, p_.free_ray_max, p_.body_half_width, ahead_unknown);
  out.free_left = freeDistance(grid, wearer, h + M_PI_2, p_.free_ray_max);
  out.free_right = freeDistance(grid, wearer, h - M_PI_2, p_.free_ray_max);
  // People crossing: judged on every cycle with a pose and a grid, whatever the status below (the
  // cue logic acts on it only when the status is OK: never on a guess).
  if (std::isfinite(t))
  {
    crossing_.addPose(t, wearer);
    out.crossing = crossing_.check(t, wearer, h, out.free_left, out.free_right);
  }

  int wx, wy;
  if (!grid.worldToCell(wearer.x, wearer.y, wx, wy))
  {
    out.status = PlanStatus::NO_MAP;
    out.message = "the wearer is outside the traversability grid";
    return out;
  }
  const int8_t here = grid.at(wx, wy);
  if (isUnknownCode(here) && !ever_planned_)
  {
    out.status = PlanStatus::IN_UNKNOWN;
    out.message = "the wearer stands in unmapped space: no path until a mapped region is reached";
    return out;
  }
  if (ahead_unknown && out.free_ahead < p_.unknown_ahead_m)
  {
    // The floor just ahead is unmapped, not blocked (after a map reset it lies below the camera's
    // view until the wearer has walked on): "stop" or "step aside" would be a guess.
    char buf[96];
    std::snprintf(buf, sizeof(buf), "unmapped floor %.2f m ahead: cannot tell what is there", out.free_ahead);
    out.status = PlanStatus::IN_UNKNOWN;
    out.message = buf;
    return out;
  }

  // target: explicit goal, else the automatic waypoint
  int gx = -1, gy = -1;
  if (has_goal_ && std::hypot(goal_.x - wearer.x, goal_.y - wearer.y) <= p_.reached_distance)
    has_goal_ = false;  // reached
  if (has_goal_)
  {
    out.explicit_goal = true;
    int cx, cy;
    if (grid.worldToCell(goal_.x, goal_.y, cx, cy) && isTraversableCode(grid.at(cx, cy)))
    {
      gx = cx;
      gy = cy;
    }
    else
    {
      // goal outside the window or not traversable: the reachable free cell nearest to it
      const TriangleSearch all = searchTriangle(grid, wearer, 0.0, 0.0, 0.0);
      double best = 1e300;
      for (int y = 0; y < grid.height; ++y)
        for (int x = 0; x < grid.width; ++x)
          if (all.reached[size_t(grid.index(x, y))] && grid.at(x, y) == CELL_FREE)
          {
            const double d = std::hypot(grid.cellX(x) - goal_.x, grid.cellY(y) - goal_.y);
            if (d < best)
            {
              best = d;
              gx = x;
              gy = y;
            }
          }
    }
    out.triangle = { wearer, wearer, wearer };
  }
  else
  {
    waypoints_.update(grid, wearer, h, motion_changed || !waypoints_.has());
    out.triangle = waypoints_.lastSearch().corners;
    if (waypoints_.has())
      grid.worldToCell(waypoints_.waypoint().x, waypoints_.waypoint().y, gx, gy);
  }
  if (gx < 0 && !has_goal_ && waypoints_.lastSearch().unreachable_free > 0)
  {
    out.status = PlanStatus::NO_PATH;
    out.message = "free space ahead but no free path to it";
    return out;
  }
  if (gx < 0)
  {
    out.status = PlanStatus::NO_WAYPOINT;
    out.message = has_goal_ ? "no reachable free cell near the goal" : "nothing traversable inside the search triangle";
    return out;
  }
  out.has_waypoint = true;
  out.waypoint = { grid.cellX(gx), grid.cellY(gy) };
  out.waypoint_distance = std::hypot(out.waypoint.x - wearer.x, out.waypoint.y - wearer.y);

  // D* Lite: a new goal restarts the search, otherwise the repaired search continues
  // a wearer standing on an obstacle cell (map noise, closing at a wall) starts from the nearest
  // passable cell within 2 cells instead of getting no path at all
  int sx = wx, sy = wy;
  if (isObstacleCode(here))
  {
    double best = 1e300;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx)
      {
        const int x = wx + dx, y = wy + dy;
        if (!grid.inside(x, y) || isObstacleCode(grid.at(x, y)))
          continue;
        const double d = std::hypot(grid.cellX(x) - wearer.x, grid.cellY(y) - wearer.y) +
                         (isUnknownCode(grid.at(x, y)) ? 100.0 : 0.0);
        if (d < best)
        {
          best = d;
          sx = x;
          sy = y;
        }
      }
  }
  dstar_.resetExpansions();
  dstar_.setGoal(gx, gy);
  dstar_.setStart(sx, sy);
  const bool ok = dstar_.plan();
  out.expansions = dstar_.expansions();
  if (!ok)
  {
    out.status = PlanStatus::NO_PATH;
    out.message = isObstacleCode(here) ? "the wearer's cell is an obstacle" : "no free path to the waypoint";
    return out;
  }
  const std::vector<int> cells = dstar_.path();
  out.path.reserve(cells.size() + 1);
  out.path.push_back(wearer);
  for (size_t i = 1; i < cells.size(); ++i)
  {
    const int x = cells[i] % grid.width, y = cells[i] / grid.width;
    out.path.push_back({ grid.cellX(x), grid.cellY(y) });
    if (isUnknownCode(grid.at(x, y)))
      out.path_through_unknown = true;
  }
  if (out.path.size() < 2)
    out.path.push_back(out.waypoint);
  double len = 0.0;
  bool heading_set = false;
  for (size_t i = 1; i < out.path.size(); ++i)
  {
    len += std::hypot(out.path[i].x - out.path[i - 1].x, out.path[i].y - out.path[i - 1].y);
    if (!heading_set && (len >= p_.path_lookahead || i + 1 == out.path.size()))
    {
      const double dx = out.path[i].x - wearer.x, dy = out.path[i].y - wearer.y;
      out.path_heading = (std::hypot(dx, dy) > 1e-6) ? std::atan2(dy, dx) : h;
      heading_set = true;
    }
  }
  out.path_length = len;
  ever_planned_ = true;
  out.status = PlanStatus::OK;
  out.message = out.path_through_unknown ? "path crosses unmapped cells (no known free path)"
                : isObstacleCode(here)   ? "the wearer's cell is an obstacle: path from the nearest free cell"
                                         : "ok";
  return out;
}
}  // namespace assistive_planner
