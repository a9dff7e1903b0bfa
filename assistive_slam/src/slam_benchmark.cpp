// slam_benchmark FILE.bag [--no-imu] [--plot OUT.png] [--frames N] [--realtime] [--set name=value ...]
// Runs the VO core (as vo_benchmark does) and the SLAM core on every stereo frame of a bag (no
// roscore), scores the VO alone and SLAM on the same frames against the bag's ground truth, counts
// loop closures (false ones: the verified relative pose disagrees with the truth by > 0.5 m or
// 5 deg; missed ones: runs of keyframes revisiting an older place with no accepted closure), and
// plots the trajectories with the closures marked. Last stdout line: one JSON object.
// --vo-reset-at FRAME [--vo-reset-frames N] [--vo-reset-grey]: a forced VO loss (issue 34) of N
// frames (default 15) from FRAME. By default SLAM gets what the VO's fail-safe publishes after a
// loss: untrusted outputs holding the last trusted position (the rotation goes on, as the gyro
// keeps it), then odom going on from the held position (the walk in between is missing from it);
// the VO itself runs on the real images. --vo-reset-grey instead replaces the images by a plain
// grey (a plain wall filling the view), and the VO does what it does (it coasts on the IMU for up
// to 2.5 s, trusted). Scores how soon and how well SLAM finds the wearer again in its map once the
// texture returns.
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

const char* const kUsage =
    "usage: slam_benchmark FILE.bag [--no-imu] [--plot OUT.png] [--frames N] [--skip N] [--realtime] [--map FILE]\n"
    "                     [--load-map FILE] [--vo-reset-at FRAME [--vo-reset-frames N] [--vo-reset-grey]]\n"
    "                     [--set name=value ...]\n"
    "  VO alone and VO + SLAM on the same frames of a stereo bag; last stdout line: JSON.\n"
    "  --map: where the map is written at the end; --load-map: start from a saved map (relocalisation);\n"
    "  --skip N: the first N frames are not run (e.g. the first loop, mapped by an earlier run).\n"
    "  --vo-reset-at FRAME: a forced VO loss of N frames (--vo-reset-frames, default 15) from FRAME: SLAM gets\n"
    "    the VO fail-safe's output (position held, then odom going on from it); --vo-reset-grey: plain grey\n"
    "    images instead; reset_relocalisation_* score finding the wearer again in the map after it\n"
    "  --set: the SLAM stage's parameters (README table), e.g. --set loop_closure=false\n"
    "  --backend keyframe_ba|fastslam|both: the metric layer (default: metric_backend); both: one run\n"
    "    each on the same frames, JSON keys prefixed keyframe_ba_ and fastslam_\n";

/// The command line of a one-backend run.
struct Options
{
  std::string bag, plot, map_path, load_path, backend, plot_suffix;
  long skip_frames = 0;
  long reset_at = -1, reset_frames = 15;  ///< --vo-reset-at FRAME, --vo-reset-frames N
  bool reset_grey = false;                ///< --vo-reset-grey
  bool imu_on = true, realtime = false;
  long max_frames = -1;
  ev::CommandLine::Sets overrides;

  void addTo(ev::CommandLine& cl)
  {
    cl.positional(&bag, "bag", true)
        .flag("--no-imu", &imu_on, false)
        .flag("--realtime", &realtime)
        .flag("--vo-reset-grey", &reset_grey)
        .text("--plot", &plot)
        .text("--map", &map_path)
        .text("--load-map", &load_path)
        .text("--backend", &backend)
        .text("--plot-suffix", &plot_suffix)
        .count("--skip", &skip_frames, 0L)
        .count("--frames", &max_frames, 0L)
        .count("--vo-reset-at", &reset_at, 0L)
        .count("--vo-reset-frames", &reset_frames, 1L)
        .sets(&overrides);
  }
};

/// fastslam: one frame of the filter's own trajectory (per filter submap, between resets).
struct FilterFrame
{
  double t;
  Eigen::Isometry3d gt, filter, vo;
  int segment;
};

/// --vo-reset-at: the forced loss as SLAM saw it. Errors are relative to the last frame before the
/// loss (the wearer's pose in map then against the truth then): what a goal known in the map right
/// before the loss is off by afterwards.
struct ResetTrack
{
  bool have_before = false;
  Eigen::Isometry3d est_before = Eigen::Isometry3d::Identity(), gt_before = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_map_odom_before = Eigen::Isometry3d::Identity();  ///< map -> odom before the loss
  bool vo_untrusted = false;  ///< the VO lost trust (else it coasted through on the IMU)
  int unplaced_frames = 0;    ///< frames SLAM said it did not know the wearer's place (from the loss on)
  int placed_frame = -1;      ///< the first frame from the texture's return on with the wearer placed
  double err_m = -1, err_deg = -1;              ///< the wearer in map there, against the truth
  double stale_err_m = -1, stale_err_deg = -1;  ///< ... on map -> odom from before the loss (the old behaviour)
  double unseen_m = -1;                         ///< the true motion from the last frame before the loss to there
  // the emulated fail-safe (no --vo-reset-grey)
  bool have_trusted = false;
  Eigen::Vector3d held = Eigen::Vector3d::Zero();            ///< the last trusted camera_link position
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();          ///< odom after the loss = VO's + offset
};

