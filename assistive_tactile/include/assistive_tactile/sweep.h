#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <assistive_common/code_grid.h>

namespace assistive_tactile
{
/// The grid the planner planned on, as the cue logic sees it (issue 33; its `planner/grid`): the
/// one grid of cell codes (assistive_common/code_grid.h), in the frame of the wearer's position
/// (`NavInput::x`, `y`; the state's `wearer`). A cell above 50 is an obstacle.
using ObstacleGrid = assistive_common::CodeGrid;

/// Distance (m) from (x, y) to the nearest obstacle cell's centre in `g`, looked for within `reach`
/// m (`reach` when none). A jamb fills every cell it touches, so its face lies inside the cell,
/// half a cell in on average: the centre is the face's best estimate (the planner's passage width
/// counts the same way).
double obstacleClearance(const ObstacleGrid& g, double x, double y, double reach);

/// The first distance (m) along the ray from (x, y) at `yaw`, in steps of `step` up to `max`, whose
/// cell's code satisfies `stop` (a point outside the grid reads CELL_UNKNOWN); `max` when none.
double alongRayUntil(const ObstacleGrid& g, double x, double y, double yaw, double max, double step,
                     bool (*stop)(int8_t));

/// Free distance (m) from (x, y) across the walk, to the left (`side` +1) or right (-1) of `yaw`,
/// until an obstacle cell (its centre's side of the cell, on the ray in steps of 2 cm), up to `max`.
double sideFree(const ObstacleGrid& g, double x, double y, double yaw, int side, double max);

/// How the wearer is predicted to move (the cue logic fills it from what it learnt of the wearer).
struct WalkModel
{
  double v0 = 0.0;          ///< m/s now
  double pace = 1.4;        ///< m/s it speeds up to while told to walk
  double accel = 1.2;       ///< m/s^2 speeding up (0: it keeps v0)
  double decel = 2.0;       ///< m/s^2 stopping
  double turn_start_s = 0;  ///< the veer being carried out (or asked) starts turning the walk then
  double turn = 0.0;        ///< by this much (rad, + = left) in all
  double turn_rate = 1.0;   ///< at this rate (rad/s)
  /// The turn goes on while it stops (a stop-and-turn buzz: it turns on the spot while it slows);
  /// false: a stop ends what is left of a veer.
  bool turn_while_stopping = false;
  double stop_at_s = 1e9;   ///< its stop begins then (the cue that stops it, felt a reaction late)
  double horizon_s = 4.0;   ///< the prediction ends then (or once it stands)
  /// The prediction's spread: the clearance a point needs grows by this per metre walked to it
  /// (never beyond the clearance the body has now less 3 cm); 0 = the radius alone.
  double spread_per_m = 0.0;
};

/// The body's disc swept along a predicted walk (`sweepWalk`).
struct SweepResult
{
  bool hit = false;          ///< the disc comes closer to an obstacle than allowed
  double hit_t = 1e9;        ///< s from now when it does
  double hit_along = 1e9;    ///< m walked by then
  double walked = 0.0;       ///< m walked over the whole prediction (until the hit, if any)
  double min_clear = 1e9;    ///< the smallest clearance (m) met (centre to the nearest obstacle cell centre)
  double end_x = 0.0, end_y = 0.0, end_yaw = 0.0;  ///< where the prediction ends (at the hit, if any)
};

/**
 * The body's disc (radius `radius`) carried along the walk `m` from (x, y, yaw) in steps of `dt`,
 * checked against `g`'s obstacle cells: a hit is a point of the walk whose clearance is under
 * `radius` (plus `m.spread_per_m` per metre walked to it), and under the clearance where the body
 * stands now less 3 cm (a body that already stands closer than `radius` to a jamb, in a doorway,
 * is stopped only when the walk takes it closer still, not at once).
 */
SweepResult sweepWalk(const ObstacleGrid& g, double x, double y, double yaw, const WalkModel& m, double radius,
                      double dt = 0.05);

/// A point on the ground (x, y), in the frame of the grid.
using GroundPoint = std::array<double, 2>;

/// The next corner of the path ahead (issue 33: a corner taken walking).
struct PathCorner
{
  bool found = false;
  double x = 0.0, y = 0.0;   ///< where the path turns
  double heading_in = 0.0;   ///< the path's direction before it: from the start point to it (rad)
  double heading_out = 0.0;  ///< and after it (rad)
  double leg_out = 0.0;      ///< m the path runs on straight after it (to its next corner or its end)
};

/**
 * The first corner of `path` seen from (x, y): the path from its point nearest (x, y) (searched
 * within its first `search_m` m) on, with (x, y) put first, cut after `max_m` m and simplified
 * (Douglas-Peucker: no point of the path further than `tolerance` m from the simplified one); the
 * simplified path's second point when it has a third. Corners joined by a leg shorter than
 * `merge_m` count as one, where the leg in and the last leg out meet. Not found: the path runs
 * straight on.
 */
PathCorner nextCorner(const std::vector<GroundPoint>& path, double x, double y, double tolerance, double max_m,
                      double merge_m = 0.6, double search_m = 3.0);

}  // namespace assistive_tactile
