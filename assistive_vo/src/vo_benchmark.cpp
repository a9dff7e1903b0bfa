// vo_benchmark FILE.bag [BAG2.bag ...] [--generated N [--kinds K,...] [--imperfect] [--keep DIR]] [--plot OUT.png] [--no-peer] [--no-imu] [--frames N] [--verbose] [--dump FILE] [--set name=value ...]
//              [--blackout START:DURATION] [--drop START:DURATION]
// (--blackout: the images from START s after the first frame for DURATION s are replaced by a
//  plain grey (a plain wall filling the view); reports the position error at its end against the
//  truth, relative to the last frame before it, and the frames to track again)
// (--drop: the stereo frames from START s for DURATION s are never given to the VO (dropped: an
//  overloaded computer), the IMU samples are; reports the first frame after the gap against the
//  truth: position error relative to the last frame before it, trusted, tracking, resets)
// (--dump FILE: per-frame ground truth and estimated pose as text rows, for analysis;
//  --verbose: per-frame stage counts on stderr: KLT tracks, epipolar kept, P3P inliers, corners)
// Runs the VO core on every stereo frame of a bag (no roscore), and on the same frames the peer:
// OpenCV contrib's cv::rgbd::RgbdOdometry fed with StereoSGBM depth. Prints per-stage times,
// trajectory errors against the bag's ground truth (assistive_eval), then one JSON line.
// Several bags or --generated N: the set run (assistive_eval/bench_set.h) runs this program once per
// bag and prints per-bag rows, the mean and the worst (bag named); --plot is then a folder.
// Times are CPU time of this thread (one core; OpenCV threading off), wall times reported too.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/rgbd.hpp>
#include <assistive_eval/bench_set.h>
#include <assistive_eval/benchmark.h>
#include <assistive_eval/metrics.h>
#include <assistive_eval/plots.h>
#include <assistive_eval/recovery.h>
#include <assistive_eval/stereo_bag.h>
#include <assistive_description/stereo_self_calibration.h>
#include "assistive_vo/frames.h"
#include "assistive_vo/vo_front_end.h"

using namespace assistive_vo;
namespace ev = assistive_eval;
using ev::percentile;

namespace
{
/// The peer: SGBM depth + RgbdOdometry, pose chained frame to frame.
struct Peer
{
  cv::Ptr<cv::StereoSGBM> sgbm;
  cv::Ptr<cv::rgbd::Odometry> odo;
  cv::Mat prev_img, prev_depth, prev_Rt;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  int failures = 0;
  double max_translation_m = 0.15;  // per frame

  void init(const StereoCamera& cam)
  {
    sgbm = cv::StereoSGBM::create(0, 128, 5, 8 * 25, 32 * 25, 1, 0, 10, 100, 2, cv::StereoSGBM::MODE_SGBM);
    const cv::Mat K = (cv::Mat_<float>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
    // Depth 0.3-8 m (SGBM depth beyond is too noisy at 0.12 m baseline), depth difference
    // 0.15 m, 20 % of the pixels: a little better than OpenCV's Kinect defaults on these bags.
    // Wider rigs (KITTI 0.54 m at 721 px) resolve farther: up to the depth of an 8 px disparity.
    // (RgbdICPOdometry and ICPOdometry were tried on the course: 4.5 % drift, worse.)
    // Its translation limit per frame: OpenCV's default 0.15 m unless --peer-max-translation M.
    const double fb = cam.fx * cam.baseline;
    auto o = cv::rgbd::RgbdOdometry::create(K, 0.3f, static_cast<float>(std::max(8.0, fb / 8.0)), 0.15f);
    o->setMaxPointsPart(0.2);
    o->setMaxTranslation(std::max(0.15, max_translation_m));
    odo = o;
  }
  void process(const StereoCamera& cam, const cv::Mat& left, const cv::Mat& right)
  {
    cv::Mat disp16;
    sgbm->compute(left, right, disp16);
    cv::Mat depth(left.size(), CV_32F, cv::Scalar(0));
    const float fb = static_cast<float>(cam.fx * cam.baseline);
    for (int y = 0; y < disp16.rows; ++y)
    {
      const int16_t* d = disp16.ptr<int16_t>(y);
      float* z = depth.ptr<float>(y);
      for (int x = 0; x < disp16.cols; ++x)
        z[x] = d[x] > 0 ? fb * 16.f / d[x] : 0.f;
    }
    if (!prev_img.empty())
    {
      cv::Mat Rt;
      const cv::Mat mask;
      bool ok = false;
      try
      {
        // The last frame's motion as the initial guess (OpenCV's compute(..., initRt)): the
        // pyramid alignment starts at zero motion otherwise and often lands in a wrong minimum
        // (course: 10.9 % drift without, 1.55 % with). After a failure it starts from zero motion
        // again (a stale guess made failures cascade: plaza 61 % drift, 283 failures).
        ok = odo->compute(prev_img, prev_depth, mask, left, depth, mask, Rt, prev_Rt);
      }
      catch (const cv::Exception&)
      {
        ok = false;
      }
      if (ok && !Rt.empty())
      {
        Eigen::Matrix4d M;
        for (int r = 0; r < 4; ++r)
          for (int c = 0; c < 4; ++c)
            M(r, c) = Rt.at<double>(r, c);
        // Rt maps points of the source (previous) frame into the destination (current) frame.
        Eigen::Isometry3d T_cur_prev(M);
        prev_Rt = Rt.clone();
        T_w_c = T_w_c * T_cur_prev.inverse();
      }
      else
      {
        ++failures;
        prev_Rt.release();  // a failed frame's guess is stale: start the next one from zero motion
      }
    }
    prev_img = left;
    prev_depth = depth;
  }
};

const char* const kUsage =
    "usage: vo_benchmark FILE.bag [--plot OUT.png] [--no-peer] [--no-imu] [--frames N] [--peer-max-translation M]\n"
    "                    [--verbose] [--dump FILE] [--set name=value ...] [--blackout START:DURATION]\n"
    "                    [--drop START:DURATION] [--bias-known] [--self-calibrate] [--rolling-shutter S|auto]\n"
    "       vo_benchmark BAG BAG... | --generated N [--kinds office,lobby,...] [--frames F] [--imperfect] [--keep DIR]\n"
    "                    [--plot DIR] [other options as above]\n"
    "  Runs the visual odometry on a stereo bag (README \"Topics of a stereo bag\"); last stdout line: JSON.\n"
    "  A set (several bags, or worlds seeds 1..N made by generate_world and render_bag): per-bag rows,\n"
    "  mean and worst of each figure (worst bag named); JSON keys <key>_mean, <key>_worst, <key>_worst_bag.\n"
    "  --bias-known: a first pass fits the gyro's bias to the truth (as the gyro floor does), the run\n"
    "  holds it instead of estimating it online: what the online estimate costs (issue 34).\n"
    "  --self-calibrate: the right image corrected by the camera driver's online estimate of the right\n"
    "  camera's rotation (issue 36), as the device does; the estimate and the bag's truth are printed.\n"
    "  --rolling-shutter S: the camera's readout time (s; --set rolling_shutter_readout=S); auto: the\n"
    "  readout render_bag recorded in the bag (/sim/camera_errors), as the sensor's data sheet gives it.\n";

/// The command line of a one-bag run.
struct Options
{
  std::string bag, plot, dump, blackout, drop, rolling_shutter;
  bool peer_on = true, imu_on = true, verbose = false, bias_known = false, self_calibrate = false;
  double peer_max_t = 0.15;
  ev::CommandLine::Sets overrides;
  long max_frames = -1;
  double bo_start = -1, bo_len = 0;  ///< --blackout START:DURATION (s after the first frame)
  double drop_start = -1, drop_len = 0;  ///< --drop START:DURATION (s after the first frame)