/// The runner: every stereo frame through the device's VO driving loop, then SLAM as its nodelet
/// takes the VO's output; keeps the trajectories, times, memory samples and the filter's matches.
class SlamRun
{
public:
  SlamRun(const Options& opt, const SlamParams& sp, bool input_has_imu);
  /// Runs the frames; false (with the message) when nothing could be scored or the map not loaded.
  bool run(ev::StereoBagReader& reader);
  /// The truth at a frame's stamp (every frame read, skipped ones included).
  bool truthOf(double stamp, Eigen::Isometry3d& T) const
  {
    auto it = gt_at.find(stamp);
    if (it == gt_at.end())
      return false;
    T = it->second;
    return true;
  }

  std::unique_ptr<SlamSystem> slam;
  ev::Trajectory gt, vo_est, online_est;
  std::vector<Eigen::Isometry3d> frame_odom;  // per scored frame: VO pose (for the final SLAM trajectory)
  // fastslam: active matching against the truth, the filter's own trajectory per submap
  std::map<uint32_t, std::pair<Eigen::Isometry3d, Eigen::Vector3d>> am_init;  // landmark -> truth at init, stereo point
  long am_checked = 0, am_false = 0;
  std::vector<double> am_err;  // px, each match against the truth
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
  ResetTrack reset;

  /// --vo-reset-at: the frame is inside the forced loss.
  bool inLoss(long frame) const
  {
    return opt_.reset_at >= 0 && frame >= opt_.reset_at && frame < opt_.reset_at + opt_.reset_frames;
  }
  /// --vo-reset-at without --vo-reset-grey: the VO fail-safe's output around a loss, from the VO's.
  assistive_vo::VoOutput emulateLoss(const assistive_vo::VoOutput& o);

private:
  /// SLAM on the first frame's camera, with --load-map's map; false when the map did not load.
  bool startSlam(const assistive_vo::StereoCamera& cam);
  /// One frame the VO published: SLAM's step, its times, the filter's figures, the trajectories.
  void slamFrame(const ev::StereoFrame& f, const assistive_vo::StereoCamera& cam, const assistive_vo::VoOutput& o);
  /// fastslam: this frame's matches against the truth, and the filter's pose.
  void scoreFilterFrame(const FastSlam& fs, const ev::StereoFrame& f, const assistive_vo::StereoCamera& cam,
                        const assistive_vo::VoOutput& o);
  /// Every 100 frames: the filter's map size and the resident memory.
  void sampleMemory();
  /// --vo-reset-at: the loss and the relocalisation after it, on one frame SLAM has taken.
  void trackReset(const ev::StereoFrame& f, const assistive_vo::VoOutput& o);

  const Options& opt_;
  const SlamParams& sp_;
  assistive_vo::VoFrontEnd fe_;
  VoAdapter adapter_;
};

assistive_vo::VoFrontEnd::Options frontEndOptions(bool input_has_imu)
{
  assistive_vo::VoFrontEnd::Options fo;
  fo.input_has_imu = input_has_imu;
  return fo;
}

assistive_vo::VoParams voParams(bool imu_on)
{
  assistive_vo::VoParams vp;
  vp.use_imu = imu_on;
  return vp;
}

/// The optical frame in camera_link as the URDF has it.
Eigen::Isometry3d linkOptical()
{
  Eigen::Isometry3d T_link_optical = Eigen::Isometry3d::Identity();
  T_link_optical.linear() = assistive_vo::R_link_optical();
  return T_link_optical;
}

// The device's VO driving loop (assistive_vo/vo_front_end.h, as its nodelet runs it). SLAM takes
// the VO's output as the nodelet does (vo_adapter.h): what vo/odom would carry
// (published_odometry.h), the optical frame in camera_link as the URDF has it.
SlamRun::SlamRun(const Options& opt, const SlamParams& sp, bool input_has_imu)
  : opt_(opt), sp_(sp), fe_(voParams(opt.imu_on), frontEndOptions(input_has_imu)),
    adapter_(SlamNodeParams().untrusted_variance, linkOptical())
{
}

bool SlamRun::run(ev::StereoBagReader& reader)
{
  ev::StereoFrame f;
  while ((opt_.max_frames < 0 || frames < opt_.max_frames) && ev::nextFrameOrExit(reader, f, "slam_benchmark", opt_.bag))
  {
    if (skipped < opt_.skip_frames)
    {
      ++skipped;
      if (f.has_gt_pose)
        gt_at[f.stamp] = f.gt_pose;  // the truth of a stored map's keyframes (same bag)
      continue;
    }
    const assistive_vo::StereoCamera cam = assistive_vo::StereoCamera::from(f.calib);
    if (!slam && !startSlam(cam))
      return false;
    if (opt_.reset_grey && inLoss(frames))
    {
      // the forced loss: a plain wall fills the view
      f.left = cv::Mat(f.left.size(), f.left.type(), cv::Scalar::all(128));
      f.right = cv::Mat(f.right.size(), f.right.type(), cv::Scalar::all(128));
    }
    for (const auto& s : f.imu)
      fe_.addImu(s.stamp, s.gyro, s.accel);
    const ev::Stopwatch vo_timer;
    const assistive_vo::FrontEndStep step = fe_.process(cam, f.left, f.right, f.stamp);
    if (!step.processed)  // waiting for the IMU (start-up rule)
    {
      ++frames;
      continue;
    }
    const assistive_vo::VoOutput o = emulateLoss(step.out);
    ms_vo.push_back(vo_timer.cpuMs());

    if (!o.pose_valid || !o.T_odom_link.matrix().allFinite())
    {
      ++frames;  // the nodelet publishes no vo/odom for it: SLAM never sees it
      continue;
    }
    slamFrame(f, cam, o);
    ++frames;
    if (frames % 100 == 0)
      sampleMemory();
  }
  if (!slam || gt.size() < 3)
  {
    std::cerr << "slam_benchmark: no scored frames (no stereo frames or no ground truth) in " << opt_.bag << "\n";
    return false;
  }
  slam->waitIdle();
  return true;
}

