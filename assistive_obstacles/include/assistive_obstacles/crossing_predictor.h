#pragma once
// Crossing prediction (issue 22): the wearer and each tracked mover walk on at constant velocity;
// their closest approach within a horizon decides whether the wearer is warned, and to which side
// to step. ROS-free; not wired into the planner / cues yet.
//
// Relative position r0 = p_mover - p_wearer, relative velocity vr = v_mover - v_wearer.
// Closest approach time t* = clamp(-r0.vr / |vr|^2, 0, horizon), distance d* = |r0 + vr t*|.
// A mover is a threat only when it closes in (closing speed -r0.vr / |r0| > min_closing_speed),
// so people walking alongside or away never warn. Warning when
//   d* - sigma_scale * sigma* < warn_distance                    (a crossing), or
//   d* < head_on_distance and the mover walks against the wearer  (head-on: its velocity within
//                                                                  head_on_angle of -heading),
// sigma* = the track's position sigma propagated to t*, across the line of closest approach.
// Side: a mover crossing the wearer's path (lateral speed >= cross_speed) is passed behind: step
// to the side it comes from; otherwise (head-on, overtaking) step away from the side it passes
// on (the right on a dead-centre course: keep_right). STOP when the approach is nearer than
// stop_time (no time to sidestep) or the chosen side is blocked.
#include <vector>

#include <Eigen/Core>

#include <assistive_obstacles/mover_tracker.h>

namespace assistive_obstacles
{
struct CrossingParams
{
  double horizon = 3.0;            ///< s, prediction horizon
  double warn_distance = 0.5;      ///< m, closest approach that warns
  double head_on_distance = 1.0;   ///< m, closest approach that warns for a mover walking against the wearer
  double head_on_angle = 0.785398; ///< rad (45 deg), mover heading within this of the wearer's reverse = head-on
  double min_closing_speed = 0.1;  ///< m/s, movers closing in slower than this never warn (alongside, away)
  double sigma_scale = 0.0;        ///< sigmas of track uncertainty subtracted from d* (0: the mean path only)
  double cross_speed = 0.3;        ///< m/s, lateral speed (relative to the wearer's heading) that makes a crossing
  double stop_time = 1.0;          ///< s, closest approach sooner than this: STOP instead of a side
  bool keep_right = true;          ///< dead-centre head-on course: step right (else left)
};

enum class AvoidSide
{
  NONE,   ///< no warning
  LEFT,
  RIGHT,
  STOP
};

struct Wearer
{
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< m, world
  double heading = 0.0;                                ///< rad, world yaw of the walking direction
  double speed = 0.0;                                  ///< m/s
  bool left_blocked = false, right_blocked = false;    ///< the map has no room on that side (from the planner)
};

struct CrossingPrediction
{
  int track_id = 0;
  double t_closest = 0.0;   ///< s, in [0, horizon]
  double d_closest = 0.0;   ///< m, mean path
  double sigma = 0.0;       ///< m, position sigma at t_closest across the line of closest approach
  double closing_speed = 0.0;  ///< m/s, now (> 0: approaching)
  bool head_on = false;
  bool warn = false;
  AvoidSide side = AvoidSide::NONE;
};

class CrossingPredictor
{
public:
  explicit CrossingPredictor(const CrossingParams& p = CrossingParams()) : params_(p) {}
  void setParams(const CrossingParams& p) { params_ = p; }
  const CrossingParams& params() const { return params_; }

  /// One mover against the wearer.
  CrossingPrediction predict(const Wearer& w, const MoverTrack& track) const;
  /// Every track; the result is in the tracks' order.
  std::vector<CrossingPrediction> predict(const Wearer& w, const std::vector<MoverTrack>& tracks) const;
  /// The most urgent warning (smallest t_closest among the warned), or nullptr when none warns.
  static const CrossingPrediction* mostUrgent(const std::vector<CrossingPrediction>& predictions);

private:
  CrossingParams params_;
};

}  // namespace assistive_obstacles
