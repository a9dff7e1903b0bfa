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
  // The walked chord is the direction of travel as soon as it is long enough to measure: after a
  // turn (on the spot or while walking) the head-turn update above catches the head mid-turn and
  // the body turns on (reaction, over-turning), so the heading would stay frozen at the head's yaw
  // of that moment (mobility trials: "on course, 5 deg off" while walking 16 deg off into a wall).
  if (p_.heading_chord_min > 0.0 && std::hypot(dx, dy) >= p_.heading_chord_min)
    heading_ = std::atan2(dy, dx);
  return false;
}
}  // namespace assistive_planner