bool SlamRun::startSlam(const assistive_vo::StereoCamera& cam)
{
  StereoModel m;
  m.fx = cam.fx;
  m.fy = cam.fy;
  m.cx = cam.cx;
  m.cy = cam.cy;
  m.baseline = cam.baseline;
  slam = std::make_unique<SlamSystem>(sp_, m, true);
  if (opt_.load_path.empty())
    return true;
  MapData md;
  std::string err;
  if (!loadMapFile(opt_.load_path, md, &err) || !slam->loadMap(md, &err))
  {
    std::cerr << "slam_benchmark: map " << opt_.load_path << " not loaded: " << err << "\n";
    return false;
  }
  stored_keyframes = md.keyframes.size();
  for (const Keyframe& k : md.keyframes)
    loaded_poses.push_back(k.T_map_cam);
  std::cerr << "[slam_benchmark] map " << opt_.load_path << ": " << md.keyframes.size() << " keyframes, "
            << md.submaps.size() << " submaps, " << md.places.size() << " places\n";
  return true;
}

void SlamRun::slamFrame(const ev::StereoFrame& f, const assistive_vo::StereoCamera& cam, const assistive_vo::VoOutput& o)
{
  const assistive_vo::PublishedOdometry po = assistive_vo::published(o);
  VoOdometry vo_odom;
  vo_odom.stamp = f.stamp;
  vo_odom.T_odom_link = po.T_odom_link;
  vo_odom.position_variance = po.pose_covariance(0, 0);
  vo_odom.twist_covariance = po.twist_covariance;
  const SlamFrame sf = adapter_.frame(vo_odom, f.left, f.right);
  const ev::Stopwatch timer;
  const bool queued = slam->addFrame(sf);
  const Eigen::Isometry3d T_map_odom = slam->mapToOdom();
  ms_added.push_back(timer.cpuMs());
  if (const FastSlam* fs = slam->filter())
    scoreFilterFrame(*fs, f, cam, o);
  if (queued)
  {
    ++keyframes_queued;
    if (!opt_.realtime)
    {
      slam->waitIdle();
      // the keyframe's work: the worker's and, on its own thread, the loop closer's
      const SlamStats st = slam->stats();
      worker_ms.push_back(st.worker_ms_last + (sp_.loop_closing_thread ? st.loop_ms_last : 0.0));
    }
  }
  if (reloc_frame < 0 && !opt_.load_path.empty() && slam->localised())
    reloc_frame = frames;
  if (opt_.reset_at >= 0)
    trackReset(f, o);

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
}

void SlamRun::scoreFilterFrame(const FastSlam& fs, const ev::StereoFrame& f, const assistive_vo::StereoCamera& cam,
                               const assistive_vo::VoOutput& o)
{
  for (const FastSlamInit& in : fs.lastInits())
    if (f.has_gt_pose)
      am_init[in.landmark] = {f.gt_pose, in.X_cam};
  for (const FastSlamMatch& m : fs.lastMatches())
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
  const bool filtered = fs.stats().frames != filter_frames_seen;  // (untrusted frames are not filtered)
  filter_frames_seen = fs.stats().frames;
  if (f.has_gt_pose && o.pose_valid && filtered)
    filter_frames.push_back({f.stamp, f.gt_pose, fs.pose(), o.T_odom_optical, fs.stats().resets});
}

assistive_vo::VoOutput SlamRun::emulateLoss(const assistive_vo::VoOutput& o)
{
  if (opt_.reset_at < 0 || opt_.reset_grey || !o.pose_valid)
    return o;
  assistive_vo::VoOutput e = o;
  ResetTrack& r = reset;
  if (frames < opt_.reset_at)
  {
    if (o.pose_trusted)
      r.held = o.T_odom_link.translation();
    r.have_trusted = r.have_trusted || o.pose_trusted;
    return e;
  }
  // In the loss: untrusted, the position held (assistive_vo README "Fail-safe"); after it: odom
  // goes on from the position held at the end of the loss.
  if (inLoss(frames))
  {
    r.offset = r.held - o.T_odom_link.translation();
    e.pose_trusted = false;
  }
  e.T_odom_link.translation() += r.offset;
  e.T_odom_optical.translation() += r.offset;
  return e;
}

