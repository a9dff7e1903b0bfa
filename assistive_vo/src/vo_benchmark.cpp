// vo_benchmark FILE.bag [BAG2.bag ...] [--generated N [--kinds K,...] [--imperfect] [--keep DIR]] [--plot OUT.png] [--no-peer] [--no-imu] [--frames N] [--verbose] [--dump FILE] [--set name=value ...]
//              [--blackout START:DURATION]
// (--blackout: the images from START s after the first frame for DURATION s are replaced by a
//  plain grey (a plain wall filling the view); reports the position error at its end against the
//  truth, relative to the last frame before it, and the frames to track again)
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
}  // namespace

int main(int argc, char** argv)
{
  std::string bag, plot, dump, blackout;
  bool peer_on = true, imu_on = true, verbose = false;
  double peer_max_t = 0.15;
  ev::CommandLine::Sets overrides;
  long max_frames = -1;
  const char* usage =
      "usage: vo_benchmark FILE.bag [--plot OUT.png] [--no-peer] [--no-imu] [--frames N] [--peer-max-translation M]\n"
      "                    [--verbose] [--dump FILE] [--set name=value ...] [--blackout START:DURATION]\n"
      "       vo_benchmark BAG BAG... | --generated N [--kinds office,lobby,...] [--frames F] [--imperfect] [--keep DIR]\n"
      "                    [--plot DIR] [other options as above]\n"
      "  Runs the visual odometry on a stereo bag (README \"Topics of a stereo bag\"); last stdout line: JSON.\n"
      "  A set (several bags, or worlds seeds 1..N made by generate_world and render_bag): per-bag rows,\n"
      "  mean and worst of each figure (worst bag named); JSON keys <key>_mean, <key>_worst, <key>_worst_bag.\n";
  ev::CommandLine cl("vo_benchmark", usage);
  ev::SetOptions set_options;
  set_options.addTo(cl);
  cl
      .flag("--no-peer", &peer_on, false)
      .flag("--no-imu", &imu_on, false)
      .flag("--verbose", &verbose)
      .text("--plot", &plot)
      .count("--frames", &max_frames, 0L)
      .number("--peer-max-translation", &peer_max_t)
      .text("--dump", &dump)
      .text("--blackout", &blackout)
      .sets(&overrides);
  if (const int rc = cl.parse(argc, argv); rc >= 0)
    return rc;
  if (set_options.isSet())
  {
    // Worst = the larger, except where more is better; rot_drift_over_gyro_floor: the target ratio (<= 2).
    const std::vector<ev::SetFigure> figures{
        {"drift_pct"}, {"drift_deg_per_m"}, {"rot_drift_over_gyro_floor"}, {"gyro_floor_deg_per_m"},
        {"ate_rmse_m"}, {"max_jump_m"}, {"endpoint_drift_pct"}, {"resets", false, true},
        {"frames_not_tracking", false, true}, {"recovery_frames_max", false, true}, {"ms_p95"},
        {"ms_median"}, {"peer_drift_pct"}, {"peer_ms_p95"}, {"path_length_m", true}, {"frames", true}};
    return ev::runSetFromCommandLine(cl, argc, argv, set_options, figures, "--plot", plot, "_vo_trajectory.png",
                                     max_frames, [](ev::BagResult& b) {
                                       const auto d = b.values.find("drift_deg_per_m");
                                       const auto g = b.values.find("gyro_floor_deg_per_m");
                                       if (d != b.values.end() && g != b.values.end() && g->second > 0)
                                         b.values["rot_drift_over_gyro_floor"] = d->second / g->second;
                                     });
  }
  if (set_options.bags.empty())
    return cl.usageError("no bag given");
  bag = set_options.bags.front();
  if (plot.empty())
  {
    const size_t dot = bag.rfind(".bag");
    plot = (dot == std::string::npos ? bag : bag.substr(0, dot)) + "_vo_trajectory.png";
  }
  cv::setNumThreads(1);
  // --blackout START:DURATION (s after the first frame)
  double bo_start = -1, bo_len = 0;
  if (!blackout.empty() && (std::sscanf(blackout.c_str(), "%lf:%lf", &bo_start, &bo_len) != 2 || bo_start < 0 || bo_len <= 0))
  {
    std::cerr << "vo_benchmark: --blackout wants START:DURATION in seconds, got " << blackout << "\n";
    return 2;
  }
  struct Blackout
  {
    bool have_a = false, have_b = false, resumed = false, trusted_end = false;
    Eigen::Isometry3d gt_a, est_a, gt_b, est_b, gt_c, est_c;
    double sigma_end = -1;
    int frames_after = 0, resume_frames = -1;
  } bo;
  double first_stamp = -1;

  const std::unique_ptr<ev::StereoBagReader> reader = ev::openStereoBag("vo_benchmark", bag);
  if (!reader)
    return 1;

  VoParams params;
  params.use_imu = imu_on;
  if (!ev::applySets(cl, overrides, params))  // --set: the node's parameter names (params.h table)
    return 2;
  // The device's driving loop (vo_front_end.h, as the nodelet runs it): start-up rule, IMU
  // integrals, gravity hint. A bag without an IMU: no wait.
  VoFrontEnd::Options fe_options;
  fe_options.input_has_imu = !reader->imuSamples().empty();
  VoFrontEnd fe(params, fe_options);
  const VisualOdometry& vo = fe.vo();
  Peer peer;
  peer.max_translation_m = peer_max_t;
  ev::Trajectory gt, est, peer_est;
  // The bag's gyro per frame in the optical frame (for the gyro-alone floor); any frame without
  // gyro (first frame aside) voids the floor.
  std::vector<Eigen::Matrix3d> gyro_rel;
  bool gyro_every_frame = imu_on;
  std::map<std::string, std::vector<double>> ms;
  std::vector<double> wall, peer_ms, peer_wall;
  int lost = 0, max_bad_run = 0, bad_run = 0, frames = 0, unusable = 0;
  ev::RecoveryCounter recovery;
  Eigen::Isometry3d peer_T_odom_o0 = Eigen::Isometry3d::Identity();
  std::ofstream dump_out;
  if (!dump.empty())
    dump_out.open(dump);
  ev::StereoFrame f;
  while ((max_frames < 0 || frames < max_frames) && ev::nextFrameOrExit(*reader, f, "vo_benchmark", bag))
  {
    const StereoCamera cam = StereoCamera::from(f.calib);
    if (frames == 0 && peer_on)
      peer.init(cam);
    for (const auto& s : f.imu)
      fe.addImu(s.stamp, s.gyro, s.accel);
    if (first_stamp < 0)
      first_stamp = f.stamp;
    const double t_rel = f.stamp - first_stamp;
    const bool blanked = bo_start >= 0 && t_rel >= bo_start && t_rel < bo_start + bo_len;
    if (blanked)
    {
      f.left = cv::Mat(f.left.size(), f.left.type(), cv::Scalar(128));
      f.right = cv::Mat(f.right.size(), f.right.type(), cv::Scalar(128));
    }
    const ev::Stopwatch timer;
    const FrontEndStep step = fe.process(cam, f.left, f.right, f.stamp);
    if (!step.processed)  // waiting for the IMU (start-up rule): not timed, not scored
    {
      ++frames;
      continue;
    }
    const VoOutput& o = step.out;
    const bool have_gyro = step.have_gyro;
    const Eigen::Quaterniond& gyro = step.gyro;
    if (bo_start >= 0 && f.has_gt_pose && o.pose_valid)
    {
      if (t_rel < bo_start)
      {
        bo.have_a = true;
        bo.gt_a = f.gt_pose;
        bo.est_a = o.T_odom_optical;
      }
      else if (blanked && bo.have_a)
      {
        bo.have_b = true;
        bo.gt_b = f.gt_pose;
        bo.est_b = o.T_odom_optical;
        bo.trusted_end = o.pose_trusted;
        bo.sigma_end = std::sqrt(o.pose_covariance.topLeftCorner<3, 3>().trace() / 3.0);
      }
      else if (bo.have_b && !bo.resumed)
      {
        ++bo.frames_after;
        if (o.state == TrackingState::TRACKING)
        {
          bo.resumed = true;
          bo.resume_frames = bo.frames_after;
          bo.gt_c = f.gt_pose;
          bo.est_c = o.T_odom_optical;
        }
      }
    }
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
    if (verbose)
      std::cerr << "frame " << frames << " " << toString(o.state) << " klt " << o.stats.klt_tracked << " epipolar "
                << o.stats.epipolar_kept << " p3p_inliers " << o.stats.inliers << " trials " << o.stats.ransac_trials
                << " lines " << o.stats.lines << " line_inliers " << o.stats.line_inliers << " ms " << o.stats.ms_total
                << (usable ? "" : " (unusable)") << " step_m " << (est.empty() ? 0.0 : (est.back().pose.translation() - o.T_odom_optical.translation()).norm())
                << " gt_step_m " << (gt.empty() || !f.has_gt_pose ? 0.0 : (gt.back().pose.translation() - f.gt_pose.translation()).norm())
                << (o.stats.keyframe ? " | keyframe: detected " + std::to_string(o.stats.detected) +
                                           " with_depth " + std::to_string(o.stats.new_features)
                                     : std::string())
                << "\n";
    if (!o.message.empty())
      std::cerr << "frame " << frames << " t=" << std::fixed << std::setprecision(3) << f.stamp << " "
                << toString(o.state) << ": " << o.message << "\n";

    if (f.has_gt_pose && o.pose_valid)
    {
      if (dump_out)
      {
        // one row per frame: stamp state keyframe inliers, then gt and estimate (x y z qx qy qz qw)
        auto row = [&](const Eigen::Isometry3d& T) {
          const Eigen::Quaterniond q(T.linear());
          dump_out << " " << T.translation().x() << " " << T.translation().y() << " " << T.translation().z() << " "
                   << q.x() << " " << q.y() << " " << q.z() << " " << q.w();
        };
        dump_out << std::setprecision(9) << f.stamp << " " << static_cast<int>(o.state) << " " << o.stats.keyframe
                 << " " << o.stats.inliers;
        row(f.gt_pose);
        row(o.T_odom_optical);
        // then the integrated gyro of this frame (camera_link, qx qy qz qw), the gyro bias estimate
        // and the mean accelerometer reading over the frame interval (camera_link)
        const Eigen::Quaterniond g = have_gyro ? gyro : Eigen::Quaterniond::Identity();
        Eigen::Vector3d acc = Eigen::Vector3d::Zero();
        fe.imu().meanAccel(f.stamp, 1.0 / 15.0, acc);
        dump_out << " " << g.x() << " " << g.y() << " " << g.z() << " " << g.w() << " " << vo.gyroBias().transpose()
                 << " " << acc.transpose() << "\n";
      }
      gt.push_back({f.stamp, f.gt_pose});
      est.push_back({f.stamp, o.T_odom_optical});
      if (gt.size() > 1 && !have_gyro)
        gyro_every_frame = false;
      gyro_rel.push_back(have_gyro ? Eigen::Matrix3d(R_link_optical().transpose() * gyro.toRotationMatrix() *
                                                     R_link_optical())
                                   : Eigen::Matrix3d::Identity());
      if (peer_on)
      {
        const ev::Stopwatch peer_timer;
        peer.process(cam, f.left, f.right);
        peer_ms.push_back(peer_timer.cpuMs());
        peer_wall.push_back(peer_timer.wallMs());
        if (peer_est.empty())
          peer_T_odom_o0 = o.T_odom_optical;  // same start pose as ours (gravity from the IMU)
        peer_est.push_back({f.stamp, peer_T_odom_o0 * peer.T_w_c});
      }
    }
    else if (!gt.empty())
      gyro_every_frame = false;  // a frame left out: the per-frame gyro no longer pairs with gt
    ++frames;
    if (frames % 50 == 0)
      std::cerr << "[vo_benchmark] " << frames << " frames\n";
  }
  if (frames == 0)
  {
    std::cerr << "vo_benchmark: no stereo frames in " << bag << "\n";
    return 1;
  }

  // ---- report ----
  std::cout << "assistive_vo benchmark: " << bag << "  (" << frames << " frames, "
            << (imu_on ? "gyro prior on" : "no IMU") << ")\n";
  std::cout << "stage          ms_median   ms_p95   (thread CPU time, one core)\n";
  for (const char* k : {"pyramid", "klt", "epipolar", "stereo", "p3p_ransac", "bundle_adj", "detect", "lines", "total"})
    std::cout << "  " << std::left << std::setw(12) << k << std::right << std::fixed << std::setprecision(3)
              << std::setw(10) << percentile(ms[k], 0.5) << std::setw(9) << percentile(ms[k], 0.95) << "\n";
  std::cout << "  total (wall)" << std::setw(10) << percentile(wall, 0.5) << std::setw(9) << percentile(wall, 0.95)
            << "\n";
  std::cout << "stereo disparity offset estimated " << vo.disparityOffset() << " px\n";
  std::cout << "resets " << vo.resets() << ", frames not tracking " << lost << ", longest non-tracking run "
            << max_bad_run << " frames; usable frames needed to track again (recovery_frames_max) "
            << recovery.maxUsableInRun() << ", unusable frames " << unusable << "\n";

  ev::TrajectoryReport rep, prep;
  ev::DriftResult gyro_floor;
  // The simulator's bags (they carry its ground-truth occupancy) have a z-up world: only there is
  // the tilt against gravity measurable (imported datasets keep their own world axes).
  bool z_up_world = false;
  const bool have_gt = gt.size() >= 3;
  if (have_gt)
  {
    rep = ev::evaluateTrajectory(gt, est);
    std::cout << "\n--- ours (assistive_vo) vs ground truth ---\n" << ev::reportTable(rep);
    std::cout << "rotational drift split  yaw " << rep.drift.drift_deg_per_m_yaw << " deg/m  tilt (roll/pitch) "
              << rep.drift.drift_deg_per_m_tilt << " deg/m\n";
    if (gyro_every_frame)
    {
      // The floor the gyro's angle random walk sets: the gyro alone, its bias fit to the truth.
      const ev::Trajectory g = ev::gyroOnlyTrajectory(gt, gyro_rel);
      if (!g.empty())
      {
        gyro_floor = ev::segmentDrift(gt, g, ev::TrajectoryEvalParams().drift_lengths_m, 1, ev::YawBandParams().up);
        std::cout << std::setprecision(4) << "gyro alone, bias fit to ground truth (the angle random walk floor): "
                  << gyro_floor.drift_deg_per_m << " deg/m (";
        for (const auto& l : gyro_floor.per_length)
          std::cout << std::setprecision(0) << l.length_m << " m: " << std::setprecision(4) << l.r_err_deg_per_m
                    << (&l == &gyro_floor.per_length.back() ? "" : ", ");
        std::cout << ")\n";
      }
    }
    if (peer_on && peer_est.size() == gt.size())
    {
      prep = ev::evaluateTrajectory(gt, peer_est);
      std::cout << "\n--- peer (SGBM + cv::rgbd::RgbdOdometry) vs ground truth ---\n" << ev::reportTable(prep);
      std::cout << "peer ms median " << percentile(peer_ms, 0.5) << "  p95 " << percentile(peer_ms, 0.95)
                << "  (wall p95 " << percentile(peer_wall, 0.95) << "), failures " << peer.failures << "\n";
    }
    // Trajectory plot: ground truth, ours and the peer, top-down over the floor plan.
    std::vector<ev::PlotSeries> series{{"ground truth", ev::positions(gt), cv::Scalar(0, 0, 0)}};
    const ev::Alignment al = rep.alignment;
    series.push_back({"assistive_vo", ev::positions(ev::applyAlignment(est, al)), cv::Scalar(0, 0, 230)});
    if (prep.ate.n > 0)
      series.push_back({"peer RgbdOdometry", ev::positions(ev::applyAlignment(peer_est, prep.alignment)),
                        cv::Scalar(230, 120, 0)});
    ev::OccupancyGrid floor;
    const bool have_floor = reader->readOccupancy(floor);
    z_up_world = have_floor;
    ev::PlotOptions po;
    po.title = "VO trajectory (SE3-aligned): " + bag;
    std::string err;
    if (ev::writePng(plot, ev::plotTopDown(series, have_floor ? &floor : nullptr, po), &err))
      std::cout << "trajectory plot: " << plot << "\n";
    else
      std::cerr << "vo_benchmark: plot not written: " << err << "\n";
  }
  else
    std::cout << "no ground truth in the bag: trajectory errors are null\n";

  auto num = [](double v, int significant = 4) { return ev::jsonNumber(v, significant); };
  // position error of the pose change since the last frame before the blackout (its axes)
  auto relErr = [&](const Eigen::Isometry3d& gt_x, const Eigen::Isometry3d& est_x) {
    return ((bo.est_a.inverse() * est_x).translation() - (bo.gt_a.inverse() * gt_x).translation()).norm();
  };
  if (bo_start >= 0)
  {
    std::cout << "blackout " << bo_start << " s + " << bo_len << " s: ";
    if (bo.have_b)
      std::cout << "position error at its end " << relErr(bo.gt_b, bo.est_b) << " m (truth moved "
                << (bo.gt_a.inverse() * bo.gt_b).translation().norm() << " m; published 1-sigma " << bo.sigma_end
                << " m, " << (bo.trusted_end ? "trusted" : "untrusted") << "), tracking again after "
                << bo.resume_frames << " frames"
                << (bo.resumed ? ", error then " + std::to_string(relErr(bo.gt_c, bo.est_c)) + " m" : "") << "\n";
    else
      std::cout << "no frame with a pose in the window\n";
  }
  ev::JsonLine js;
  js.add("frames", frames).add("ms_median", num(percentile(ms["total"], 0.5)))
      .add("ms_p95", num(percentile(ms["total"], 0.95))).add("ms_p95_wall", num(percentile(wall, 0.95)));
  if (have_gt)
    js.add("drift_pct", num(rep.drift.drift_pct)).add("drift_deg_per_m", num(rep.drift.drift_deg_per_m, 6))
        .add("drift_deg_per_m_yaw", num(rep.drift.drift_deg_per_m_yaw, 6))
        .add("drift_deg_per_m_tilt", num(rep.drift.drift_deg_per_m_tilt, 6)).add("ate_rmse_m", num(rep.ate.rmse))
        .add("max_jump_m", num(rep.max_jump_m)).add("gyro_floor_deg_per_m", num(gyro_floor.drift_deg_per_m, 6))
        .add("tilt_err_deg_mean", z_up_world ? num(rep.tilt_deg.mean) : "null")
        .add("tilt_err_deg_max", z_up_world ? num(rep.tilt_deg.max) : "null")
        .add("endpoint_drift_pct", num(rep.endpoint_drift_pct)).add("path_length_m", num(rep.path_length_m));
  else
    js.addNull("drift_pct").addNull("drift_deg_per_m").addNull("ate_rmse_m").addNull("max_jump_m");
  // Net estimated motion first -> last pose (a still clip must stay near zero).
  if (est.size() >= 2)
  {
    const Eigen::Isometry3d d = est.front().pose.inverse() * est.back().pose;
    js.add("est_net_motion_m", num(d.translation().norm(), 6))
        .add("est_net_rotation_deg", num(Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI, 6));
  }
  else
    js.addNull("est_net_motion_m").addNull("est_net_rotation_deg");
  if (bo_start >= 0)
    js.add("blackout_err_m", bo.have_b ? num(relErr(bo.gt_b, bo.est_b)) : "null")
        .add("blackout_moved_m", bo.have_b ? num((bo.gt_a.inverse() * bo.gt_b).translation().norm()) : "null")
        .add("blackout_sigma_m", bo.have_b ? num(bo.sigma_end) : "null")
        .add("blackout_trusted_end", bo.have_b ? (bo.trusted_end ? "true" : "false") : "null")
        .add("blackout_resume_frames", bo.resumed ? std::to_string(bo.resume_frames) : "null")
        .add("blackout_err_resumed_m", bo.resumed ? num(relErr(bo.gt_c, bo.est_c)) : "null");
  js.add("resets", vo.resets()).add("frames_not_tracking", lost).add("max_recovery_frames", max_bad_run)
      .add("recovery_frames_max", recovery.maxUsableInRun()).add("unusable_frames", unusable);
  for (const char* k : {"pyramid", "klt", "epipolar", "stereo", "p3p_ransac", "bundle_adj", "detect", "lines"})
    js.add(std::string("ms_p95_") + k, num(percentile(ms[k], 0.95)));
  if (have_gt)
    for (const auto& b : rep.yaw_bands)
      js.add("yaw_err_deg_" + b.name, num(b.mean_err_deg, 5));
  const bool peer_ok = peer_on && have_gt && prep.ate.n > 0;
  js.add("peer_ms_median", peer_on ? num(percentile(peer_ms, 0.5)) : "null")
      .add("peer_ms_p95", peer_on ? num(percentile(peer_ms, 0.95)) : "null")
      .add("peer_drift_pct", peer_ok ? num(prep.drift.drift_pct) : "null")
      .add("peer_drift_deg_per_m", peer_ok ? num(prep.drift.drift_deg_per_m, 6) : "null")
      .add("peer_ate_rmse_m", peer_ok ? num(prep.ate.rmse) : "null")
      .add("peer_failures", peer_on ? std::to_string(peer.failures) : "null");
  std::cout << js.str() << std::endl;
  return 0;
}
