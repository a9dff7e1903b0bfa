#pragma once
// Decides, per stereo frame, whether the map may be trusted ("never guide on a guess"): a frame
// that yields no depth does not refresh the map, and after a gap or a time jump the map is
// cleared and held back until it has been rebuilt from fresh frames. ROS-free.
#include <cstddef>
#include <string>

namespace assistive_obstacles
{
struct FrameGateParams
{
  double max_frame_gap_s = 0.5;  ///< s: a longer gap between frames (or time going back) clears the map
  int rebuild_frames = 5;        ///< fresh frames after a clear before the grid is published again
  int min_fresh_points = 500;    ///< a frame with fewer 3D points "yields no depth" and refreshes nothing
};

class FrameGate
{
public:
  enum class Verdict
  {
    FRESH,       ///< map updated from this frame: publish the grid with this frame's stamp
    NO_DEPTH,    ///< too few points (black, saturated, textureless, covered lens): map untouched, no grid
    REBUILDING,  ///< map updated but still too young after a clear: no grid
  };

  explicit FrameGate(const FrameGateParams& p = FrameGateParams()) : p_(p) {}
  const FrameGateParams& params() const { return p_; }

  /// Call first for every frame with its image stamp (s): true when the map must be cleared now
  /// (the first frame, a gap longer than max_frame_gap_s, time going backwards, or an untrusted
  /// VO pose since the last frame).
  bool clearBefore(double stamp);
  /// The VO marked a pose untrusted (lost, frozen camera, gap): when it trusts its pose again the
  /// pose may have jumped against the map, so the next frame starts a new map.
  void poseUntrusted() { pose_lost_ = true; }
  /// Call after the frame's points are known; says whether the map takes it and may be published.
  Verdict verdict(std::size_t points);

  /// Whether evidence stamped `stamp` (s) belongs to the map since its last clear: stamped at or
  /// after the frame that started it, and not beyond the newest frame by more than
  /// max_frame_gap_s. Evidence from before a clear (a ranger reading queued through a black-out,
  /// placed with a pose tf interpolates across the spell the VO could not trust, or from before a
  /// bag loop) would build the new map on the old, lost pose chain.
  bool inEpoch(double stamp) const
  {
    return have_stamp_ && stamp >= epoch_start_ && stamp <= last_stamp_ + p_.max_frame_gap_s;
  }

  /// Why the last frame was not FRESH (empty when it was).
  const std::string& reason() const { return reason_; }
  long clears() const { return clears_; }
  long noDepthFrames() const { return no_depth_; }

private:
  FrameGateParams p_;
  bool have_stamp_ = false;
  bool pose_lost_ = false;
  double last_stamp_ = 0.0;
  double epoch_start_ = 0.0;  ///< stamp of the frame that started the map (the last clear)
  int fresh_since_clear_ = 0;
  std::string reason_;
  long clears_ = 0, no_depth_ = 0;
};

const char* toString(FrameGate::Verdict v);
}  // namespace assistive_obstacles
