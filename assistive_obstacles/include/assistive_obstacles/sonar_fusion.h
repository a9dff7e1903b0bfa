#pragma once
// The vest's forward ultrasonic ranger (sensor_msgs/Range `sonar/front`, issue 20) fused into the
// obstacle map. A stereo camera sees through clean glass; sound reflects off it. ROS-free.
//
// - An echo at range r is obstacle evidence in every cell the cone's arc at r crosses above the
//   floor (feet + step_height .. camera + head_clearance), voted into the same temporal filter as
//   the camera's labels (`sonar_hit_votes` full-weight votes per reading and cell).
// - Only an echo the camera cannot explain counts: when a cell the map already holds as an obstacle
//   lies on the arc (or half a cell beyond), or the camera's last frame has points in the cone at
//   the echo's range (an opaque surface not mapped yet), the echo is that surface, and the arc's
//   other cells are most likely the free space in front of an oblique wall: no votes, no holds.
// - Those cells are HELD: from then on camera free / step votes skip them (camera rays that
//   passed through a panel never free it).
// - A hold ends only when the ranger itself sees through the cell: `sonar_release_readings`
//   echoes from beyond it (the cell inside the inner half of the cone, nearer than the echo by
//   `sonar_release_margin`). "No echo" never ends a hold: a flat panel seen at a grazing angle
//   sends the echo away and returns nothing, which cannot be told from open space.
// - An echo whose arc reaches below feet + step_height may be the floor: no evidence.
// - Bad input (NaN, -Inf, out of the sensor's limits, a field of view outside (0, 90 deg)) is
//   rejected by check() and never used; +Inf is "no echo within max_range" (REP 117).
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include <assistive_obstacles/elevation_map.h>
#include <assistive_obstacles/params.h>
#include <assistive_obstacles/temporal_filter.h>

namespace assistive_obstacles
{
/// One ranger reading with its pose (x forward along the cone's axis) in the map's world frame.
struct RangeReading
{
  double range = 0.0;          ///< m; +inf = no echo within max_range
  double min_range = 0.2;      ///< m, the sensor's limits
  double max_range = 4.0;
  double field_of_view = 0.26; ///< rad, full cone angle
  Eigen::Isometry3f T_world_sensor = Eigen::Isometry3f::Identity();
};

/// Verdict of SonarFusion::check.
enum class RangeCheck : uint8_t
{
  ECHO = 0,      ///< a range within the limits: evidence
  NO_ECHO,       ///< +inf: nothing within max_range (no evidence either way)
  NOT_A_NUMBER,  ///< NaN range or limits
  OUT_OF_LIMITS, ///< below min_range, above max_range, -inf, or limits that make no sense
  BAD_FOV,       ///< field of view not in (0, 90 deg)
};
const char* rangeCheckName(RangeCheck c);

/// What the last apply() did (diagnostics, tests).
struct SonarStats
{
  int arc_cells = 0;       ///< cells voted obstacle
  int released = 0;        ///< holds the ranger ended by seeing through
  bool floor_ambiguous = false;  ///< the arc reached the floor: no evidence
  bool explained = false;  ///< an obstacle the map already has lies on the arc: no new evidence
  size_t held = 0;         ///< holds now
};

class SonarFusion
{
public:
  explicit SonarFusion(const ObstaclesParams& p = ObstaclesParams()) : params_(p) {}
  void setParams(const ObstaclesParams& p) { params_ = p; }

  static RangeCheck check(const RangeReading& r);

  /// Fuses one reading into `filter` within `window`; `feet` = floor height under the wearer,
  /// `z_top` = highest point that can touch the wearer. Returns the reading's check (only ECHO
  /// changes anything).
  /// `camera_surface`: the camera's last frame holds a surface in the cone at the echo's range
  /// (ObstacleMap checks its points): the echo is explained.
  RangeCheck apply(const RangeReading& r, const Window& window, float feet, float z_top, TemporalFilter& filter,
                   bool camera_surface = false);

  /// Whether a camera free vote on global cell (gx, gy) must be skipped (the ranger hit it).
  bool held(int gx, int gy) const { return !holds_.empty() && holds_.count(key(gx, gy)) > 0; }
  /// Forgets holds outside the window (it scrolled away).
  void retain(const Window& w);
  void clear() { holds_.clear(); }
  const SonarStats& stats() const { return stats_; }

private:
  static int64_t key(int gx, int gy)
  {
    return static_cast<int64_t>((static_cast<uint64_t>(static_cast<uint32_t>(gx)) << 32) | static_cast<uint32_t>(gy));
  }
  /// Points on the cone at distance `dist` within `half_angle` of the axis, sampled finely enough
  /// to touch every cell they cross.
  void conePoints(const RangeReading& r, double dist, double half_angle, std::vector<Eigen::Vector3f>& out) const;

  ObstaclesParams params_;
  std::unordered_map<int64_t, uint8_t> holds_;  ///< held cell -> see-through readings so far
  SonarStats stats_;
  std::vector<Eigen::Vector3f> scratch_;
};

}  // namespace assistive_obstacles
