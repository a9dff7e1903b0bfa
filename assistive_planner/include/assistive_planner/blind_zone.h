#pragma once
// The blind zone: the floor just ahead of the wearer that the head-mounted camera cannot see (at
// 1.6 m, pitched 15 deg down, vertical half field of view about 25 deg, its nearest floor lies about
// 1.9 m ahead). At the start and after every map reset nobody has mapped it; a standing wearer
// never will. The device vouches for it only on evidence it has (README "The blind zone"). ROS-free.
#include <cmath>
#include <limits>

#include "assistive_planner/grid.h"

namespace assistive_planner
{
/// The forward ultrasonic ranger's newest reading (sensor_msgs/Range on `sonar/front`), as the
/// planner judges it.
struct RangerReading
{
  double stamp = std::numeric_limits<double>::quiet_NaN();  ///< camera clock (s); NaN: no reading
  double range = std::numeric_limits<double>::infinity();   ///< m; +Inf: no echo within max_range
  double max_range = 0.0;                                   ///< m: the farthest echo it can hear
  double yaw = std::numeric_limits<double>::quiet_NaN();    ///< its axis in the planner's frame (rad)
  double field_of_view = 0.0;                               ///< its cone's full angle (rad; 0: unknown)

  /// A reading the planner may use: a stamp, a finite axis, a positive max_range, and a range that
  /// is +Inf (no echo) or within (0, max_range].
  bool valid() const
  {
    return std::isfinite(stamp) && std::isfinite(yaw) && std::isfinite(max_range) && max_range > 0.0 &&
           (range == std::numeric_limits<double>::infinity() || (std::isfinite(range) && range > 0.0 && range <= max_range));
  }
  /// How far along its axis nothing echoed: the echo's range, or max_range without an echo; 0 when
  /// not valid().
  double clearDistance() const
  {
    if (!valid())
      return 0.0;
    return std::isfinite(range) ? range : max_range;
  }
};

/// Vouches for the blind zone: every unknown cell of `grid` whose centre lies within `zone_m` of
/// the wearer, within `half_angle` (rad) of `facing` (the way the camera points; a cell partly inside
/// counts: the cells next to the body subtend tens of degrees) and nearer than the ranger's clear
/// distance less one cell (it heard nothing nearer), becomes free, when along the ray from the
/// wearer through it (1) no cell before it is known and not free (never behind an obstacle or a
/// step) and (2) something past it is known: a known cell follows within `zone_m` plus `view_m`
/// (at least one cell: the camera saw at that bearing past the zone, the floor or what stands on
/// it), or the ray lies in the ranger's cone and the ranger heard an echo within `zone_m` plus one
/// cell (a solid there, nothing nearer, e.g. a plain wall the camera gets no depth from). An echo
/// within the zone is also what the obstacle stage makes of it: the unknown cells on its arc (centre
/// within half a cell of the range, inside the cone) become obstacles, so the way ahead ends at a
/// solid, not at "cannot tell". The caller checks the reading's age and axis. Judged on the grid as
/// given (a cell vouched for is no evidence for another). Returns the number of cells changed; 0
/// when zone_m or half_angle is not positive or the reading is not valid().
int vouchBlindZone(Grid& grid, const Point2& wearer, double facing, const RangerReading& ranger, double zone_m,
                   double half_angle, double view_m = 1.0);
}  // namespace assistive_planner
