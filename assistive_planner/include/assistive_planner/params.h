#pragma once
// All planner parameters: ONE table (assistive_common/param_table.h). Each row is the field, its
// ROS parameter name, default, range, unit and text; the nodelet reads every row, clamps by the
// ranges and README.md lists them (test_params).
#include <string>

#include <assistive_common/param_table.h>

namespace assistive_planner
{
// clang-format off
// X(type, field, ROS name, default, lo, hi, unit, text)
#define ASSISTIVE_PLANNER_PARAMS(X) \
  /* Motion vector (seed 4.3.1) */ \
  X(double, motion_update_distance, "motion_update_distance", 1.0, 0.05, 10.0, "m", "the previous position moves only after this travel") \
  X(double, heading_update_angle, "heading_update_angle", 15.0, 0.0, 180.0, "deg", "the heading follows the head only beyond this yaw change") \
  X(double, heading_chord_min, "heading_chord_min", 0.3, 0.0, 10.0, "m", "once the wearer has walked this far from the anchor the heading is the walked chord (updated every cycle), not the head yaw of the last head-turn update; 0 = only after `motion_update_distance`") \
  /* Waypoint search triangle */ \
  X(double, triangle_length, "triangle_length", 4.0, 0.2, 20.0, "m", "search triangle: apex (wearer) to base") \
  X(double, triangle_half_angle, "triangle_half_angle", 30.0, 1.0, 89.0, "deg", "half the apex angle") \
  X(double, switch_area_ratio, "switch_area_ratio", 1.0, 0.0, 100.0, "", "a new waypoint replaces the current one only if its free area > ratio x current") \
  X(double, abandon_angle, "abandon_angle", 90.0, 0.0, 180.0, "deg", "a waypoint this far off the motion vector is given up (turn-around)") \
  X(double, reached_distance, "reached_distance", 0.5, 0.0, 5.0, "m", "a waypoint this close is reached and replaced") \
  /* Costs */ \
  X(double, step_cost, "step_cost", 2.0, 0.0, 1000.0, "per cell length", "extra cost on step/curb cells (free = 1)") \
  X(double, clearance_weight, "clearance_weight", 2.0, 0.0, 1000.0, "per cell length", "extra cost at an obstacle's side, decaying to 0 at `clearance_radius`") \
  X(double, clearance_radius, "clearance_radius", 0.6, 0.0, 5.0, "m", "reach of the clearance cost") \
  X(double, inflation_radius, "inflation_radius", 0.25, 0.0, 2.0, "m", "the body's radius: a cell whose centre lies closer than this plus half a cell to an obstacle cell's centre is not passable (a 0.80 m doorway keeps at least one passable cell on 0.2 m cells; 0 = off)") \
  X(bool, unknown_traversable, "unknown_traversable", true, {}, {}, "", "unknown cells: a last resort at a cost above any known path (false: blocked)") \
  /* Outputs */ \
  X(double, path_lookahead, "path_lookahead", 1.0, 0.05, 10.0, "m", "along the path for `path_heading`") \
  /* Steering (pure pursuit on the path, issue 33) */ \
  X(double, steer_lookahead_s, "steer_lookahead_s", 1.4, 0.0, 5.0, "s", "the steering point lies this many seconds of walking ahead on the path (regulated pure pursuit), within the two bounds below") \
  X(double, steer_lead_s, "steer_lead_s", 0.6, 0.0, 3.0, "s", "the steering point is looked up from where the walk takes the wearer in this time (a cue acts only after the wearer's reaction, 0.3-1.2 s): turns are cued before the corner") \
  X(double, steer_lookahead_min, "steer_lookahead_min", 0.3, 0.05, 5.0, "m", "nearest steering point (standing, slow)") \
  X(double, steer_lookahead_max, "steer_lookahead_max", 1.8, steer_lookahead_min, 5.0, "m", "farthest steering point (fast walking)") \
  X(double, path_refine_m, "path_refine_m", 0.5, 0.0, 2.0, "m", "the path's points are moved (on a 5 cm distance field, at most half a cell) towards the middle of a passage until this far from the nearest obstacle cell: the middle of doorways and aisles, finer than the cells (0 = off)") \
  X(double, passage_width_m, "passage_width_m", 1.3, 0.0, 5.0, "m", "a doorway or gap on the path narrower than this (`findPassage`'s width: the free cells' gap across the path plus one cell; 1.3 m: up to 1.0 m of free cells, doorways and the narrowed aisles of 1.2-1.5 m, as before the width counted the jambs' half cells: at 1.1 m, shops and offices 4001-4020 lost the routine in their aisles, furniture collisions while standing 5 -> 31) is a passage: `passage_*` of the state, for the cue logic's stop-and-align (0 = off)") \
  X(double, passage_range_m, "passage_range_m", 3.0, 0.0, 10.0, "m", "passages are looked for this far along the path ahead") \
  X(double, walk_window_s, "walk_window_s", 0.4, 0.05, 5.0, "s", "the walking direction and speed are the chord of the wearer's positions over this last window") \
  X(double, free_ray_max, "free_ray_max", 5.0, 0.1, 50.0, "m", "longest free-distance ray") \
  X(double, body_half_width, "body_half_width", 0.0, 0.0, 1.0, "m", "> 0: `free_ahead` is the free length of the strip the body sweeps (this half-width either side of the motion vector): the line, and every cell that is not free whose centre lies in the strip ahead of the body's front arc; 0 (default) = the line alone: at 0.25 the fault suite saw false ALERTs on map noise at 0.84-1.04 m") \
  /* after a map reset (a fault, a gap) the floor just ahead lies below the camera's view until the */ \
  /* wearer has walked on: unseen floor must not read as an obstacle to the cue logic */ \
  X(double, unknown_ahead_m, "unknown_ahead_m", 1.0, 0.0, 5.0, "m", "when the ray ahead ends in unmapped floor (not at an obstacle) closer than this, the status is `IN_UNKNOWN` (vest quiet) instead of a proximity or stop cue decided on floor nobody has seen (0 switches it off)") \
  /* the wearer stands on the floor under its feet: unseen at the start (below the camera's view) */ \
  X(double, footprint_radius_m, "footprint_radius_m", 0.25, 0.0, 2.0, "m", "unknown cells whose centre lies within this of a place the wearer has stood since the last reset (the body's footprint, radius 0.25 m) count as free floor; cells ahead that nobody has seen or walked stay unknown (0 switches it off)") \
  /* the blind zone (issue 34): the floor nearer than about 1.9 m ahead lies below the camera's view; */ \
  /* at the start and after a map reset nobody has mapped it, and a standing wearer never will */ \
  X(double, blind_zone_m, "blind_zone_m", 2.0, 0.0, 5.0, "m", "unknown cells nearer than this ahead (the camera's nearest floor: eye 1.6 m, pitched 15 deg down, vertical half field of view 25 deg: 1.9 m) count as free floor when the device vouches for them: a fresh ranger reading heard nothing nearer, nothing known before them on the ray from the wearer is other than free, and the camera saw something (floor, obstacle) past them within this plus one cell (README, the blind zone; 0 switches it off)") \
  X(double, blind_zone_half_angle_deg, "blind_zone_half_angle_deg", 30.0, 0.0, 90.0, "deg", "the blind zone is vouched for within this of the head's facing (the camera's horizontal half field of view is 33 deg); keep it at least the cue logic's `stand_turn_deg`: a standing wearer whose way lies farther off is turned on the spot first, and the floor that way is judged once it faces it") \
  X(double, blind_zone_view_m, "blind_zone_view_m", 1.0, 0.0, 5.0, "m", "a blind-zone cell is vouched for only when the camera mapped something (floor or what stands on it) on the ray through it within this beyond `blind_zone_m` (at least one cell): the camera works at that bearing (not dark, not bare); the floor's first rows past the zone are thin and often undecided") \
  X(double, ranger_max_age_s, "ranger_max_age_s", 0.5, 0.05, 10.0, "s", "a ranger reading vouches for the blind zone only while its stamp lies this close to the grid's camera time") \
  X(double, unseen_hold_s, "unseen_hold_s", 3.0, 0.0, 60.0, "s", "a standing wearer kept this long on `IN_UNKNOWN` by unmapped floor just ahead along its way (below the camera's view, or hidden behind what it stopped at: it is never seen from where the wearer stands) has that floor taken for an obstacle (planned around, and the way ahead ends at it), until it is mapped or the wearer is `blind_zone_m` (at least `unknown_ahead_m`) away from it; the way round goes over known floor, and from there the camera sees it (vision trial on `plaza`: 65 s on `IN_UNKNOWN` beside a sign until the timeout); 0 = off") \
  /* a step or curb (a floor level change the wearer can climb, CELL_STEP) stops a walker like an */ \
  /* obstacle; held for good it stood a wearer before phantom steps on a plain floor for the rest of */ \
  /* the trial (vision trials: gen_office_2305, the floor's stereo read as steps) */ \
  X(double, step_stand_s, "step_stand_s", 2.0, 0.0, 60.0, "s", "a wearer standing this long with the body's strip ahead ending at a step or curb (`CELL_STEP`) within `step_cross_m` is sent over it: the step cells within `step_cross_m` ahead count as free floor for what lies ahead until the wearer is 1 m farther than that from them (the stop was the warning; the cane finds the edge); 0 = a step stops the wearer for good") \
  X(double, step_cross_m, "step_cross_m", 1.5, 0.1, 5.0, "m", "reach of that: a step nearer than this ahead holds a standing wearer's stop, and the step cells this near ahead are crossed") \
  /* People crossing (CrossingWatch, issue 22): obstacles/movers + assistive_obstacles' CrossingPredictor */ \
  X(double, crossing_max_age_s, "crossing_max_age_s", 0.5, 0.05, 10.0, "s", "movers whose stamp lies further than this from the planning cycle's camera time, or none received: `CROSSING_NONE` (never a stale warning)") \
  X(double, crossing_side_free_m, "crossing_side_free_m", 0.6, 0.0, 10.0, "m", "a side whose free distance is below this is blocked: a crossing whose avoiding side it is gives `CROSSING_STOP`") \
  X(double, crossing_sticky_s, "crossing_sticky_s", 3.0, 0.0, 30.0, "s", "a person advised a side (`CROSSING_LEFT` / `RIGHT`) keeps it while advised again within this, unless that side is blocked: a track's jitter never flips the side-step under way (issue 37); 0 = each cycle judged afresh") \
  X(double, crossing_speed_window_s, "crossing_speed_window_s", 1.0, 0.1, 10.0, "s", "the wearer's walking speed is the distance walked over the poses of this last window (0 while they span less than half of it)") \
  /* Trust in the inputs (InputMonitor) */ \
  X(double, max_input_age_s, "max_input_age_s", 0.5, 0.05, 10.0, "s", "grid or pose lagging the newest camera frame by more -> `NO_MAP` / `NO_POSE`") \
  X(double, max_frame_gap_s, "max_frame_gap_s", 0.5, 0.05, 60.0, "s", "a longer pause between poses, or time going back, resets the planner")

// The nodelet's own parameters.
#define ASSISTIVE_PLANNER_NODE_PARAMS(X) \
  X(std::string, world_frame, "world_frame", "odom", {}, {}, "", "frame the planner runs in; the grid must be in it") \
  X(std::string, camera_frame, "camera_frame", "camera_link", {}, {}, "", "the wearer's head") \
  X(double, grid_timeout, "grid_timeout", 2.0, 0.05, 60.0, "s", "wall time without any grid -> `NO_MAP` (the last line of defence)") \
  X(double, goal_tf_max_age, "goal_tf_max_age", 1.0, 0.05, 60.0, "s", "an explicit goal's frame whose newest transform to `world_frame` is older than this against the grid (SLAM no longer places the wearer) -> `NO_POSE`; static frames never age") \
  X(bool, use_odom, "use_odom", true, {}, {}, "", "judge the VO's trust and the grid's freshness against `vo/odom`; false trusts tf alone (tests that publish tf without a VO)")
// clang-format on

/// All planner parameters. The table's initializers are the only defaults (README table matches).
struct PlannerParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_PLANNER_PARAMS)
};

struct PlannerNodeParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_PLANNER_NODE_PARAMS)
};
}  // namespace assistive_planner
