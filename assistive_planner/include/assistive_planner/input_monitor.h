#pragma once
// Whether the planner may decide anything from its inputs ("never guide on a guess"). The VO marks
// a pose it cannot trust (lost, frozen camera, after a gap); the obstacle stage publishes a grid
// only from frames that yielded depth. This class turns both into one verdict, judged on the
// camera's clock (image stamps), so a replay at any speed gives the same answer. ROS-free.
#include <string>

#include "assistive_planner/planner.h"

namespace assistive_planner
{
struct InputVerdict
{
  PlanStatus status = PlanStatus::OK;  ///< OK, NO_POSE or NO_MAP
  std::string reason;                  ///< in words, empty when OK
  bool ok() const { return status == PlanStatus::OK; }
};

class InputMonitor
{
public:
  /// `max_input_age_s`: the grid and the pose may lag the newest camera frame by at most this.
  /// `max_frame_gap_s`: a longer pause between poses, or time going back, restarts everything.
  InputMonitor(double max_input_age_s = 0.5, double max_frame_gap_s = 0.5)
    : max_age_(max_input_age_s), max_gap_(max_frame_gap_s)
  {
  }

  /// A VO pose at image time `stamp`. Returns true when the planner must be reset (a gap longer
  /// than max_frame_gap_s, time going back, or the first trusted pose after untrusted ones): the
  /// motion vector and the waypoint belong to a place the wearer may have left, and the grid from
  /// before is forgotten.
  bool onPose(double stamp, bool trusted);
  /// A traversability grid built from the frame at `stamp`. Returns false (grid ignored) when that
  /// frame is more than max_frame_gap_s away from the newest pose: from before a gap or a bag loop.
  bool onGrid(double stamp);
  /// The verdict at the newest image time seen. With `require_pose` false (no VO subscription,
  /// e.g. the pose comes from tf alone) only the grid is judged.
  InputVerdict check(bool require_pose = true) const;

  double newest() const { return newest_; }
  double gridStamp() const { return grid_stamp_; }
  long resets() const { return resets_; }

private:
  double max_age_, max_gap_;
  bool have_pose_ = false, pose_trusted_ = false, have_grid_ = false;
  double pose_stamp_ = 0.0, grid_stamp_ = 0.0, newest_ = 0.0;
  long resets_ = 0;
};
}  // namespace assistive_planner
