#include <assistive_obstacles/frame_gate.h>

#include <cstdio>

namespace assistive_obstacles
{
bool FrameGate::clearBefore(double stamp)
{
  bool clear = false;
  reason_.clear();
  if (!have_stamp_)
  {
    clear = true;
  }
  else if (stamp < last_stamp_)
  {
    char b[96];
    std::snprintf(b, sizeof(b), "time went back %.2f s: map cleared", last_stamp_ - stamp);
    reason_ = b;
    clear = true;
  }
  else if (stamp - last_stamp_ > p_.max_frame_gap_s)
  {
    char b[96];
    std::snprintf(b, sizeof(b), "%.2f s without frames: map cleared", stamp - last_stamp_);
    reason_ = b;
    clear = true;
  }
  else if (pose_lost_)
  {
    reason_ = "the visual odometry lost its pose: map cleared";
    clear = true;
  }
  pose_lost_ = false;
  if (clear)
  {
    // The first frame starts an empty map too, but is not counted as a clear.
    if (have_stamp_)
      ++clears_;
    fresh_since_clear_ = 0;
    epoch_start_ = stamp;
  }
  have_stamp_ = true;
  last_stamp_ = stamp;
  return clear;
}

FrameGate::Verdict FrameGate::verdict(std::size_t points)
{
  if (points < static_cast<std::size_t>(p_.min_fresh_points))
  {
    ++no_depth_;
    char b[96];
    std::snprintf(b, sizeof(b), "frame yields no depth (%zu points): map not refreshed", points);
    reason_ = b;
    return Verdict::NO_DEPTH;
  }
  ++fresh_since_clear_;
  if (fresh_since_clear_ < p_.rebuild_frames)
  {
    char b[96];
    std::snprintf(b, sizeof(b), "rebuilding the map (%d of %d fresh frames)", fresh_since_clear_, p_.rebuild_frames);
    reason_ = b;
    return Verdict::REBUILDING;
  }
  reason_.clear();
  return Verdict::FRESH;
}

const char* toString(FrameGate::Verdict v)
{
  switch (v)
  {
    case FrameGate::Verdict::FRESH:
      return "fresh";
    case FrameGate::Verdict::NO_DEPTH:
      return "no depth";
    case FrameGate::Verdict::REBUILDING:
      return "rebuilding";
  }
  return "?";
}
}  // namespace assistive_obstacles
