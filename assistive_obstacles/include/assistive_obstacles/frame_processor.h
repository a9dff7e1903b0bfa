#pragma once
// The obstacle stage's whole frame step, in one place for the nodelet, obstacles_benchmark and
// the chain benchmark (issue 32): frame gate, disparity and points, the forward ranger's queued
// readings, the movers' scene flow, the map update, the grid the stage publishes and the OctoMap
// insertion. Fed with plain types; ROS-free. Not thread-safe: a caller with several threads
// serialises its calls.
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <assistive_obstacles/disparity.h>
#include <assistive_obstacles/frame_gate.h>
#include <assistive_obstacles/mover_pipeline.h>
#include <assistive_obstacles/obstacle_map.h>
#include <assistive_obstacles/params.h>

namespace assistive_obstacles
{
/// One forward-ranger reading as it arrives (sensor_msgs/Range without the header's frame).
struct RangeSample
{
  double stamp = 0.0;  ///< s
  double range = 0.0, min_range = 0.2, max_range = 4.0, field_of_view = 0.26;  ///< m, m, m, rad
  std::string frame;   ///< the sensor's frame (for the caller's pose lookup)
};

/// The ranger's pose in the map's world frame at the reading's stamp (x along the cone's axis);
/// false when there is none (the nodelet: tf; the benchmarks: the truth, interpolated).
using RangePoseLookup = std::function<bool(const RangeSample&, Eigen::Isometry3f& T_world_sensor)>;

/// One stereo frame.
struct ObstacleFrame
{
  double stamp = 0.0;     ///< s, the images' stamp
  cv::Mat left, right;    ///< rectified, CV_8UC1, full resolution
  StereoModel model;      ///< of `left`
  /// The left optical frame's pose in the world (z up); `has_pose` false: no pose for this stamp
  /// (the frame still passes the gate and gives a disparity, but the map does not take it).
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  bool has_pose = true;
  /// The pose source (the VO) marked its pose untrusted since the last frame (also poseUntrusted()).
  bool pose_trusted = true;
  /// Optional disparity at the matcher's scale (CV_32F, invalid < 0) used instead of the matcher's
  /// (obstacles_benchmark --gt-depth).
  const cv::Mat* disparity = nullptr;
  /// The movers' ego-motion from another pose than the map's (obstacles_benchmark --mover-poses):
  /// `own_mover_pose` with `mover_pose` null = no pose for the movers this frame (no scene flow).
  bool own_mover_pose = false;
  const Eigen::Isometry3d* mover_pose = nullptr;
  /// An active camera (issue 35): `left`/`right` are its emitter-on pair (the projector's dots give
  /// the disparity), and this is the emitter-off pair just before it, which the movers' scene flow
  /// tracks instead (the dots move with the head, not with the world: tracked, they are movers).
  /// Its stamp and pose; the disparity of `left` is its features' stereo prior. Null: `left`.
  const cv::Mat* track_left = nullptr;
  const cv::Mat* track_right = nullptr;
  double track_stamp = 0.0;
  Eigen::Isometry3d track_pose = Eigen::Isometry3d::Identity();
};

/// A ranger reading the frame applied (after the frame gate's epoch check and the pose lookup).
struct AppliedRange
{
  RangeSample sample;
  Eigen::Isometry3f T_world_sensor = Eigen::Isometry3f::Identity();
  RangeCheck check = RangeCheck::ECHO;
  SonarStats stats;  ///< the fusion's account of this reading
};

/// What one frame gave: what the stage publishes and why not.
struct ObstacleFrameResult
{
  bool disparity_ok = false;  ///< false: unusable images (the frame did nothing else)
  bool has_pose = false;
  bool cleared = false;       ///< the map was cleared before this frame (the gate)
  FrameGate::Verdict verdict = FrameGate::Verdict::NO_DEPTH;
  std::string gate_reason;    ///< why not FRESH, or why cleared; empty otherwise
  bool map_updated = false;   ///< the map took the frame (FRESH or REBUILDING)
  bool has_grid = false;      ///< FRESH: publish `grid` with the frame's stamp
  GridData grid;
  bool movers_enabled = false;         ///< publish `movers` (every frame the map took, also empty)
  std::vector<ReportedMover> movers;
  double feet_z = 0.0;                 ///< m, the wearer's feet in the world (camera z - camera_height)
  bool octomap_inserted = false;
  std::vector<AppliedRange> ranges;    ///< readings applied before this frame's update
  double ms_disparity = 0.0;  ///< disparity + points
  double ms_ranger = 0.0;     ///< the queued readings into the map
  double ms_movers = 0.0;     ///< scene flow + segmentation + tracking (wall clock around the pipeline)
  double ms_map = 0.0;        ///< elevation + MLS + temporal
  double ms_octomap = 0.0;
  double ms_total = 0.0;
};

/// Counters for the stage's diagnostics, over the processor's life.
struct ObstacleFrameCounters
{
  long frames = 0;          ///< frames the map took
  long bad_input = 0;       ///< frames whose disparity failed
  long no_pose = 0;         ///< frames without a pose
  long ranges_echo = 0, ranges_no_echo = 0, ranges_rejected = 0;
  long ranges_stale = 0;    ///< from before the map's last clear: not used
  long ranges_no_pose = 0;  ///< no pose at their stamp: not used
  std::string last_rejection;  ///< rangeCheckName of the last rejected reading
};

class ObstacleFrameProcessor
{
public:
  /// Readings kept while no frame takes them (a black-out): the latest 5 s at 20 Hz.
  static constexpr size_t MaxQueuedRanges = 100;

