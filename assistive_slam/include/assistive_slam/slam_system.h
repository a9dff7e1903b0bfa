#pragma once
// The SLAM core (seed 3.2.3): keyframes from the VO's frames, bounded submaps linked by relative
// transforms, a local bundle adjustment over a sliding window of keyframes and a pose-graph
// optimisation of the submap graph after every accepted loop closure. Keyframe work runs on a
// worker thread fed by a bounded queue: addFrame() never waits for it. Loop closing (detection,
// verification, pose-graph correction) runs on a thread of its own behind the worker (ORB-SLAM's
// LoopClosing; `loop_closing_thread`), so that the next keyframe's features are extracted while a
// closure is verified.
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <memory>
#include "assistive_slam/appearance_model.h"
#include "assistive_slam/fastslam.h"
#include "assistive_slam/keyframe.h"
#include "assistive_slam/local_ba.h"
#include "assistive_slam/params.h"
#include "assistive_slam/pose_graph.h"
#include "assistive_slam/stereo_check.h"

namespace assistive_slam
{
/// One frame of the VO: the rectified pair and the VO's pose of the left optical frame in odom.
struct SlamFrame
{
  double stamp = 0;
  cv::Mat left, right;  ///< mono8; copied only when the frame becomes a keyframe
  Eigen::Isometry3d T_odom_cam = Eigen::Isometry3d::Identity();
  bool vo_replenished = false;  ///< the VO started a new keyframe (replenished its tracks) here
  bool pose_trusted = true;     ///< untrusted VO poses never become keyframes
  /// Covariance of the VO's motion since the previous frame (left optical axes, x y z rotx roty
  /// rotz, right perturbation): Q_t of the fastslam backend (zero: its floor alone).
  Matrix6d vo_covariance = Matrix6d::Zero();
};

struct LoopEvent
{
  double stamp = 0;
  uint32_t keyframe_old = 0, keyframe_new = 0, submap_old = 0, submap_new = 0;
  bool accepted = false;
  int matches = 0, inliers = 0;
  double correction_m = 0, correction_deg = 0;  ///< how far the closure moves the new keyframe
  Eigen::Isometry3d T_old_new = Eigen::Isometry3d::Identity();  ///< verified relative pose
  std::string reason;                           ///< why rejected (empty when accepted)
  bool relocalisation = false;                  ///< the first link to a loaded map, not a loop closure
};

struct SubmapInfo
{
  uint32_t id = 0;
  Eigen::Isometry3d T_map_origin = Eigen::Isometry3d::Identity();  ///< pose of its first keyframe
  std::vector<uint32_t> keyframes;
};

struct SubmapLinkInfo
{
  uint32_t from = 0, to = 0;
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  Matrix6d covariance = Matrix6d::Identity();
  bool loop_closure = false;
};

/// A tagged place (the way back): the wearer's pose when tagged, anchored to the newest keyframe
/// then, so that it moves with that keyframe when the map is corrected.
struct Place
{
  std::string name;
  uint32_t keyframe = 0;
  Eigen::Isometry3d T_kf_place = Eigen::Isometry3d::Identity();  ///< left optical frame at the tag, in the keyframe
  double stamp = 0;
};

struct SlamStats
{
  int keyframes = 0, submaps = 0, loops_accepted = 0, loops_rejected = 0, queue_depth = 0, dropped = 0;
  int ba_runs = 0, ba_rejected = 0, pose_graph_runs = 0;
  int loop_queue_depth = 0;           ///< mapped keyframes waiting for the loop closer
  double worker_ms_last = 0;          ///< the last keyframe's work (with loop_closing_thread: without loop closing)
  double loop_ms_last = 0;            ///< the last keyframe's loop closing
  bool localised = true;              ///< false after a load until a stored place is recognised, and
                                      ///< after a VO loss until the wearer is found again in the map
  double relocalised_stamp = -1;      ///< the keyframe that relocalised the wearer (-1: none)
  int relocalisation_queries = 0;     ///< keyframes tried against the loaded map or after a VO loss
  int vo_losses = 0;                  ///< untrusted VO stretches after the first keyframe (issue 34)
  int reset_relocalisations = 0;      ///< ... after which the wearer was found again in the map
  int reset_gave_up = 0;              ///< ... after which mapping resumed unplaced (reset_relocalisation_timeout)
  int reset_bridged = 0;              ///< ... so short (reset_bridge), and not found within reset_bridge_after, that the wearer was placed on the VO's held pose
  bool relocalising_after_reset = false;  ///< keyframes are queries against the map before the loss
};

struct MapData;

/// Candidate keyframes to verify against a new keyframe (ids, best first). The default is the
/// proximity search of the map; helper "loop"'s appearance model plugs in here.
using CandidateSource = std::function<std::vector<uint32_t>(const Keyframe& kf)>;

class SlamSystem
{
public:
  /// `threaded`: keyframes are processed on a worker thread, and with `loop_closing_thread` their
  /// loop closing on another (false: both inside addFrame, for tests and chain_benchmark).
  SlamSystem(const SlamParams& p, const StereoModel& cam, bool threaded = true);
  ~SlamSystem();
  SlamSystem(const SlamSystem&) = delete;
  SlamSystem& operator=(const SlamSystem&) = delete;

