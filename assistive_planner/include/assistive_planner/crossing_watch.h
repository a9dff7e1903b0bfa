#pragma once
// People crossing the wearer's way (issue 22): the planner's side of the crossing warning. The
// obstacle stage tracks movers (obstacles/movers: confirmed tracks, world frame, every frame); each
// planning cycle this class runs the CrossingPredictor (assistive_common/crossing_predictor.h, the
// one place of the prediction, shared with the obstacle stage's benchmark: constant-velocity
// closest approach within its horizon, a side or STOP) with the
// wearer as the planner knows it: position, the motion vector's heading, the walking speed from
// the recent poses, and each side blocked when the planner's own free distance to that side is
// under `crossing_side_free_m`. Movers older than `crossing_max_age_s` against the cycle's camera
// time (or none ever received) give no advice: never a stale warning. ROS-free.
#include <deque>
#include <map>
#include <utility>
#include <vector>

#include <assistive_common/codes.h>
#include <assistive_common/crossing_predictor.h>

#include "assistive_planner/grid.h"
#include "assistive_planner/params.h"

namespace assistive_planner
{
using assistive_common::CrossingAdvice;
using assistive_common::CrossingParams;
using assistive_common::CrossingPredictor;
/// A tracked mover: id, (x, y, vx, vy) in the world frame, its 4x4 covariance.
using assistive_common::MoverState;

/// The most urgent crossing at one planning cycle.
struct CrossingResult
{
  CrossingAdvice advice = CrossingAdvice::NONE;
  int id = 0;               ///< mover behind the advice (0: none)
  double time = 0.0;        ///< s until the closest approach (0 when NONE)
  double distance = 0.0;    ///< m, predicted closest distance (0 when NONE)
  bool movers_fresh = false;  ///< the movers were recent enough to judge
  int movers = 0;           ///< movers judged (0 when not fresh)
  double wearer_speed = 0.0;  ///< m/s, used for the prediction
  Point2 mover;             ///< the warned mover now (at the cycle's time)
  Point2 mover_at_closest;  ///< ... and at the closest approach
  Point2 wearer_at_closest; ///< the wearer at the closest approach
};

using assistive_common::crossingName;

class CrossingWatch
{
public:
  explicit CrossingWatch(const PlannerParams& p = PlannerParams(),
                         const CrossingParams& cp = CrossingParams());

  /// The movers known at camera time `stamp` (s): confirmed tracks in the planner's world frame.
  /// Replaces the previous set (an empty set is news too: nobody around).
  void setMovers(double stamp, std::vector<MoverState> movers);
  /// Forget the movers (e.g. in a frame the planner does not run in): no advice until new ones.
  void clearMovers();
  bool haveMovers() const { return have_movers_; }
  double moversStamp() const { return movers_stamp_; }

  /// The wearer at camera time `t` (s). Time going back forgets the earlier poses.
  void addPose(double t, const Point2& p);
  /// Walking speed (m/s): the distance between the newest pose and the oldest within
  /// `crossing_speed_window_s` of it, over their time apart; 0 while they span less than half the
  /// window (at the start, after a reset).
  double speed() const;

  /// The advice at camera time `t` for a wearer at `wearer` walking along `heading` (rad) with
  /// `free_left` / `free_right` (m) of free floor to its sides. The movers are carried at constant
  /// velocity from their stamp to `t` first. A person advised a side keeps it while advised again
  /// within `crossing_sticky_s`, unless that side is blocked (the side per person id is kept).
  CrossingResult check(double t, const Point2& wearer, double heading, double free_left, double free_right);

  const CrossingPredictor& predictor() const { return predictor_; }

private:
  PlannerParams p_;
  CrossingPredictor predictor_;
  bool have_movers_ = false;
  double movers_stamp_ = 0.0;
  std::vector<MoverState> movers_;
  std::deque<std::pair<double, Point2>> poses_;
  /// The predictor's side for person `id` at time `t`, or the side it was advised before (within
  /// `crossing_sticky_s`, that side not blocked); remembered.
  CrossingAdvice keepSide(double t, int id, CrossingAdvice side, bool left_blocked, bool right_blocked);
  /// The side last advised per person id (LEFT / RIGHT) and when (s, camera time).
  std::map<int, std::pair<CrossingAdvice, double>> sides_;
};
}  // namespace assistive_planner
