#include "assistive_planner/input_monitor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace assistive_planner
{
namespace
{
std::string fmt(const char* f, double a)
{
  char b[128];
  std::snprintf(b, sizeof(b), f, a);
  return b;
}
}  // namespace

bool InputMonitor::onPose(double stamp, bool trusted)
{
  bool reset = false;
  // After a gap, a time jump or a spell the VO did not trust, the pose may have jumped against
  // everything built before: start again.
  if (have_pose_ && (stamp < pose_stamp_ || stamp - pose_stamp_ > max_gap_ || (trusted && !pose_trusted_)))
  {
    reset = true;
    ++resets_;
    have_grid_ = false;
    newest_ = stamp;  // time may have gone back
  }
  have_pose_ = true;
  pose_trusted_ = trusted;
  pose_stamp_ = stamp;
  newest_ = std::max(newest_, stamp);
  return reset;
}

bool InputMonitor::onGrid(double stamp)
{
  if (have_pose_ && std::abs(stamp - pose_stamp_) > max_gap_)
    return false;  // built before a gap or a bag loop: a place the wearer may have left
  have_grid_ = true;
  grid_stamp_ = stamp;
  newest_ = std::max(newest_, stamp);
  return true;
}

InputVerdict InputMonitor::check(bool require_pose) const
{
  InputVerdict v;
  if (require_pose)
  {
    if (!have_pose_)
    {
      v.status = PlanStatus::NO_POSE;
      v.reason = "no pose from the visual odometry yet";
      return v;
    }
    if (!pose_trusted_)
    {
      v.status = PlanStatus::NO_POSE;
      v.reason = "the visual odometry cannot trust its pose";
      return v;
    }
    if (newest_ - pose_stamp_ > max_age_)
    {
      v.status = PlanStatus::NO_POSE;
      v.reason = fmt("pose %.2f s behind the newest frame", newest_ - pose_stamp_);
      return v;
    }
  }
  if (!have_grid_)
  {
    v.status = PlanStatus::NO_MAP;
    v.reason = "no traversability grid since the start or the last gap";
    return v;
  }
  if (newest_ - grid_stamp_ > max_age_)
  {
    v.status = PlanStatus::NO_MAP;
    v.reason = fmt("map not refreshed for %.2f s (no depth)", newest_ - grid_stamp_);
    return v;
  }
  return v;
}
}  // namespace assistive_planner
