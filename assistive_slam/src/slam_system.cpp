#include "assistive_slam/slam_system.h"
#include <algorithm>
#include "assistive_slam/map_file.h"
#include <chrono>
#include <cmath>
#include <set>

namespace assistive_slam
{
namespace
{
constexpr double kDeg = M_PI / 180.0;
/// The path "walked" between the last stored keyframe and the first of a new session: the link
/// between them in the pose graph is then weak (the relocalisation is the real link).
constexpr double kSessionGapM = 100.0;

/// The descriptors the appearance model sees: the first n rows (its memory grows with them).
cv::Mat appearanceRows(const cv::Mat& d, int n)
{
  return d.rows > n ? d.rowRange(0, n) : d;
}

/// Keyframe optical axis (z) angle between two poses, degrees.
double viewAngleDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
  const double c = a.linear().col(2).dot(b.linear().col(2));
  return std::acos(std::clamp(c, -1.0, 1.0)) / kDeg;
}
}  // namespace

SlamSystem::SlamSystem(const SlamParams& p, const StereoModel& cam, bool threaded)
  : p_(p), cam_(cam), threaded_(threaded), extractor_(p), policy_(p)
{
  if (p_.appearance_candidates > 0)
  {
    AppearanceParams ap;
    ap.recent_submaps_excluded = p_.loop_skip_submaps;
    ap.max_candidates = p_.appearance_candidates;
    appearance_ = std::make_unique<AppearanceModel>(ap);
  }
  if (p_.metric_backend == "fastslam")
    filter_ = std::make_unique<FastSlam>(p_, cam_);
  loop_threaded_ = threaded_ && p_.loop_closing_thread;
  if (loop_threaded_)
    loop_thread_ = std::thread(&SlamSystem::loopClosingLoop, this);
  if (threaded_)
    worker_ = std::thread(&SlamSystem::workerLoop, this);
}

SlamSystem::~SlamSystem()
{
  {
    std::lock_guard<std::mutex> l(qm_);
    stop_ = true;
  }
  qcv_.notify_all();
  loop_cv_.notify_all();
  if (worker_.joinable())
    worker_.join();
  if (loop_thread_.joinable())
    loop_thread_.join();
}

bool SlamSystem::addFrame(const SlamFrame& f)
{
  if (!f.pose_trusted)
    noteUntrusted();
  if (!f.pose_trusted || f.left.empty() || f.right.empty())
    return false;
  if (filter_)
    filter_->process(f.left, f.right, f.T_odom_cam, f.vo_covariance);  // every trusted frame
  Job job;
  const bool take = takeFrame(f, job);
  loss_.last_trusted = f.T_odom_cam;
  loss_.last_trusted_stamp = f.stamp;
  loss_.recent.emplace_back(f.stamp, f.T_odom_cam.translation());
  while (loss_.recent.size() > 1 && loss_.recent.front().first < f.stamp - kSpeedSpanS)
    loss_.recent.pop_front();
  if (!take)
    return false;
  loss_.mapped = true;
  job.frame = f;
  job.T_metric_cam = filter_ ? filter_->pose() : f.T_odom_cam;
  job.frame.left = f.left.clone();
  job.frame.right = f.right.clone();
  if (!threaded_)
  {
    processKeyframe(job);
    return true;
  }
  enqueue(std::move(job));
  return true;
}

void SlamSystem::noteUntrusted()
{
  // The VO holds its last trusted pose while untrusted and goes on from it when trust returns: the
  // wearer's motion in between is lost, so odom no longer sits where map -> odom puts it.
  if (!p_.reset_relocalisation || !loss_.mapped || loss_.untrusted)
    return;
  loss_.untrusted = true;
  // the walking speed when the loss began: over the trusted frames of the last kSpeedSpanS (one
  // frame's step is mostly the pose's noise)
  loss_.speed_at_loss = -1.0;
  if (loss_.recent.size() >= 2 && loss_.recent.back().first - loss_.recent.front().first >= 0.2)
    loss_.speed_at_loss = (loss_.recent.back().second - loss_.recent.front().second).norm() /
                          (loss_.recent.back().first - loss_.recent.front().first);
  loss_.recent.clear();
  std::lock_guard<std::mutex> l(mm_);
  vo_lost_ = true;  // unplaced at once (the worker takes the loss up with the next keyframe)
  stats_.localised = false;
}

double SlamSystem::unseenReach(double tau, double v0) const
{
  const double vmax = p_.reset_max_speed, a = p_.reset_max_accel;
  tau = std::max(0.0, tau);
  if (!(v0 >= 0.0) || v0 >= vmax)
    return vmax * tau;
  const double t1 = (vmax - v0) / a;  // when it would reach reset_max_speed
  if (tau <= t1)
    return v0 * tau + 0.5 * a * tau * tau;
  return 0.5 * (v0 + vmax) * t1 + vmax * (tau - t1);
}

bool SlamSystem::takeFrame(const SlamFrame& f, Job& job)
{
  if (loss_.untrusted)
  {
    loss_.untrusted = false;
    // So short that the unseen walk is within reset_bridge: the held pose places the wearer nearly
    // as well as a relocalisation, and a search at a bare wall (where such losses happen) may never
    // end (vision corridor: 52 s unplaced after a 0.2 s loss). Only for a placed wearer (not during
    // a search: beginReset keeps that one as it was).
    job.bridgeable = !loss_.relocalising && p_.reset_bridge_m > 0.0 &&
                     unseenReach(f.stamp - loss_.last_trusted_stamp, loss_.speed_at_loss) <= p_.reset_bridge_m;
    // The first trusted frame after the loss: always a query, carrying the anchor.
    loss_.relocalising = true;
    job.reset = true;
    job.T_odom_last_trusted = loss_.last_trusted;
    job.last_trusted_stamp = loss_.last_trusted_stamp;
    std::lock_guard<std::mutex> l(mm_);
    ++resets_queued_;
    return true;
  }
  if (loss_.relocalising)
  {
    bool searching;
    {
      std::lock_guard<std::mutex> l(mm_);
      searching = resets_begun_ < resets_queued_ || (reset_.active && !reset_.gave_up);
    }
    if (searching)
    {
      // Every frame is a query while the worker has none waiting (it never falls behind on them).
      std::lock_guard<std::mutex> l(qm_);
      return !threaded_ || (queue_.empty() && !busy_);
    }
    loss_.relocalising = false;
    policy_.reset();  // placed again (or given up): keyframes by the policy from here
  }
  return policy_.take(f.T_odom_cam, f.vo_replenished);
}

