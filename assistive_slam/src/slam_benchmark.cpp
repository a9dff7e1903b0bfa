// slam_benchmark FILE.bag [--no-imu] [--plot OUT.png] [--frames N] [--realtime] [--set name=value ...]
// Runs the VO core (as vo_benchmark does) and the SLAM core on every stereo frame of a bag (no
// roscore), scores the VO alone and SLAM on the same frames against the bag's ground truth, counts
// loop closures (false ones: the verified relative pose disagrees with the truth by > 0.5 m or
// 5 deg; missed ones: runs of keyframes revisiting an older place with no accepted closure), and
// plots the trajectories with the closures marked. Last stdout line: one JSON object.
// By default the frame loop waits for the worker after each keyframe, outside the timed part, so
// that the accuracy figures do not depend on the machine's load; --realtime lets it run free.
#include <sys/resource.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>
#include <opencv2/core.hpp>
#include <assistive_eval/benchmark.h>
#include <assistive_eval/metrics.h>
#include <assistive_eval/plots.h>
#include <assistive_eval/stereo_bag.h>
#include "assistive_slam/map_file.h"
#include "assistive_slam/slam_system.h"
#include "assistive_slam/vo_adapter.h"
#include "assistive_vo/frames.h"
#include "assistive_vo/published_odometry.h"
#include "assistive_vo/vo_front_end.h"

namespace ev = assistive_eval;
using ev::percentile;
using namespace assistive_slam;

namespace
{
double peakRssMb()
{
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // kB on Linux
}
double currentRssMb()
{
  std::ifstream f("/proc/self/statm");
  long pages = 0, resident = 0;
  f >> pages >> resident;
  return resident * (sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0));
}
double angDeg(const Eigen::Matrix3d& R)
{
  return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI;
}

/// The flat JSON object of a run's last line as (key, value text) pairs, in order.
std::vector<std::pair<std::string, std::string>> parseFlatJson(const std::string& line)
{
  std::vector<std::pair<std::string, std::string>> kv;
  size_t i = line.find('{');
  while (i != std::string::npos)
  {
    const size_t k0 = line.find('"', i);
    if (k0 == std::string::npos)
      break;
    const size_t k1 = line.find('"', k0 + 1);
    const size_t colon = line.find(':', k1);
    size_t end = line.find_first_of(",}", colon);
    if (k1 == std::string::npos || colon == std::string::npos || end == std::string::npos)
      break;
    std::string v = line.substr(colon + 1, end - colon - 1);
    v.erase(0, v.find_first_not_of(' '));
    kv.push_back({line.substr(k0 + 1, k1 - k0 - 1), v});
    i = line[end] == '}' ? std::string::npos : end + 1;
  }
  return kv;
}

/// --backend both: this program once per backend on the same bag and frames (the VO is
/// deterministic, so both see the same VO poses: vo_ate_rmse_m agrees), each in its own process so
/// that peak memory is its own; their JSON merged with the backend's name as prefix.
int runBoth(int argc, char** argv)
{
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i)
  {
    if (std::string(argv[i]) == "--backend" && i + 1 < argc)
    {
      ++i;
      continue;
    }
    args.push_back(argv[i]);
  }
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> res;
  const std::vector<std::string> backends{"keyframe_ba", "fastslam"};
  for (const std::string& b : backends)
  {
    char self[4096] = {0};  // this program (/proc/self/exe inside popen would be the shell)
    if (readlink("/proc/self/exe", self, sizeof self - 1) <= 0)
      return 1;
    std::string cmd = std::string("'") + self + "'";
    for (std::string a : args)
    {
      if (b == "fastslam" && a.size() > 4 && a.substr(a.size() - 4) == ".png")
        a = a.substr(0, a.size() - 4) + "_fastslam.png";
      std::string q;
      for (char c : a)
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
      cmd += " '" + q + "'";
    }
    cmd += " --backend " + b;
    if (b == "fastslam" && std::find(args.begin(), args.end(), "--plot") == args.end())
      cmd += " --plot-suffix _fastslam";
    std::cout << "===== backend " << b << " =====" << std::endl;
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe)
      return 1;
    std::string out, last;
    char buf[4096];
    while (fgets(buf, sizeof buf, pipe))
    {
      std::cout << buf;
      const std::string l(buf);
      if (!l.empty() && l[0] == '{')
        last = l;
    }
    if (pclose(pipe) != 0 || last.empty())
    {
      std::cerr << "slam_benchmark: the " << b << " run failed\n";
      return 1;
    }
    res[b] = parseFlatJson(last);
  }
  auto get = [&](const std::string& b, const std::string& k) {
    for (const auto& p : res[b])
      if (p.first == k)
        return p.second;
    return std::string("-");
  };
  std::cout << "===== side by side =====\n";
  std::cout << std::left << std::setw(26) << "figure" << std::setw(14) << "keyframe_ba" << "fastslam\n";
  for (const char* k : {"ate_rmse_m", "vo_ate_rmse_m", "submap_ate_m", "vo_submap_ate_m", "drift_pct", "drift_deg_per_m",
                        "ms_median", "ms_p95", "particles", "landmarks", "resamplings", "loop_closures",
                        "false_loop_closures", "peak_rss_mb", "am_refound_share", "am_false_match_rate"})
    std::cout << std::setw(26) << k << std::setw(14) << get("keyframe_ba", k) << get("fastslam", k) << "\n";
  ev::JsonLine js;
  for (const std::string& b : backends)
    for (const auto& p : res[b])
      js.add(b + "_" + p.first, p.second);
  std::cout << js.str() << std::endl;
  return 0;
}
}  // namespace