  /// Frame loop. Returns true when the frame was queued as a keyframe.
  bool addFrame(const SlamFrame& f);
  /// Blocks until the worker's queue is empty, the keyframe in work is done and the loop closer
  /// has handled every keyframe the worker gave it. Called after each queued keyframe (as
  /// slam_benchmark does), the threads run in the same order as inline: the same map, the same
  /// figures.
  void waitIdle();

  Eigen::Isometry3d mapToOdom() const;
  SlamStats stats() const;
  std::vector<LoopEvent> loopEvents() const;
  /// Keyframes (copies without images), in order.
  std::vector<Keyframe> keyframes(bool with_features = false) const;
  std::vector<SubmapInfo> submaps() const;
  std::vector<SubmapLinkInfo> links() const;
  uint32_t currentSubmap() const;
  /// The wearer's pose in map is known: false after a load until a stored place is recognised, and
  /// from a VO loss (an untrusted VO pose after the first keyframe: the VO held its pose while the
  /// wearer moved) until a keyframe after it is verified against the keyframes near the last
  /// trusted pose (and the next one agrees). mapToOdom() is then stale: publish none.
  bool localised() const;
  /// Installs a stored map (map_file.h) before the first frame: keyframes, submaps, loop links,
  /// places; the appearance model is rebuilt from the stored descriptors. The wearer is then not
  /// localised (mapToOdom() is meaningless) until a keyframe and the next one both verify against
  /// stored keyframes proposed by the appearance model with the same map -> odom. False with `err`
  /// after the first frame or on an inconsistent map.
  bool loadMap(const MapData& m, std::string* err);
  /// Tags the place at the VO pose `T_odom_cam` (the newest frame), anchored to the newest
  /// processed keyframe by the VO's motion since it. An empty name becomes "place<N>"; a name
  /// already tagged is moved. False with `err` before the first keyframe is processed.
  bool tagPlace(const std::string& name, const Eigen::Isometry3d& T_odom_cam, double stamp, Place* out,
                std::string* err);
  /// The place's pose in map now (empty name: the last tagged). False with `err` when unknown.
  bool placePose(const std::string& name, Eigen::Isometry3d* T_map_place, std::string* err) const;
  /// Tagged places in tag order, with their poses in map now.
  std::vector<std::pair<Place, Eigen::Isometry3d>> places() const;
  /// Extra candidate source (appearance model); proximity candidates are always added.
  void setCandidateSource(CandidateSource s);
  const SlamParams& params() const { return p_; }
  /// The FastSLAM filter (metric_backend fastslam; nullptr otherwise). Frame thread only.
  const FastSlam* filter() const { return filter_.get(); }

private:
  struct Job
  {
    SlamFrame frame;
    /// The metric layer's pose of the frame: the keyframes are chained by its motion (the VO pose
    /// for keyframe_ba, the filter's for fastslam).
    Eigen::Isometry3d T_metric_cam = Eigen::Isometry3d::Identity();
    /// The first trusted frame after an untrusted VO stretch: the last trusted frame before it
    /// (its VO pose and stamp) anchors the relocalisation.
    bool reset = false;
    Eigen::Isometry3d T_odom_last_trusted = Eigen::Isometry3d::Identity();
    double last_trusted_stamp = 0;
    /// The loss was short enough to be bridged (reset_bridge) if the search does not place the
    /// wearer within reset_bridge_after.
    bool bridgeable = false;
  };
  /// Frame thread: an untrusted VO frame (a loss once the map exists).
  void noteUntrusted();
  /// Worker: the search has not placed the wearer within reset_bridge_after of a bridgeable loss:
  /// placed on the VO's held pose (the old map -> odom), a new submap weakly linked, as after giving up.
  void bridgeLoss();
  /// Worker, under mm_: after a search that gave up or a bridge, the map goes on from the VO's held
  /// pose (the old map -> odom) in a new submap without a verified link.
  void mapOnFromHeldPose();
  /// Frame thread: whether a trusted frame is a keyframe (a relocalisation query while the worker
  /// looks for the wearer after a loss), and the reset flag of the first frame after a loss.
  bool takeFrame(const SlamFrame& f, Job& job);
  /// Queues a job for the worker (the oldest waiting one is dropped beyond queue_size; a dropped
  /// job's reset flag passes to the next one).
  void enqueue(Job&& job);
  void workerLoop();
  void processKeyframe(const Job& job);
  /// The keyframe's mapping step (map pose, submap, associations, local BA), under map_update_m_;
  /// false: the first keyframe of a session.
  bool mapKeyframe(const Job& job, const KeyframePtr& kf);
  /// A mapped keyframe for the loop closer (`first_of_session`: just verified by relocalisation).
  struct LoopJob
  {
    KeyframePtr kf;
    bool first_of_session = false;
  };
  void loopClosingLoop();
  /// Loop closing of one mapped keyframe: the appearance model learns it, closures are detected,
  /// verified and the pose graph corrected (under map_update_m_); map -> odom updated.
  void closeLoops(const LoopJob& job);
  void associate(Keyframe& kf);
  void localBundleAdjustment();
  void detectLoop(const KeyframePtr& kf, const std::vector<uint32_t>& appearance);
  bool relocalise(const KeyframePtr& kf);
  /// Worker: a reset job: the wearer is no longer placed; the last trusted pose in map anchors the search.
  void beginReset(const Job& job);
  /// Worker, after a VO loss: the keyframes near the last trusted pose (then the appearance model's)
  /// verified against the query; two consecutive queries must agree on map -> odom.
  bool relocaliseAfterReset(const KeyframePtr& kf);
  /// The keyframes to verify after a loss, near the anchor first (within the radius the wearer
  /// can have walked, looking within 60 deg of the predicted view).
  std::vector<uint32_t> resetCandidates(const Keyframe& kf, const Eigen::Isometry3d& T_map_pred, double radius) const;
  /// The query's pose in map from localMapCheck's result, refined with the inliers' points seen in
  /// both stereo views and by every candidate keyframe that shares them (the keyframes held), the
  /// predicted rotation (the gyro's) a prior; the P3P pose when the adjustment fails.
  Eigen::Isometry3d refineOnLocalMap(const std::vector<std::pair<const Keyframe*, Eigen::Isometry3d>>& local,
                                     const StereoCheckResult& r, const Keyframe& q, const Eigen::Isometry3d& T_map_pred) const;
  /// A relocalised pose after a loss is plausible: within `radius` of the anchor, turned at most
  /// reset_max_rotation_deg from the predicted pose, at most reset_max_backward behind the anchor
  /// along the wearer's (level) view direction.
  bool plausibleAfterReset(const Eigen::Isometry3d& T_map_b, const Eigen::Isometry3d& T_map_pred, double radius) const;
  /// The stored submaps a query after a load verifies, in order: the one the previous query
  /// verified (its match waits for this one's agreement), the appearance model's candidates, then
  /// the next relocalisation_sweep submaps in turn (reloc_sweep_ moves on).
  std::vector<uint32_t> relocalisationSubmaps(const AppearanceResult& ar, int query);
  /// A verified match of query `kf` on stored keyframe `a`: held until the next query agrees
  /// (loop_confirm); true (and localised, the next mapped keyframe opening a session) when it does.
  bool confirmRelocalisation(const Keyframe& a, const StereoCheckResult& r, const KeyframePtr& kf, int query);
  /// After reset_relocalisation_timeout: mapping resumes in a new submap (weak link) while the
  /// wearer stays unplaced until a loop closure reaches a submap from before the loss.
  void giveUpRelocalisation();
  /// Loop closer: an accepted closure to `old_submap` ends a search that gave up when that submap
  /// is from before the loss.
  void placeAfterGivingUp(uint32_t old_submap);
  /// Blocks until the loop closer has nothing left (worker only).
  void waitLoopIdle();
  void optimiseGraph();
  Matrix6d odomInformation(double path_m) const;
  Matrix6d odomCovariance(double path_m) const;
  std::vector<uint32_t> proximityCandidates(const Keyframe& kf) const;
  /// The geometric check of a loop closure or a relocalisation (loop_min_inliers, ...).
  StereoCheckOptions loopCheckOptions() const;
  Eigen::Isometry3d submapOdometry(uint32_t i) const;  ///< origin_i -> origin_i+1 from the keyframe chain

