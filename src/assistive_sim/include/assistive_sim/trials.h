#pragma once
// Closed-loop mobility trials (issue 19; seed 5.4-5.5): a simulated wearer walks a world's course
// on the vest's cues (or with a cane) from a randomised start; collisions by obstacle kind,
// completion, time, percentage of preferred walking speed (PPWS, seed 5.5.2.2) against a
// sighted-guide walk from the same start, clearance, and the path for the heat maps.
// `truth` mode feeds the world's occupancy to the real planner and cue logic cores (no ROS).
// ROS-free.
#include <array>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include <assistive_planner/params.h>
#include <assistive_sim/wearer.h>
#include <assistive_tactile/params.h>

namespace assistive_sim
{
enum class TrialMode
{
  TRUTH,  ///< ground-truth occupancy -> planner core -> cue logic core -> vest wearer
  CANE    ///< cane-only walker
};

struct TrialOptions
{
  TrialMode mode = TrialMode::TRUTH;
  WearerParams wearer;
  CaneParams cane;
  assistive_planner::PlannerParams planner;
  assistive_tactile::CueParams cues;
  double rate_hz = 15.0;        ///< planner + cue rate (the camera's frame rate)
  double dt = 1.0 / 60.0;       ///< s, body simulation step
  double start_jitter_m = 0.3;  ///< start position: uniform in this radius around the course's start
  double start_yaw_deg = 20.0;  ///< start heading: +- this around the way to the first place
  double goal_radius_m = 1.0;   ///< a place of the route counts as reached this close
  double timeout_factor = 4.0;  ///< a trial ends unfinished after this x the sighted guide's time (+ 20 s)
  bool cues_enabled = true;     ///< false: the cue stage is removed from the chain (vest silent)
};

struct TrialResult
{
  int index = 0;
  uint32_t seed = 0;
  BodyState start;
  bool completed = false;
  double time_s = 0.0;        ///< to completion (or the timeout)
  double guide_time_s = 0.0;  ///< sighted guide from the same start
  double ppws_pct = 0.0;      ///< guide time / time x 100 (0 when not completed)
  std::array<int, size_t(ObstacleKind::NUM_KINDS)> collisions{};
  int totalCollisions() const;
  double mean_clearance_m = 0.0;  ///< body surface to the nearest obstacle, mean over the walk
  double min_clearance_m = 0.0;
  std::array<int, 5> cue_modes{};  ///< planner/cue cycles per CueMode (IDLE .. UNSURE)
  std::vector<Eigen::Vector2d> path;      ///< body positions, one per body step
  std::vector<Eigen::Vector2d> collision_places;
};

/// The course of a world: its script's waypoints (start, then the places to walk through).
std::vector<Eigen::Vector2d> courseOf(const World& world);

/// One trial, deterministic in `seed` (start pose, the wearer's choices).
TrialResult runTrial(const World& world, const TrialOptions& opt, uint32_t seed, int index = 0);

/// Heat map in the style of the seed's figures 5.9 / 5.21: the floor plan from above (obstacles
/// grey, glass blue), time spent per place in red (brighter = longer, summed over the trials),
/// collisions as yellow crosses, the course's places as green dots. `px_per_m` sets the scale.
cv::Mat heatMap(const World& world, const std::vector<TrialResult>& trials, double dt, const std::string& title,
                double px_per_m = 40.0);

}  // namespace assistive_sim
