#pragma once

#include <array>
#include <vector>

#include "assistive_planner/grid.h"
#include "assistive_planner/params.h"

namespace assistive_planner
{
/// Traversable cells reachable from the apex through the whole grid (8-connected, no corner cutting past
/// obstacles, unknown is not traversable) that lie inside a triangle: apex at the wearer, axis along `yaw`,
/// `length` to the base, apex half-angle `half_angle` (rad). length <= 0: the whole grid.
struct TriangleSearch
{
  bool found = false;     ///< a free cell other than the apex cell was reached
  int x = 0, y = 0;       ///< the farthest reachable free cell along the axis (ties: nearest to the axis)
  double distance = 0.0;  ///< apex -> that cell (m)
  size_t cells = 0;       ///< reachable traversable cells (the free area, in cells)
  double area = 0.0;      ///< m^2
  size_t unreachable_free = 0;  ///< free cells inside the triangle walled off (not even through unmapped cells)
  size_t free_behind_unknown = 0;  ///< free cells inside the triangle reachable only through unmapped cells
  std::vector<char> reached;  ///< per grid cell
  std::array<Point2, 3> corners;  ///< apex, left base corner, right base corner
};
TriangleSearch searchTriangle(const Grid& grid, const Point2& apex, double yaw, double length, double half_angle);

/// Waypoint rules (seed 4.3.1): the farthest traversable cell in the search triangle around the motion
/// vector; a new waypoint replaces the current one only if the free area leading to it is larger
/// (switch_area_ratio), or the current one is gone (no longer free or reachable, out of the grid, reached,
/// or more than abandon_angle off the motion vector, e.g. after a turn-around).
class WaypointSelector
{
public:
  explicit WaypointSelector(const PlannerParams& p = PlannerParams()) : p_(p) {}
  /// Returns true if a waypoint is set after the update. `reconsider`: the motion vector changed (moved
  /// more than 1 m or turned more than 15 degrees), so a new candidate may replace a still valid waypoint;
  /// otherwise a valid waypoint is kept as is (seed 4.4: the waypoint is recomputed when the user has moved
  /// significantly or changed orientation).
  bool update(const Grid& grid, const Point2& wearer, double heading, bool reconsider = true);
  void reset() { has_ = false; }
  bool has() const { return has_; }
  const Point2& waypoint() const { return waypoint_; }
  double area() const { return area_; }              ///< free area leading to the current waypoint (m^2)
  bool switched() const { return switched_; }        ///< the last update picked a new waypoint
  const TriangleSearch& lastSearch() const { return last_; }
  /// Free area leading to a point: reachable cells in the triangle from the wearer towards it (m^2, <0: unreachable).
  double areaTo(const Grid& grid, const Point2& wearer, const Point2& target) const;

private:
  PlannerParams p_;
  bool has_ = false;
  bool switched_ = false;
  Point2 waypoint_;
  double area_ = 0.0;
  TriangleSearch last_;
};
}  // namespace assistive_planner
