#include "assistive_planner/motion_vector.h"

#include <cmath>

namespace assistive_planner
{
bool MotionVector::update(const Point2& position, double head_yaw)
{
  if (!valid_)
  {
    valid_ = true;
    anchor_ = position;
    heading_ = wrapAngle(head_yaw);
    ref_yaw_ = heading_;
    return true;
  }
  const double dx = position.x - anchor_.x, dy = position.y - anchor_.y;
  if (std::hypot(dx, dy) > p_.motion_update_distance)
  {
    const double h = std::atan2(dy, dx);
    anchor_ = position;
    ref_yaw_ = wrapAngle(head_yaw);
    heading_ = h;
    return true;  // moved significantly: the waypoint may be recomputed
  }
  if (std::abs(wrapAngle(head_yaw - ref_yaw_)) > p_.heading_update_angle * M_PI / 180.0)
  {
    heading_ = wrapAngle(head_yaw);
    ref_yaw_ = heading_;
    // The travel before a turn is not the direction after it: the next chord starts here (else,
    // 1 m after turning on the spot, the heading became the chord across the turn and the wearer
    // walking straight on was told it was on course while heading for a wall; mobility trials).
    anchor_ = position;
    return true;
  }
  return false;
}
}  // namespace assistive_planner
