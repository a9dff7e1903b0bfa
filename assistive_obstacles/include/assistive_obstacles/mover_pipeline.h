#pragma once
// People who move (issue 22), one frame at a time: scene flow (scene_flow.h) -> moving points and
// detections against the ego-motion (mover_segmentation.h) -> Kalman tracks (mover_tracker.h) ->
// the footprints ObstacleMap::setMovers() keeps out of the static map. The nodelet and
// obstacles_benchmark run this same object. ROS-free.
//
// Ego-motion: T_cur_prev = T_world_cur^-1 T_world_prev (prev = the frame the flow paired with,
// `frames_apart` back) from the poses the stage places its points
// with (tf in the nodelet, the bag's truth in the benchmark).
// Footprints: every detection of this frame, and every confirmed track that was not detected this
// frame (coasting: a person whose flow was lost for a frame or two still takes no vote), at its
// predicted position with the radius of its last detection; except the detections of a
// stationary track: one at least `speed_age` old whose net displacement since its birth is below
// `min_speed` times its age. Such a track is a static surface whose flow fails the same way frame
// after frame (repeated texture, a streak of stereo errors: the shipped course has one), not a
// person (people walk 0.6-1.6 m/s); it is not reported either, and the map votes there again.
//
// Reported only when seen moving (issue 31): a confirmed track is reported from the detection at
// which two witnesses of its recent detections (the last `history_s`) agree that it moves, until
// it ends or turns stationary:
// - its points' own motion: each detection's mean scene-flow residual against the ego-motion over
//   the frames it spans (MoverDetection::displacement / dt), averaged over the detections, at least
//   `min_speed` and `confirm_sigmas` of its standard error (their scatter over sqrt(n), at least
//   `flow_sigma` / sqrt(n)), and each of the last three detections alone moving that way at
//   half `min_speed` or more;
// - its position: the velocity fitted to the detections' centres by least squares within
//   half the flow velocity plus `confirm_sigmas` of its standard error (the centres' scatter about
//   the fit, at least the tracker's meas_sigma, over sqrt(sum (t - mean t)^2)).
// Without it, a static surface whose flow fails frame after frame (the course's thin column: the
// corners along its silhouettes take depth from the wrong side, their residuals point back and
// forth along the ray) became a mover at its third hit, with a velocity the tracker's two-point
// start made of 0.1 m of centroid jitter over one frame (1-2 m/s), and the crossing watch answered
// it with STOP. A person's points all move the same way from the first frame on.
#include <deque>
#include <map>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <assistive_obstacles/disparity.h>
#include <assistive_obstacles/mover_segmentation.h>
#include <assistive_obstacles/mover_tracker.h>
#include <assistive_obstacles/obstacle_map.h>
#include <assistive_obstacles/params.h>
#include <assistive_obstacles/scene_flow.h>