  void addTo(ev::CommandLine& cl)
  {
    cl
        .flag("--no-peer", &peer_on, false)
        .flag("--no-imu", &imu_on, false)
        .flag("--verbose", &verbose)
        .flag("--bias-known", &bias_known)
        .flag("--self-calibrate", &self_calibrate)
        .text("--plot", &plot)
        .count("--frames", &max_frames, 0L)
        .number("--peer-max-translation", &peer_max_t)
        .text("--dump", &dump)
        .text("--blackout", &blackout)
        .text("--drop", &drop)
        .text("--rolling-shutter", &rolling_shutter)
        .sets(&overrides);
  }
  /// --blackout and --drop START:DURATION into bo_start, bo_len / drop_start, drop_len; false (with
  /// the message) when malformed.
  bool parseBlackout()
  {
    return parseWindow("--blackout", blackout, bo_start, bo_len) && parseWindow("--drop", drop, drop_start, drop_len);
  }
  static bool parseWindow(const char* name, const std::string& text, double& start, double& len)
  {
    if (!text.empty() && (std::sscanf(text.c_str(), "%lf:%lf", &start, &len) != 2 || start < 0 || len <= 0))
    {
      std::cerr << "vo_benchmark: " << name << " wants START:DURATION in seconds, got " << text << "\n";
      return false;
    }
    return true;
  }
};

/// --rolling-shutter S|auto into params.rolling_shutter_readout_s; false (with the message) when
/// malformed. A bag without a recorded readout (real data): auto leaves the parameter.
bool applyRollingShutter(const Options& opt, VoParams& params)
{
  if (opt.rolling_shutter.empty())
    return true;
  double s = -1;
  if (opt.rolling_shutter == "auto")
  {
    s = ev::rollingShutterReadout(ev::readBagString(opt.bag));
    if (s < 0)
    {
      std::cout << "rolling shutter: the bag records no readout; rolling_shutter_readout "
                << params.rolling_shutter_readout_s << " s kept\n";
      return true;
    }
  }
  else if (std::sscanf(opt.rolling_shutter.c_str(), "%lf", &s) != 1 || s < 0 || s > 0.1)
  {
    std::cerr << "vo_benchmark: --rolling-shutter wants a readout in [0, 0.1] s or auto, got " << opt.rolling_shutter
              << "\n";
    return false;
  }
  params.rolling_shutter_readout_s = s;
  std::cout << "rolling shutter: readout " << s * 1e3 << " ms\n";
  return true;
}

/// The set run (several bags or --generated): this program once per bag, per-bag rows, mean and worst.
int runSet(const ev::CommandLine& cl, int argc, char** argv, const ev::SetOptions& set_options, const Options& opt)
{
  // Worst = the larger, except where more is better; rot_drift_over_gyro_floor: the target ratio (<= 2).
  const std::vector<ev::SetFigure> figures{
      {"drift_pct"}, {"drift_deg_per_m"}, {"rot_drift_over_gyro_floor"}, {"gyro_floor_deg_per_m"},
      {"ate_rmse_m"}, {"max_jump_m"}, {"endpoint_drift_pct"}, {"resets", false, true},
      {"frames_not_tracking", false, true}, {"recovery_frames_max", false, true}, {"ms_p95"},
      {"ms_median"}, {"peer_drift_pct"}, {"peer_ms_p95"}, {"path_length_m", true}, {"frames", true}};
  return ev::runSetFromCommandLine(cl, argc, argv, set_options, figures, "--plot", opt.plot, "_vo_trajectory.png",
                                   opt.max_frames, [](ev::BagResult& b) {
                                     const auto d = b.values.find("drift_deg_per_m");
                                     const auto g = b.values.find("gyro_floor_deg_per_m");
                                     if (d != b.values.end() && g != b.values.end() && g->second > 0)
                                       b.values["rot_drift_over_gyro_floor"] = d->second / g->second;
                                   });
}

/// --blackout: the poses before it, at its end and where tracking resumed, against the truth.
struct Blackout
{
  bool have_a = false, have_b = false, resumed = false, trusted_end = false;
  Eigen::Isometry3d gt_a, est_a, gt_b, est_b, gt_c, est_c;
  double sigma_end = -1;
  int frames_after = 0, resume_frames = -1;