int main(int argc, char** argv)
{
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--backend" && std::string(argv[i + 1]) == "both")
      return runBoth(argc, argv);
  std::string bag, plot, map_path, load_path, backend, plot_suffix;
  long skip_frames = 0;
  bool imu_on = true, realtime = false;
  long max_frames = -1;
  ev::CommandLine::Sets overrides;
  const char* usage =
      "usage: slam_benchmark FILE.bag [--no-imu] [--plot OUT.png] [--frames N] [--skip N] [--realtime] [--map FILE]\n"
      "                     [--load-map FILE] [--set name=value ...]\n"
      "  VO alone and VO + SLAM on the same frames of a stereo bag; last stdout line: JSON.\n"
      "  --map: where the map is written at the end; --load-map: start from a saved map (relocalisation);\n"
      "  --skip N: the first N frames are not run (e.g. the first loop, mapped by an earlier run).\n"
      "  --set: the SLAM stage's parameters (README table), e.g. --set loop_closure=false\n"
      "  --backend keyframe_ba|fastslam|both: the metric layer (default: metric_backend); both: one run\n"
      "    each on the same frames, JSON keys prefixed keyframe_ba_ and fastslam_\n";
  ev::CommandLine cl("slam_benchmark", usage);
  cl.positional(&bag, "bag", true)
      .flag("--no-imu", &imu_on, false)
      .flag("--realtime", &realtime)
      .text("--plot", &plot)
      .text("--map", &map_path)
      .text("--load-map", &load_path)
      .text("--backend", &backend)
      .text("--plot-suffix", &plot_suffix)
      .count("--skip", &skip_frames, 0L)
      .count("--frames", &max_frames, 0L)
      .sets(&overrides);
  if (const int rc = cl.parse(argc, argv); rc >= 0)
    return rc;
  if (plot.empty())
  {
    const size_t dot = bag.rfind(".bag");
    plot = (dot == std::string::npos ? bag : bag.substr(0, dot)) + "_slam_trajectory" + plot_suffix + ".png";
  }
  cv::setNumThreads(1);
  SlamParams sp;
  if (!ev::applySets(cl, overrides, sp))
    return 2;
  if (!backend.empty())
    sp.metric_backend = backend;
  if (sp.metric_backend != "keyframe_ba" && sp.metric_backend != "fastslam")
  {
    std::cerr << "slam_benchmark: unknown backend " << sp.metric_backend << " (keyframe_ba | fastslam | both)\n";
    return 2;
  }
  const std::unique_ptr<ev::StereoBagReader> reader = ev::openStereoBag("slam_benchmark", bag);
  if (!reader)
    return 1;

  assistive_vo::VoParams vp;
  vp.use_imu = imu_on;
  // The device's VO driving loop (assistive_vo/vo_front_end.h, as its nodelet runs it).
  assistive_vo::VoFrontEnd::Options fo;
  fo.input_has_imu = !reader->imuSamples().empty();
  assistive_vo::VoFrontEnd fe(vp, fo);
  std::unique_ptr<SlamSystem> slam;
  // SLAM takes the VO's output as the nodelet does (vo_adapter.h): what vo/odom would carry
  // (published_odometry.h), the optical frame in camera_link as the URDF has it.
  Eigen::Isometry3d T_link_optical = Eigen::Isometry3d::Identity();
  T_link_optical.linear() = assistive_vo::R_link_optical();
  VoAdapter adapter(SlamNodeParams().untrusted_variance, T_link_optical);

  ev::Trajectory gt, vo_est, online_est;
  std::vector<Eigen::Isometry3d> frame_odom;  // per scored frame: VO pose (for the final SLAM trajectory)
  // fastslam: active matching against the truth, the filter's own trajectory per submap
  std::map<uint32_t, std::pair<Eigen::Isometry3d, Eigen::Vector3d>> am_init;  // landmark -> truth at init, stereo point
  long am_checked = 0, am_false = 0;
  std::vector<double> am_err;  // px, each match against the truth
  struct FilterFrame
  {
    double t;
    Eigen::Isometry3d gt, filter, vo;
    int segment;
  };
  std::vector<FilterFrame> filter_frames;
  size_t peak_map_nodes = 0;
  int filter_frames_seen = 0;
  std::map<double, Eigen::Isometry3d> gt_at;  // stamp -> truth
  std::vector<std::pair<double, Eigen::Isometry3d>> session_truth;  // every run frame's truth, in order
  std::vector<double> ms_added, ms_vo, worker_ms;
  std::vector<std::pair<double, double>> rss_samples;  // (keyframes, resident MB) every 100 frames
  int frames = 0, keyframes_queued = 0;
  long skipped = 0;
  size_t stored_keyframes = 0;
  std::vector<Eigen::Isometry3d> loaded_poses;  // the stored keyframes' map poses as loaded
  int reloc_frame = -1;       // session frame at which the wearer was relocalised
  ev::StereoFrame f;
  while ((max_frames < 0 || frames < max_frames) && ev::nextFrameOrExit(*reader, f, "slam_benchmark", bag))
  {
    if (skipped < skip_frames)
    {
      ++skipped;
      if (f.has_gt_pose)
        gt_at[f.stamp] = f.gt_pose;  // the truth of a stored map's keyframes (same bag)
      continue;
    }
    const assistive_vo::StereoCamera cam = assistive_vo::StereoCamera::from(f.calib);
    if (!slam)
    {
      StereoModel m;
      m.fx = cam.fx;
      m.fy = cam.fy;
      m.cx = cam.cx;
      m.cy = cam.cy;
      m.baseline = cam.baseline;
      slam = std::make_unique<SlamSystem>(sp, m, true);
      if (!load_path.empty())
      {
        MapData md;
        std::string err;
        if (!loadMapFile(load_path, md, &err) || !slam->loadMap(md, &err))
        {
          std::cerr << "slam_benchmark: map " << load_path << " not loaded: " << err << "\n";
          return 1;
        }
        stored_keyframes = md.keyframes.size();
        for (const Keyframe& k : md.keyframes)
          loaded_poses.push_back(k.T_map_cam);
        std::cerr << "[slam_benchmark] map " << load_path << ": " << md.keyframes.size() << " keyframes, "
                  << md.submaps.size() << " submaps, " << md.places.size() << " places\n";
      }
    }
    for (const auto& s : f.imu)
      fe.addImu(s.stamp, s.gyro, s.accel);
    const ev::Stopwatch vo_timer;
    const assistive_vo::FrontEndStep step = fe.process(cam, f.left, f.right, f.stamp);
    if (!step.processed)  // waiting for the IMU (start-up rule)
    {
      ++frames;
      continue;
    }
    const assistive_vo::VoOutput& o = step.out;
    ms_vo.push_back(vo_timer.cpuMs());

    if (!o.pose_valid || !o.T_odom_link.matrix().allFinite())
    {
      ++frames;  // the nodelet publishes no vo/odom for it: SLAM never sees it
      continue;
    }
    const assistive_vo::PublishedOdometry po = assistive_vo::published(o);
    VoOdometry vo_odom;
    vo_odom.stamp = f.stamp;
    vo_odom.T_odom_link = po.T_odom_link;
    vo_odom.position_variance = po.pose_covariance(0, 0);
    vo_odom.twist_covariance = po.twist_covariance;
    const SlamFrame sf = adapter.frame(vo_odom, f.left, f.right);
    const ev::Stopwatch timer;
    const bool queued = slam->addFrame(sf);
    const Eigen::Isometry3d T_map_odom = slam->mapToOdom();
    ms_added.push_back(timer.cpuMs());
    if (const FastSlam* fs = slam->filter())
    {
      for (const FastSlamInit& in : fs->lastInits())
        if (f.has_gt_pose)
          am_init[in.landmark] = {f.gt_pose, in.X_cam};
      for (const FastSlamMatch& m : fs->lastMatches())
      {
        auto it = am_init.find(m.landmark);
        if (!f.has_gt_pose || it == am_init.end())
          continue;
        // The truth of a match: the landmark lies on the true ray of its first pixel (exact), at a
        // depth its stereo initialisation knows to a few per cent. A match is false when it lies
        // more than 3 px from that ray's image between 0.75 and 1.33 x the stereo depth (the
        // stereo depth alone would blame far landmarks' depth error on the matcher).
        const Eigen::Isometry3d T_cur_init = f.gt_pose.inverse() * it->second.first;
        auto proj = [&](double k, Eigen::Vector2d* z) {
          const Eigen::Vector3d p = T_cur_init * (it->second.second * k);
          if (p.z() <= 0.05)
            return false;
          *z = Eigen::Vector2d(cam.fx * p.x() / p.z() + cam.cx, cam.fy * p.y() / p.z() + cam.cy);
          return true;
        };
        Eigen::Vector2d a, b;
        if (!proj(0.75, &a) || !proj(1.0 / 0.75, &b))
          continue;
        const Eigen::Vector2d ab = b - a;
        const double tpar = ab.squaredNorm() > 1e-12 ? std::clamp((m.z - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
        const double err = (a + tpar * ab - m.z).norm();
        ++am_checked;
        am_false += err > 3.0;
        am_err.push_back(err);
      }
      const bool filtered = fs->stats().frames != filter_frames_seen;  // (untrusted frames are not filtered)
      filter_frames_seen = fs->stats().frames;
      if (f.has_gt_pose && o.pose_valid && filtered)
        filter_frames.push_back({f.stamp, f.gt_pose, fs->pose(), o.T_odom_optical, fs->stats().resets});
    }
    if (queued)
    {
      ++keyframes_queued;
      if (!realtime)
      {
        slam->waitIdle();
        worker_ms.push_back(slam->stats().worker_ms_last);
      }
    }
    if (reloc_frame < 0 && !load_path.empty() && slam->localised())
      reloc_frame = frames;

    if (f.has_gt_pose)
      session_truth.push_back({f.stamp, f.gt_pose});
    if (f.has_gt_pose && o.pose_valid)
    {
      gt.push_back({f.stamp, f.gt_pose});
      gt_at[f.stamp] = f.gt_pose;
      vo_est.push_back({f.stamp, o.T_odom_optical});
      online_est.push_back({f.stamp, T_map_odom * o.T_odom_optical});
      frame_odom.push_back(o.T_odom_optical);
    }
    ++frames;
    if (frames % 100 == 0)
    {
      if (const FastSlam* fs = slam->filter())
        peak_map_nodes = std::max(peak_map_nodes, fs->mapNodes());
      const SlamStats st = slam->stats();
      const double rss = currentRssMb();
      rss_samples.push_back({static_cast<double>(st.keyframes), rss});
      std::cerr << "[slam_benchmark] " << frames << " frames, " << st.keyframes << " keyframes, " << st.submaps
                << " submaps, loop closures " << st.loops_accepted << " (rejected " << st.loops_rejected << "), RSS "
                << rss << " MB\n";
    }
  }
  if (!slam || gt.size() < 3)
  {
    std::cerr << "slam_benchmark: no scored frames (no stereo frames or no ground truth) in " << bag << "\n";
    return 1;
  }
  slam->waitIdle();
  const SlamStats st = slam->stats();
  const std::vector<Keyframe> kfs = slam->keyframes();
  const std::vector<Keyframe> session_kfs(kfs.begin() + static_cast<long>(std::min(stored_keyframes, kfs.size())), kfs.end());
  const std::vector<LoopEvent> events = slam->loopEvents();

  // Final SLAM trajectory: each frame rides on the last keyframe before it (optimised pose).
  ev::Trajectory slam_est;
  {
    size_t k = 0;
    for (size_t i = 0; i < gt.size(); ++i)
    {
      while (k + 1 < session_kfs.size() && session_kfs[k + 1].stamp <= gt[i].t)
        ++k;
      Eigen::Isometry3d T = frame_odom[i];
      if (!session_kfs.empty() && session_kfs[k].stamp <= gt[i].t)
        T = session_kfs[k].T_map_cam * session_kfs[k].T_odom_cam.inverse() * frame_odom[i];
      slam_est.push_back({gt[i].t, T});
    }
  }

  // Loop closures against the truth.
  auto truthOf = [&](double stamp, Eigen::Isometry3d& T) {
    auto it = gt_at.find(stamp);
    if (it == gt_at.end())
      return false;
    T = it->second;
    return true;
  };
  int accepted = 0, false_closures = 0;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> closure_lines;
  std::set<uint32_t> closed_new;
  for (const LoopEvent& e : events)
  {
    if (!e.accepted)
      continue;
    ++accepted;
    Eigen::Isometry3d Ta, Tb;
    if (!truthOf(kfs[e.keyframe_old].stamp, Ta) || !truthOf(kfs[e.keyframe_new].stamp, Tb))
      continue;
    const Eigen::Isometry3d T_true = Ta.inverse() * Tb;
    const Eigen::Isometry3d d = T_true.inverse() * e.T_old_new;
    const bool wrong = d.translation().norm() > 0.5 || angDeg(d.linear()) > 5.0;
    false_closures += wrong;
    std::cout << (wrong ? "FALSE " : "") << "loop closure: keyframe " << e.keyframe_new << " (submap "
              << e.submap_new << ") -> " << e.keyframe_old << " (submap " << e.submap_old << "), " << e.inliers
              << " inliers, correction " << std::setprecision(3) << e.correction_m << " m " << e.correction_deg
              << " deg; error vs truth " << d.translation().norm() << " m " << angDeg(d.linear()) << " deg\n";
    closure_lines.push_back({Ta.translation(), Tb.translation()});
    closed_new.insert(e.keyframe_new);
  }
  // Revisits: keyframes whose true position is within 1 m (view within 30 deg) of a keyframe at
  // least 15 m of path earlier; consecutive revisiting keyframes form one run; a run with no
  // accepted closure is missed.
  int revisit_runs = 0, missed = 0;
  {
    std::vector<Eigen::Isometry3d> kgt(kfs.size());
    std::vector<bool> has(kfs.size(), false);
    for (size_t i = 0; i < kfs.size(); ++i)
      has[i] = truthOf(kfs[i].stamp, kgt[i]);
    bool in_run = false, run_closed = false;
    for (size_t b = 0; b < kfs.size(); ++b)
    {
      bool revisit = false;
      for (size_t a = 0; a < b && has[b] && !revisit; ++a)
        revisit = has[a] && kfs[b].path_m - kfs[a].path_m > 15.0 &&
                  (kgt[a].translation() - kgt[b].translation()).norm() < 1.0 &&
                  angDeg(kgt[a].linear().transpose() * kgt[b].linear()) < 30.0;
      if (revisit)
      {
        if (!in_run)
        {
          ++revisit_runs;
          run_closed = false;
        }
        in_run = true;
        run_closed = run_closed || closed_new.count(static_cast<uint32_t>(b));
      }
      else if (in_run)
      {
        missed += !run_closed;
        in_run = false;
      }
    }
    if (in_run)
      missed += !run_closed;
  }

  // Relocalisation (--load-map): frames from the first one with a stored keyframe in view (truly
  // within 1 m and 30 deg; needs the stored keyframes' truth, i.e. the same bag) to the one that
  // relocalised, and the error of the relocalised pose in world through the fit of the stored
  // keyframes' map poses to their truth.
  double reloc_frames = -1, reloc_err_m = -1, reloc_err_deg = -1;
  if (!load_path.empty())
  {
    std::vector<Eigen::Isometry3d> stored_gt;
    Eigen::Matrix3Xd a(3, 0), b(3, 0);
    for (size_t i = 0; i < stored_keyframes; ++i)
    {
      Eigen::Isometry3d T;
      if (!truthOf(kfs[i].stamp, T))
        continue;
      stored_gt.push_back(T);
      a.conservativeResize(3, a.cols() + 1);
      b.conservativeResize(3, b.cols() + 1);
      a.col(a.cols() - 1) = loaded_poses[i].translation();
      b.col(b.cols() - 1) = T.translation();
    }
    int in_view = stored_gt.empty() ? 0 : -1;
    for (size_t i = 0; i < session_truth.size() && in_view < 0; ++i)
      for (const Eigen::Isometry3d& S : stored_gt)
        if ((S.translation() - session_truth[i].second.translation()).norm() < 1.0 &&
            angDeg(S.linear().transpose() * session_truth[i].second.linear()) < 30.0)
        {
          in_view = static_cast<int>(i);
          break;
        }
    std::cout << "relocalisation: " << (stored_gt.empty() ? "no truth for the stored keyframes (another bag?); " : "")
              << "first stored place in view at session frame " << in_view << ", relocalised at frame " << reloc_frame
              << " (" << st.relocalisation_queries << " keyframes tried)\n";
    if (reloc_frame >= 0 && in_view >= 0)
      reloc_frames = std::max(0, reloc_frame - in_view);
    Eigen::Isometry3d Tt;
    if (st.relocalised_stamp >= 0 && a.cols() >= 3 && truthOf(st.relocalised_stamp, Tt))
    {
      Eigen::Isometry3d A;
      A.matrix() = Eigen::umeyama(a, b, false);
      for (const LoopEvent& e : events)
        if (e.relocalisation)
        {
          // the pose the relocalisation gave: the stored keyframe times the verified relative pose
          const Eigen::Isometry3d Tm = A * loaded_poses.at(e.keyframe_old) * e.T_old_new;
          reloc_err_m = (Tm.translation() - Tt.translation()).norm();
          reloc_err_deg = angDeg(Tm.linear().transpose() * Tt.linear());
        }
      std::cout << "relocalised pose vs truth (world through the fit of the stored keyframes as loaded): " << reloc_err_m << " m, "
                << reloc_err_deg << " deg\n";
    }
  }

  if (!load_path.empty() && st.relocalised_stamp >= 0)
  {
    // A loaded map: frames before the relocalisation have no map pose; all figures from it on.
    auto from = [&](const ev::Trajectory& t) {
      ev::Trajectory o;
      for (const auto& p : t)
        if (p.t >= st.relocalised_stamp)
          o.push_back(p);
      return o;
    };
    gt = from(gt);
    vo_est = from(vo_est);
    slam_est = from(slam_est);
    online_est = from(online_est);
  }
  const ev::TrajectoryReport vrep = ev::evaluateTrajectory(gt, vo_est);
  const ev::TrajectoryReport srep = ev::evaluateTrajectory(gt, slam_est);
  const ev::TrajectoryReport orep = ev::evaluateTrajectory(gt, online_est);
  std::cout << "assistive_slam benchmark: " << bag << "  (" << frames << " frames, " << (imu_on ? "IMU" : "no IMU")
            << ", " << (realtime ? "realtime" : "worker awaited per keyframe") << ")\n";
  std::cout << "--- VO alone vs ground truth ---\n" << ev::reportTable(vrep);
  std::cout << "--- SLAM (final, optimised keyframes) vs ground truth ---\n" << ev::reportTable(srep);
  std::cout << "--- SLAM (online: map->odom at the time) vs ground truth ---\n" << ev::reportTable(orep);
  std::cout << std::fixed << std::setprecision(3) << "frame-loop time added by SLAM: median " << percentile(ms_added, 0.5)
            << " ms, p95 " << percentile(ms_added, 0.95) << " ms (thread CPU; VO p95 " << percentile(ms_vo, 0.95)
            << " ms); worker per keyframe: median " << percentile(worker_ms, 0.5) << " ms, p95 "
            << percentile(worker_ms, 0.95) << " ms (wall)\n";
  std::cout << "keyframes " << st.keyframes << " (queued " << keyframes_queued << ", dropped " << st.dropped
            << "), submaps " << st.submaps << ", local BA runs " << st.ba_runs << " (rejected " << st.ba_rejected << ")" << ", pose-graph runs "
            << st.pose_graph_runs << ", loop closures " << accepted << " accepted (" << false_closures
            << " false), " << st.loops_rejected << " verified but rejected; revisit runs " << revisit_runs
            << ", missed " << missed << "\n";

  // Plot: truth, VO and SLAM (SE3-aligned like the ATE), closures as green segments (truth positions).
  std::vector<ev::PlotSeries> series{{"ground truth", ev::positions(gt), cv::Scalar(0, 0, 0)}};
  series.push_back({"VO alone", ev::positions(ev::applyAlignment(vo_est, vrep.alignment)), cv::Scalar(0, 0, 230)});
  series.push_back({"SLAM", ev::positions(ev::applyAlignment(slam_est, srep.alignment)), cv::Scalar(230, 120, 0)});
  for (size_t i = 0; i < closure_lines.size(); ++i)
    series.push_back({i == 0 ? "loop closures" : "", {closure_lines[i].first, closure_lines[i].second + Eigen::Vector3d(0.15, 0.15, 0)},
                      cv::Scalar(0, 180, 0)});
  ev::OccupancyGrid floor;
  const bool have_floor = reader->readOccupancy(floor);
  ev::PlotOptions po;
  po.title = "SLAM trajectory (SE3-aligned): " + bag;
  std::string err;
  if (ev::writePng(plot, ev::plotTopDown(series, have_floor ? &floor : nullptr, po), &err))
    std::cout << "trajectory plot: " << plot << "\n";
  else
    std::cerr << "slam_benchmark: plot not written: " << err << "\n";

  // The map file as slam/save_map would write it: its size.
  if (map_path.empty())
    map_path = plot.substr(0, plot.rfind('.')) + ".map";
  double map_mb = -1;
  {
    std::string merr;
    if (saveMapFile(map_path, exportMap(*slam), &merr))
    {
      std::ifstream mf(map_path, std::ios::binary | std::ios::ate);
      map_mb = static_cast<double>(mf.tellg()) / (1024.0 * 1024.0);
      std::cout << "map file: " << map_path << " (" << map_mb << " MB)\n";
    }
    else
      std::cerr << "slam_benchmark: " << merr << "\n";
  }
  // Memory: least-squares slope of the resident size against the keyframes (second half of the
  // samples: the start-up allocations are behind).
  double rss_slope = -1;
  {
    const size_t h = rss_samples.size() / 2;
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = h; i < rss_samples.size(); ++i, ++n)
    {
      sx += rss_samples[i].first;
      sy += rss_samples[i].second;
      sxx += rss_samples[i].first * rss_samples[i].first;
      sxy += rss_samples[i].first * rss_samples[i].second;
    }
    if (n >= 3 && n * sxx - sx * sx > 0)
      rss_slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    std::cout << "resident memory: " << (rss_samples.empty() ? 0.0 : rss_samples.back().second) << " MB at "
              << (rss_samples.empty() ? 0.0 : rss_samples.back().first) << " keyframes; slope " << rss_slope * 1024
              << " kB per keyframe (second half of the run)\n";
  }
  auto num = [](double v, int significant = 4) { return ev::jsonNumber(v, significant); };
  // The filter (fastslam): its own per-frame trajectory, whole and per filter submap (between
  // resets), against the VO's on the same frames; SE3-aligned ATE each.
  const FastSlamStats fst = slam->filter() ? slam->filter()->stats() : FastSlamStats();
  double filter_ate = -1, seg_filter = 0, seg_vo = 0;
  int seg_n = 0, seg_better = 0;
  if (!filter_frames.empty())
  {
    ev::Trajectory g, e;
    for (const FilterFrame& ff : filter_frames)
    {
      g.push_back({ff.t, ff.gt});
      e.push_back({ff.t, ff.filter});
    }
    filter_ate = ev::evaluateTrajectory(g, e).ate.rmse;
    for (size_t a = 0; a < filter_frames.size();)
    {
      size_t b = a;
      ev::Trajectory sg, sf, sv;
      while (b < filter_frames.size() && filter_frames[b].segment == filter_frames[a].segment)
      {
        sg.push_back({filter_frames[b].t, filter_frames[b].gt});
        sf.push_back({filter_frames[b].t, filter_frames[b].filter});
        sv.push_back({filter_frames[b].t, filter_frames[b].vo});
        ++b;
      }
      if (sg.size() >= 20)
      {
        const double ef = ev::evaluateTrajectory(sg, sf).ate.rmse, evo = ev::evaluateTrajectory(sg, sv).ate.rmse;
        seg_filter += ef;
        seg_vo += evo;
        ++seg_n;
        seg_better += ef <= evo + 1e-4;
      }
      a = b;
    }
    std::cout << "fastslam: " << fst.particles << " particles, " << fst.landmarks_total << " landmarks, "
              << fst.resamplings << " resamplings, " << fst.resets << " filter submaps, "
              << static_cast<double>(fst.matches_total) / std::max(1, fst.frames) << " matches per frame (of "
              << static_cast<double>(fst.candidates_total) / std::max(1, fst.frames)
              << " candidates); filter ATE " << filter_ate << " m; per filter submap: filter " << seg_filter / std::max(1, seg_n)
              << " m vs VO " << seg_vo / std::max(1, seg_n) << " m (" << seg_better << " of " << seg_n
              << " not worse); active matching: " << fst.refound << " of " << fst.revisits << " revisits re-found, "
              << am_false << " of " << am_checked << " matches > 3 px off the true ray (median " << percentile(am_err, 0.5)
              << " px, p90 " << percentile(am_err, 0.9) << " px)\n";
  }
  ev::JsonLine js;
  js.add("frames", frames)
      .add("ms_p95", num(percentile(ms_added, 0.95)))
      .add("ms_median", num(percentile(ms_added, 0.5)))
      .add("worker_ms_p95", num(percentile(worker_ms, 0.95)))
      .add("ate_rmse_m", num(srep.ate.rmse))
      .add("ate_rmse_online_m", num(orep.ate.rmse))
      .add("vo_ate_rmse_m", num(vrep.ate.rmse))
      .add("drift_deg_per_m", num(srep.drift.drift_deg_per_m, 6))
      .add("vo_drift_deg_per_m", num(vrep.drift.drift_deg_per_m, 6))
      .add("drift_pct", num(srep.drift.drift_pct))
      .add("vo_drift_pct", num(vrep.drift.drift_pct))
      .add("loop_closures", accepted)
      .add("false_loop_closures", false_closures)
      .add("loop_closures_rejected", st.loops_rejected)
      .add("loop_closures_missed", missed)
      .add("revisit_runs", revisit_runs)
      .add("keyframes", st.keyframes)
      .add("keyframes_dropped", st.dropped)
      .add("submaps", st.submaps)
      .add("peak_rss_mb", num(peakRssMb()))
      .add("rss_mb_per_keyframe", rss_slope >= 0 ? num(rss_slope) : "null")
      .add("relocalisation_frames", reloc_frames >= 0 ? num(reloc_frames) : "null")
      .add("relocalisation_err_m", reloc_err_m >= 0 ? num(reloc_err_m) : "null")
      .add("relocalisation_err_deg", reloc_err_deg >= 0 ? num(reloc_err_deg) : "null")
      .add("map_file_mb", map_mb >= 0 ? num(map_mb) : "null")
      .add("path_length_m", num(vrep.path_length_m))
      .add("backend", "\"" + sp.metric_backend + "\"")
      .add("particles", fst.particles)
      .add("landmarks", fst.landmarks_total)
      .add("resamplings", fst.resamplings)
      .add("filter_resets", fst.resets)
      .add("matches_per_frame", fst.frames > 0 ? num(static_cast<double>(fst.matches_total) / fst.frames) : "null")
      .add("map_nodes_peak", static_cast<long>(peak_map_nodes))
      .add("filter_ate_rmse_m", filter_ate >= 0 ? num(filter_ate) : "null")
      .add("submap_ate_m", seg_n > 0 ? num(seg_filter / seg_n) : "null")
      .add("vo_submap_ate_m", seg_n > 0 ? num(seg_vo / seg_n) : "null")
      .add("submaps_scored", seg_n)
      .add("submaps_filter_not_worse", seg_better)
      .add("am_revisits", fst.revisits)
      .add("am_refound_share", fst.revisits > 0 ? num(static_cast<double>(fst.refound) / fst.revisits) : "null")
      .add("am_matches_checked", am_checked)
      .add("am_false_match_rate", am_checked > 0 ? num(static_cast<double>(am_false) / am_checked) : "null");
  std::cout << js.str() << std::endl;
  return 0;
}