void SlamRun::trackReset(const ev::StereoFrame& f, const assistive_vo::VoOutput& o)
{
  const Eigen::Isometry3d T_map_odom = slam->mapToOdom();
  const bool placed = slam->localised();
  if (frames < opt_.reset_at)
  {
    if (f.has_gt_pose && o.pose_trusted && placed)
    {
      reset.have_before = true;
      reset.est_before = T_map_odom * o.T_odom_optical;
      reset.gt_before = f.gt_pose;
      reset.T_map_odom_before = T_map_odom;
    }
    return;
  }
  reset.vo_untrusted = reset.vo_untrusted || !o.pose_trusted;
  if (reset.placed_frame >= 0)
    return;
  reset.unplaced_frames += !placed;
  if (inLoss(frames) || !placed || !o.pose_trusted || !f.has_gt_pose || !reset.have_before)
    return;
  reset.placed_frame = frames;
  const Eigen::Isometry3d gt = reset.gt_before.inverse() * f.gt_pose;
  reset.unseen_m = gt.translation().norm();
  const Eigen::Isometry3d d = gt.inverse() * reset.est_before.inverse() * T_map_odom * o.T_odom_optical;
  const Eigen::Isometry3d ds = gt.inverse() * reset.est_before.inverse() * reset.T_map_odom_before * o.T_odom_optical;
  reset.err_m = d.translation().norm();
  reset.err_deg = angDeg(d.linear());
  reset.stale_err_m = ds.translation().norm();
  reset.stale_err_deg = angDeg(ds.linear());
}

void SlamRun::sampleMemory()
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

/// What SLAM holds at the end of the run.
struct SlamEnd
{
  SlamStats st;
  std::vector<Keyframe> kfs, session_kfs;  ///< every keyframe; those of this session (not loaded)
  std::vector<LoopEvent> events;
};

SlamEnd slamEnd(const SlamRun& run)
{
  SlamEnd e;
  e.st = run.slam->stats();
  e.kfs = run.slam->keyframes();
  e.session_kfs.assign(e.kfs.begin() + static_cast<long>(std::min(run.stored_keyframes, e.kfs.size())), e.kfs.end());
  e.events = run.slam->loopEvents();
  return e;
}

/// Final SLAM trajectory: each frame rides on the last keyframe before it (optimised pose).
ev::Trajectory finalTrajectory(const SlamRun& run, const std::vector<Keyframe>& session_kfs)
{
  ev::Trajectory slam_est;
  size_t k = 0;
  for (size_t i = 0; i < run.gt.size(); ++i)
  {
    while (k + 1 < session_kfs.size() && session_kfs[k + 1].stamp <= run.gt[i].t)
      ++k;
    Eigen::Isometry3d T = run.frame_odom[i];
    if (!session_kfs.empty() && session_kfs[k].stamp <= run.gt[i].t)
      T = session_kfs[k].T_map_cam * session_kfs[k].T_odom_cam.inverse() * run.frame_odom[i];
    slam_est.push_back({run.gt[i].t, T});
  }
  return slam_est;
}

/// Loop closures against the truth, and the revisits they should have closed.
struct ClosureScore
{
  int accepted = 0, false_closures = 0;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> closure_lines;  ///< truth positions, for the plot
  std::set<uint32_t> closed_new;
  int revisit_runs = 0, missed = 0;
};

/// The accepted closures against the truth (a line each on stdout; false: > 0.5 m or 5 deg off).
void scoreClosures(const SlamRun& run, const SlamEnd& end, ClosureScore& cs)
{
  for (const LoopEvent& e : end.events)
  {
    if (!e.accepted)
      continue;
    ++cs.accepted;
    Eigen::Isometry3d Ta, Tb;
    if (!run.truthOf(end.kfs[e.keyframe_old].stamp, Ta) || !run.truthOf(end.kfs[e.keyframe_new].stamp, Tb))
      continue;
    const Eigen::Isometry3d T_true = Ta.inverse() * Tb;
    const Eigen::Isometry3d d = T_true.inverse() * e.T_old_new;
    const bool wrong = d.translation().norm() > 0.5 || angDeg(d.linear()) > 5.0;
    cs.false_closures += wrong;
    std::cout << (wrong ? "FALSE " : "") << "loop closure: keyframe " << e.keyframe_new << " (submap "
              << e.submap_new << ") -> " << e.keyframe_old << " (submap " << e.submap_old << "), " << e.inliers
              << " inliers, correction " << std::setprecision(3) << e.correction_m << " m " << e.correction_deg
              << " deg; error vs truth " << d.translation().norm() << " m " << angDeg(d.linear()) << " deg\n";
    cs.closure_lines.push_back({Ta.translation(), Tb.translation()});
    cs.closed_new.insert(e.keyframe_new);
  }
}

// Revisits: keyframes whose true position is within 1 m (view within 30 deg) of a keyframe at
// least 15 m of path earlier; consecutive revisiting keyframes form one run; a run with no
// accepted closure is missed.
void scoreRevisits(const SlamRun& run, const std::vector<Keyframe>& kfs, ClosureScore& cs)
{
  std::vector<Eigen::Isometry3d> kgt(kfs.size());
  std::vector<bool> has(kfs.size(), false);
  for (size_t i = 0; i < kfs.size(); ++i)
    has[i] = run.truthOf(kfs[i].stamp, kgt[i]);
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
        ++cs.revisit_runs;
        run_closed = false;
      }
      in_run = true;
      run_closed = run_closed || cs.closed_new.count(static_cast<uint32_t>(b));
    }
    else if (in_run)
    {
      cs.missed += !run_closed;
      in_run = false;
    }
  }
  if (in_run)
    cs.missed += !run_closed;
}