void SlamSystem::enqueue(Job&& job)
{
  {
    std::lock_guard<std::mutex> l(qm_);
    // Bounded: the oldest waiting keyframe goes (the frame loop never waits); a reset it carried
    // passes to the next one with its anchor (the earliest last trusted pose).
    if (static_cast<int>(queue_.size()) >= p_.queue_size)
    {
      Job old = std::move(queue_.front());
      queue_.pop_front();
      ++dropped_;
      Job& next = queue_.empty() ? job : queue_.front();
      if (old.reset)
      {
        if (next.reset)
        {
          std::lock_guard<std::mutex> lm(mm_);
          --resets_queued_;  // two losses merged into one
        }
        next.reset = true;
        next.T_odom_last_trusted = old.T_odom_last_trusted;
        next.last_trusted_stamp = old.last_trusted_stamp;
      }
    }
    queue_.push_back(std::move(job));
  }
  qcv_.notify_one();
}

void SlamSystem::waitIdle()
{
  if (!threaded_)
    return;
  std::unique_lock<std::mutex> l(qm_);
  idle_cv_.wait(l, [&] { return queue_.empty() && !busy_ && loop_queue_.empty() && !loop_busy_; });
}

void SlamSystem::workerLoop()
{
  for (;;)
  {
    Job job;
    {
      std::unique_lock<std::mutex> l(qm_);
      qcv_.wait(l, [&] { return stop_ || !queue_.empty(); });
      if (stop_)
        return;
      job = std::move(queue_.front());
      queue_.pop_front();
      busy_ = true;
    }
    processKeyframe(job);
    {
      std::lock_guard<std::mutex> l(qm_);
      busy_ = false;
    }
    idle_cv_.notify_all();
  }
}

void SlamSystem::loopClosingLoop()
{
  for (;;)
  {
    LoopJob job;
    {
      std::unique_lock<std::mutex> l(qm_);
      loop_cv_.wait(l, [&] { return stop_ || !loop_queue_.empty(); });
      if (stop_)
        return;
      job = std::move(loop_queue_.front());
      loop_queue_.pop_front();
      loop_busy_ = true;
    }
    closeLoops(job);
    {
      std::lock_guard<std::mutex> l(qm_);
      loop_busy_ = false;
    }
    idle_cv_.notify_all();
  }
}

Matrix6d SlamSystem::odomCovariance(double path_m) const
{
  const double st = std::max(p_.odom_sigma_floor_m, p_.odom_sigma_per_m * path_m);
  const double sr = std::max(p_.odom_sigma_floor_deg, p_.odom_sigma_deg_per_m * path_m) * kDeg;
  Matrix6d C = Matrix6d::Zero();
  C.diagonal() << st * st, st * st, st * st, sr * sr, sr * sr, sr * sr;
  return C;
}

Matrix6d SlamSystem::odomInformation(double path_m) const
{
  return odomCovariance(path_m).inverse();
}

