#include <assistive_obstacles/frame_processor.h>

#include <algorithm>
#include <chrono>

namespace assistive_obstacles
{
namespace
{
double msSince(std::chrono::steady_clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

ObstacleFrameProcessor::ObstacleFrameProcessor(const ObstaclesParams& p, int octomap_insert_every)
  : params_(p)
  , octomap_insert_every_(std::max(1, octomap_insert_every))
  , disparity_(p)
  , map_(p)
  , gate_({ p.max_frame_gap_s, p.rebuild_frames, p.min_fresh_points })
{
}

void ObstacleFrameProcessor::queueRange(const RangeSample& r)
{
  if (!params_.sonar_enabled) return;  // the nodelet does not subscribe then
  // Time went back (a bag loop, a restarted clock): the queued readings belong to the other walk and,
  // stamped after every new frame, would block the queue and then be placed at new poses.
  if (!ranges_.empty() && r.stamp < ranges_.back().stamp) ranges_.clear();
  ranges_.push_back(r);
  while (ranges_.size() > MaxQueuedRanges) ranges_.pop_front();
}

const ObstacleFrameResult& ObstacleFrameProcessor::process(const ObstacleFrame& f, const RangePoseLookup& range_pose)
{
  const auto t0 = std::chrono::steady_clock::now();
  result_ = ObstacleFrameResult();
  ObstacleFrameResult& r = result_;
  // A gap, a time jump (bag loop) or an untrusted pose makes the old map a guess about a place the
  // wearer has left.
  if (!f.pose_trusted) gate_.poseUntrusted();
  r.cleared = gate_.clearBefore(f.stamp);
  r.gate_reason = gate_.reason();
  if (r.cleared)
  {
    map_.reset();
    if (movers_) movers_->reset();
  }
  if (f.disparity)
    f.disparity->copyTo(disp_);
  else if (!disparity_.compute(f.left, f.right, disp_))
  {
    ++counters_.bad_input;
    r.ms_total = msSince(t0);
    return r;
  }
  r.disparity_ok = true;
  const bool want_normals = map_.usesNormals();
  disparity_.toPoints(disp_, f.model, points_, want_normals ? &normals_ : nullptr);
  r.ms_disparity = msSince(t0);
  r.has_pose = f.has_pose;
  if (!f.has_pose)
  {
    ++counters_.no_pose;
    r.ms_total = msSince(t0);
    return r;
  }
  // A frame without depth must not make the old map look fresh: no update, no grid (the planner
  // then sees the grid's stamp fall behind the pose's and stops guiding); the ranger's readings
  // wait for the next frame with depth.
  r.verdict = gate_.verdict(points_.size());
  r.gate_reason = gate_.reason();
  if (r.verdict == FrameGate::Verdict::NO_DEPTH)
  {
    r.ms_total = msSince(t0);
    return r;
  }
  // The map's pose is single precision; the movers take the same one (as on the device).
  const Eigen::Isometry3f T_world_cam = f.T_world_cam.cast<float>();
  const auto t_ranger = std::chrono::steady_clock::now();
  if (params_.sonar_enabled) applyRanges(f.stamp, range_pose);
  r.ms_ranger = msSince(t_ranger);
  const auto t_movers = std::chrono::steady_clock::now();
  runMovers(f, T_world_cam);
  r.ms_movers = msSince(t_movers);
  const auto t_map = std::chrono::steady_clock::now();
  map_.update(points_, T_world_cam, &f.model, &disp_, want_normals ? &normals_ : nullptr);
  r.ms_map = msSince(t_map);
  r.map_updated = true;
  r.movers_enabled = movers_ != nullptr;
  if (movers_)
  {
    // Every frame with depth, also with no one (an empty list: "no one", not "no news").
    r.movers = movers_->confirmed();
    r.feet_z = T_world_cam.translation().z() - params_.camera_height;
  }
  if (r.verdict == FrameGate::Verdict::FRESH)
  {
    map_.grid(r.grid);
    r.has_grid = true;
  }
  ++counters_.frames;
  if (params_.octomap_enabled && counters_.frames % octomap_insert_every_ == 0)
  {
    const auto t_oct = std::chrono::steady_clock::now();
    map_.insertOctomap();
    r.octomap_inserted = true;
    r.ms_octomap = msSince(t_oct);
  }
  r.ms_total = msSince(t0);
  return r;
}

void ObstacleFrameProcessor::applyRanges(double stamp, const RangePoseLookup& range_pose)
{
  while (!ranges_.empty() && ranges_.front().stamp <= stamp)
  {
    const RangeSample s = ranges_.front();
    ranges_.pop_front();
    if (!gate_.inEpoch(s.stamp))
    {
      // Queued through a black-out or a gap: its pose would be interpolated across the spell the
      // pose could not be trusted, and its echo would hold cells of the new map for good.
      ++counters_.ranges_stale;
      continue;
    }
    RangeReading reading;
    reading.range = s.range;
    reading.min_range = s.min_range;
    reading.max_range = s.max_range;
    reading.field_of_view = s.field_of_view;
    if (!range_pose || !range_pose(s, reading.T_world_sensor))
    {
      ++counters_.ranges_no_pose;
      continue;
    }
    AppliedRange a;
    a.sample = s;
    a.T_world_sensor = reading.T_world_sensor;
    a.check = map_.addRange(reading);
    a.stats = map_.sonar().stats();
    if (a.check == RangeCheck::ECHO)
      ++counters_.ranges_echo;
    else if (a.check == RangeCheck::NO_ECHO)
      ++counters_.ranges_no_echo;
    else
    {
      ++counters_.ranges_rejected;
      counters_.last_rejection = rangeCheckName(a.check);
    }
    result_.ranges.push_back(a);
  }
}

void ObstacleFrameProcessor::runMovers(const ObstacleFrame& f, const Eigen::Isometry3f& T_world_cam)
{
  // Movers (issue 22): scene flow against the ego-motion between this pose and the last one;
  // their cells take no vote in this update.
  if (!params_.movers) return;
  if (!movers_) movers_ = std::make_unique<MoverPipeline>(moverPipelineParams(params_, f.model));
  if (f.own_mover_pose && !f.mover_pose)
  {
    map_.setMovers({});  // no pose for the movers (the VO lost it): no flow, as in the chain
    return;
  }
  if (f.track_left && f.track_right)
  {
    map_.setMovers(movers_->process(f.track_stamp, *f.track_left, disp_, f.model,
                                    f.own_mover_pose ? *f.mover_pose : f.track_pose, f.track_right));
    return;
  }
  const Eigen::Isometry3d ego = f.own_mover_pose ? *f.mover_pose : T_world_cam.cast<double>();
  map_.setMovers(movers_->process(f.stamp, f.left, disp_, f.model, ego, &f.right));
}

}  // namespace assistive_obstacles
