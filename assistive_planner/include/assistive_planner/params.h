#pragma once

namespace assistive_planner
{
/// All planner parameters. The initializers are the only defaults (README table matches).
struct PlannerParams
{
  // Motion vector (seed 4.3.1)
  double motion_update_distance = 1.0;   ///< m, the previous position moves only after this travel
  double heading_update_angle = 15.0;    ///< deg, the heading follows the head only beyond this yaw change

  // Waypoint search triangle
  double triangle_length = 4.0;          ///< m, apex (wearer) to base
  double triangle_half_angle = 30.0;     ///< deg, half the apex angle
  double switch_area_ratio = 1.0;        ///< a new waypoint replaces the current one only if its free area > ratio * current
  double abandon_angle = 90.0;           ///< deg, a waypoint this far off the motion vector is given up (turn-around)
  double reached_distance = 0.5;         ///< m, a waypoint this close is reached and replaced

  // Costs
  double step_cost = 2.0;                ///< extra cost per unit length on step/curb cells (free = 1)
  double clearance_weight = 2.0;         ///< extra cost at an obstacle's side, decaying to 0 at clearance_radius
  double clearance_radius = 0.6;         ///< m
  bool unknown_traversable = true;       ///< unknown cells: a last resort at a cost above any known path (false: blocked)

  // Outputs
  double path_lookahead = 1.0;           ///< m along the path for path_heading
  double free_ray_max = 5.0;             ///< m, longest free-distance ray
  double unknown_ahead_m = 1.0;          ///< m: unmapped floor (not an obstacle) closer ahead -> IN_UNKNOWN (vest quiet)

  // Node
  double grid_timeout = 2.0;             ///< s of wall time without any grid -> NO_MAP (the last line of defence)
  bool use_odom = true;                  ///< judge the VO's trust (vo/odom covariance) and freshness, not only tf's age
  double max_input_age_s = 0.5;          ///< s: grid or pose lagging the newest camera frame by more -> NO_MAP / NO_POSE
  double max_frame_gap_s = 0.5;          ///< s: a longer pause between poses, or time going back, resets the planner
  double camera_height = 1.6;            ///< m, informational: the pose is projected onto the ground (z = 0)
};
}  // namespace assistive_planner