  /// One frame with a pose and its truth; `t_rel` s after the first frame, `blanked` inside the window.
  void add(double t_rel, bool blanked, double bo_start, const Eigen::Isometry3d& gt, const VoOutput& o)
  {
    if (t_rel < bo_start)
    {
      have_a = true;
      gt_a = gt;
      est_a = o.T_odom_optical;
    }
    else if (blanked && have_a)
    {
      have_b = true;
      gt_b = gt;
      est_b = o.T_odom_optical;
      trusted_end = o.pose_trusted;
      sigma_end = std::sqrt(o.pose_covariance.topLeftCorner<3, 3>().trace() / 3.0);
    }
    else if (have_b && !resumed)
    {
      ++frames_after;
      if (o.state == TrackingState::TRACKING)
      {
        resumed = true;
        resume_frames = frames_after;
        gt_c = gt;
        est_c = o.T_odom_optical;
      }
    }
  }
  /// Position error of the pose change since the last frame before the blackout (its axes).
  double relErr(const Eigen::Isometry3d& gt_x, const Eigen::Isometry3d& est_x) const
  {
    return ((est_a.inverse() * est_x).translation() - (gt_a.inverse() * gt_x).translation()).norm();
  }
};

/// --drop: the last frame before the gap and the first after it, against the truth.
struct DroppedGap
{
  bool have_a = false, have_b = false, trusted_b = false, tracking_b = false;
  Eigen::Isometry3d gt_a, est_a, gt_b, est_b;
  int resets_a = 0, resets_b = 0, dropped = 0;

  /// One processed frame with a pose and its truth; `before`: it precedes the gap.
  void add(bool before, const Eigen::Isometry3d& gt, const VoOutput& o, int resets)
  {
    if (before)
    {
      have_a = true;
      gt_a = gt;
      est_a = o.T_odom_optical;
      resets_a = resets;
    }
    else if (have_a && !have_b && dropped > 0)
    {
      have_b = true;
      gt_b = gt;
      est_b = o.T_odom_optical;
      trusted_b = o.pose_trusted;
      tracking_b = o.state == TrackingState::TRACKING;
      resets_b = resets;
    }
  }
  /// Position error of the pose change across the gap (the last frame before it, its axes).
  double err() const
  {
    return ((est_a.inverse() * est_b).translation() - (gt_a.inverse() * gt_b).translation()).norm();
  }
  double moved() const { return (gt_a.inverse() * gt_b).translation().norm(); }
};

/// The stage names of the VO's timing table and JSON keys (ms_p95_<stage>), in their order.
const char* const kStages[] = {"pyramid", "klt", "epipolar", "stereo", "p3p_ransac", "bundle_adj", "detect", "lines"};

/// The runner: every stereo frame of the bag through the device's VO driving loop (and the peer),
/// timed, with the poses kept for scoring.
class BagRun
{
public:
  BagRun(const Options& opt, VoFrontEnd& fe) : vo(fe.vo()), opt_(opt), fe_(fe)
  {
    peer.max_translation_m = opt.peer_max_t;
    gyro_every_frame = opt.imu_on;
    if (!opt.dump.empty())
      dump_out_.open(opt.dump);
  }
  /// Runs the frames; false (with the message) when the bag has none.
  bool run(ev::StereoBagReader& reader);
  /// The times (ms) of a stage ("total": the whole VO call), empty when no frame was processed.
  std::vector<double> times(const char* stage) const
  {
    const auto it = ms.find(stage);
    return it == ms.end() ? std::vector<double>() : it->second;
  }

  const VisualOdometry& vo;
  Peer peer;
  ev::Trajectory gt, est, peer_est;
  // The bag's gyro per frame in the optical frame (for the gyro-alone floor); any frame without
  // gyro (first frame aside) voids the floor.
  std::vector<Eigen::Matrix3d> gyro_rel;
  bool gyro_every_frame = true;
  std::map<std::string, std::vector<double>> ms;
  std::vector<double> wall, peer_ms, peer_wall;
  int lost = 0, max_bad_run = 0, bad_run = 0, frames = 0, unusable = 0;
  /// Frames where the truth's neck (VoParams standing_pivot_*, the simulator's neck) moved under
  /// kOnSpotSpeed since the previous processed frame: standing or turning on the spot; of them, not
  /// tracking and untrusted (issue 34: none should be lost while the wearer only turns).
  int on_spot = 0, on_spot_not_tracking = 0, on_spot_untrusted = 0;
  static constexpr double kOnSpotSpeed = 0.1;  // m/s
  ev::RecoveryCounter recovery;
  Blackout bo;
  DroppedGap gap;

private:
  /// Times, tracking state and recovery of one processed frame.
  void countFrame(const ev::StereoFrame& f, const VoOutput& o, const ev::Stopwatch& timer);
  /// --verbose: the frame's stage counts on stderr; and the VO's message of the frame.
  void logFrame(const ev::StereoFrame& f, const VoOutput& o, bool usable);
  bool logged_trusted_ = true, logged_held_ = false;  ///< logFrame: the trust and hold it last printed
  /// A frame with a pose and its truth: the trajectories, the gyro and the peer (and --dump's row).
  void keepPose(const StereoCamera& cam, const ev::StereoFrame& f, const FrontEndStep& step);
  /// --dump: one row per frame.
  void dumpRow(const ev::StereoFrame& f, const FrontEndStep& step);