/// --load-map: how soon and how well the wearer was relocalised (-1: not measured).
struct RelocScore
{
  double frames = -1, err_m = -1, err_deg = -1;
};

// Relocalisation (--load-map): frames from the first one with a stored keyframe in view (truly
// within 1 m and 30 deg; needs the stored keyframes' truth, i.e. the same bag) to the one that
// relocalised, and the error of the relocalised pose in world through the fit of the stored
// keyframes' map poses to their truth.
RelocScore scoreRelocalisation(const SlamRun& run, const SlamEnd& end)
{
  RelocScore r;
  std::vector<Eigen::Isometry3d> stored_gt;
  Eigen::Matrix3Xd a(3, 0), b(3, 0);
  for (size_t i = 0; i < run.stored_keyframes; ++i)
  {
    Eigen::Isometry3d T;
    if (!run.truthOf(end.kfs[i].stamp, T))
      continue;
    stored_gt.push_back(T);
    a.conservativeResize(3, a.cols() + 1);
    b.conservativeResize(3, b.cols() + 1);
    a.col(a.cols() - 1) = run.loaded_poses[i].translation();
    b.col(b.cols() - 1) = T.translation();
  }
  int in_view = stored_gt.empty() ? 0 : -1;
  for (size_t i = 0; i < run.session_truth.size() && in_view < 0; ++i)
    for (const Eigen::Isometry3d& S : stored_gt)
      if ((S.translation() - run.session_truth[i].second.translation()).norm() < 1.0 &&
          angDeg(S.linear().transpose() * run.session_truth[i].second.linear()) < 30.0)
      {
        in_view = static_cast<int>(i);
        break;
      }
  std::cout << "relocalisation: " << (stored_gt.empty() ? "no truth for the stored keyframes (another bag?); " : "")
            << "first stored place in view at session frame " << in_view << ", relocalised at frame " << run.reloc_frame
            << " (" << end.st.relocalisation_queries << " keyframes tried)\n";
  if (run.reloc_frame >= 0 && in_view >= 0)
    r.frames = std::max(0, run.reloc_frame - in_view);
  Eigen::Isometry3d Tt;
  if (end.st.relocalised_stamp >= 0 && a.cols() >= 3 && run.truthOf(end.st.relocalised_stamp, Tt))
  {
    Eigen::Isometry3d A;
    A.matrix() = Eigen::umeyama(a, b, false);
    for (const LoopEvent& e : end.events)
      if (e.relocalisation)
      {
        // the pose the relocalisation gave: the stored keyframe times the verified relative pose
        const Eigen::Isometry3d Tm = A * run.loaded_poses.at(e.keyframe_old) * e.T_old_new;
        r.err_m = (Tm.translation() - Tt.translation()).norm();
        r.err_deg = angDeg(Tm.linear().transpose() * Tt.linear());
      }
    std::cout << "relocalised pose vs truth (world through the fit of the stored keyframes as loaded): " << r.err_m << " m, "
              << r.err_deg << " deg\n";
  }
  return r;
}

/// The three trajectories scored against the truth: VO alone, SLAM final and online.
struct TrajectoryScores
{
  ev::Trajectory gt, vo_est, slam_est, online_est;
  ev::TrajectoryReport vrep, srep, orep;
};

TrajectoryScores scoreTrajectories(const Options& opt, const SlamRun& run, const SlamEnd& end)
{
  TrajectoryScores t{run.gt, run.vo_est, finalTrajectory(run, end.session_kfs), run.online_est, {}, {}, {}};
  if (!opt.load_path.empty() && end.st.relocalised_stamp >= 0)
  {
    // A loaded map: frames before the relocalisation have no map pose; all figures from it on.
    auto from = [&](const ev::Trajectory& tr) {
      ev::Trajectory o;
      for (const auto& p : tr)
        if (p.t >= end.st.relocalised_stamp)
          o.push_back(p);
      return o;
    };
    t.gt = from(t.gt);
    t.vo_est = from(t.vo_est);
    t.slam_est = from(t.slam_est);
    t.online_est = from(t.online_est);
  }
  t.vrep = ev::evaluateTrajectory(t.gt, t.vo_est);
  t.srep = ev::evaluateTrajectory(t.gt, t.slam_est);
  t.orep = ev::evaluateTrajectory(t.gt, t.online_est);
  return t;
}