  /// `octomap_insert_every`: frames the map takes between OctoMap insertions (node parameter).
  explicit ObstacleFrameProcessor(const ObstaclesParams& p = ObstaclesParams(), int octomap_insert_every = 5);

  const ObstaclesParams& params() const { return params_; }
  /// A ranger reading as it arrives: queued, applied before the update of the first frame stamped
  /// at or after it (the oldest dropped beyond MaxQueuedRanges).
  void queueRange(const RangeSample& r);
  /// The pose source marked its pose untrusted: the next frame starts a new map.
  void poseUntrusted() { gate_.poseUntrusted(); }
  /// One frame; `range_pose` places the queued readings (may be empty without readings).
  const ObstacleFrameResult& process(const ObstacleFrame& frame, const RangePoseLookup& range_pose = {});

  const ObstacleFrameResult& last() const { return result_; }
  const ObstacleFrameCounters& counters() const { return counters_; }
  const FrameGate& gate() const { return gate_; }
  const DisparityEstimator& disparityEstimator() const { return disparity_; }
  /// The last frame's disparity at the matcher's scale (CV_32F) and its points / normals (left optical frame).
  const cv::Mat& disparity() const { return disp_; }
  const std::vector<Eigen::Vector3f>& points() const { return points_; }
  const ObstacleMap& map() const { return map_; }
  ObstacleMap& map() { return map_; }
  /// Null until the first frame the map took (the pipeline needs the rig), or with movers off.
  const MoverPipeline* movers() const { return movers_.get(); }

private:
  void applyRanges(double stamp, const RangePoseLookup& range_pose);
  void runMovers(const ObstacleFrame& f, const Eigen::Isometry3f& T_world_cam);

  ObstaclesParams params_;
  int octomap_insert_every_;
  DisparityEstimator disparity_;
  ObstacleMap map_;
  FrameGate gate_;
  std::unique_ptr<MoverPipeline> movers_;
  std::deque<RangeSample> ranges_;
  cv::Mat disp_;
  std::vector<Eigen::Vector3f> points_, normals_;
  ObstacleFrameResult result_;
  ObstacleFrameCounters counters_;
};

}  // namespace assistive_obstacles