  const Options& opt_;
  VoFrontEnd& fe_;
  std::ofstream dump_out_;
  double first_stamp_ = -1;
  bool have_neck_ = false;
  double neck_stamp_ = 0;
  Eigen::Vector3d neck_ = Eigen::Vector3d::Zero();
  /// The on-spot counts of one frame (its truth's neck against the previous frame's).
  void countOnSpot(const ev::StereoFrame& f, const VoOutput& o);
  Eigen::Isometry3d peer_T_odom_o0_ = Eigen::Isometry3d::Identity();
};

bool BagRun::run(ev::StereoBagReader& reader)
{
  ev::StereoFrame f;
  // The vest's forward ranger (range_aided_coast), as the nodelet feeds it: the wearer's URDF
  // mounts sonar_front on camera_link without rotation, so its axis is camera_link's x.
  std::vector<ev::RangeSample> ranges;
  reader.readRanges(ranges);
  size_t next_range = 0;
  while ((opt_.max_frames < 0 || frames < opt_.max_frames) && ev::nextFrameOrExit(reader, f, "vo_benchmark", opt_.bag))
  {
    const StereoCamera cam = StereoCamera::from(f.calib);
    if (frames == 0 && opt_.peer_on)
      peer.init(cam);
    for (const auto& s : f.imu)
      fe_.addImu(s.stamp, s.gyro, s.accel);
    for (; next_range < ranges.size() && ranges[next_range].stamp <= f.stamp; ++next_range)
    {
      const ev::RangeSample& r = ranges[next_range];
      fe_.addRange(r.stamp, r.range, r.min_range, r.max_range, Eigen::Vector3d::UnitX());
    }
    if (first_stamp_ < 0)
      first_stamp_ = f.stamp;
    const double t_rel = f.stamp - first_stamp_;
    const bool blanked = opt_.bo_start >= 0 && t_rel >= opt_.bo_start && t_rel < opt_.bo_start + opt_.bo_len;
    if (opt_.drop_start >= 0 && t_rel >= opt_.drop_start && t_rel < opt_.drop_start + opt_.drop_len)
    {
      ++gap.dropped;  // never given to the VO (its IMU samples are)
      ++frames;
      continue;
    }
    if (blanked)
    {
      f.left = cv::Mat(f.left.size(), f.left.type(), cv::Scalar(128));
      f.right = cv::Mat(f.right.size(), f.right.type(), cv::Scalar(128));
    }
    const ev::Stopwatch timer;
    const FrontEndStep step = fe_.process(cam, f.left, f.right, f.stamp);
    if (!step.processed)  // waiting for the IMU (start-up rule): not timed, not scored
    {
      ++frames;
      continue;
    }
    const VoOutput& o = step.out;
    if (opt_.bo_start >= 0 && f.has_gt_pose && o.pose_valid)
      bo.add(t_rel, blanked, opt_.bo_start, f.gt_pose, o);
    if (opt_.drop_start >= 0 && f.has_gt_pose && o.pose_valid)
      gap.add(t_rel < opt_.drop_start, f.gt_pose, o, vo.resets());
    countFrame(f, o, timer);

    if (f.has_gt_pose && o.pose_valid)
      keepPose(cam, f, step);
    else if (!gt.empty())
      gyro_every_frame = false;  // a frame left out: the per-frame gyro no longer pairs with gt
    ++frames;
    if (frames % 50 == 0)
      std::cerr << "[vo_benchmark] " << frames << " frames\n";
  }
  if (frames == 0)
  {
    std::cerr << "vo_benchmark: no stereo frames in " << opt_.bag << "\n";
    return false;
  }
  return true;
}

void BagRun::countFrame(const ev::StereoFrame& f, const VoOutput& o, const ev::Stopwatch& timer)
{
  ms["total"].push_back(timer.cpuMs());
  wall.push_back(timer.wallMs());
  ms["pyramid"].push_back(o.stats.ms_pyramid);
  ms["klt"].push_back(o.stats.ms_klt);
  ms["epipolar"].push_back(o.stats.ms_epipolar);
  ms["stereo"].push_back(o.stats.ms_stereo);
  ms["p3p_ransac"].push_back(o.stats.ms_ransac);
  ms["bundle_adj"].push_back(o.stats.ms_ba);
  ms["detect"].push_back(o.stats.ms_detect);
  ms["lines"].push_back(o.stats.ms_lines);
  // Recovery counted in usable frames only (objective image test, outside the timed call).
  const bool usable = ev::stereoPairUsable(f.left, f.right);
  unusable += !usable;
  recovery.add(o.state == TrackingState::TRACKING, usable);
  if (o.state != TrackingState::TRACKING)
  {
    ++lost;
    max_bad_run = std::max(max_bad_run, ++bad_run);
  }
  else
    bad_run = 0;
  countOnSpot(f, o);
  logFrame(f, o, usable);
}

void BagRun::countOnSpot(const ev::StereoFrame& f, const VoOutput& o)
{
  if (!f.has_gt_pose)
  {
    have_neck_ = false;
    return;
  }
  const VoParams& p = vo.params();
  const Eigen::Vector3d r_link(p.standing_pivot_forward, 0.0, p.standing_pivot_up);
  const Eigen::Vector3d neck = f.gt_pose.translation() - f.gt_pose.linear() * R_link_optical().transpose() * r_link;
  const double dt = f.stamp - neck_stamp_;
  if (have_neck_ && dt > 1e-6 && (neck - neck_).norm() / dt < kOnSpotSpeed)
  {
    ++on_spot;
    on_spot_not_tracking += o.state != TrackingState::TRACKING;
    on_spot_untrusted += !o.pose_trusted;
  }
  have_neck_ = true;
  neck_stamp_ = f.stamp;
  neck_ = neck;
}

void BagRun::logFrame(const ev::StereoFrame& f, const VoOutput& o, bool usable)
{
  if (opt_.verbose)
    std::cerr << "frame " << frames << " " << toString(o.state) << " klt " << o.stats.klt_tracked << " epipolar "
              << o.stats.epipolar_kept << " p3p_inliers " << o.stats.inliers << " trials " << o.stats.ransac_trials
              << " lines " << o.stats.lines << " line_inliers " << o.stats.line_inliers << " ms " << o.stats.ms_total
              << (usable ? "" : " (unusable)") << " step_m " << (est.empty() ? 0.0 : (est.back().pose.translation() - o.T_odom_optical.translation()).norm())
              << " gt_step_m " << (gt.empty() || !f.has_gt_pose ? 0.0 : (gt.back().pose.translation() - f.gt_pose.translation()).norm())
              << (o.stats.keyframe ? " | keyframe: detected " + std::to_string(o.stats.detected) +
                                         " with_depth " + std::to_string(o.stats.new_features) +
                                         (o.stats.coarse_features ? " coarse " + std::to_string(o.stats.coarse_features)
                                                                  : std::string())
                                   : std::string())
              << "\n";
  if (!o.message.empty())
    std::cerr << "frame " << frames << " t=" << std::fixed << std::setprecision(3) << f.stamp << " "
              << toString(o.state) << ": " << o.message << "\n";
  // where trust is lost or a standing hold begins or ends, and why: the frames to look at in a loss
  if (o.pose_trusted != logged_trusted_ || vo.holdingStill() != logged_held_)
    std::cerr << "frame " << frames << " t=" << std::fixed << std::setprecision(3) << f.stamp << " "
              << (o.pose_trusted ? "trusted" : "untrusted: " + o.untrusted_reason)
              << (vo.holdingStill() ? ", held standing" : "") << "\n";
  logged_trusted_ = o.pose_trusted;
  logged_held_ = vo.holdingStill();
}

void BagRun::keepPose(const StereoCamera& cam, const ev::StereoFrame& f, const FrontEndStep& step)
{
  const VoOutput& o = step.out;
  if (dump_out_)
    dumpRow(f, step);
  gt.push_back({f.stamp, f.gt_pose});
  est.push_back({f.stamp, o.T_odom_optical});
  if (gt.size() > 1 && !step.have_gyro)
    gyro_every_frame = false;
  gyro_rel.push_back(step.have_gyro ? Eigen::Matrix3d(R_link_optical().transpose() * step.gyro.toRotationMatrix() *
                                                      R_link_optical())
                                    : Eigen::Matrix3d::Identity());
  if (opt_.peer_on)
  {
    const ev::Stopwatch peer_timer;
    peer.process(cam, f.left, f.right);
    peer_ms.push_back(peer_timer.cpuMs());
    peer_wall.push_back(peer_timer.wallMs());
    if (peer_est.empty())
      peer_T_odom_o0_ = o.T_odom_optical;  // same start pose as ours (gravity from the IMU)
    peer_est.push_back({f.stamp, peer_T_odom_o0_ * peer.T_w_c});
  }
}

void BagRun::dumpRow(const ev::StereoFrame& f, const FrontEndStep& step)
{
  const VoOutput& o = step.out;
  // one row per frame: stamp state keyframe inliers, then gt and estimate (x y z qx qy qz qw)
  auto row = [&](const Eigen::Isometry3d& T) {
    const Eigen::Quaterniond q(T.linear());
    dump_out_ << " " << T.translation().x() << " " << T.translation().y() << " " << T.translation().z() << " "
              << q.x() << " " << q.y() << " " << q.z() << " " << q.w();
  };
  dump_out_ << std::setprecision(9) << f.stamp << " " << static_cast<int>(o.state) << " " << o.stats.keyframe
            << " " << o.stats.inliers;
  row(f.gt_pose);
  row(o.T_odom_optical);
  // then the integrated gyro of this frame (camera_link, qx qy qz qw), the gyro bias estimate
  // and the mean accelerometer reading over the frame interval (camera_link)
  const Eigen::Quaterniond g = step.have_gyro ? step.gyro : Eigen::Quaterniond::Identity();
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();
  fe_.imu().meanAccel(f.stamp, 1.0 / 15.0, acc);
  // and whether the pose is trusted and the frame held standing
  dump_out_ << " " << g.x() << " " << g.y() << " " << g.z() << " " << g.w() << " " << vo.gyroBias().transpose()
            << " " << acc.transpose() << " " << o.pose_trusted << " " << vo.holdingStill() << "\n";
}

/// The report's first part: per-stage times, resets, tracking and recovery.
void printRun(const Options& opt, const BagRun& run)
{
  std::cout << "assistive_vo benchmark: " << opt.bag << "  (" << run.frames << " frames, "
            << (opt.imu_on ? "gyro prior on" : "no IMU") << ")\n";
  std::cout << "stage          ms_median   ms_p95   (thread CPU time, one core)\n";
  for (const char* k : {"pyramid", "klt", "epipolar", "stereo", "p3p_ransac", "bundle_adj", "detect", "lines", "total"})
    std::cout << "  " << std::left << std::setw(12) << k << std::right << std::fixed << std::setprecision(3)
              << std::setw(10) << percentile(run.times(k), 0.5) << std::setw(9) << percentile(run.times(k), 0.95)
              << "\n";
  std::cout << "  total (wall)" << std::setw(10) << percentile(run.wall, 0.5) << std::setw(9)
            << percentile(run.wall, 0.95) << "\n";
  std::cout << "stereo disparity offset estimated " << run.vo.disparityOffset() << " px\n";
  std::cout << "resets " << run.vo.resets() << ", frames not tracking " << run.lost << ", longest non-tracking run "
            << run.max_bad_run << " frames; usable frames needed to track again (recovery_frames_max) "
            << run.recovery.maxUsableInRun() << ", unusable frames " << run.unusable << "\n";
  std::cout << "coasted frames corrected by the ranger " << run.vo.rangeAidedFrames() << ", untrusted frames "
            << run.vo.failSafe().untrusted_frames << "\n";
}

/// --bias-known's first pass: the VO once over the bag (no peer, dump or plot) for the truth and
/// the gyro per frame, the gyro's bias fitted to the truth (camera_link, rad/s). False, with the
/// message, when the bag has no truth or a frame without the gyro.
bool fitGyroBias(const Options& opt, const VoParams& params, const VoFrontEnd::Options& fe_options,
                 ev::StereoBagReader& reader, Eigen::Vector3d& bias_link)
{
  Options first = opt;
  first.peer_on = false;
  first.dump.clear();
  VoFrontEnd fe(params, fe_options);
  BagRun run(first, fe);
  const bool ran = run.run(reader);
  reader.rewind();
  Eigen::Vector3d bias_opt;
  if (!ran || !run.gyro_every_frame || run.gt.size() < 3 || ev::gyroOnlyTrajectory(run.gt, run.gyro_rel, &bias_opt).empty())
  {
    std::cerr << "vo_benchmark: --bias-known needs the truth and the gyro on every frame of " << opt.bag << "\n";
    return false;
  }
  bias_link = R_link_optical() * bias_opt;
  return true;
}

/// The scorer's figures: ours and the peer's trajectory against the truth, the gyro's floor.
struct Scores
{
  ev::TrajectoryReport rep, prep;
  ev::DriftResult gyro_floor;
  // The simulator's bags (they carry its ground-truth occupancy) have a z-up world: only there is
  // the tilt against gravity measurable (imported datasets keep their own world axes).
  bool z_up_world = false;
  bool have_gt = false;
};

/// The floor the gyro's angle random walk sets: the gyro alone, its bias fit to the truth.
void scoreGyroFloor(const BagRun& run, Scores& sc)
{
  const ev::Trajectory g = ev::gyroOnlyTrajectory(run.gt, run.gyro_rel);
  if (g.empty())
    return;
  sc.gyro_floor = ev::segmentDrift(run.gt, g, ev::TrajectoryEvalParams().drift_lengths_m, 1, ev::YawBandParams().up);
  std::cout << std::setprecision(4) << "gyro alone, bias fit to ground truth (the angle random walk floor): "
            << sc.gyro_floor.drift_deg_per_m << " deg/m (";
  for (const auto& l : sc.gyro_floor.per_length)
    std::cout << std::setprecision(0) << l.length_m << " m: " << std::setprecision(4) << l.r_err_deg_per_m
              << (&l == &sc.gyro_floor.per_length.back() ? "" : ", ");
  std::cout << ")\n";
}

/// Trajectory plot: ground truth, ours and the peer, top-down over the floor plan.
void plotTrajectories(const Options& opt, const BagRun& run, ev::StereoBagReader& reader, Scores& sc)
{
  std::vector<ev::PlotSeries> series{{"ground truth", ev::positions(run.gt), cv::Scalar(0, 0, 0)}};
  const ev::Alignment al = sc.rep.alignment;
  series.push_back({"assistive_vo", ev::positions(ev::applyAlignment(run.est, al)), cv::Scalar(0, 0, 230)});
  if (sc.prep.ate.n > 0)
    series.push_back({"peer RgbdOdometry", ev::positions(ev::applyAlignment(run.peer_est, sc.prep.alignment)),
                      cv::Scalar(230, 120, 0)});
  ev::OccupancyGrid floor;
  const bool have_floor = reader.readOccupancy(floor);
  sc.z_up_world = have_floor;
  ev::PlotOptions po;
  po.title = "VO trajectory (SE3-aligned): " + opt.bag;
  std::string err;
  if (ev::writePng(opt.plot, ev::plotTopDown(series, have_floor ? &floor : nullptr, po), &err))
    std::cout << "trajectory plot: " << opt.plot << "\n";
  else
    std::cerr << "vo_benchmark: plot not written: " << err << "\n";
}

/// The scorer: ours and the peer against the truth (printed), the gyro floor, the plot.
Scores scoreRun(const Options& opt, const BagRun& run, ev::StereoBagReader& reader)
{
  Scores sc;
  sc.have_gt = run.gt.size() >= 3;
  if (!sc.have_gt)
  {
    std::cout << "no ground truth in the bag: trajectory errors are null\n";
    return sc;
  }
  sc.rep = ev::evaluateTrajectory(run.gt, run.est);
  std::cout << "\n--- ours (assistive_vo) vs ground truth ---\n" << ev::reportTable(sc.rep);
  std::cout << "rotational drift split  yaw " << sc.rep.drift.drift_deg_per_m_yaw << " deg/m  tilt (roll/pitch) "
            << sc.rep.drift.drift_deg_per_m_tilt << " deg/m\n";
  if (run.gyro_every_frame)
    scoreGyroFloor(run, sc);
  if (opt.peer_on && run.peer_est.size() == run.gt.size())
  {
    sc.prep = ev::evaluateTrajectory(run.gt, run.peer_est);
    std::cout << "\n--- peer (SGBM + cv::rgbd::RgbdOdometry) vs ground truth ---\n" << ev::reportTable(sc.prep);
    std::cout << "peer ms median " << percentile(run.peer_ms, 0.5) << "  p95 " << percentile(run.peer_ms, 0.95)
              << "  (wall p95 " << percentile(run.peer_wall, 0.95) << "), failures " << run.peer.failures << "\n";
  }
  plotTrajectories(opt, run, reader, sc);
  return sc;
}

/// --drop's line of the report.
void printDrop(const Options& opt, const DroppedGap& g)
{
  std::cout << "drop " << opt.drop_start << " s + " << opt.drop_len << " s (" << g.dropped << " frames): ";
  if (g.have_b)
    std::cout << "first frame after it: position error " << g.err() << " m (truth moved " << g.moved() << " m), "
              << (g.trusted_b ? "trusted" : "untrusted") << ", " << (g.tracking_b ? "tracking" : "not tracking")
              << ", resets " << g.resets_b - g.resets_a << "\n";
  else
    std::cout << "no frame with a pose after it\n";
}

/// --blackout's line of the report.
void printBlackout(const Options& opt, const Blackout& bo)
{
  std::cout << "blackout " << opt.bo_start << " s + " << opt.bo_len << " s: ";
  if (bo.have_b)
    std::cout << "position error at its end " << bo.relErr(bo.gt_b, bo.est_b) << " m (truth moved "
              << (bo.gt_a.inverse() * bo.gt_b).translation().norm() << " m; published 1-sigma " << bo.sigma_end
              << " m, " << (bo.trusted_end ? "trusted" : "untrusted") << "), tracking again after "
              << bo.resume_frames << " frames"
              << (bo.resumed ? ", error then " + std::to_string(bo.relErr(bo.gt_c, bo.est_c)) + " m" : "") << "\n";
  else
    std::cout << "no frame with a pose in the window\n";
}

std::string num(double v, int significant = 4)
{
  return ev::jsonNumber(v, significant);
}

/// The JSON line's trajectory keys (drift, ATE, tilt, the estimate's net motion).
void addTrajectoryKeys(const BagRun& run, const Scores& sc, ev::JsonLine& js)
{
  const ev::TrajectoryReport& rep = sc.rep;
  if (sc.have_gt)
    js.add("drift_pct", num(rep.drift.drift_pct)).add("drift_deg_per_m", num(rep.drift.drift_deg_per_m, 6))
        .add("drift_deg_per_m_yaw", num(rep.drift.drift_deg_per_m_yaw, 6))
        .add("drift_deg_per_m_tilt", num(rep.drift.drift_deg_per_m_tilt, 6)).add("ate_rmse_m", num(rep.ate.rmse))
        .add("max_jump_m", num(rep.max_jump_m)).add("gyro_floor_deg_per_m", num(sc.gyro_floor.drift_deg_per_m, 6))
        .add("tilt_err_deg_mean", sc.z_up_world ? num(rep.tilt_deg.mean) : "null")
        .add("tilt_err_deg_max", sc.z_up_world ? num(rep.tilt_deg.max) : "null")
        .add("endpoint_drift_pct", num(rep.endpoint_drift_pct)).add("path_length_m", num(rep.path_length_m));
  else
    js.addNull("drift_pct").addNull("drift_deg_per_m").addNull("ate_rmse_m").addNull("max_jump_m");
  // Net estimated motion first -> last pose (a still clip must stay near zero).
  if (run.est.size() >= 2)
  {
    const Eigen::Isometry3d d = run.est.front().pose.inverse() * run.est.back().pose;
    js.add("est_net_motion_m", num(d.translation().norm(), 6))
        .add("est_net_rotation_deg", num(Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI, 6));
  }
  else
    js.addNull("est_net_motion_m").addNull("est_net_rotation_deg");
}

/// The last stdout line (docs/design.md: its keys are read by others).
ev::JsonLine jsonLine(const Options& opt, const BagRun& run, const Scores& sc)
{
  const Blackout& bo = run.bo;
  ev::JsonLine js;
  js.add("frames", run.frames).add("ms_median", num(percentile(run.times("total"), 0.5)))
      .add("ms_p95", num(percentile(run.times("total"), 0.95))).add("ms_p95_wall", num(percentile(run.wall, 0.95)));
  addTrajectoryKeys(run, sc, js);
  if (opt.bo_start >= 0)
    js.add("blackout_err_m", bo.have_b ? num(bo.relErr(bo.gt_b, bo.est_b)) : "null")
        .add("blackout_moved_m", bo.have_b ? num((bo.gt_a.inverse() * bo.gt_b).translation().norm()) : "null")
        .add("blackout_sigma_m", bo.have_b ? num(bo.sigma_end) : "null")
        .add("blackout_trusted_end", bo.have_b ? (bo.trusted_end ? "true" : "false") : "null")
        .add("blackout_resume_frames", bo.resumed ? std::to_string(bo.resume_frames) : "null")
        .add("blackout_err_resumed_m", bo.resumed ? num(bo.relErr(bo.gt_c, bo.est_c)) : "null");
  if (opt.drop_start >= 0)
  {
    const DroppedGap& g = run.gap;
    js.add("drop_frames", g.dropped).add("drop_err_m", g.have_b ? num(g.err()) : "null")
        .add("drop_moved_m", g.have_b ? num(g.moved()) : "null")
        .add("drop_trusted_after", g.have_b ? (g.trusted_b ? "true" : "false") : "null")
        .add("drop_tracking_after", g.have_b ? (g.tracking_b ? "true" : "false") : "null")
        .add("drop_resets", g.have_b ? std::to_string(g.resets_b - g.resets_a) : "null");
  }
  js.add("resets", run.vo.resets()).add("frames_not_tracking", run.lost).add("max_recovery_frames", run.max_bad_run)
      .add("recovery_frames_max", run.recovery.maxUsableInRun()).add("unusable_frames", run.unusable)
      .add("untrusted_frames", run.vo.failSafe().untrusted_frames).add("standing_frames", run.vo.standingFrames())
      .add("standing_holds", run.vo.standingHolds()).add("gaps_bridged", run.vo.gapsBridged())
      .add("on_spot_frames", run.on_spot).add("on_spot_not_tracking", run.on_spot_not_tracking)
      .add("on_spot_untrusted", run.on_spot_untrusted);
  for (const char* k : kStages)
    js.add(std::string("ms_p95_") + k, num(percentile(run.times(k), 0.95)));
  if (sc.have_gt)
    for (const auto& b : sc.rep.yaw_bands)
      js.add("yaw_err_deg_" + b.name, num(b.mean_err_deg, 5));
  const bool peer_on = opt.peer_on;
  const bool peer_ok = peer_on && sc.have_gt && sc.prep.ate.n > 0;
  js.add("peer_ms_median", peer_on ? num(percentile(run.peer_ms, 0.5)) : "null")
      .add("peer_ms_p95", peer_on ? num(percentile(run.peer_ms, 0.95)) : "null")
      .add("peer_drift_pct", peer_ok ? num(sc.prep.drift.drift_pct) : "null")
      .add("peer_drift_deg_per_m", peer_ok ? num(sc.prep.drift.drift_deg_per_m, 6) : "null")
      .add("peer_ate_rmse_m", peer_ok ? num(sc.prep.ate.rmse) : "null")
      .add("peer_failures", peer_on ? std::to_string(run.peer.failures) : "null");
  return js;
}
}  // namespace

int main(int argc, char** argv)
{
  Options opt;
  ev::CommandLine cl("vo_benchmark", kUsage);
  ev::SetOptions set_options;
  set_options.addTo(cl);
  opt.addTo(cl);
  const auto run_set = [&] { return runSet(cl, argc, argv, set_options, opt); };
  if (const int rc = set_options.parse(cl, argc, argv, run_set, opt.bag); rc >= 0)
    return rc;
  if (opt.plot.empty())
  {
    const size_t dot = opt.bag.rfind(".bag");
    opt.plot = (dot == std::string::npos ? opt.bag : opt.bag.substr(0, dot)) + "_vo_trajectory.png";
  }
  cv::setNumThreads(1);
  if (!opt.parseBlackout())
    return 2;

  const std::unique_ptr<ev::StereoBagReader> reader = ev::openStereoBag("vo_benchmark", opt.bag);
  if (!reader)
    return 1;

  VoParams params;
  params.use_imu = opt.imu_on;
  if (!ev::applySets(cl, opt.overrides, params))  // --set: the node's parameter names (params.h table)
    return 2;
  if (!applyRollingShutter(opt, params))
    return 2;
  // The device's driving loop (vo_front_end.h, as the nodelet runs it): start-up rule, IMU
  // integrals, gravity hint. A bag without an IMU: no wait.
  VoFrontEnd::Options fe_options;
  fe_options.input_has_imu = !reader->imuSamples().empty();
  VoFrontEnd fe(params, fe_options);
  if (opt.bias_known)
  {
    Eigen::Vector3d b;
    if (!fitGyroBias(opt, params, fe_options, *reader, b))
      return 1;
    // sigma 0.02 deg/s sets only the gyro prior's weight (the held bias never moves); glass gave
    // 0.81-1.00x the floor for 0.005-0.05 deg/s (docs/results/assistive_vo.md)
    fe.setKnownGyroBias(b, 0.02 * M_PI / 180.0);
    std::cout << "gyro bias known (fitted to the truth by a first pass, camera_link): " << std::setprecision(4)
              << (b * 180.0 / M_PI).transpose() << " deg/s\n";
  }
  // --self-calibrate: the driver's correction of the right camera's rotation on the bag's pairs.
  // The driver sees an active camera's emitter-on pairs too (their dots are features on pale
  // walls): those up to each frame feed the estimate first, as they would have on the device.
  std::shared_ptr<assistive_description::StereoSelfCalibration> self_cal;
  std::shared_ptr<ev::StereoBagReader> dots;
  if (opt.self_calibrate)
  {
    self_cal = std::make_shared<assistive_description::StereoSelfCalibration>();
    const ev::StereoBagTopics topics;
    if (ev::bagHasTopic(opt.bag, topics.projected_left_image))
      dots = ev::openStereoBag("vo_benchmark", opt.bag, topics.projected());
    auto dot_frame = std::make_shared<ev::StereoFrame>();
    auto have_dot = std::make_shared<bool>(dots && dots->next(*dot_frame));
    reader->setFrameFilter([self_cal, dots, dot_frame, have_dot](ev::StereoFrame& f) {
      for (; *have_dot && dot_frame->stamp < f.stamp; *have_dot = dots->next(*dot_frame))
      {
        const ev::StereoCalib& c = dot_frame->calib;
        self_cal->correctAndEstimate(dot_frame->left, dot_frame->right, {c.fx, c.fy, c.cx, c.cy}, true);
      }
      self_cal->correctAndEstimate(f.left, f.right, {f.calib.fx, f.calib.fy, f.calib.cx, f.calib.cy}, true);
    });
  }
  BagRun run(opt, fe);
  if (!run.run(*reader))
    return 1;
  if (self_cal)
  {
    const cv::Vec3d a = self_cal->applied() * (180.0 / M_PI);
    std::cout << self_cal->describe() << ev::rightRotationAgainstTruth(ev::readBagString(opt.bag), a.val) << "\n";
  }

  // ---- report ----
  printRun(opt, run);
  const Scores sc = scoreRun(opt, run, *reader);
  if (opt.bo_start >= 0)
    printBlackout(opt, run.bo);
  if (opt.drop_start >= 0)
    printDrop(opt, run.gap);
  std::cout << jsonLine(opt, run, sc).str() << std::endl;
  return 0;
}
