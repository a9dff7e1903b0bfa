#include <assistive_obstacles/mover_pipeline.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace assistive_obstacles
{
namespace
{
double msSince(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

MoverPipelineParams moverPipelineParams(const ObstaclesParams& p, const StereoModel& model)
{
  MoverPipelineParams m;
  m.flow.max_features = p.mover_max_features;
  m.flow.fast_threshold = p.mover_fast_threshold;
  m.flow.spread_blocks = p.mover_spread_blocks;
  m.tracker.death_misses = p.mover_death_misses;
  m.flow.half_resolution_corners = p.mover_half_resolution_corners;
  m.flow.max_fb_error = p.mover_max_fb_error;
  m.flow.edge_window = p.mover_edge_window;
  m.flow.fair_backward = p.mover_fair_backward;
  m.flow.keep_tracks = p.mover_keep_tracks;
  m.flow.backward_base_px = p.mover_backward_base_px;
  m.flow.stereo_search = p.mover_stereo_search;
  m.flow.stereo_min_ncc = p.mover_stereo_min_ncc;
  m.flow.frames_apart = p.mover_frames_apart;
  m.flow.min_depth = p.min_depth;
  m.flow.max_depth = p.max_depth;
  m.segmentation.fx = model.fx;
  m.segmentation.baseline = model.baseline;
  m.segmentation.disparity_sigma = p.mover_disparity_sigma;
  m.segmentation.sigma_scale = p.mover_sigma_scale;
  m.segmentation.min_residual = p.mover_min_residual;
  m.segmentation.min_cluster_points = p.mover_min_cluster_points;
  m.segmentation.cell_size = p.cell_size;
  m.min_speed = p.mover_min_speed;
  m.max_gap_s = p.max_frame_gap_s;
  m.confirm_sigmas = p.mover_confirm_sigmas;
  m.flow_sigma = p.mover_flow_sigma;
  return m;
}

MotionFit fitMotion(const std::deque<TrackDetection>& detections, double sigma_floor)
{
  MotionFit f;
  f.n = static_cast<int>(detections.size());
  if (f.n < 2) return f;
  f.span = detections.back().t - detections.front().t;
  double tm = 0.0;
  Eigen::Vector2d zm = Eigen::Vector2d::Zero();
  for (const TrackDetection& d : detections)
  {
    tm += d.t;
    zm += d.z;
  }
  tm /= f.n;
  zm /= f.n;
  double stt = 0.0;
  Eigen::Vector2d stz = Eigen::Vector2d::Zero();
  for (const TrackDetection& d : detections)
  {
    stt += (d.t - tm) * (d.t - tm);
    stz += (d.t - tm) * (d.z - zm);
  }
  if (!(stt > 0.0)) return f;
  f.velocity = stz / stt;
  double ss = 0.0;
  for (const TrackDetection& d : detections) ss += (d.z - zm - f.velocity * (d.t - tm)).squaredNorm();
  f.scatter = f.n > 2 ? std::sqrt(ss / (2.0 * (f.n - 2))) : 0.0;
  f.sigma_v = std::max(f.scatter, sigma_floor) / std::sqrt(stt);
  return f;
}

bool seenMoving(const std::deque<TrackDetection>& detections, const MoverPipelineParams& p)
{
  if (!(p.confirm_sigmas > 0.0)) return true;  // the test switched off
  const int n = static_cast<int>(detections.size());
  if (n < 3) return false;
  // The points' own motion against the ego-motion.
  Eigen::Vector2d vf = Eigen::Vector2d::Zero();
  for (const TrackDetection& d : detections) vf += d.v_flow;
  vf /= n;
  double ss = 0.0;
  for (const TrackDetection& d : detections) ss += (d.v_flow - vf).squaredNorm();
  const double scatter = std::sqrt(ss / (2.0 * (n - 1)));  // per axis
  const double sf = std::max(scatter, p.flow_sigma) / std::sqrt(static_cast<double>(n));
  const double speed = vf.norm();
  if (!(speed >= p.min_speed && speed >= p.confirm_sigmas * sf)) return false;
  // Each of the last three detections moves that way on its own: a walker's points do in every
  // frame; a flickering depth's only now and then, and its mean can pass the test by chance.
  const Eigen::Vector2d dir = vf / speed;
  for (int k = std::max(0, n - 3); k < n; ++k)
    if (detections[static_cast<size_t>(k)].v_flow.dot(dir) < 0.5 * p.min_speed) return false;
  // The centres go the same way.
  const MotionFit c = fitMotion(detections, p.tracker.meas_sigma);
  return (c.velocity - vf).norm() <= 0.5 * speed + p.confirm_sigmas * c.sigma_v;
}

MoverPipeline::MoverPipeline(const MoverPipelineParams& p) { setParams(p); }

void MoverPipeline::setParams(const MoverPipelineParams& p)
{
  params_ = p;
  flow_.setParams(p.flow);
  segmentation_.setParams(p.segmentation);
  tracker_.setParams(p.tracker);
}

void MoverPipeline::reset()
{
  flow_.reset();
  tracker_.reset();
  footprints_.clear();
  shape_.clear();
  origin_.clear();
  history_.clear();
  seen_moving_.clear();
  poses_.clear();
  has_prev_ = false;
}

bool MoverPipeline::stationary(const MoverTrack& tr) const
{
  const double age = tr.last_seen - tr.born;
  const auto it = origin_.find(tr.id);
  return it != origin_.end() && age >= params_.speed_age &&
         (tr.last_z - it->second).norm() < params_.min_speed * age;
}

bool MoverPipeline::reported(const MoverTrack& tr) const
{
  if (!tr.confirmed || stationary(tr)) return false;
  const auto it = seen_moving_.find(tr.id);
  return it != seen_moving_.end() && it->second;
}

std::vector<ReportedMover> MoverPipeline::confirmed() const
{
  std::vector<ReportedMover> out;
  for (const MoverTrack& t : tracker_.tracks())
  {
    if (!reported(t)) continue;
    ReportedMover r;
    r.track = t;
    const auto it = shape_.find(t.id);
    if (it != shape_.end())
    {
      r.radius = it->second.first;
      r.height = it->second.second;
    }
    out.push_back(r);
  }
  return out;
}

const std::vector<MoverFootprint>& MoverPipeline::process(double t, const cv::Mat& grey, const cv::Mat& disp,
                                                          const StereoModel& model, const Eigen::Isometry3d& T_world_cam,
                                                          const cv::Mat* right)
{
  footprints_.clear();
  if (has_prev_ && (t <= prev_t_ || t - prev_t_ > params_.max_gap_s)) reset();
  // The rig may differ from the defaults (camera_info): the depth noise model follows it.
  MoverSegmentationParams sp = segmentation_.params();
  sp.fx = model.fx;
  sp.baseline = model.baseline;
  segmentation_.setParams(sp);

  auto t0 = std::chrono::steady_clock::now();
  const std::vector<SceneFlowPoint>& flow = flow_.process(grey, disp, model, &T_world_cam, right);
  ms_flow_ = msSince(t0);
  t0 = std::chrono::steady_clock::now();
  const int back = flow_.pairedBack();
  const bool paired = has_prev_ && !flow.empty() && back >= 1 && back <= static_cast<int>(poses_.size());
  std::vector<Eigen::Vector2d> z;
  double paired_t = t;  // the frame the flow paired with
  if (paired)
  {
    const std::pair<double, Eigen::Isometry3d>& then = poses_[poses_.size() - static_cast<size_t>(back)];
    paired_t = then.first;
    const Eigen::Isometry3d T_cur_prev = T_world_cam.inverse() * then.second;
    // A residual faster than anyone walks is a mismatch (repeated texture, a corner on a
    // silhouette), not a mover: such points are dropped.
    const double max_step = params_.max_speed * (t - then.first);
    kept_.clear();
    for (const SceneFlowPoint& f : flow)
      if (MoverSegmentation::residual(f, T_cur_prev) <= max_step) kept_.push_back(f);
    segmentation_.segment(kept_, T_cur_prev, T_world_cam);
    // The camera sees a body's front: the centroid of its points lies nearer than its centre, by
    // ~pi/4 of its radius for a round body. Moved away from the camera along the horizontal ray.
    const Eigen::Vector2d cam = T_world_cam.translation().head<2>();
    for (const MoverDetection& d : segmentation_.detections())
    {
      const Eigen::Vector2d ray = d.centroid - cam;
      const double n = ray.norm();
      z.push_back(n > 1e-6 ? Eigen::Vector2d(d.centroid + ray / n * params_.surface_offset) : d.centroid);
    }
  }
  ms_segmentation_ = msSince(t0);
  t0 = std::chrono::steady_clock::now();
  if (has_prev_)
  {
    const std::vector<int> ids = tracker_.update(t, z);
    const std::vector<MoverDetection>& dets = segmentation_.detections();
    for (size_t j = 0; j < z.size(); ++j)
    {
      if (ids[j] > 0)
      {
        shape_[ids[j]] = {dets[j].radius, dets[j].max_z - dets[j].min_z};
        origin_.emplace(ids[j], z[j]);  // kept from the first detection on
        std::deque<TrackDetection>& h = history_[ids[j]];
        h.push_back({t, z[j], dets[j].displacement / std::max(1e-3, t - paired_t)});
        while (!h.empty() && h.front().t < t - params_.history_s) h.pop_front();
        bool& moving = seen_moving_[ids[j]];
        moving = moving || seenMoving(h, params_);
        const MoverTrack* tr = tracker_.find(ids[j]);
        if (tr && stationary(*tr)) continue;  // a static surface: the map votes there
      }
      footprints_.push_back({z[j].x(), z[j].y(), dets[j].radius});
    }
    // Coasting confirmed tracks (not detected this frame) keep their footprint.
    for (const MoverTrack& tr : tracker_.tracks())
    {
      if (!tr.confirmed || tr.misses == 0 || stationary(tr)) continue;
      const auto it = shape_.find(tr.id);
      if (it != shape_.end()) footprints_.push_back({tr.x(0), tr.x(1), it->second.first});
    }
    // Shapes of ended tracks go.
    for (auto it = shape_.begin(); it != shape_.end();)
      it = tracker_.find(it->first) ? std::next(it) : shape_.erase(it);
    for (auto it = origin_.begin(); it != origin_.end();)
      it = tracker_.find(it->first) ? std::next(it) : origin_.erase(it);
    for (auto it = history_.begin(); it != history_.end();)
      it = tracker_.find(it->first) ? std::next(it) : history_.erase(it);
    for (auto it = seen_moving_.begin(); it != seen_moving_.end();)
      it = tracker_.find(it->first) ? std::next(it) : seen_moving_.erase(it);
  }
  ms_tracking_ = msSince(t0);
  poses_.emplace_back(t, T_world_cam);
  while (static_cast<int>(poses_.size()) > std::max(1, params_.flow.frames_apart)) poses_.pop_front();
  prev_t_ = t;
  has_prev_ = true;
  return footprints_;
}

}  // namespace assistive_obstacles