namespace assistive_obstacles
{
struct MoverPipelineParams
{
  SceneFlowParams flow;
  MoverSegmentationParams segmentation;
  MoverTrackerParams tracker;
  double max_speed = 3.0;  ///< m/s, flow points whose residual is faster are mismatches (dropped); people walk 0.6-1.6 m/s
  double surface_offset = 0.15;  ///< m, a detection's centre = its points' centroid moved this far away from the camera (the seen front of a body of ~0.2 m radius)
  double min_speed = 0.3;  ///< m/s, net speed since birth below which an old enough track is stationary
  double speed_age = 0.5;  ///< s, age from which that is judged
  double max_gap_s = 0.5;  ///< a longer gap between frames (or time going back) restarts the flow and the tracks
  double confirm_sigmas = 3.0;  ///< standard errors of the motion evidence (see above); 0 reports every confirmed track
  double flow_sigma = 0.3;      ///< m/s, floor of one detection's flow velocity scatter
  double history_s = 1.5;       ///< s, the detections the evidence is taken from
};

/// One detection of a track, as the "seen moving" test uses it.
struct TrackDetection
{
  double t = 0.0;                                      ///< s
  Eigen::Vector2d z = Eigen::Vector2d::Zero();         ///< m, world x, y of its centre
  Eigen::Vector2d v_flow = Eigen::Vector2d::Zero();    ///< m/s, its points' mean residual motion
};

/// Least-squares constant-velocity fit to a track's detections (t in s, world x, y in m).
struct MotionFit
{
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< m/s
  double span = 0.0;         ///< s, last minus first detection time
  double scatter = 0.0;      ///< m, RMS per axis of the detections about the fitted line (n - 2 degrees of freedom)
  double sigma_v = 0.0;      ///< m/s, the velocity's standard error per axis with a position sigma of max(scatter, floor)
  int n = 0;
};
MotionFit fitMotion(const std::deque<TrackDetection>& detections, double sigma_floor);

/// The "seen moving" test (see above) on a track's recent detections.
bool seenMoving(const std::deque<TrackDetection>& detections, const MoverPipelineParams& p);

/// The pipeline's parameters from the stage's table (params.h) and the rig.
MoverPipelineParams moverPipelineParams(const ObstaclesParams& p, const StereoModel& model);

/// A confirmed track as reported (obstacles/movers): state, covariance, footprint radius.
struct ReportedMover
{
  MoverTrack track;
  double radius = 0.0;  ///< m, of its last detection
  double height = 0.0;  ///< m, top of its last detection above the lowest point (0 = unknown)
};

class MoverPipeline
{
public:
  explicit MoverPipeline(const MoverPipelineParams& p = MoverPipelineParams());
  void setParams(const MoverPipelineParams& p);

  /// One frame at time `t` (s): `grey` the rectified left image (CV_8UC1, full resolution),
  /// `disp` its disparity at the matcher's scale, `T_world_cam` the left optical frame's pose.
  /// Returns the footprints for ObstacleMap::setMovers() (empty at the first frame).
  /// `right`: the rectified right image (optional): the features' own stereo match (scene_flow.h).
  const std::vector<MoverFootprint>& process(double t, const cv::Mat& grey, const cv::Mat& disp,
                                             const StereoModel& model, const Eigen::Isometry3d& T_world_cam,
                                             const cv::Mat* right = nullptr);
  const std::vector<MoverFootprint>& footprints() const { return footprints_; }
  const std::vector<MoverDetection>& detections() const { return segmentation_.detections(); }
  const std::vector<SceneFlowPoint>& flow() const { return flow_.flow(); }
  /// The flow points segmented (residual speed within max_speed).
  const std::vector<SceneFlowPoint>& segmented() const { return kept_; }
  const MoverTracker& tracker() const { return tracker_; }
  /// The last segmentation (its moving() / cluster() are per segmented() point).
  const MoverSegmentation& segmentation() const { return segmentation_; }
  /// Confirmed tracks that are not stationary, with their footprint radius (what obstacles/movers publishes).
  std::vector<ReportedMover> confirmed() const;
  /// Milliseconds of the last process(): flow, segmentation, tracking.
  double msFlow() const { return ms_flow_; }
  double msSegmentation() const { return ms_segmentation_; }
  double msTracking() const { return ms_tracking_; }
  void reset();

private:
  MoverPipelineParams params_;
  SceneFlowExtractor flow_;
  MoverSegmentation segmentation_;
  MoverTracker tracker_;
  std::vector<MoverFootprint> footprints_;
  std::vector<SceneFlowPoint> kept_;
  std::map<int, std::pair<double, double>> shape_;  ///< track id -> (radius, height) of its last detection
  std::map<int, Eigen::Vector2d> origin_;           ///< track id -> its first detection
  std::map<int, std::deque<TrackDetection>> history_;  ///< track id -> its recent detections
  std::map<int, bool> seen_moving_;                 ///< track id -> seen moving at one of its detections so far
  /// Whether a live track is stationary (see above).
  bool stationary(const MoverTrack& tr) const;
  /// Whether a confirmed track is reported: seen moving, and not stationary.
  bool reported(const MoverTrack& tr) const;
  std::deque<std::pair<double, Eigen::Isometry3d>> poses_;  ///< (t, pose) of the frames the flow may pair with, oldest first
  double prev_t_ = 0.0;
  bool has_prev_ = false;
  double ms_flow_ = 0.0, ms_segmentation_ = 0.0, ms_tracking_ = 0.0;
};

}  // namespace assistive_obstacles