/// The report's tables: the three trajectories, the times, keyframes and closures.
void printTables(const Options& opt, const SlamRun& run, const SlamEnd& end, const TrajectoryScores& t,
                 const ClosureScore& cs)
{
  const SlamStats& st = end.st;
  std::cout << "assistive_slam benchmark: " << opt.bag << "  (" << run.frames << " frames, " << (opt.imu_on ? "IMU" : "no IMU")
            << ", " << (opt.realtime ? "realtime" : "worker awaited per keyframe") << ")\n";
  std::cout << "--- VO alone vs ground truth ---\n" << ev::reportTable(t.vrep);
  std::cout << "--- SLAM (final, optimised keyframes) vs ground truth ---\n" << ev::reportTable(t.srep);
  std::cout << "--- SLAM (online: map->odom at the time) vs ground truth ---\n" << ev::reportTable(t.orep);
  std::cout << std::fixed << std::setprecision(3) << "frame-loop time added by SLAM: median " << percentile(run.ms_added, 0.5)
            << " ms, p95 " << percentile(run.ms_added, 0.95) << " ms (thread CPU; VO p95 " << percentile(run.ms_vo, 0.95)
            << " ms); worker per keyframe: median " << percentile(run.worker_ms, 0.5) << " ms, p95 "
            << percentile(run.worker_ms, 0.95) << " ms (wall)\n";
  std::cout << "keyframes " << st.keyframes << " (queued " << run.keyframes_queued << ", dropped " << st.dropped
            << "), submaps " << st.submaps << ", local BA runs " << st.ba_runs << " (rejected " << st.ba_rejected << ")" << ", pose-graph runs "
            << st.pose_graph_runs << ", loop closures " << cs.accepted << " accepted (" << cs.false_closures
            << " false), " << st.loops_rejected << " verified but rejected; revisit runs " << cs.revisit_runs
            << ", missed " << cs.missed << "\n";
}

// Plot: truth, VO and SLAM (SE3-aligned like the ATE), closures as green segments (truth positions).
void plotTrajectories(const Options& opt, ev::StereoBagReader& reader, const TrajectoryScores& t, const ClosureScore& cs)
{
  std::vector<ev::PlotSeries> series{{"ground truth", ev::positions(t.gt), cv::Scalar(0, 0, 0)}};
  series.push_back({"VO alone", ev::positions(ev::applyAlignment(t.vo_est, t.vrep.alignment)), cv::Scalar(0, 0, 230)});
  series.push_back({"SLAM", ev::positions(ev::applyAlignment(t.slam_est, t.srep.alignment)), cv::Scalar(230, 120, 0)});
  for (size_t i = 0; i < cs.closure_lines.size(); ++i)
    series.push_back({i == 0 ? "loop closures" : "", {cs.closure_lines[i].first, cs.closure_lines[i].second + Eigen::Vector3d(0.15, 0.15, 0)},
                      cv::Scalar(0, 180, 0)});
  ev::OccupancyGrid floor;
  const bool have_floor = reader.readOccupancy(floor);
  ev::PlotOptions po;
  po.title = "SLAM trajectory (SE3-aligned): " + opt.bag;
  std::string err;
  if (ev::writePng(opt.plot, ev::plotTopDown(series, have_floor ? &floor : nullptr, po), &err))
    std::cout << "trajectory plot: " << opt.plot << "\n";
  else
    std::cerr << "slam_benchmark: plot not written: " << err << "\n";
}

/// The map file as slam/save_map would write it: its size in MB (-1: not written).
double writeMapFile(const SlamRun& run, std::string map_path, const std::string& plot)
{
  if (map_path.empty())
    map_path = plot.substr(0, plot.rfind('.')) + ".map";
  double map_mb = -1;
  std::string merr;
  if (saveMapFile(map_path, exportMap(*run.slam), &merr))
  {
    std::ifstream mf(map_path, std::ios::binary | std::ios::ate);
    map_mb = static_cast<double>(mf.tellg()) / (1024.0 * 1024.0);
    std::cout << "map file: " << map_path << " (" << map_mb << " MB)\n";
  }
  else
    std::cerr << "slam_benchmark: " << merr << "\n";
  return map_mb;
}

// Memory: least-squares slope of the resident size against the keyframes (second half of the
// samples: the start-up allocations are behind). MB per keyframe, -1 when too few samples.
double memorySlope(const std::vector<std::pair<double, double>>& rss_samples)
{
  double rss_slope = -1;
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
  return rss_slope;
}

/// fastslam: the filter's own trajectory against the truth, whole and per filter submap.
struct FilterScore
{
  FastSlamStats fst;
  double filter_ate = -1, seg_filter = 0, seg_vo = 0;
  int seg_n = 0, seg_better = 0;
};

