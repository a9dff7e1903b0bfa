#pragma once

#include "assistive_planner/grid.h"
#include "assistive_planner/params.h"

namespace assistive_planner
{
/// The wearer's intended direction of travel (seed 4.3.1): the line from the previous to the current
/// position. The previous position (anchor) moves only after more than motion_update_distance of travel;
/// the heading follows the head only when its yaw changed by more than heading_update_angle since the
/// last heading update, so small head turns while walking do not move the waypoint.
class MotionVector
{
public:
  explicit MotionVector(const PlannerParams& p = PlannerParams()) : p_(p) {}
  /// Returns true when the motion vector was updated (the anchor moved or the heading followed the head).
  bool update(const Point2& position, double head_yaw);
  void reset() { valid_ = false; }
  bool valid() const { return valid_; }
  double heading() const { return heading_; }
  const Point2& anchor() const { return anchor_; }

private:
  PlannerParams p_;
  bool valid_ = false;
  Point2 anchor_;
  double heading_ = 0.0;
  double ref_yaw_ = 0.0;  // head yaw at the last heading update
};
}  // namespace assistive_planner