  SlamParams p_;
  StereoModel cam_;
  bool threaded_;
  bool loop_threaded_ = false;  ///< loop closing on loop_thread_ (threaded_ and loop_closing_thread)
  StereoFeatureExtractor extractor_;
  KeyframePolicy policy_;
  std::unique_ptr<FastSlam> filter_;  ///< frame thread only
  Eigen::Isometry3d prev_metric_ = Eigen::Isometry3d::Identity();  ///< worker: metric pose of the last mapped keyframe

  // ---- worker queue and loop closer queue (both under qm_)
  mutable std::mutex qm_;
  std::condition_variable qcv_, idle_cv_, loop_cv_;
  std::deque<Job> queue_;
  bool busy_ = false, stop_ = false;
  int dropped_ = 0;
  std::thread worker_;
  std::deque<LoopJob> loop_queue_;  ///< unbounded: closures are confirmed by consecutive keyframes
  bool loop_busy_ = false;
  std::thread loop_thread_;
  /// Held while the map's poses change or are read for a closure: the worker's mapping step
  /// (insertion, associations, local BA) and the loop closer's detection and pose graph exclude
  /// each other (feature extraction and the appearance model run beside either). Taken before mm_.
  std::mutex map_update_m_;

  // ---- map (written by the worker and the loop closer under map_update_m_; readers lock mm_)
  mutable std::mutex mm_;
  std::vector<KeyframePtr> kfs_;
  std::vector<Eigen::Isometry3d> kf_rel_;  ///< T_prev_cur per keyframe (BA-refined odometry), [0] = identity
  std::vector<SubmapInfo> submaps_;
  struct LoopLink
  {
    uint32_t from, to;
    Eigen::Isometry3d T;
  };
  std::vector<LoopLink> loop_links_;
  struct Pending
  {
    bool valid = false;
    LoopEvent ev;
    LoopLink link{0, 0, Eigen::Isometry3d::Identity()};
    Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
  };
  Pending pending_;  ///< a verified closure waiting for the next keyframe's confirmation (loop closer only)
  std::vector<LoopEvent> events_;
  Eigen::Isometry3d T_map_odom_ = Eigen::Isometry3d::Identity();
  SlamStats stats_;
  int64_t next_landmark_ = 0;
  CandidateSource candidates_;
  std::vector<Place> places_;  ///< guarded by mm_; tag order (the last is the default way back)
  /// The loop closer's (it learns every mapped keyframe); before the first mapped keyframe of a
  /// loaded map the worker's (relocalisation), while the loop closer has nothing to do.
  std::unique_ptr<AppearanceModel> appearance_;
  // ---- after a load (worker only, except localised_ under mm_)
  bool localised_ = true;
  bool session_start_ = false;  ///< the next mapped keyframe is the first of this session
  struct Reloc
  {
    bool valid = false;
    int query = 0;
    Eigen::Isometry3d T_map_odom = Eigen::Isometry3d::Identity();
    LoopLink link{0, 0, Eigen::Isometry3d::Identity()};  ///< stored submap -> (new submap), T_origin_newkf
    LoopEvent ev;
  };
  std::vector<Reloc> reloc_run_;  ///< consecutive verified queries agreeing on map -> odom
  uint32_t reloc_sweep_ = 0;      ///< the next stored submap relocalisationSubmaps() sweeps
  Reloc reloc_done_;
  /// The mean map -> odom of reloc_run_.
  Eigen::Isometry3d meanMapToOdom() const;
  // ---- after a VO loss (issue 34)
  /// Frame thread: the VO's trust as addFrame sees it.
  struct FrameLoss
  {
    bool mapped = false;        ///< a keyframe was queued: there is a map to be lost from
    bool untrusted = false;     ///< inside an untrusted stretch
    bool relocalising = false;  ///< a reset job was queued; the worker has not placed the wearer yet
    Eigen::Isometry3d last_trusted = Eigen::Isometry3d::Identity();  ///< VO pose of the last trusted frame
    double last_trusted_stamp = 0;
    /// The trusted frames of the last kSpeedSpanS (stamp, camera position in odom), for the speed
    /// the wearer walked at when the loss began (`speed_at_loss`; < 0: unknown).
    std::deque<std::pair<double, Eigen::Vector3d>> recent;
    double speed_at_loss = -1.0;
  };
  static constexpr double kSpeedSpanS = 0.5;
  /// How far the wearer can have walked unseen in `tau` s from `v0` m/s (< 0: unknown, taken as
  /// reset_max_speed): speeding up at reset_max_accel, never beyond reset_max_speed.
  double unseenReach(double tau, double v0) const;
  FrameLoss loss_;
  bool vo_lost_ = false;  ///< under mm_: set by the frame thread on a loss, cleared when the worker takes it up
  int resets_queued_ = 0, resets_begun_ = 0;  ///< under mm_: reset jobs queued / taken up by the worker
  /// Worker: the search after a loss.
  struct ResetSearch
  {
    bool active = false;   ///< keyframes are queries (or, gave_up, mapped but unplaced)
    bool gave_up = false;  ///< reset_relocalisation_timeout passed: mapping resumed from first_submap
    uint32_t first_submap = 0;
    Eigen::Isometry3d T_map_anchor = Eigen::Isometry3d::Identity();  ///< the last trusted pose in map
    Eigen::Isometry3d T_map_odom = Eigen::Isometry3d::Identity();    ///< map -> odom before the loss
    double stamp = 0;                                                ///< of the last trusted frame
    bool bridgeable = false;        ///< placed on the held pose after reset_bridge_after (Job::bridgeable)
    double first_query_stamp = 0;   ///< the first trusted frame after the loss
  };
  ResetSearch reset_;
  bool link_session_ = true;  ///< the next session start has a verified link (false: given up)
};

}  // namespace assistive_slam