// The filter (fastslam): its own per-frame trajectory, whole and per filter submap (between
// resets), against the VO's on the same frames; SE3-aligned ATE each.
FilterScore scoreFilter(const SlamRun& run)
{
  FilterScore fsc;
  fsc.fst = run.slam->filter() ? run.slam->filter()->stats() : FastSlamStats();
  const std::vector<FilterFrame>& filter_frames = run.filter_frames;
  if (filter_frames.empty())
    return fsc;
  ev::Trajectory g, e;
  for (const FilterFrame& ff : filter_frames)
  {
    g.push_back({ff.t, ff.gt});
    e.push_back({ff.t, ff.filter});
  }
  fsc.filter_ate = ev::evaluateTrajectory(g, e).ate.rmse;
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
      fsc.seg_filter += ef;
      fsc.seg_vo += evo;
      ++fsc.seg_n;
      fsc.seg_better += ef <= evo + 1e-4;
    }
    a = b;
  }
  const FastSlamStats& fst = fsc.fst;
  std::cout << "fastslam: " << fst.particles << " particles, " << fst.landmarks_total << " landmarks, "
            << fst.resamplings << " resamplings, " << fst.resets << " filter submaps, "
            << static_cast<double>(fst.matches_total) / std::max(1, fst.frames) << " matches per frame (of "
            << static_cast<double>(fst.candidates_total) / std::max(1, fst.frames)
            << " candidates); filter ATE " << fsc.filter_ate << " m; per filter submap: filter " << fsc.seg_filter / std::max(1, fsc.seg_n)
            << " m vs VO " << fsc.seg_vo / std::max(1, fsc.seg_n) << " m (" << fsc.seg_better << " of " << fsc.seg_n
            << " not worse); active matching: " << fst.refound << " of " << fst.revisits << " revisits re-found, "
            << run.am_false << " of " << run.am_checked << " matches > 3 px off the true ray (median " << percentile(run.am_err, 0.5)
            << " px, p90 " << percentile(run.am_err, 0.9) << " px)\n";
  return fsc;
}

std::string num(double v, int significant = 4)
{
  return ev::jsonNumber(v, significant);
}

/// --vo-reset-at's line of the report.
void printReset(const Options& opt, const SlamRun& run, const SlamStats& st)
{
  const ResetTrack& r = run.reset;
  const long back = opt.reset_at + opt.reset_frames;
  std::cout << "forced VO loss: frames " << opt.reset_at << "-" << back - 1
            << (opt.reset_grey ? " grey (the VO " : " the VO fail-safe's output (")
            << (r.vo_untrusted ? "untrusted" : "coasted through, trusted") << "); SLAM: " << st.vo_losses
            << " VO losses, " << st.reset_relocalisations << " found again, " << st.reset_gave_up << " given up, " << st.reset_bridged << " bridged, "
            << st.relocalisation_queries << " queries; unplaced on " << r.unplaced_frames << " frames; ";
  if (r.placed_frame < 0)
  {
    std::cout << "not placed again after the texture returned on frame " << back << "\n";
    return;
  }
  std::cout << "placed on frame " << r.placed_frame << " (" << r.placed_frame - back
            << " after the texture returned, " << r.unseen_m << " m from the last frame before the loss): " << r.err_m << " m, " << r.err_deg
            << " deg off the truth since the last frame before the loss (on map -> odom from before the loss: "
            << r.stale_err_m << " m, " << r.stale_err_deg << " deg)\n";
}

/// The keys of --vo-reset-at (null without it, or when not placed again) and the loss counters.
void addResetKeys(const Options& opt, const SlamRun& run, const SlamStats& st, ev::JsonLine& js)
{
  const ResetTrack& r = run.reset;
  const bool on = opt.reset_at >= 0, placed = on && r.placed_frame >= 0;
  js.add("vo_losses", st.vo_losses)
      .add("reset_relocalisations", st.reset_relocalisations)
      .add("reset_gave_up", st.reset_gave_up)
      .add("reset_bridged", st.reset_bridged)
      .add("reset_at_frame", on ? std::to_string(opt.reset_at) : "null")
      .add("reset_frames", on ? std::to_string(opt.reset_frames) : "null")
      .add("reset_mode", on ? (opt.reset_grey ? "\"grey\"" : "\"fail_safe\"") : "null")
      .add("reset_unseen_m", placed ? num(r.unseen_m) : "null")
      .add("reset_vo_untrusted", on ? (r.vo_untrusted ? "true" : "false") : "null")
      .add("reset_unplaced_frames", on ? std::to_string(r.unplaced_frames) : "null")
      .add("reset_relocalisation_frames", placed ? std::to_string(r.placed_frame - opt.reset_at - opt.reset_frames) : "null")
      .add("reset_relocalisation_err_m", placed ? num(r.err_m) : "null")
      .add("reset_relocalisation_err_deg", placed ? num(r.err_deg) : "null")
      .add("reset_stale_err_m", placed ? num(r.stale_err_m) : "null")
      .add("reset_stale_err_deg", placed ? num(r.stale_err_deg) : "null");
}

/// The JSON line's keys from fastslam (the filter, its map, active matching); null / 0 for keyframe_ba.
void addFilterKeys(const SlamRun& run, const FilterScore& fsc, ev::JsonLine& js)
{
  const FastSlamStats& fst = fsc.fst;
  js.add("particles", fst.particles)
      .add("landmarks", fst.landmarks_total)
      .add("resamplings", fst.resamplings)
      .add("filter_resets", fst.resets)
      .add("matches_per_frame", fst.frames > 0 ? num(static_cast<double>(fst.matches_total) / fst.frames) : "null")
      .add("map_nodes_peak", static_cast<long>(run.peak_map_nodes))
      .add("filter_ate_rmse_m", fsc.filter_ate >= 0 ? num(fsc.filter_ate) : "null")
      .add("submap_ate_m", fsc.seg_n > 0 ? num(fsc.seg_filter / fsc.seg_n) : "null")
      .add("vo_submap_ate_m", fsc.seg_n > 0 ? num(fsc.seg_vo / fsc.seg_n) : "null")
      .add("submaps_scored", fsc.seg_n)
      .add("submaps_filter_not_worse", fsc.seg_better)
      .add("am_revisits", fst.revisits)
      .add("am_refound_share", fst.revisits > 0 ? num(static_cast<double>(fst.refound) / fst.revisits) : "null")
      .add("am_matches_checked", run.am_checked)
      .add("am_false_match_rate", run.am_checked > 0 ? num(static_cast<double>(run.am_false) / run.am_checked) : "null");
}