void SlamSystem::processKeyframe(const Job& job)
{
  const auto t0 = std::chrono::steady_clock::now();
  auto kf = std::make_shared<Keyframe>();
  kf->stamp = job.frame.stamp;
  kf->T_odom_cam = job.frame.T_odom_cam;
  extractor_.extract(job.frame.left, job.frame.right, cam_, *kf);
  if (job.reset)
    beginReset(job);
  bool localised, searching, gave_up;
  {
    std::lock_guard<std::mutex> l(mm_);  // (the loop closer ends a given-up search)
    localised = localised_;
    searching = reset_.active;
    gave_up = reset_.gave_up;
  }
  const bool placed = localised || (searching ? (gave_up || relocaliseAfterReset(kf)) : relocalise(kf));
  if (!placed)
  {
    std::lock_guard<std::mutex> l(mm_);
    stats_.worker_ms_last = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    stats_.loop_ms_last = 0.0;
    return;  // not in the map: the keyframe was only a query (no loop closing)
  }

  LoopJob lj;
  lj.kf = kf;
  lj.first_of_session = mapKeyframe(job, kf);
  if (loop_threaded_)
  {
    {
      std::lock_guard<std::mutex> l(mm_);
      T_map_odom_ = kfs_.back()->T_map_cam * kfs_.back()->T_odom_cam.inverse();
    }
    {
      std::lock_guard<std::mutex> l(qm_);
      loop_queue_.push_back(std::move(lj));
    }
    loop_cv_.notify_one();
  }
  else
    closeLoops(lj);
  std::lock_guard<std::mutex> l(mm_);
  stats_.worker_ms_last = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool SlamSystem::mapKeyframe(const Job& job, const KeyframePtr& kf)
{
  std::lock_guard<std::mutex> mu(map_update_m_);
  const bool first_of_session = session_start_;
  Eigen::Isometry3d rel = Eigen::Isometry3d::Identity();
  if (session_start_)
  {
    // First keyframe after a relocalisation: its map pose from the verified stored keyframe.
    kf->T_map_cam = T_map_odom_ * kf->T_odom_cam;
    rel = kfs_.back()->T_map_cam.inverse() * kf->T_map_cam;
    kf->path_m = kfs_.back()->path_m + kSessionGapM;
  }
  else if (!kfs_.empty())
  {
    const Keyframe& prev = *kfs_.back();
    rel = prev_metric_.inverse() * job.T_metric_cam;  // the metric layer's motion between keyframes
    kf->T_map_cam = prev.T_map_cam * rel;
    kf->path_m = prev.path_m + rel.translation().norm();
  }
  else
    kf->T_map_cam = kf->T_odom_cam;  // the map starts where odom starts
  kf->id = static_cast<uint32_t>(kfs_.size());
  prev_metric_ = job.T_metric_cam;

  {
    std::lock_guard<std::mutex> l(mm_);
    // Bounded submaps: a new one after submap_max_keyframes or beyond submap_max_extent.
    const bool new_submap =
        submaps_.empty() || session_start_ || static_cast<int>(submaps_.back().keyframes.size()) >= p_.submap_max_keyframes ||
        (submaps_.back().T_map_origin.inverse() * kf->T_map_cam).translation().norm() > p_.submap_max_extent_m;
    if (new_submap)
    {
      SubmapInfo s;
      s.id = static_cast<uint32_t>(submaps_.size());
      s.T_map_origin = kf->T_map_cam;
      submaps_.push_back(s);
    }
    kf->submap = submaps_.back().id;
    submaps_.back().keyframes.push_back(kf->id);
    kfs_.push_back(kf);
    kf_rel_.push_back(rel);
    stats_.keyframes = static_cast<int>(kfs_.size());
    stats_.submaps = static_cast<int>(submaps_.size());
    if (session_start_ && link_session_)
    {
      // the relocalisation is a loop link: stored submap -> the new session's first submap
      reloc_done_.link.to = kf->submap;
      loop_links_.push_back(reloc_done_.link);
      reloc_done_.ev.keyframe_new = kf->id;
      reloc_done_.ev.submap_new = kf->submap;
      events_.push_back(reloc_done_.ev);
    }
    session_start_ = false;
  }
  if (!first_of_session)
    associate(*kf);  // (the first keyframe of a session has no odometry to the stored ones)
  if (!filter_)
    localBundleAdjustment();  // (the filter is the metric layer of fastslam)
  return first_of_session;
}

void SlamSystem::closeLoops(const LoopJob& job)
{
  const auto t0 = std::chrono::steady_clock::now();
  const KeyframePtr& kf = job.kf;
  std::vector<uint32_t> seen;
  if (p_.appearance_loop && appearance_)  // (appearance_loop off: the worker may drop the model after a relocalisation)
  {
    // the model learns every mapped keyframe; its candidates come from older submaps only
    for (const LoopCandidate& c : appearance_->process(static_cast<int>(kf->id), static_cast<int>(kf->submap),
                                                             appearanceRows(kf->descriptors, p_.appearance_features)).candidates)
      if (c.keyframe_id >= 0)
        seen.push_back(static_cast<uint32_t>(c.keyframe_id));
  }
  if (p_.loop_closure && !job.first_of_session)  // (the first of a session has just been verified)
  {
    std::lock_guard<std::mutex> mu(map_update_m_);
    detectLoop(kf, seen);
  }
  std::lock_guard<std::mutex> l(mm_);
  T_map_odom_ = kfs_.back()->T_map_cam * kfs_.back()->T_odom_cam.inverse();
  stats_.loop_ms_last = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void SlamSystem::associate(Keyframe& kf)
{
  // Match against the last two keyframes: each of their features is projected into the new
  // keyframe with the current estimate and matched by descriptor inside the gate (mutually best).
  const int n = static_cast<int>(kfs_.size());
  for (int back = 2; back <= 3 && n - back >= 0; ++back)
  {
    Keyframe& old = *kfs_[n - back];
    if (old.descriptors.empty() || kf.descriptors.empty())
      continue;
    const Eigen::Isometry3d T_new_old = kf.T_map_cam.inverse() * old.T_map_cam;
    std::vector<int> best_for_new(kf.keypoints.size(), -1);
    std::vector<int> best_dist_new(kf.keypoints.size(), 1 << 20);
    std::vector<std::pair<int, int>> cand;  // (old, new)
    for (size_t i = 0; i < old.points.size(); ++i)
    {
      const Eigen::Vector3d X = T_new_old * old.points[i];
      if (X.z() < p_.min_depth_m)
        continue;
      const Eigen::Vector3d uvr = cam_.project(X);
      int best = -1, bd = 1 << 20, second = 1 << 20;
      for (size_t j = 0; j < kf.keypoints.size(); ++j)
      {
        const cv::Point2f& q = kf.keypoints[j].pt;
        if (std::abs(q.x - uvr.x()) > p_.match_gate_px || std::abs(q.y - uvr.y()) > p_.match_gate_px)
          continue;
        const int d = static_cast<int>(cv::norm(old.descriptors.row(static_cast<int>(i)),
                                                kf.descriptors.row(static_cast<int>(j)), cv::NORM_HAMMING));
        if (d < bd)
        {
          second = bd;
          bd = d;
          best = static_cast<int>(j);
        }
        else if (d < second)
          second = d;
      }
      if (best < 0 || bd > p_.match_max_hamming || bd > 0.9 * second)
        continue;
      cand.emplace_back(static_cast<int>(i), best);
      if (bd < best_dist_new[best])
      {
        best_dist_new[best] = bd;
        best_for_new[best] = static_cast<int>(i);
      }
    }
    for (const auto& [i, j] : cand)
    {
      if (best_for_new[j] != i || kf.landmark[j] >= 0)
        continue;
      if (old.landmark[i] < 0)
        old.landmark[i] = next_landmark_++;
      kf.landmark[j] = old.landmark[i];
    }
  }
}

void SlamSystem::localBundleAdjustment()
{
  const int n = static_cast<int>(kfs_.size());
  const int w = std::min(n, p_.ba_window);
  if (w < 3 || p_.ba_iterations == 0)
    return;
  const int first = n - w;
  BaProblem pb;
  std::map<int64_t, int> count;
  for (int k = first; k < n; ++k)
    for (int64_t id : kfs_[k]->landmark)
      if (id >= 0)
        ++count[id];
  for (int k = first; k < n; ++k)
  {
    const Keyframe& kf = *kfs_[k];
    const int fi = k - first;
    pb.poses.push_back(kf.T_map_cam);
    pb.fixed.push_back(fi < 2);  // the oldest two hold the gauge (position, orientation and scale)
    for (size_t i = 0; i < kf.landmark.size(); ++i)
    {
      const int64_t id = kf.landmark[i];
      if (id < 0 || count[id] < p_.ba_min_observations)
        continue;
      if (!pb.landmarks.count(id))
        pb.landmarks[id] = kf.T_map_cam * kf.points[i];
      pb.observations.push_back({fi, id, Eigen::Vector3d(kf.keypoints[i].pt.x, kf.keypoints[i].pt.y, kf.u_right[i]),
                                 std::pow(1.2, kf.keypoints[i].octave)});
    }
    if (fi > 0)
    {
      // The VO's motion between consecutive keyframes as a weak prior (windows with few shared
      // landmarks stay where the VO put them).
      PoseGraphEdge e;
      e.from = fi - 1;
      e.to = fi;
      e.T_from_to = kfs_[k - 1]->T_odom_cam.inverse() * kf.T_odom_cam;
      e.information = odomInformation(e.T_from_to.translation().norm());
      pb.priors.push_back(e);
    }
  }
  if (pb.observations.size() < 30)
    return;
  BaOptions o;
  o.max_iterations = p_.ba_iterations;
  o.huber_px = p_.ba_huber_px;
  o.pixel_sigma_px = p_.pixel_sigma_px;
  const std::vector<Eigen::Isometry3d> before = pb.poses;
  const BaResult r = bundleAdjust(pb, cam_, o);
  if (!r.solved || !(r.final_rms_px <= r.initial_rms_px))
    return;
  // A window that moves a keyframe by more than the VO could be off between keyframes is a
  // failed adjustment (wrong associations, a degenerate window): the VO's poses are kept.
  for (size_t i = 0; i < before.size(); ++i)
  {
    const Eigen::Isometry3d d = before[i].inverse() * pb.poses[i];
    if (!d.matrix().allFinite() || d.translation().norm() > 0.2 || angleDeg(d) > 2.0)
    {
      ++stats_.ba_rejected;
      return;
    }
  }
  std::lock_guard<std::mutex> l(mm_);
  ++stats_.ba_runs;
  for (int k = first + 2; k < n; ++k)
  {
    kfs_[k]->T_map_cam = pb.poses[k - first];
    kf_rel_[k] = kfs_[k - 1]->T_map_cam.inverse() * kfs_[k]->T_map_cam;
  }
  for (SubmapInfo& s : submaps_)
    s.T_map_origin = kfs_[s.keyframes.front()]->T_map_cam;
}

StereoCheckOptions SlamSystem::loopCheckOptions() const
{
  StereoCheckOptions so;
  so.min_inliers = p_.loop_min_inliers;
  so.min_inlier_ratio = p_.loop_min_inlier_ratio;
  so.inlier_px = p_.loop_inlier_px;
  return so;
}

std::vector<uint32_t> SlamSystem::proximityCandidates(const Keyframe& kf) const
{
  // Keyframes of older submaps near where the map puts the new one, looking the same way; the
  // radius grows with the path walked since (the drift the closure may have to absorb).
  std::vector<std::pair<double, uint32_t>> near;
  const int last_submap = static_cast<int>(kf.submap) - p_.loop_skip_submaps;
  for (const KeyframePtr& c : kfs_)
  {
    if (static_cast<int>(c->submap) > last_submap)
      break;
    const double d = (c->T_map_cam.translation() - kf.T_map_cam.translation()).norm();
    const double radius = p_.loop_max_correction_m + 0.05 * (kf.path_m - c->path_m);
    if (d < radius && viewAngleDeg(c->T_map_cam, kf.T_map_cam) < 45.0)
      near.emplace_back(d, c->id);
  }
  std::sort(near.begin(), near.end());
  std::vector<uint32_t> out;
  for (const auto& [d, id] : near)
    out.push_back(id);
  return out;
}

void SlamSystem::detectLoop(const KeyframePtr& kf, const std::vector<uint32_t>& appearance)
{
  // Proximity first (the map knows roughly where the wearer is), then the appearance model's
  // proposals (places the drift has carried beyond the search radius), each verified alike.
  std::vector<uint32_t> cand;
  if (candidates_)
    cand = candidates_(*kf);
  for (uint32_t id : proximityCandidates(*kf))
    if (std::find(cand.begin(), cand.end(), id) == cand.end())
      cand.push_back(id);
  if (static_cast<int>(cand.size()) > p_.loop_candidates)
    cand.resize(p_.loop_candidates);
  for (uint32_t id : appearance)
    if (std::find(cand.begin(), cand.end(), id) == cand.end())
      cand.push_back(id);
  const StereoCheckOptions so = loopCheckOptions();
  int tried = 0;
  for (uint32_t id : cand)
  {
    if (tried >= p_.loop_candidates + p_.appearance_candidates)
      break;
    if (id >= kfs_.size() || static_cast<int>(kfs_[id]->submap) > static_cast<int>(kf->submap) - p_.loop_skip_submaps)
      continue;
    ++tried;
    const Keyframe& a = *kfs_[id];
    const StereoCheckResult r = stereoCheck(a, *kf, cam_, so);
    LoopEvent ev;
    ev.stamp = kf->stamp;
    ev.keyframe_old = a.id;
    ev.keyframe_new = kf->id;
    ev.submap_old = a.submap;
    ev.submap_new = kf->submap;
    ev.matches = r.matches;
    ev.inliers = r.inliers;
    ev.T_old_new = r.T_a_b;
    if (!r.accepted)
      continue;  // not verified: no event (most candidates simply do not match)
    const Eigen::Isometry3d T_map_b = a.T_map_cam * r.T_a_b;
    const Eigen::Isometry3d corr = kf->T_map_cam.inverse() * T_map_b;
    ev.correction_m = corr.translation().norm();
    ev.correction_deg = angleDeg(corr);
    const double max_m = p_.loop_max_correction_m + 0.05 * (kf->path_m - a.path_m);
    if (ev.correction_m > max_m || ev.correction_deg > p_.loop_max_correction_deg)
    {
      ev.reason = "verified but inconsistent with the map: moves the wearer " + std::to_string(ev.correction_m) +
                  " m / " + std::to_string(ev.correction_deg) + " deg";
      std::lock_guard<std::mutex> l(mm_);
      events_.push_back(ev);
      ++stats_.loops_rejected;
      continue;
    }
    LoopLink link;
    {
      const Eigen::Isometry3d& Oa = submaps_[a.submap].T_map_origin;
      const Eigen::Isometry3d& Ob = submaps_[kf->submap].T_map_origin;
      const Eigen::Isometry3d T_b_in_submap = Ob.inverse() * kf->T_map_cam;
      link = {a.submap, kf->submap, Oa.inverse() * a.T_map_cam * r.T_a_b * T_b_in_submap.inverse()};
    }
    // Temporal consistency: a closure is only accepted when the next keyframe's verified closure
    // implies the same correction of the map (look-alike places pass one P3P check far more
    // often than two in a row with the same answer: a generated street had one at 40 inliers).
    const Eigen::Isometry3d delta = T_map_b * kf->T_map_cam.inverse();
    auto rejectPending = [&](const std::string& why) {
      if (!pending_.valid)
        return;
      pending_.ev.reason = why;
      std::lock_guard<std::mutex> l(mm_);
      events_.push_back(pending_.ev);
      ++stats_.loops_rejected;
      pending_.valid = false;
    };
    if (pending_.valid && pending_.ev.keyframe_new + 1 == kf->id)
    {
      const Eigen::Isometry3d dd = pending_.delta.inverse() * delta;
      if (dd.translation().norm() <= p_.loop_confirm_m && angleDeg(dd) <= p_.loop_confirm_deg)
      {
        ev.accepted = true;
        pending_.ev.accepted = true;
        {
          std::lock_guard<std::mutex> l(mm_);
          loop_links_.push_back(pending_.link);
          loop_links_.push_back(link);
          events_.push_back(pending_.ev);
          events_.push_back(ev);
          stats_.loops_accepted += 2;
        }
        pending_.valid = false;
        optimiseGraph();
        placeAfterGivingUp(std::min(pending_.link.from, link.from));
        return;
      }
      rejectPending("not confirmed: the next keyframe's verified closure implies another correction");
    }
    else
      rejectPending("not confirmed by the next keyframe");
    pending_.valid = true;
    pending_.ev = ev;
    pending_.link = link;
    pending_.delta = delta;
    return;  // one closure per keyframe
  }
}

void SlamSystem::placeAfterGivingUp(uint32_t old_submap)
{
  // A search that gave up ends when a closure reaches a submap from before the loss: the map's
  // correction has placed the new session in it.
  std::lock_guard<std::mutex> l(mm_);
  if (!reset_.active || !reset_.gave_up || old_submap >= reset_.first_submap)
    return;
  reset_ = ResetSearch();
  localised_ = true;
  stats_.localised = !vo_lost_;
  ++stats_.reset_relocalisations;
}

Eigen::Isometry3d SlamSystem::submapOdometry(uint32_t i) const
{
  // Chain of the keyframes' relative motions (VO, refined by the local BA) from the origin of
  // submap i to the origin of submap i + 1: unaffected by earlier pose-graph corrections.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const uint32_t a = submaps_[i].keyframes.front(), b = submaps_[i + 1].keyframes.front();
  for (uint32_t k = a + 1; k <= b; ++k)
    T = T * kf_rel_[k];
  return T;
}

void SlamSystem::optimiseGraph()
{
  PoseGraph g;
  std::lock_guard<std::mutex> l(mm_);
  for (const SubmapInfo& s : submaps_)
    g.addNode(s.id, s.T_map_origin);
  for (size_t i = 0; i + 1 < submaps_.size(); ++i)
  {
    PoseGraphEdge e;
    e.from = static_cast<uint32_t>(i);
    e.to = static_cast<uint32_t>(i + 1);
    e.T_from_to = submapOdometry(static_cast<uint32_t>(i));
    e.information = odomInformation(kfs_[submaps_[i + 1].keyframes.front()]->path_m -
                                    kfs_[submaps_[i].keyframes.front()]->path_m);
    g.addEdge(e);
  }
  const Matrix6d loop_info = isotropicInformation(p_.loop_sigma_m, p_.loop_sigma_deg * kDeg);
  for (const LoopLink& ll : loop_links_)
  {
    PoseGraphEdge e;
    e.from = ll.from;
    e.to = ll.to;
    e.T_from_to = ll.T;
    e.information = loop_info;
    g.addEdge(e);
  }
  g.setFixed(0);
  g.optimise(50);
  ++stats_.pose_graph_runs;
  // Every keyframe moves rigidly with its submap.
  for (SubmapInfo& s : submaps_)
  {
    const Eigen::Isometry3d delta = g.pose(s.id) * s.T_map_origin.inverse();
    for (uint32_t k : s.keyframes)
      kfs_[k]->T_map_cam = delta * kfs_[k]->T_map_cam;
    s.T_map_origin = g.pose(s.id);
  }
}

Eigen::Isometry3d SlamSystem::mapToOdom() const
{
  std::lock_guard<std::mutex> l(mm_);
  return T_map_odom_;
}

SlamStats SlamSystem::stats() const
{
  SlamStats s;
  {
    std::lock_guard<std::mutex> l(mm_);
    s = stats_;
  }
  std::lock_guard<std::mutex> l(qm_);
  s.queue_depth = static_cast<int>(queue_.size());
  s.loop_queue_depth = static_cast<int>(loop_queue_.size());
  s.dropped = dropped_;
  return s;
}

std::vector<LoopEvent> SlamSystem::loopEvents() const
{
  std::lock_guard<std::mutex> l(mm_);
  return events_;
}

std::vector<Keyframe> SlamSystem::keyframes(bool with_features) const
{
  std::lock_guard<std::mutex> l(mm_);
  std::vector<Keyframe> out;
  out.reserve(kfs_.size());
  for (const KeyframePtr& k : kfs_)
  {
    Keyframe c;
    c.id = k->id;
    c.submap = k->submap;
    c.stamp = k->stamp;
    c.T_odom_cam = k->T_odom_cam;
    c.T_map_cam = k->T_map_cam;
    c.path_m = k->path_m;
    if (with_features)
    {
      c.keypoints = k->keypoints;
      c.u_right = k->u_right;
      c.descriptors = k->descriptors.clone();
      c.points = k->points;
      c.landmark = k->landmark;
    }
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<SubmapInfo> SlamSystem::submaps() const
{
  std::lock_guard<std::mutex> l(mm_);
  return submaps_;
}

std::vector<SubmapLinkInfo> SlamSystem::links() const
{
  std::lock_guard<std::mutex> l(mm_);
  std::vector<SubmapLinkInfo> out;
  for (size_t i = 0; i + 1 < submaps_.size(); ++i)
  {
    SubmapLinkInfo li;
    li.from = static_cast<uint32_t>(i);
    li.to = static_cast<uint32_t>(i + 1);
    li.T_from_to = submapOdometry(static_cast<uint32_t>(i));
    li.covariance = odomCovariance(kfs_[submaps_[i + 1].keyframes.front()]->path_m -
                                   kfs_[submaps_[i].keyframes.front()]->path_m);
    out.push_back(li);
  }
  const Matrix6d loop_cov = isotropicInformation(p_.loop_sigma_m, p_.loop_sigma_deg * kDeg).inverse();
  for (const LoopLink& ll : loop_links_)
    out.push_back({ll.from, ll.to, ll.T, loop_cov, true});
  return out;
}

uint32_t SlamSystem::currentSubmap() const
{
  std::lock_guard<std::mutex> l(mm_);
  return submaps_.empty() ? 0 : submaps_.back().id;
}

bool SlamSystem::relocalise(const KeyframePtr& kf)
{
  // The stored submaps relocalisationSubmaps() lists, verified like a loop closure; two
  // consecutive keyframes must agree on map -> odom.
  // The map is only read here and only the worker writes it: no lock while verifying (readers in
  // the frame loop must never wait for this); the state is written under mm_ below.
  int query;
  {
    std::lock_guard<std::mutex> l(mm_);
    query = ++stats_.relocalisation_queries;
  }
  if (!appearance_ || kf->descriptors.empty())
    return false;
  const AppearanceResult ar = appearance_->query(appearanceRows(kf->descriptors, p_.appearance_features), -1, 0);
  const StereoCheckOptions so = loopCheckOptions();
  // The model ranks submaps; its keyframe within a submap is a weak guess (on a generated parking
  // walk it was the submap's first for 8 queries in a row while another of its keyframes matched),
  // so every keyframe of a listed submap is verified and the one with the most inliers is kept.
  for (uint32_t s : relocalisationSubmaps(ar, query))
  {
    const Keyframe* best = nullptr;
    StereoCheckResult r;
    for (uint32_t id : submaps_[s].keyframes)
    {
      const StereoCheckResult ri = stereoCheck(*kfs_[id], *kf, cam_, so);
      if (ri.accepted && (!best || ri.inliers > r.inliers))
      {
        best = kfs_[id].get();
        r = ri;
      }
    }
    if (!best)
      continue;
    const bool confirmed = confirmRelocalisation(*best, r, kf, query);
    if (confirmed && !p_.appearance_loop)
      appearance_.reset();  // relocalisation is done: its grids would only cost memory
    return confirmed;
  }
  return false;
}

std::vector<uint32_t> SlamSystem::relocalisationSubmaps(const AppearanceResult& ar, int query)
{
  // The model's ranking alone is not enough: on the rendered parking walks its words barely match
  // between two views of one place (1-5 of 800 observations), so the ranking hardly depends on the
  // query, and the stored place in view was verified only when it happened to be among the
  // model's best on two queries in a row (83 keyframes on the shipped walk). Hence the submap
  // verified by the previous query comes first (the confirmation needs this one's agreement), and
  // every stored submap gets its turn.
  const auto n = static_cast<uint32_t>(submaps_.size());
  std::vector<uint32_t> out;
  auto add = [&](uint32_t s) {
    if (s < n && std::find(out.begin(), out.end(), s) == out.end())
      out.push_back(s);
  };
  if (!reloc_run_.empty() && reloc_run_.back().query + 1 == query)
    add(reloc_run_.back().ev.submap_old);
  for (const LoopCandidate& c : ar.candidates)
    if (c.submap_id >= 0)
      add(static_cast<uint32_t>(c.submap_id));
  const size_t wanted = out.size() + static_cast<size_t>(std::max(0, p_.relocalisation_sweep));
  for (uint32_t i = 0; i < n && out.size() < wanted; ++i)
  {
    const uint32_t s = reloc_sweep_;
    reloc_sweep_ = (reloc_sweep_ + 1) % n;
    add(s);
  }
  return out;
}

bool SlamSystem::confirmRelocalisation(const Keyframe& a, const StereoCheckResult& r, const KeyframePtr& kf, int query)
{
  const Eigen::Isometry3d T_map_b = a.T_map_cam * r.T_a_b;
  const Eigen::Isometry3d T_mo = T_map_b * kf->T_odom_cam.inverse();
  Reloc now;
  now.valid = true;
  now.query = query;
  now.T_map_odom = T_mo;
  now.link = {a.submap, 0, submaps_[a.submap].T_map_origin.inverse() * T_map_b};
  now.ev.stamp = kf->stamp;
  now.ev.keyframe_old = a.id;
  now.ev.submap_old = a.submap;
  now.ev.matches = r.matches;
  now.ev.inliers = r.inliers;
  now.ev.T_old_new = r.T_a_b;
  now.ev.accepted = true;
  now.ev.relocalisation = true;
  // A run of consecutive queries agreeing with its first on map -> odom: after a load 2 of them
  // within loop_confirm, after a VO loss reset_confirm_queries within reset_confirm (the 0.1 m the
  // wearer's place needs: single queries scatter by 0.1-0.2 m on sparse features), at their mean.
  const double tol_m = reset_.active ? p_.reset_confirm_m : p_.loop_confirm_m;
  const double tol_deg = reset_.active ? p_.reset_confirm_deg : p_.loop_confirm_deg;
  const bool agrees = !reloc_run_.empty() && reloc_run_.back().query + 1 == query && [&] {
    const Eigen::Isometry3d dd = reloc_run_.front().T_map_odom.inverse() * T_mo;
    return dd.translation().norm() <= tol_m && angleDeg(dd) <= tol_deg;
  }();
  if (!agrees)
    reloc_run_.clear();
  reloc_run_.push_back(now);
  const int needed = reset_.active ? p_.reset_confirm_queries : 2;
  if (static_cast<int>(reloc_run_.size()) < needed)
    return false;
  if (reset_.active)
  {
    now.T_map_odom = meanMapToOdom();
    const Eigen::Isometry3d T_map_mean = now.T_map_odom * kf->T_odom_cam;
    now.link.T = submaps_[a.submap].T_map_origin.inverse() * T_map_mean;
    now.ev.T_old_new = a.T_map_cam.inverse() * T_map_mean;
  }
  reloc_done_ = now;
  reloc_run_.clear();
  std::lock_guard<std::mutex> l(mm_);
  T_map_odom_ = now.T_map_odom;
  localised_ = true;
  session_start_ = true;
  link_session_ = true;
  stats_.localised = !vo_lost_;
  stats_.relocalised_stamp = kf->stamp;
  if (reset_.active)
    ++stats_.reset_relocalisations;
  reset_ = ResetSearch();
  stats_.relocalising_after_reset = false;
  return true;
}

Eigen::Isometry3d SlamSystem::meanMapToOdom() const
{
  // translations averaged, rotations by the normalised sum of sign-aligned quaternions (they agree
  // within loop_confirm_deg)
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector4d q = Eigen::Vector4d::Zero();
  const Eigen::Quaterniond q0(reloc_run_.front().T_map_odom.linear());
  for (const Reloc& r : reloc_run_)
  {
    t += r.T_map_odom.translation();
    Eigen::Quaterniond qi(r.T_map_odom.linear());
    if (qi.dot(q0) < 0)
      qi.coeffs() *= -1.0;
    q += qi.coeffs();
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(q.normalized()).toRotationMatrix();
  T.translation() = t / static_cast<double>(reloc_run_.size());
  return T;
}

void SlamSystem::waitLoopIdle()
{
  if (!loop_threaded_)
    return;
  std::unique_lock<std::mutex> l(qm_);
  idle_cv_.wait(l, [&] { return stop_ || (loop_queue_.empty() && !loop_busy_); });
}

void SlamSystem::beginReset(const Job& job)
{
  // Nothing is mapped while the wearer is unplaced, so the loop closer runs dry: wait for it, then
  // the map holds still for the search (the anchor comes from map -> odom after its last correction).
  waitLoopIdle();
  std::lock_guard<std::mutex> l(mm_);
  ++resets_begun_;
  if (resets_begun_ >= resets_queued_)
    vo_lost_ = false;  // taken up: localised_ says it from here
  ++stats_.vo_losses;
  reloc_run_.clear();  // odom moved under the pending matches
  if (kfs_.empty() || !localised_)
  {
    // No map yet, or still unplaced (a loaded map, an earlier loss): the search goes on as it was;
    // a search that had given up looks again near its anchor
    if (reset_.active && reset_.gave_up && !kfs_.empty())
      reset_.gave_up = false;
    stats_.localised = localised_ && !vo_lost_;
    stats_.relocalising_after_reset = reset_.active && !reset_.gave_up;
    return;
  }
  reset_.active = true;
  reset_.gave_up = false;
  reset_.T_map_odom = T_map_odom_;
  reset_.T_map_anchor = T_map_odom_ * job.T_odom_last_trusted;
  reset_.stamp = job.last_trusted_stamp;
  reset_.bridgeable = job.bridgeable;
  reset_.first_query_stamp = job.frame.stamp;
  localised_ = false;
  stats_.localised = false;
  stats_.relocalising_after_reset = true;
}

bool SlamSystem::plausibleAfterReset(const Eigen::Isometry3d& T_map_b, const Eigen::Isometry3d& T_map_pred,
                                     double radius) const
{
  // No farther from the anchor than the wearer can have walked, turned as the gyro said, and not
  // behind where they were facing by more than reset_max_backward (people walk where they look;
  // the plaza's repeated structure, seen again ahead, passed every other check with up to 46
  // inliers, three queries in a row, placing the wearer 1.8-2.5 m behind the last trusted pose
  // after 3.4-7.6 m walked on).
  const Eigen::Vector3d d = T_map_b.translation() - reset_.T_map_anchor.translation();
  if (d.norm() > radius || angleDeg(T_map_pred.inverse() * T_map_b) > p_.reset_max_rotation_deg)
    return false;
  // the mean of the view directions then and now, level (map z is up: odom is gravity-aligned)
  Eigen::Vector3d h = reset_.T_map_anchor.linear().col(2) + T_map_pred.linear().col(2);
  h.z() = 0.0;
  if (h.norm() < 1e-6)
    return true;  // turned about: no direction to hold against
  return d.dot(h.normalized()) >= -p_.reset_max_backward_m;
}

std::vector<uint32_t> SlamSystem::resetCandidates(const Keyframe& kf, const Eigen::Isometry3d& T_map_pred,
                                                  double radius) const
{
  (void)kf;
  std::vector<std::pair<double, uint32_t>> near;
  for (const KeyframePtr& c : kfs_)
  {
    const double d = (c->T_map_cam.translation() - reset_.T_map_anchor.translation()).norm();
    // The VO's rotation went on with the gyro while untrusted: the predicted view direction holds.
    if (d < radius && viewAngleDeg(c->T_map_cam, T_map_pred) < 60.0 && !c->descriptors.empty())
      near.emplace_back(d, c->id);
  }
  std::sort(near.begin(), near.end());
  std::vector<uint32_t> out;
  for (const auto& [d, id] : near)
    if (static_cast<int>(out.size()) < p_.reset_candidates)
      out.push_back(id);
  return out;
}

bool SlamSystem::relocaliseAfterReset(const KeyframePtr& kf)
{
  int query;
  {
    std::lock_guard<std::mutex> l(mm_);
    query = ++stats_.relocalisation_queries;
  }
  const double since = kf->stamp - reset_.stamp;
  if (p_.reset_relocalisation_timeout_s > 0 && since > p_.reset_relocalisation_timeout_s)
  {
    giveUpRelocalisation();
    return true;  // mapped (unplaced)
  }
  if (reset_.bridgeable && kf->stamp - reset_.first_query_stamp >= p_.reset_bridge_after_s)
  {
    bridgeLoss();
    return true;  // mapped (placed on the held pose)
  }
  if (kf->descriptors.empty())
    return false;
  // Where the wearer would be on the old map -> odom: the rotation is right (gyro), the position
  // is off by what was walked unseen, at most the radius.
  const Eigen::Isometry3d T_map_pred = reset_.T_map_odom * kf->T_odom_cam;
  const double radius = p_.reset_search_radius_m + p_.reset_max_speed * std::max(0.0, since);
  std::vector<uint32_t> cand = resetCandidates(*kf, T_map_pred, radius);
  if (p_.appearance_loop && appearance_)  // (the model learns keyframes only with appearance_loop)
    for (const LoopCandidate& c : appearance_->query(appearanceRows(kf->descriptors, p_.appearance_features), -1, 0).candidates)
      if (c.keyframe_id >= 0 && std::find(cand.begin(), cand.end(), static_cast<uint32_t>(c.keyframe_id)) == cand.end())
        cand.push_back(static_cast<uint32_t>(c.keyframe_id));
  if (cand.empty())
    return false;
  // One check against the candidates together (a local map in map coordinates): walking on, each
  // keyframe shares few features with the query, their union enough.
  StereoCheckOptions so = loopCheckOptions();
  so.min_inliers = p_.reset_min_inliers;
  so.min_inlier_ratio = p_.reset_min_inlier_ratio;
  if (p_.reset_fixed_rotation)
    so.R_ref_b = T_map_pred.linear();  // the gyro kept it through the loss
  std::vector<std::pair<const Keyframe*, Eigen::Isometry3d>> local;
  for (uint32_t id : cand)
    local.emplace_back(kfs_[id].get(), kfs_[id]->T_map_cam);
  const StereoCheckResult r = localMapCheck(local, *kf, cam_, so);
  const Eigen::Isometry3d& T_map_b = r.T_a_b;
  if (!r.accepted || !plausibleAfterReset(T_map_b, T_map_pred, radius))
    return false;
  // The link to the map: from the nearest candidate (the keyframes near the anchor come first).
  const Keyframe& a = *kfs_[cand.front()];
  StereoCheckResult ra = r;
  ra.T_a_b = a.T_map_cam.inverse() * refineOnLocalMap(local, r, *kf, T_map_pred);
  return confirmRelocalisation(a, ra, kf, query);
}

Eigen::Isometry3d SlamSystem::refineOnLocalMap(const std::vector<std::pair<const Keyframe*, Eigen::Isometry3d>>& local,
                                               const StereoCheckResult& r, const Keyframe& q,
                                               const Eigen::Isometry3d& T_map_pred) const
{
  // The P3P pose rests on the keyframes' stereo points alone, whose depth errors grow with the
  // distance (ORB's coarse levels): each inlier's point is re-estimated from both stereo views,
  // the keyframe's (held) and the query's, together with the query's pose.
  BaProblem pb;
  for (const auto& l : local)
  {
    pb.poses.push_back(l.second);
    pb.fixed.push_back(true);
  }
  const int qi = static_cast<int>(pb.poses.size());
  pb.poses.push_back(r.T_a_b);
  pb.fixed.push_back(false);
  // A landmark the keyframes share (their associations) is observed by each of them: its depth
  // then rests on the baseline between keyframes, not only on the stereo one.
  std::vector<std::map<int64_t, int>> by_landmark(local.size());
  for (size_t i = 0; i < local.size(); ++i)
    for (size_t f = 0; f < local[i].first->landmark.size(); ++f)
      if (local[i].first->landmark[f] >= 0)
        by_landmark[i][local[i].first->landmark[f]] = static_cast<int>(f);
  auto observe = [&](int frame, int64_t id, const Keyframe& k, int f) {
    pb.observations.push_back({frame, id, Eigen::Vector3d(k.keypoints[f].pt.x, k.keypoints[f].pt.y, k.u_right[f]),
                               std::pow(1.2, k.keypoints[f].octave)});
  };
  int64_t lone = -1;
  for (const StereoCheckResult::Inlier& m : r.inlier_matches)
  {
    const Keyframe& k = *local[m.keyframe].first;
    const int64_t landmark = k.landmark[m.a];
    const int64_t id = landmark >= 0 ? landmark : lone--;
    if (pb.landmarks.count(id))
      continue;  // a second query feature on the same landmark: one is enough
    pb.landmarks[id] = local[m.keyframe].second * k.points[m.a];
    observe(qi, id, q, m.b);
    if (landmark < 0)
    {
      observe(m.keyframe, id, k, m.a);
      continue;
    }
    for (size_t i = 0; i < local.size(); ++i)
    {
      auto it = by_landmark[i].find(landmark);
      if (it != by_landmark[i].end())
        observe(static_cast<int>(i), id, *local[i].first, it->second);
    }
  }
  // The rotation the gyro kept (the predicted pose's) as a prior: far points alone trade a pitch
  // error for a height error (corridor: 1.3 deg for 0.26 m); the position is left free.
  PoseGraphEdge prior;
  prior.from = 0;
  prior.to = static_cast<uint32_t>(qi);
  prior.T_from_to = local[0].second.inverse() * T_map_pred;
  const double sr = p_.reset_rotation_sigma_deg * kDeg;
  prior.information.setZero();
  prior.information.diagonal() << 1e-6, 1e-6, 1e-6, 1.0 / (sr * sr), 1.0 / (sr * sr), 1.0 / (sr * sr);
  pb.priors.push_back(prior);
  BaOptions o;
  o.max_iterations = 20;
  o.huber_px = p_.ba_huber_px;
  o.pixel_sigma_px = p_.pixel_sigma_px;
  const BaResult br = bundleAdjust(pb, cam_, o);
  const Eigen::Isometry3d d = r.T_a_b.inverse() * pb.poses[qi];
  if (!br.solved || !(br.final_rms_px <= br.initial_rms_px) || !d.matrix().allFinite() || d.translation().norm() > 0.5 ||
      angleDeg(d) > 5.0)
    return r.T_a_b;  // a failed adjustment: the P3P pose
  return pb.poses[qi];
}

void SlamSystem::mapOnFromHeldPose()
{
  // (under mm_) the map goes on from map -> odom before the loss: a new submap, no verified link
  // (the odometry across the loss is all there is)
  T_map_odom_ = reset_.T_map_odom;
  session_start_ = true;
  link_session_ = false;
  reloc_run_.clear();
  stats_.relocalising_after_reset = false;
}

void SlamSystem::bridgeLoss()
{
  std::lock_guard<std::mutex> l(mm_);
  mapOnFromHeldPose();
  reset_ = ResetSearch();
  localised_ = true;
  ++stats_.reset_bridged;
  stats_.localised = !vo_lost_;
}

void SlamSystem::giveUpRelocalisation()
{
  // Not found again: the map goes on (a new submap, weakly linked by the VO's held pose), and the
  // wearer stays unplaced until a loop closure links it to a submap from before the loss.
  std::lock_guard<std::mutex> l(mm_);
  reset_.gave_up = true;
  reset_.first_submap = static_cast<uint32_t>(submaps_.size());
  mapOnFromHeldPose();
  ++stats_.reset_gave_up;
}

bool SlamSystem::loadMap(const MapData& m, std::string* err)
{
  auto fail = [&](const std::string& e) {
    if (err)
      *err = e;
    return false;
  };
  {
    std::lock_guard<std::mutex> lq(qm_);
    if (busy_ || !queue_.empty() || loop_busy_ || !loop_queue_.empty())
      return fail("a map can only be loaded before the first frame");
  }
  std::lock_guard<std::mutex> l(mm_);
  if (!kfs_.empty())
    return fail("a map can only be loaded before the first frame");
  if (m.keyframes.empty() || m.submaps.empty())
    return fail("the map holds no keyframe");
  for (size_t i = 0; i < m.keyframes.size(); ++i)
    if (m.keyframes[i].id != i || m.keyframes[i].submap >= m.submaps.size())
      return fail("keyframe " + std::to_string(i) + " is out of order or in no submap");
  for (size_t i = 0; i < m.submaps.size(); ++i)
  {
    if (m.submaps[i].id != i || m.submaps[i].keyframes.empty())
      return fail("submap " + std::to_string(i) + " is out of order or empty");
    for (uint32_t k : m.submaps[i].keyframes)
      if (k >= m.keyframes.size() || m.keyframes[k].submap != i)
        return fail("submap " + std::to_string(i) + " lists a keyframe it does not hold");
  }
  for (const SubmapLinkInfo& li : m.loop_links)
    if (li.from >= m.submaps.size() || li.to >= m.submaps.size())
      return fail("a loop link joins unknown submaps");
  for (const Keyframe& k : m.keyframes)
  {
    auto kf = std::make_shared<Keyframe>(k);
    kf->landmark.assign(kf->keypoints.size(), -1);
    kf_rel_.push_back(kfs_.empty() ? Eigen::Isometry3d::Identity() : kfs_.back()->T_map_cam.inverse() * kf->T_map_cam);
    kfs_.push_back(kf);
    if (appearance_)
      appearance_->add(static_cast<int>(kf->id), static_cast<int>(kf->submap), appearanceRows(kf->descriptors, p_.appearance_features));
  }
  submaps_ = m.submaps;
  for (const SubmapLinkInfo& li : m.loop_links)
    loop_links_.push_back({li.from, li.to, li.T_from_to});
  places_ = m.places;
  localised_ = false;
  stats_.localised = false;
  stats_.keyframes = static_cast<int>(kfs_.size());
  stats_.submaps = static_cast<int>(submaps_.size());
  return true;
}

bool SlamSystem::localised() const
{
  std::lock_guard<std::mutex> l(mm_);
  return localised_ && !vo_lost_;
}

bool SlamSystem::tagPlace(const std::string& name, const Eigen::Isometry3d& T_odom_cam, double stamp, Place* out,
                          std::string* err)
{
  std::lock_guard<std::mutex> l(mm_);
  if (kfs_.empty() || !localised_ || vo_lost_)
  {
    if (err)
      *err = kfs_.empty() ? "no keyframe yet: the map cannot hold a place before its first keyframe"
                          : "not localised in the map yet (a loaded map, or the VO lost tracking)";
    return false;
  }
  if (!T_odom_cam.matrix().allFinite())
  {
    if (err)
      *err = "the current VO pose is not finite";
    return false;
  }
  const Keyframe& kf = *kfs_.back();
  Place p;
  p.name = name.empty() ? "place" + std::to_string(places_.size() + 1) : name;
  p.keyframe = kf.id;
  // The VO's own motion since the keyframe: independent of any map correction.
  p.T_kf_place = kf.T_odom_cam.inverse() * T_odom_cam;
  p.stamp = stamp;
  places_.erase(std::remove_if(places_.begin(), places_.end(), [&](const Place& q) { return q.name == p.name; }),
                places_.end());
  places_.push_back(p);
  if (out)
    *out = p;
  return true;
}

bool SlamSystem::placePose(const std::string& name, Eigen::Isometry3d* T_map_place, std::string* err) const
{
  std::lock_guard<std::mutex> l(mm_);
  if (places_.empty())
  {
    if (err)
      *err = "no place tagged";
    return false;
  }
  auto it = name.empty() ? std::prev(places_.end())
                         : std::find_if(places_.begin(), places_.end(), [&](const Place& q) { return q.name == name; });
  if (it == places_.end() || it->keyframe >= kfs_.size())
  {
    if (err)
      *err = "no place named '" + name + "'";
    return false;
  }
  *T_map_place = kfs_[it->keyframe]->T_map_cam * it->T_kf_place;
  return true;
}

std::vector<std::pair<Place, Eigen::Isometry3d>> SlamSystem::places() const
{
  std::lock_guard<std::mutex> l(mm_);
  std::vector<std::pair<Place, Eigen::Isometry3d>> out;
  for (const Place& p : places_)
    if (p.keyframe < kfs_.size())
      out.emplace_back(p, kfs_[p.keyframe]->T_map_cam * p.T_kf_place);
  return out;
}

void SlamSystem::setCandidateSource(CandidateSource s)
{
  std::lock_guard<std::mutex> l(mm_);
  candidates_ = std::move(s);
}

}  // namespace assistive_slam