/// The run's resources: memory, the map file.
struct Resources
{
  double rss_slope = -1, map_mb = -1;
};

/// The last stdout line (docs/design.md: its keys are read by others).
ev::JsonLine jsonLine(const Options& opt, const SlamParams& sp, const SlamRun& run, const SlamEnd& end, const TrajectoryScores& t,
                      const ClosureScore& cs, const RelocScore& reloc, const Resources& res, const FilterScore& fsc)
{
  const SlamStats& st = end.st;
  ev::JsonLine js;
  js.add("frames", run.frames)
      .add("ms_p95", num(percentile(run.ms_added, 0.95)))
      .add("ms_median", num(percentile(run.ms_added, 0.5)))
      .add("worker_ms_p95", num(percentile(run.worker_ms, 0.95)))
      .add("ate_rmse_m", num(t.srep.ate.rmse))
      .add("ate_rmse_online_m", num(t.orep.ate.rmse))
      .add("vo_ate_rmse_m", num(t.vrep.ate.rmse))
      .add("drift_deg_per_m", num(t.srep.drift.drift_deg_per_m, 6))
      .add("vo_drift_deg_per_m", num(t.vrep.drift.drift_deg_per_m, 6))
      .add("drift_pct", num(t.srep.drift.drift_pct))
      .add("vo_drift_pct", num(t.vrep.drift.drift_pct))
      .add("loop_closures", cs.accepted)
      .add("false_loop_closures", cs.false_closures)
      .add("loop_closures_rejected", st.loops_rejected)
      .add("loop_closures_missed", cs.missed)
      .add("revisit_runs", cs.revisit_runs)
      .add("keyframes", st.keyframes)
      .add("keyframes_dropped", st.dropped)
      .add("submaps", st.submaps)
      .add("peak_rss_mb", num(peakRssMb()))
      .add("rss_mb_per_keyframe", res.rss_slope >= 0 ? num(res.rss_slope) : "null")
      .add("relocalisation_frames", reloc.frames >= 0 ? num(reloc.frames) : "null")
      .add("relocalisation_err_m", reloc.err_m >= 0 ? num(reloc.err_m) : "null")
      .add("relocalisation_err_deg", reloc.err_deg >= 0 ? num(reloc.err_deg) : "null")
      .add("map_file_mb", res.map_mb >= 0 ? num(res.map_mb) : "null")
      .add("path_length_m", num(t.vrep.path_length_m))
      .add("backend", "\"" + sp.metric_backend + "\"");
  addFilterKeys(run, fsc, js);
  addResetKeys(opt, run, st, js);
  return js;
}
}  // namespace

int main(int argc, char** argv)
{
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--backend" && std::string(argv[i + 1]) == "both")
      return runBoth(argc, argv);
  Options opt;
  ev::CommandLine cl("slam_benchmark", kUsage);
  opt.addTo(cl);
  if (const int rc = cl.parse(argc, argv); rc >= 0)
    return rc;
  if (opt.plot.empty())
  {
    const size_t dot = opt.bag.rfind(".bag");
    opt.plot = (dot == std::string::npos ? opt.bag : opt.bag.substr(0, dot)) + "_slam_trajectory" + opt.plot_suffix + ".png";
  }
  cv::setNumThreads(1);
  SlamParams sp;
  if (!ev::applySets(cl, opt.overrides, sp))
    return 2;
  if (!opt.backend.empty())
    sp.metric_backend = opt.backend;
  if (sp.metric_backend != "keyframe_ba" && sp.metric_backend != "fastslam")
  {
    std::cerr << "slam_benchmark: unknown backend " << sp.metric_backend << " (keyframe_ba | fastslam | both)\n";
    return 2;
  }
  const std::unique_ptr<ev::StereoBagReader> reader = ev::openStereoBag("slam_benchmark", opt.bag);
  if (!reader)
    return 1;

  SlamRun run(opt, sp, !reader->imuSamples().empty());
  if (!run.run(*reader))
    return 1;

  // ---- scores and report ----
  const SlamEnd end = slamEnd(run);
  ClosureScore cs;
  scoreClosures(run, end, cs);
  scoreRevisits(run, end.kfs, cs);
  const RelocScore reloc = opt.load_path.empty() ? RelocScore() : scoreRelocalisation(run, end);
  const TrajectoryScores t = scoreTrajectories(opt, run, end);
  printTables(opt, run, end, t, cs);
  plotTrajectories(opt, *reader, t, cs);
  Resources res;
  res.map_mb = writeMapFile(run, opt.map_path, opt.plot);
  res.rss_slope = memorySlope(run.rss_samples);
  const FilterScore fsc = scoreFilter(run);
  if (opt.reset_at >= 0)
    printReset(opt, run, end.st);
  std::cout << jsonLine(opt, sp, run, end, t, cs, reloc, res, fsc).str() << std::endl;
  return 0;
}
