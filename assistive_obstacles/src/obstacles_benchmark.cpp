// rosrun assistive_obstacles obstacles_benchmark FILE.bag [--frames N] [--png OUT.png] [--skip N]
//   several bags or --generated N [--kinds K,...] [--imperfect] [--keep DIR]: the set run
//   (assistive_eval/bench_set.h): per-bag rows, mean and worst (bag named); --png is then a folder.
// Replays a stereo bag through the obstacle stage's core (no roscore) with the GROUND-TRUTH camera
// poses of the bag, so the map is scored independently of VO. Per frame: dense disparity, points,
// elevation + MLS + temporal update (timed separately); the map is scored against the bag's
// ground-truth occupancy within 3 m and 5 m of the wearer at every frame (counts summed over
// frames). Writes a PNG of the scored map at the last frame. Last stdout line: one JSON object.
// --gt-depth feeds the bag's /ground_truth/left/depth (render_bag --depth) instead of SGBM, which
// separates stereo errors from mapping errors. Diagnostics on stderr (environment variables):
// OBST_DEBUG=1 temporal counters of the false-positive cells at the last frame; OBST_CELL=gx,gy
// per-frame label and heights of one global cell; OBST_FPMAP=1 the most frequent false-positive and
// false-negative cells within 3 m; OBST_BIAS=1 per-frame SGBM disparity error vs
// the true depth (needs a --depth bag), binned by metre of depth; OBST_SONAR=1 each fused echo.
// The vest's forward ranger (/sonar/front, sensor_msgs/Range) is fused as the nodelet does it
// (readings stamped up to a frame are added before that frame's update; the ranger's pose = the
// ground-truth camera pose, interpolated, times the URDF mount); --no-sonar leaves it out.
// --world auto|none|W (default auto: <stem>.yaml beside the bag, else the shipped world of the
// bag's stem; W a shipped world's name or a YAML path) scores partly covered cells neither way and
// adds free_where_glass_cells (distinct glass-pane cells ever reported free within 5 m) and the
// ranger's hits on glass.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <array>
#include <map>
#include <set>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <assistive_eval/bench_set.h>
#include <assistive_eval/benchmark.h>
#include <assistive_eval/map_score.h>
#include <assistive_eval/plots.h>
#include <assistive_eval/stereo_bag.h>
#include <assistive_description/stereo_self_calibration.h>

#include <assistive_common/crossing_predictor.h>
#include <assistive_obstacles/frame_processor.h>
#include <assistive_obstacles/people_score.h>

#include <assistive_msgs/MoverArray.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#ifdef HAVE_ASSISTIVE_SIM
#include <filesystem>

#include <assistive_sim/ultrasonic.h>
#include <assistive_sim/world.h>
#endif

#include <opencv2/imgproc.hpp>

using namespace assistive_obstacles;
using assistive_common::CrossingPrediction;
using assistive_common::CrossingPredictor;
using assistive_common::Wearer;
namespace eval = assistive_eval;

namespace
{
struct Sum
{
  size_t tp = 0, fp = 0, fn = 0, tn = 0, unknown = 0, known = 0;
  eval::MapScore last;
  void add(const eval::MapScore& s)
  {
    last = s;
    tp += s.tp;
    fp += s.fp;
    fn += s.fn;
    tn += s.tn;
    unknown += s.est_unknown;
    known += s.gt_known;
  }
  double precision() const { return tp + fp ? static_cast<double>(tp) / (tp + fp) : NAN; }
  double recall() const { return tp + fn ? static_cast<double>(tp) / (tp + fn) : NAN; }
  double misclassified() const
  {
    const size_t n = tp + fp + fn + tn;
    return n ? static_cast<double>(fp + fn) / n : NAN;
  }
  double coverage() const { return known ? static_cast<double>(tp + fp + fn + tn) / known : NAN; }
};
/// The simulator's people truth (/ground_truth/people, assistive_msgs/MoverArray in gt_world, the
/// frame of the bag's truth poses and grid): stamp -> people. Empty when the bag has none.
std::vector<std::pair<double, std::vector<PersonState>>> readPeople(const std::string& bag)
{
  std::vector<std::pair<double, std::vector<PersonState>>> out;
  try
  {
    rosbag::Bag b(bag, rosbag::bagmode::Read);
    rosbag::View v(b, rosbag::TopicQuery("/ground_truth/people"));
    for (const rosbag::MessageInstance& m : v)
    {
      const auto msg = m.instantiate<assistive_msgs::MoverArray>();
      if (!msg) continue;
      std::vector<PersonState> ps;
      for (const assistive_msgs::Mover& mv : msg->movers)
      {
        PersonState q;
        q.id = static_cast<int>(mv.id);
        q.position = Eigen::Vector2d(mv.position.x, mv.position.y);
        q.velocity = Eigen::Vector2d(mv.velocity.x, mv.velocity.y);
        q.radius = mv.radius;
        q.age = mv.position.z + 0.5 * (mv.height > 0 ? mv.height : 1.7);  // (truth: age unused) body centre height
        ps.push_back(q);
      }
      out.emplace_back(msg->header.stamp.toSec(), ps);
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "obstacles_benchmark: people truth: " << e.what() << "\n";
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return out;
}

/// The people truth nearest to `t` (within 50 ms), or nullptr.
const std::vector<PersonState>* peopleAt(const std::vector<std::pair<double, std::vector<PersonState>>>& people, double t)
{
  auto it = std::lower_bound(people.begin(), people.end(), t, [](const auto& a, double v) { return a.first < v; });
  const std::vector<PersonState>* best = nullptr;
  double bd = 0.05;
  for (auto c : {it, it == people.begin() ? it : it - 1})
    if (c != people.end() && std::abs(c->first - t) <= bd)
    {
      bd = std::abs(c->first - t);
      best = &c->second;
    }
  return best;
}

/// Ground-truth pose (left optical frame) at `t`, interpolated between the two nearest samples.
bool poseAt(const std::vector<std::pair<double, Eigen::Isometry3d>>& gt, double t, Eigen::Isometry3d& out)
{
  if (gt.empty() || t < gt.front().first - 0.1 || t > gt.back().first + 0.1) return false;
  auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const auto& a, double v) { return a.first < v; });
  if (it == gt.begin() || it == gt.end())
  {
    out = (it == gt.end() ? gt.back() : gt.front()).second;
    return true;
  }
  const auto& b = *it;
  const auto& a = *(it - 1);
  const double u = b.first > a.first ? (t - a.first) / (b.first - a.first) : 0.0;
  if (b.first - a.first > 0.5) return false;  // a gap: no pose to trust
  out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(a.second.linear()).slerp(u, Eigen::Quaterniond(b.second.linear())).toRotationMatrix();
  out.translation() = (1.0 - u) * a.second.translation() + u * b.second.translation();
  return true;
}

/// The world file behind a bag: `arg` a path, "none", or "auto" (`<stem>.yaml` beside the bag, else
/// the shipped world named by the bag's stem, e.g. course.bag -> course). "" when none.
std::string worldFor(const std::string& arg, const std::string& bag)
{
#ifdef HAVE_ASSISTIVE_SIM
  namespace fs = std::filesystem;
  if (arg == "none") return "";
  if (arg != "auto")
  {
    try
    {
      return assistive_sim::resolveWorldPath(arg, ASSISTIVE_SIM_WORLDS_DIR);  // a path or a shipped name
    }
    catch (const std::exception& e)
    {
      std::cerr << "obstacles_benchmark: --world: " << e.what() << "\n";
      return "";
    }
  }
  const fs::path b(bag);
  const fs::path beside = b.parent_path() / (b.stem().string() + ".yaml");
  if (fs::exists(beside)) return beside.string();
  const fs::path shipped = fs::path(ASSISTIVE_SIM_WORLDS_DIR) / (b.stem().string() + ".yaml");
  if (fs::exists(shipped)) return shipped.string();
#else
  (void)arg;
  (void)bag;
#endif
  return "";
}

#ifdef HAVE_ASSISTIVE_SIM
/// Partial-cell (exclude) and glass masks of the world's truth grid at `op`'s cell.
void masksFromWorld(const assistive_sim::World& w, const assistive_sim::OccupancyParams& op, double partial_depth,
                    std::vector<uint8_t>& exclude, std::vector<uint8_t>& glass)
{
  const std::vector<uint8_t> f = assistive_sim::computeOccupancyDetail(w, op, partial_depth);
  exclude.resize(f.size());
  glass.resize(f.size());
  for (size_t i = 0; i < f.size(); ++i)
  {
    exclude[i] = (f[i] & (assistive_sim::DETAIL_PARTIAL | assistive_sim::DETAIL_NEAR)) ? 1 : 0;
    glass[i] = (f[i] & assistive_sim::DETAIL_GLASS) ? 1 : 0;
  }
}
#endif

/// Partial-cell (exclude) and glass masks of the truth grid from the world's solids; false (masks
/// empty) when there is no world or its grid does not match the bag's truth.
bool worldMasks(const std::string& path, const eval::OccupancyGrid& truth, double partial_depth,
                std::vector<uint8_t>& exclude, std::vector<uint8_t>& glass, double* eye_height)
{
  exclude.clear();
  glass.clear();
  *eye_height = NAN;
#ifdef HAVE_ASSISTIVE_SIM
  if (path.empty()) return false;
  try
  {
    const assistive_sim::World w = assistive_sim::World::load(path);
    *eye_height = w.trajectory.eye_height;
    assistive_sim::OccupancyParams op;
    op.resolution = truth.resolution;
    const assistive_sim::OccupancyGrid g = assistive_sim::computeOccupancy(w, op);
    if (g.width != truth.width || g.height != truth.height || g.data != truth.data ||
        std::abs(g.origin_x - truth.origin_x) > 1e-6 || std::abs(g.origin_y - truth.origin_y) > 1e-6)
    {
      std::cerr << "obstacles_benchmark: world " << path << " does not give the bag's truth grid: partial cells not scored apart\n";
      return false;
    }
    masksFromWorld(w, op, partial_depth, exclude, glass);
    return true;
  }
  catch (const std::exception& e)
  {
    std::cerr << "obstacles_benchmark: world " << path << ": " << e.what() << "\n";
  }
#else
  (void)path;
  (void)truth;
  (void)partial_depth;
#endif
  return false;
}

/// The truth at the map's cell when the bag's truth is at another: the world's solids rasterised
/// again at `cell` (with their partial-cell and glass masks), so that a map run at any `cell_size`
/// is scored cell for cell from one bag. Only when the world gives the bag's own truth grid (the
/// masks were found), else the bag's truth stays and a warning says the figures mix cell sizes.
void truthAtCell(const std::string& path, double cell, double partial_depth, eval::OccupancyGrid& truth,
                 std::vector<uint8_t>& exclude, std::vector<uint8_t>& glass, bool have_world)
{
  if (std::abs(cell - truth.resolution) < 1e-6) return;  // float32 in nav_msgs/MapMetaData
  if (!have_world)
  {
    std::cerr << "obstacles_benchmark: the map's cell " << cell << " m is not the bag's truth cell " << truth.resolution
              << " m and no world gives the truth at it: cells scored by their centres across sizes\n";
    return;
  }
#ifdef HAVE_ASSISTIVE_SIM
  const assistive_sim::World w = assistive_sim::World::load(path);
  assistive_sim::OccupancyParams op;
  op.resolution = cell;
  truth = assistive_sim::computeOccupancy(w, op);
  masksFromWorld(w, op, partial_depth, exclude, glass);
  std::cerr << "obstacles_benchmark: truth rasterised from " << path << " at the map's cell " << cell << " m\n";
#else
  (void)path;
  (void)partial_depth;
  (void)exclude;
  (void)glass;
#endif
}

const char* const kUsage =
    "usage: obstacles_benchmark FILE.bag [--frames N] [--png OUT.png] [--skip N] [--gt-depth] [--passive] [--set PARAM=VALUE ...]\n"
    "                           [--no-sonar] [--world auto|none|W.yaml] [--partial-depth M] [--mover-poses FILE]\n"
    "                           [--self-calibrate]\n"
    "       obstacles_benchmark BAG BAG... | --generated N [--kinds office,lobby,...] [--frames F] [--imperfect]\n"
    "                           [--keep DIR] [--png DIR] [other options as above]\n"
    "  Runs the obstacle stage on a stereo bag with ground truth; last stdout line: JSON.\n"
    "  A bag with an active camera's emitter-on pairs (/stereo/projected) is mapped from those, unless --passive.\n"
    "  A set (several bags, or worlds seeds 1..N made by generate_world and render_bag): per-bag rows,\n"
    "  mean and worst of each figure (worst bag named); JSON keys <key>_mean, <key>_worst, <key>_worst_bag.\n"
    "  --self-calibrate: the right images corrected by the camera driver's online estimate of the right\n"
    "  camera's rotation (issue 36), as the device does; the estimate and the bag's truth are printed.\n";

/// The command line of a one-bag run.
struct Options
{
  std::string bag;
  int max_frames = -1, skip = 0;
  bool gt_depth = false;  // --gt-depth: feed the bag's true depth instead of SGBM (isolates stereo noise)
  // --passive: the emitter-off pairs even when the bag has the projector's emitter-on pairs (issue
  // 35: a passive vs active comparison on one bag); without it those are what the map is built from
  bool passive = false;
  bool projected = false;  // (set from the bag: the emitter-on pairs are read)
  eval::CommandLine::Sets overrides;  // --set name=value (tuning; the figures of record use the defaults)
  std::string png;
  bool no_sonar = false;           // --no-sonar: leave the bag's /sonar/front out
  bool self_calibrate = false;     // --self-calibrate: the driver's right-camera rotation estimate applied
  std::string world_arg = "auto";  // --world: partial-cell and glass scoring from the world's solids
  double partial_depth = 0.05;     // --partial-depth: m an obstacle may reach into a cell and leave it unscored
  // --mover-poses: the scene flow's ego-motion from these poses (vo_benchmark --dump rows: the VO's
  // left optical frame per image, as the chain's tf gives it) instead of the truth; the map stays on
  // the truth, so that its figures stay comparable
  std::string mover_poses_path;

  void addTo(eval::CommandLine& cl)
  {
    cl
        .flag("--gt-depth", &gt_depth)
        .flag("--passive", &passive)
        .flag("--no-sonar", &no_sonar)
        .flag("--self-calibrate", &self_calibrate)
        .count("--frames", &max_frames, 0)
        .count("--skip", &skip, 0)
        .text("--png", &png)
        .text("--world", &world_arg)
        .number("--partial-depth", &partial_depth)
        .text("--mover-poses", &mover_poses_path)
        .sets(&overrides);
  }
};

/// The set run (several bags or --generated): this program once per bag, per-bag rows, mean and worst.
int runSet(const eval::CommandLine& cl, int argc, char** argv, const eval::SetOptions& set_options, const Options& opt)
{
  // Worst = the smaller where more is better (recall, precision, coverage), else the larger.
  const std::vector<eval::SetFigure> figures{
      {"recall_3m", true}, {"precision_3m", true}, {"free_where_obstacle_cells", false, true},
      {"free_where_glass_cells", false, true}, {"free_where_obstacle_cells_strict", false, true},
      {"recall_3m_strict", true}, {"precision_3m_strict", true},
      {"misclassified_3m"}, {"recall_5m", true}, {"precision_5m", true}, {"coverage_3m", true},
      {"ms_p95_map"}, {"ms_p95_disparity"}, {"points_per_frame", true}, {"frames", true}};
  return eval::runSetFromCommandLine(cl, argc, argv, set_options, figures, "--png", opt.png, "_obstacles_map.png",
                                     opt.max_frames);
}

/// The bag's truth: the occupancy grid and, from the world's solids, the partial-cell and glass masks.
struct Truth
{
  eval::OccupancyGrid grid;
  bool has_truth = false;
  std::vector<uint8_t> exclude_mask, glass_mask;
  double eye_height = NAN;  ///< the world walk's camera height
  bool partial_scoring = false;
  std::vector<Eigen::Vector2d> glass_cells;  ///< glass-pane cells of the world (their centres)
};

Truth readTruth(const Options& opt, eval::StereoBagReader& reader)
{
  Truth t;
  eval::OccupancyGrid& truth = t.grid;
  t.has_truth = reader.readOccupancy(truth);
  if (!t.has_truth) std::cerr << "obstacles_benchmark: no /ground_truth/occupancy in the bag: map not scored\n";
  const std::string world_path = t.has_truth ? worldFor(opt.world_arg, opt.bag) : "";
  t.partial_scoring = worldMasks(world_path, truth, opt.partial_depth, t.exclude_mask, t.glass_mask, &t.eye_height);
  if (t.partial_scoring) std::cerr << "obstacles_benchmark: partial cells from " << world_path << "\n";
  // The map's cell (--set cell_size=...) before the stage's parameters are set, which need the truth's
  // eye height (quietly: main applies the sets again and reports their errors and clamps)
  ObstaclesParams cell_params;
  std::string err;
  std::vector<std::string> clamped;
  if (t.has_truth && assistive_common::applyOverrides(cell_params, opt.overrides, &err, &clamped))
    truthAtCell(world_path, cell_params.cell_size, opt.partial_depth, truth, t.exclude_mask, t.glass_mask,
                t.partial_scoring);
  // Glass-pane cells of the world (their centres), for the ranger's hits on glass.
  for (size_t i = 0; i < t.glass_mask.size(); ++i)
    if (t.glass_mask[i])
      t.glass_cells.push_back({truth.origin_x + (static_cast<double>(i % truth.width) + 0.5) * truth.resolution,
                               truth.origin_y + (static_cast<double>(i / truth.width) + 0.5) * truth.resolution});
  return t;
}

/// The vest's forward ranger in the bag, and its mount (camera_link -> sonar_front, URDF).
struct Ranger
{
  std::vector<eval::RangeSample> ranges;
  Eigen::Isometry3d link_to_sonar = Eigen::Isometry3d::Identity();
};

Ranger readRanger(const Options& opt, eval::StereoBagReader& reader)
{
  Ranger r;
  bool sonar_pose = false;
#ifdef HAVE_ASSISTIVE_SIM
  r.link_to_sonar = assistive_sim::linkToSonar();
  sonar_pose = true;
#endif
  if (!opt.no_sonar)
  {
    if (!reader.readRanges(r.ranges)) std::cerr << "obstacles_benchmark: no /sonar/front in the bag: map without the ranger\n";
    if (!sonar_pose && !r.ranges.empty())
    {
      std::cerr << "obstacles_benchmark: built without assistive_sim (the ranger's mount): map without the ranger\n";
      r.ranges.clear();
    }
  }
  return r;
}

/// --mover-poses: stamp in microseconds -> pose (the estimate of vo_benchmark --dump rows).
std::map<long, Eigen::Isometry3d> readMoverPoses(const std::string& path)
{
  std::map<long, Eigen::Isometry3d> mover_poses;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream row(line);
    double t, v[17];  // stamp, then state keyframe inliers, gt x y z qx qy qz qw, estimate x y z qx qy qz qw
    if (!(row >> t)) continue;
    bool ok = true;
    for (double& x : v) ok = ok && static_cast<bool>(row >> x);
    if (!ok) continue;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(v[10], v[11], v[12]);
    T.linear() = Eigen::Quaterniond(v[16], v[13], v[14], v[15]).normalized().toRotationMatrix();
    mover_poses[std::lround(t * 1e6)] = T;
  }
  std::cerr << "obstacles_benchmark: " << mover_poses.size() << " mover poses from " << path << "\n";
  return mover_poses;
}

/// True depth -> disparity at the matcher's scale `sc` (nearest-neighbour downsampling).
cv::Mat trueDisparity(const cv::Mat& gt_depth, const StereoModel& model, double sc)
{
  cv::Mat true_disp;
  cv::Mat z;
  cv::resize(gt_depth, z, cv::Size(), sc, sc, cv::INTER_NEAREST);
  true_disp.create(z.size(), CV_32F);
  const float k = static_cast<float>(model.fx * sc * model.baseline);
  for (int v = 0; v < z.rows; ++v)
    for (int u = 0; u < z.cols; ++u)
    {
      const float zz = z.at<float>(v, u);
      true_disp.at<float>(v, u) = zz > 0.f ? k / zz : -1.f;
    }
  return true_disp;
}

// ------------------------------------------------------------------------------ diagnostics (stderr)
/// OBST_BIAS: disparity error vs the true depth (matcher's scale), binned by true depth.
void printDisparityBias(const cv::Mat& gt_depth, const cv::Mat& disp, const StereoModel& model, int frames)
{
  const double sc = static_cast<double>(disp.cols) / model.width;
  cv::Mat z;
  cv::resize(gt_depth, z, disp.size(), 0, 0, cv::INTER_NEAREST);
  const double k = model.fx * sc * model.baseline;
  std::vector<std::vector<float>> err(6);
  for (int v = 0; v < z.rows; ++v)
    for (int u = 0; u < z.cols; ++u)
    {
      const float zz = z.at<float>(v, u), d = disp.at<float>(v, u);
      if (zz > 0.f && d > 0.f && zz < 6.f) err[static_cast<int>(zz)].push_back(d - static_cast<float>(k / zz));
    }
  std::fprintf(stderr, "bias frame %d:", frames);
  for (auto& e : err)
    if (e.size() > 50)
    {
      std::sort(e.begin(), e.end());
      std::fprintf(stderr, " [%zu] med %.3f p10 %.3f p90 %.3f;", e.size(), e[e.size() / 2], e[e.size() / 10], e[e.size() * 9 / 10]);
    }
    else
      std::fprintf(stderr, " - ;");
  std::fprintf(stderr, "\n");
}

/// OBST_SONAR: each echo fused this frame.
void printSonar(const std::vector<AppliedRange>& ranges)
{
  for (const AppliedRange& a : ranges)
  {
    if (a.check != RangeCheck::ECHO) continue;
    const SonarStats& ss = a.stats;
    const Eigen::Vector3f o = a.T_world_sensor.translation(), ax = a.T_world_sensor.linear().col(0);
    std::fprintf(stderr, "sonar t %.2f r %.2f at (%.2f %.2f %.2f) dir (%.2f %.2f %.2f): floor %d explained %d arc %d held %zu\n",
                 a.sample.stamp, a.sample.range, o.x(), o.y(), o.z(), ax.x(), ax.y(), ax.z(), int(ss.floor_ambiguous),
                 int(ss.explained), ss.arc_cells, ss.held);
  }
}

/// OBST_MOVERS=1: per frame, the pipeline's timing and its detections / confirmed tracks.
void printMovers(const MoverPipeline& movers, double stamp)
{
  std::fprintf(stderr, "movers t %.2f ms flow %.2f seg %.2f trk %.3f flow %zu det %zu:", stamp, movers.msFlow(),
               movers.msSegmentation(), movers.msTracking(), movers.flow().size(), movers.detections().size());
  for (const MoverDetection& d : movers.detections())
    std::fprintf(stderr, " (%.2f %.2f n%d r%.2f z%.2f-%.2f d%.3f,%.3f)", d.centroid.x(), d.centroid.y(), d.points, d.radius,
                 d.min_z, d.max_z, d.displacement.x(), d.displacement.y());
  for (const ReportedMover& r : movers.confirmed())
    std::fprintf(stderr, " [#%d %.2f %.2f v %.2f %.2f]", r.track.id, r.track.x(0), r.track.x(1), r.track.x(2), r.track.x(3));
  std::fprintf(stderr, "\n");
}

/// OBST_UNMATCHED: reported tracks within the scoring radius matched to no one, with the nearest truth person.
void printUnmatched(const std::vector<PersonState>& truth, const std::vector<PersonState>& est, const PeopleFrameScore& ps,
                    const Eigen::Vector2d& wearer, double stamp, double radius)
{
  for (const PersonState& q : est)
  {
    if (ps.track_to_truth.count(q.id) || (q.position - wearer).norm() > radius) continue;
    double best = 1e9;
    int who = 0;
    for (const PersonState& p : truth)
      if ((p.position - q.position).norm() < best)
      {
        best = (p.position - q.position).norm();
        who = p.id;
      }
    std::fprintf(stderr, "unmatched t %.2f track %d at %.2f %.2f v %.2f %.2f age %.2f; nearest person %d at %.2f m\n", stamp,
                 q.id, q.position.x(), q.position.y(), q.velocity.x(), q.velocity.y(), q.age, who, best);
  }
}

/// OBST_PEOPLE_PTS: per frame, the stage's depth points on each walking person (within its radius
/// + 0.1 m, 0.5-2.0 m above the feet): whether stereo saw them at all.
void printPeoplePoints(const std::vector<PersonState>& truth, const std::vector<Eigen::Vector3f>& world_points,
                       const Eigen::Vector2d& wearer, double stamp, double feet, const Eigen::Isometry3d& T_world_cam,
                       const StereoModel& model, const std::map<int, int>& track_to_truth)
{
  std::set<int> matched;
  for (const auto& kv : track_to_truth) matched.insert(kv.second);
  std::fprintf(stderr, "ppts t %.2f", stamp);
  for (const PersonState& q : truth)
  {
    if (q.velocity.norm() < 0.3) continue;
    int n = 0;
    for (const Eigen::Vector3f& p : world_points)
      n += (p.head<2>().cast<double>() - q.position).norm() < q.radius + 0.1 && p.z() > feet + 0.5 && p.z() < feet + 2.0;
    const Eigen::Vector3d c = T_world_cam.inverse() * Eigen::Vector3d(q.position.x(), q.position.y(), q.age);
    const double u = c.z() > 0.3 ? model.fx * c.x() / c.z() + model.cx : -1.0;
    std::fprintf(stderr, " p%d d%.1f n%d u%.0f %s", q.id, (q.position - wearer).norm(), n, u, matched.count(q.id) ? "M" : "-");
  }
  std::fprintf(stderr, "\n");
}

/// OBST_FLOWDUMP=T0:T1: per frame in [T0, T1], every clustered moving point: pixels then and now,
/// depths, the pixel a static point would have now, residual along / across the ray (m),
/// the 3x3 / 5x5 / 7x7 disparity ranges (matcher px) around each end.
void printFlow(const char* fd, const MoverPipeline& movers, const cv::Mat& disp, const StereoModel& model, double stamp,
               const Eigen::Isometry3d& ego)
{
  double ta = 0, tb = 0;
  std::sscanf(fd, "%lf:%lf", &ta, &tb);
  static cv::Mat prev_disp;
  static Eigen::Isometry3d prev_pose = Eigen::Isometry3d::Identity();
  if (stamp >= ta && stamp <= tb && !prev_disp.empty())
  {
    const Eigen::Isometry3d T_cur_prev = ego.inverse() * prev_pose;
    const double sc = static_cast<double>(disp.cols) / model.width;
    auto range = [&](const cv::Mat& d, double u, double v, int r) {
      const int cu = static_cast<int>(std::lround((u + 0.5) * sc - 0.5)), cv_ = static_cast<int>(std::lround((v + 0.5) * sc - 0.5));
      float lo = 1e9f, hi = -1e9f;
      for (int dv = -r; dv <= r; ++dv)
        for (int du = -r; du <= r; ++du)
        {
          const int x = cu + du, y = cv_ + dv;
          if (x < 0 || y < 0 || x >= d.cols || y >= d.rows) continue;
          const float q = d.at<float>(y, x);
          if (!(q > 0.f)) return -1.f;
          lo = std::min(lo, q);
          hi = std::max(hi, q);
        }
      return hi - lo;
    };
    const std::vector<SceneFlowPoint>& sp = movers.segmented();
    const std::vector<int>& cl = movers.segmentation().cluster();
    for (size_t i = 0; i < sp.size() && i < cl.size(); ++i)
    {
      if (cl[i] < 0) continue;
      const SceneFlowPoint& q = sp[i];
      const Eigen::Vector3d pred = T_cur_prev * q.prev, r = q.cur - pred, ray = q.cur.normalized();
      const double rr = r.dot(ray);
      const Eigen::Vector3d w = ego * q.cur;
      std::fprintf(stderr,
                   "flow t %.2f c%d w(%.2f %.2f %.2f) px0 (%.1f %.1f) Z0 %.2f px1 (%.1f %.1f) Z1 %.2f static (%.1f %.1f) "
                   "r_ray %.3f r_across %.3f rng0 %.2f/%.2f/%.2f rng1 %.2f/%.2f/%.2f\n",
                   stamp, cl[i], w.x(), w.y(), w.z(), model.fx * q.prev.x() / q.prev.z() + model.cx,
                   model.fy * q.prev.y() / q.prev.z() + model.cy, q.prev.z(), model.fx * q.cur.x() / q.cur.z() + model.cx,
                   model.fy * q.cur.y() / q.cur.z() + model.cy, q.cur.z(), model.fx * pred.x() / pred.z() + model.cx,
                   model.fy * pred.y() / pred.z() + model.cy, rr, (r - rr * ray).norm(),
                   range(prev_disp, model.fx * q.prev.x() / q.prev.z() + model.cx, model.fy * q.prev.y() / q.prev.z() + model.cy, 1),
                   range(prev_disp, model.fx * q.prev.x() / q.prev.z() + model.cx, model.fy * q.prev.y() / q.prev.z() + model.cy, 2),
                   range(prev_disp, model.fx * q.prev.x() / q.prev.z() + model.cx, model.fy * q.prev.y() / q.prev.z() + model.cy, 3),
                   range(disp, model.fx * q.cur.x() / q.cur.z() + model.cx, model.fy * q.cur.y() / q.cur.z() + model.cy, 1),
                   range(disp, model.fx * q.cur.x() / q.cur.z() + model.cx, model.fy * q.cur.y() / q.cur.z() + model.cy, 2),
                   range(disp, model.fx * q.cur.x() / q.cur.z() + model.cx, model.fy * q.cur.y() / q.cur.z() + model.cy, 3));
    }
  }
  disp.copyTo(prev_disp);
  prev_pose = ego;
}

/// OBST_CELL=gx,gy: the cell's label this frame and the heights of its points.
void printCell(const char* dc, const ObstacleMap& map, const std::vector<Eigen::Vector3f>& points,
               const eval::StereoFrame& f, const ObstaclesParams& params, int frames)
{
  int gx = 0, gy = 0;
  std::sscanf(dc, "%d,%d", &gx, &gy);
  const Window& w = map.window();
  const int lx = gx - w.ox, ly = gy - w.oy;
  if (lx >= 0 && ly >= 0 && lx < w.n && ly < w.n)
  {
    std::vector<float> zs;
    double rng = 0;
    for (size_t i = 0; i < map.worldPoints().size(); ++i)
    {
      const auto& q = map.worldPoints()[i];
      if (std::floor(q.x() / w.res) == gx && std::floor(q.y() / w.res) == gy)
      {
        zs.push_back(q.z());
        rng += points[i].z();
      }
    }
    std::sort(zs.begin(), zs.end());
    const float feet = f.gt_pose.translation().z() - params.camera_height;
    std::fprintf(stderr, "frame %d cell label %d n=%zu zrange %s", frames, int(map.frameLabels()[w.index(lx, ly)]), zs.size(),
                 zs.empty() ? "" : "");
    if (!zs.empty())
      std::fprintf(stderr, " z-feet: %.3f %.3f %.3f %.3f %.3f camZ %.2f", zs[0] - feet, zs[zs.size() / 10] - feet,
                   zs[zs.size() / 2] - feet, zs[zs.size() * 9 / 10] - feet, zs.back() - feet, rng / zs.size());
    std::fprintf(stderr, "\n");
  }
}

// ------------------------------------------------------------------------------ the run
/// The runner (every frame through the stage's frame step on the truth poses), the scorer (the
/// map and the people against the truth, summed over frames) and the report.
class ObstaclesRun
{
public:
  ObstaclesRun(const Options& opt, const ObstaclesParams& params, const Truth& t, const Ranger& ranger,
               std::map<long, Eigen::Isometry3d> mover_poses, eval::StereoBagReader& reader);
  /// Every frame of the bag; false (with the message) when none was usable.
  bool run();
  /// The movers track the emitter-off pairs of an active camera's bag (opt_.projected).
  void setTrackReader(std::unique_ptr<eval::StereoBagReader> reader);
  /// The PNG of the scored map at the last frame.
  void plotMap();
  /// The report on stdout (and OBST_FPMAP's cells on stderr).
  void printReport() const;
  /// The last stdout line (docs/design.md: its keys are read by others).
  eval::JsonLine jsonLine() const;

private:
  /// One frame with a truth pose through the stage; true when the map took it (scored).
  bool processFrame();
  /// The next emitter-off pair of the track reader at or before the frame.
  void advanceTrack();
  /// The frame's diagnostics asked for in the environment (stderr).
  void printDiagnostics(const ObstacleFrameResult& res, const StereoModel& model, const Eigen::Isometry3d* ego);
  /// The wearer now (truth): position, speed over 0.5 s, heading.
  Wearer wearerNow() const;
  /// People: tracks against the truth, the crossing predictor's warnings, ghosts and locks; the
  /// tracker + predictor time added to `ms_track`.
  void scorePeople(const std::vector<ReportedMover>& reported, const StereoModel& model, double& ms_track);
  /// The people walking and those in the camera's view, matched by the tracks.
  void scoreMovingPeople(const std::vector<PersonState>& truth_people, const std::vector<PersonState>& est,
                         const Eigen::Vector2d& wearer_pos, const StereoModel& model);
  /// Cells under a person now; cells on people's paths that read obstacle once they left;
  /// truth-free cells locked for good.
  void scoreGhosts(const std::vector<PersonState>& truth_people, const Eigen::Vector2d& wearer_pos);
  /// The map against the truth within 3 m and 5 m of the wearer.
  void scoreMap();
  /// False positives by class: next to a true obstacle (8-neighbour) or isolated; STEP code.
  void classifyFalsePositives(const eval::OccupancyGrid& est);
  /// Glass cells the ranger hit (held by the map), and those reported free after that hit.
  void scoreGlass(const eval::OccupancyGrid& est);
  /// OBST_BANDS: column clearance per band over the truth-free cells within 3 m.
  void printBands() const;
  void printPeople() const;
  void printFpCells() const;

  const Options& opt_;
  const ObstaclesParams& params;
  const Truth& t_;
  const eval::OccupancyGrid& truth;
  const std::vector<eval::RangeSample>& ranges;
  const Eigen::Isometry3d link_to_sonar;
  const std::map<long, Eigen::Isometry3d> mover_poses;  // stamp in microseconds -> pose (--mover-poses)
  eval::StereoBagReader& reader_;
  // The stage's whole frame step, as the nodelet runs it (frame gate, disparity, ranger, movers,
  // map, OctoMap insertion).
  ObstacleFrameProcessor proc;
  const ObstacleMap& map;
  RangePoseLookup range_pose;
  size_t next_range = 0;
  int no_depth_frames = 0;
  // People who move (issue 22): the stage's mover pipeline on the bag's left image and the truth
  // poses (the ego-motion the stage would take from tf), scored when the bag has people.
  std::vector<std::pair<double, std::vector<PersonState>>> people;
  bool has_people = false;
  CrossingPredictor predictor;
  PeopleScoreParams pscore;  // 5 m, gate 0.5 m, velocity after 0.5 s of track
  CrossingScore crossing;
  long people_truth = 0, people_truth_matched = 0, people_tracks = 0, people_tracks_matched = 0, vel_n = 0;
  // Recall of the people who walk (truth speed >= 0.3 m/s: a person standing still has no scene flow
  // and is mapped as an obstacle), and of those also in the camera's view (body centre in the image).
  long moving_truth = 0, moving_matched = 0, view_truth = 0, view_matched = 0;
  long standing_truth = 0, standing_held = 0;  // standing people in view within 5 m, held by the map
  long standing_near_truth = 0, standing_near_held = 0;  // ... within the map's obstacle evidence range
  double evidence_range_m = 0.0;                         // (obstacleEvidenceRange of the bag's rig)
  double vel_sum = 0.0;
  GhostCount ghosts;
  std::set<std::pair<int, int>> locked_free, people_path, ghost_people_path;  // global cells
  std::vector<double> ms_movers, ms_tracking;
  double confirmed_sum = 0.0, mover_cells_sum = 0.0;
  std::vector<double> ms_disp, ms_map, npts;
  Sum s3, s5;
  size_t fp_adjacent = 0, fp_isolated = 0, fp_step = 0;  // within 3 m, summed over frames
  std::map<std::pair<int, int>, std::array<int, 3>> fp_cells;  // OBST_FPMAP: frames each cell was a FP (obstacle, step) / FN
  std::set<size_t> free_where_obstacle, free_where_partial, free_where_glass;
  Sum s3_strict;  // the truth's own codes, every partly covered cell an obstacle
  std::set<size_t> ranger_hit_glass, freed_after_hit;  // indices into glass_cells
  eval::StereoFrame f;
  // An active camera's bag (opt_.projected): its emitter-off pairs, which the movers track; the
  // latest at or before the emitter-on frame `f`, and the one after it.
  std::unique_ptr<eval::StereoBagReader> track_reader_;
  eval::StereoFrame track_f, track_next;
  bool have_track = false, have_track_next = false;
  int frames = 0, used = 0, no_pose = 0;
  GridData grid;
  Eigen::Vector2d wearer{0, 0};
  const size_t total;
};

ObstaclesRun::ObstaclesRun(const Options& opt, const ObstaclesParams& p, const Truth& t, const Ranger& ranger,
                           std::map<long, Eigen::Isometry3d> poses, eval::StereoBagReader& reader)
  : opt_(opt), params(p), t_(t), truth(t.grid), ranges(ranger.ranges), link_to_sonar(ranger.link_to_sonar),
    mover_poses(std::move(poses)), reader_(reader), proc(p, ObstaclesNodeParams().octomap_insert_every),
    map(proc.map()), total(reader.size())
{
  // The ranger's pose: the ground-truth camera pose at the reading's stamp, interpolated, times
  // the URDF mount.
  range_pose = [this](const RangeSample& rs, Eigen::Isometry3f& T) {
    Eigen::Isometry3d T_left;
    if (!poseAt(reader_.groundTruth(), rs.stamp, T_left)) return false;
    T = (T_left * eval::linkToLeftOptical().inverse() * link_to_sonar).cast<float>();
    return true;
  };
  people = readPeople(opt.bag);
  has_people = !people.empty();
  if (has_people) std::cerr << "obstacles_benchmark: " << people.size() << " people truth messages\n";
}

bool ObstaclesRun::run()
{
  while (eval::nextFrameOrExit(reader_, f, "obstacles_benchmark", opt_.bag))
  {
    ++frames;
    if (frames <= opt_.skip) continue;
    if (opt_.max_frames > 0 && used >= opt_.max_frames) break;
    // (an active camera's emitter-on pairs lie half a frame after the truth's samples: interpolated)
    if (!f.has_gt_pose && opt_.projected)
      f.has_gt_pose = poseAt(reader_.groundTruth(), f.stamp, f.gt_pose);
    if (!f.has_gt_pose)
    {
      ++no_pose;
      continue;
    }
    if (!processFrame()) continue;
    if (used % 20 == 0) std::cerr << "\r[obstacles_benchmark] frame " << frames << "/" << total << std::flush;
  }
  std::cerr << "\n";
  if (used == 0 && no_depth_frames == 0)
  {
    std::cerr << "obstacles_benchmark: no usable frame (need stereo images with ground-truth poses)\n";
    return false;
  }
  return true;
}

void ObstaclesRun::setTrackReader(std::unique_ptr<eval::StereoBagReader> reader)
{
  track_reader_ = std::move(reader);
  have_track_next = track_reader_ && track_reader_->next(track_next);
}

void ObstaclesRun::advanceTrack()
{
  while (have_track_next && track_next.stamp <= f.stamp + 1e-6)
  {
    std::swap(track_f, track_next);
    have_track = true;
    have_track_next = track_reader_->next(track_next);
  }
}

bool ObstaclesRun::processFrame()
{
  const eval::StereoCalib& c = f.calib;
  const StereoModel model{c.width, c.height, c.fx, c.fy, c.cx, c.cy, c.baseline};
  const double t0 = eval::wallMs();
  ObstacleFrame in;
  in.stamp = f.stamp;
  in.left = f.left;
  in.right = f.right;
  in.model = model;
  in.T_world_cam = f.gt_pose;
  advanceTrack();
  if (have_track && track_f.has_gt_pose && f.stamp - track_f.stamp < 0.1)
  {
    in.track_left = &track_f.left;
    in.track_right = &track_f.right;
    in.track_stamp = track_f.stamp;
    in.track_pose = track_f.gt_pose;
  }
  cv::Mat true_disp;
  if (opt_.gt_depth)
  {
    if (f.gt_depth.empty()) return false;
    true_disp = trueDisparity(f.gt_depth, model, params.disparity_scale);
    in.disparity = &true_disp;
  }
  const double ms_true_disp = eval::wallMs() - t0;
  const Eigen::Isometry3d* ego = in.track_left ? &in.track_pose : &f.gt_pose;  // the movers' frame
  if (!mover_poses.empty())
  {
    // (an active bag's movers track the emitter-off pair: the VO's pose of that frame)
    const auto it = mover_poses.find(std::lround((in.track_left ? in.track_stamp : f.stamp) * 1e6));
    ego = it != mover_poses.end() ? &it->second : nullptr;  // no pose (the VO lost it): no flow, as in the chain
    in.own_mover_pose = true;
    in.mover_pose = ego;
  }
  // The ranger's readings as they would have arrived by this frame; the stage applies those
  // stamped up to it before the frame's update.
  for (; next_range < ranges.size() && ranges[next_range].stamp <= f.stamp; ++next_range)
  {
    const eval::RangeSample& rs = ranges[next_range];
    proc.queueRange({rs.stamp, rs.range, rs.min_range, rs.max_range, rs.field_of_view, rs.frame_id});
  }
  const ObstacleFrameResult& res = proc.process(in, range_pose);
  if (!res.disparity_ok) return false;
  // The stereo figures count every frame; the map's only the frames the map took.
  ms_disp.push_back(ms_true_disp + res.ms_disparity);
  npts.push_back(static_cast<double>(proc.points().size()));
  if (!res.map_updated)
  {
    ++no_depth_frames;  // the stage's gate: no depth, no update, no grid (not scored)
    return false;
  }
  const MoverPipeline* movers = proc.movers();
  printDiagnostics(res, model, ego);
  double ms_track = movers ? movers->msTracking() : 0.0;
  ms_map.push_back(res.ms_ranger + res.ms_map);  // the map alone (ranger included, movers not)
  std::vector<ReportedMover> reported;
  if (movers)
  {
    ms_movers.push_back(movers->msFlow() + movers->msSegmentation() + movers->msTracking());
    reported = res.movers;
    confirmed_sum += static_cast<double>(reported.size());
    mover_cells_sum += map.stats().mover_cells;
  }
  scorePeople(reported, model, ms_track);
  if (movers) ms_tracking.push_back(ms_track);
  ++used;
  wearer = f.gt_pose.translation().head<2>();
  if (t_.has_truth) scoreMap();
  return true;
}

void ObstaclesRun::printDiagnostics(const ObstacleFrameResult& res, const StereoModel& model, const Eigen::Isometry3d* ego)
{
  const cv::Mat& disp = proc.disparity();
  const MoverPipeline* movers = proc.movers();
  if (!opt_.gt_depth && !f.gt_depth.empty() && std::getenv("OBST_BIAS")) printDisparityBias(f.gt_depth, disp, model, frames);
  if (std::getenv("OBST_SONAR")) printSonar(res.ranges);
  if (movers)
  {
    if (std::getenv("OBST_MOVERS")) printMovers(*movers, f.stamp);
    if (const char* fd = std::getenv("OBST_FLOWDUMP"); fd && ego) printFlow(fd, *movers, disp, model, f.stamp, *ego);
  }
  if (const char* dc = std::getenv("OBST_CELL")) printCell(dc, map, proc.points(), f, params, frames);
}

Wearer ObstaclesRun::wearerNow() const
{
  Wearer w;
  w.position = f.gt_pose.translation().head<2>();
  Eigen::Isometry3d before;
  Eigen::Vector2d v(0, 0);
  if (poseAt(reader_.groundTruth(), f.stamp - 0.5, before))
    v = (w.position - before.translation().head<2>()) / 0.5;  // over 0.5 s: the gait's sway averages out
  w.speed = v.norm();
  const Eigen::Vector3d fwd = f.gt_pose.linear().col(2);  // optical axis
  w.heading = w.speed > 0.2 ? std::atan2(v.y(), v.x()) : std::atan2(fwd.y(), fwd.x());
  return w;
}

void ObstaclesRun::scorePeople(const std::vector<ReportedMover>& reported, const StereoModel& model, double& ms_track)
{
  const std::vector<PersonState>* truth_people = has_people ? peopleAt(people, f.stamp) : nullptr;
  if (proc.movers() && !has_people)
  {
    // A world without people: every mover is false, and so is every crossing warning.
    std::vector<MoverTrack> tracks;
    for (const ReportedMover& r : reported) tracks.push_back(r.track);
    std::set<int> warned;
    for (const CrossingPrediction& cp : predictor.predict(wearerNow(), tracks))
      if (cp.warn) warned.insert(cp.track_id);
    crossing.addFrame(f.stamp, f.gt_pose.translation().head<2>(), {}, warned, {});
  }
  if (!truth_people) return;
  const double tp0 = eval::wallMs();
  const Wearer w = wearerNow();
  std::vector<MoverTrack> tracks;
  std::vector<PersonState> est;
  for (const ReportedMover& r : reported)
  {
    tracks.push_back(r.track);
    PersonState q;
    q.id = r.track.id;
    q.position = r.track.position();
    q.velocity = r.track.velocity();
    q.radius = r.radius;
    q.age = f.stamp - r.track.born;
    est.push_back(q);
  }
  std::set<int> warned;
  for (const CrossingPrediction& cp : predictor.predict(w, tracks))
    if (cp.warn) warned.insert(cp.track_id);
  ms_track += eval::wallMs() - tp0;
  const PeopleFrameScore ps = scorePeopleFrame(*truth_people, est, w.position, pscore);
  scoreMovingPeople(*truth_people, est, w.position, model);
  if (std::getenv("OBST_UNMATCHED")) printUnmatched(*truth_people, est, ps, w.position, f.stamp, pscore.radius);
  if (std::getenv("OBST_PEOPLE_PTS"))
    printPeoplePoints(*truth_people, map.worldPoints(), w.position, f.stamp,
                      f.gt_pose.translation().z() - params.camera_height, f.gt_pose, model, ps.track_to_truth);
  people_truth += ps.truth_in_range;
  people_truth_matched += ps.truth_matched;
  people_tracks += ps.tracks_in_range;
  people_tracks_matched += ps.tracks_matched;
  vel_sum += ps.velocity_err_sum;
  vel_n += ps.velocity_n;
  crossing.addFrame(f.stamp, w.position, *truth_people, warned, ps.track_to_truth);
  if (t_.has_truth) scoreGhosts(*truth_people, w.position);
}

void ObstaclesRun::scoreMovingPeople(const std::vector<PersonState>& truth_people, const std::vector<PersonState>& est,
                                     const Eigen::Vector2d& wearer_pos, const StereoModel& model)
{
  std::vector<PersonState> moving, in_view;
  std::set<int> visible;  // walking where the camera can see and match them (the crossings' floor)
  const Eigen::Isometry3d cam_world = f.gt_pose.inverse();
  bool have_grid = false;
  for (const PersonState& q : truth_people)
  {
    const Eigen::Vector3d c = cam_world * Eigen::Vector3d(q.position.x(), q.position.y(), q.age);
    const bool ahead = c.z() >= 0.3;
    const double u = ahead ? model.fx * c.x() / c.z() + model.cx : -1.0, v = ahead ? model.fy * c.y() / c.z() + model.cy : -1.0;
    const bool in_image = ahead && u >= 0 && v >= 0 && u < model.width && v < model.height;
    if (q.velocity.norm() < 0.3)
    {
      // Standing: no flow, an ordinary obstacle of the map (issue 37: found when the map holds them).
      if (!in_image || (q.position - wearer_pos).norm() > pscore.radius) continue;
      if (!have_grid) map.grid(grid);
      have_grid = true;
      const bool held = heldByMap(grid, q);
      ++standing_truth;
      standing_held += held;
      evidence_range_m = obstacleEvidenceRange(params, model);
      if ((q.position - wearer_pos).norm() <= evidence_range_m)
      {
        ++standing_near_truth;
        standing_near_held += held;
      }
      continue;
    }
    moving.push_back(q);
    if (!ahead) continue;
    if (in_image) in_view.push_back(q);
    // The matcher gives no disparity in the left image's first max_disparity columns.
    if (u >= params.max_disparity && u < model.width && v >= 0 && v < model.height && c.z() <= params.max_depth)
      visible.insert(q.id);
  }
  crossing.addVisible(f.stamp, visible);
  const PeopleFrameScore pm = scorePeopleFrame(moving, est, wearer_pos, pscore);
  const PeopleFrameScore pv = scorePeopleFrame(in_view, est, wearer_pos, pscore);
  moving_truth += pm.truth_in_range;
  moving_matched += pm.truth_matched;
  view_truth += pv.truth_in_range;
  view_matched += pv.truth_matched;
}

void ObstaclesRun::scoreGhosts(const std::vector<PersonState>& truth_people, const Eigen::Vector2d& wearer_pos)
{
  map.grid(grid);
  const GhostCount g = countGhostCells(truth, grid, wearer_pos, 5.0, truth_people);
  ghosts.free_known += g.free_known;
  ghosts.ghost += g.ghost;
  // Cells under a person now; cells on people's paths that read obstacle once they left;
  // truth-free cells locked for good.
  const double res = params.cell_size;
  std::set<std::pair<int, int>> under;
  for (const PersonState& q : truth_people)
  {
    const int r = static_cast<int>(std::ceil(q.radius / res)) + 1;
    const int gx = static_cast<int>(std::floor(q.position.x() / res)), gy = static_cast<int>(std::floor(q.position.y() / res));
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx)
      {
        const Eigen::Vector2d c((gx + dx + 0.5) * res, (gy + dy + 0.5) * res);
        if ((c - q.position).norm() < q.radius + res * std::sqrt(0.5)) under.insert({gx + dx, gy + dy});
      }
  }
  people_path.insert(under.begin(), under.end());
  const Window& win = map.window();
  for (int ly = 0; ly < win.n; ++ly)
    for (int lx = 0; lx < win.n; ++lx)
    {
      const int gx = win.ox + lx, gy = win.oy + ly;
      const double x = (gx + 0.5) * res, y = (gy + 0.5) * res;
      if ((Eigen::Vector2d(x, y) - wearer_pos).squaredNorm() > 25.0) continue;
      const int tx = static_cast<int>(std::floor((x - truth.origin_x) / truth.resolution));
      const int ty = static_cast<int>(std::floor((y - truth.origin_y) / truth.resolution));
      if (tx < 0 || ty < 0 || tx >= truth.width || ty >= truth.height ||
          truth.data[static_cast<size_t>(ty) * truth.width + tx] != 0)
        continue;
      const CellCounters* cc = map.temporal().find(gx, gy);
      if (cc && cc->permanent) locked_free.insert({gx, gy});
      if (people_path.count({gx, gy}) && !under.count({gx, gy}))
      {
        const int ex = static_cast<int>(std::floor((x - grid.origin_x) / grid.resolution));
        const int ey = static_cast<int>(std::floor((y - grid.origin_y) / grid.resolution));
        if (ex >= 0 && ey >= 0 && ex < grid.width && ey < grid.height &&
            grid.data[static_cast<size_t>(ey) * grid.width + ex] == 100)
          ghost_people_path.insert({gx, gy});
      }
    }
}

void ObstaclesRun::scoreMap()
{
  map.grid(grid);
  const eval::OccupancyGrid& est = grid;
  eval::MapScoreParams p3, p5;
  p3.radius_m = 3.0;
  p5.radius_m = 5.0;
  s3_strict.add(eval::scoreMap(truth, est, wearer, p3));
  if (t_.partial_scoring)
  {
    p3.exclude = p5.exclude = &t_.exclude_mask;
    p3.glass = p5.glass = &t_.glass_mask;
  }
  s3.add(t_.partial_scoring ? eval::scoreMap(truth, est, wearer, p3) : s3_strict.last);
  classifyFalsePositives(est);
  scoreGlass(est);
  if (std::getenv("OBST_BANDS") && params.column_bands > 0) printBands();
  const auto sc5 = eval::scoreMap(truth, est, wearer, p5);
  s5.add(sc5);
  free_where_obstacle.insert(sc5.free_where_obstacle_cells.begin(), sc5.free_where_obstacle_cells.end());
  free_where_partial.insert(sc5.free_where_partial_cells.begin(), sc5.free_where_partial_cells.end());
  free_where_glass.insert(sc5.free_where_glass_cells.begin(), sc5.free_where_glass_cells.end());
}

void ObstaclesRun::classifyFalsePositives(const eval::OccupancyGrid& est)
{
  for (int cy = 0; cy < truth.height; ++cy)
    for (int cx = 0; cx < truth.width; ++cx)
    {
      const int8_t g = truth.data[static_cast<size_t>(cy) * truth.width + cx];
      if (g != 0 && !(g > 0 && std::getenv("OBST_FPMAP"))) continue;  // ground-truth free only (the scored false positives)
      const double x = truth.origin_x + (cx + 0.5) * truth.resolution, y = truth.origin_y + (cy + 0.5) * truth.resolution;
      if ((Eigen::Vector2d(x, y) - wearer).squaredNorm() > 9.0) continue;
      const int ex = static_cast<int>(std::floor((x - est.origin_x) / est.resolution));
      const int ey = static_cast<int>(std::floor((y - est.origin_y) / est.resolution));
      if (ex < 0 || ey < 0 || ex >= est.width || ey >= est.height) continue;
      const int8_t e = est.data[static_cast<size_t>(ey) * est.width + ex];
      if (g != 0)
      {
        // false negative (OBST_FPMAP only), as scored: a partly covered cell is not one
        const bool partial = t_.partial_scoring && t_.exclude_mask[static_cast<size_t>(cy) * truth.width + cx];
        if (e == 0 && !partial) ++fp_cells[{cx, cy}][2];
        continue;
      }
      if (e != 50 && e != 100) continue;
      if (e == 50) ++fp_step;
      if (std::getenv("OBST_FPMAP")) ++fp_cells[{cx, cy}][e == 50 ? 1 : 0];
      bool adj = false;
      for (int dy = -1; dy <= 1 && !adj; ++dy)
        for (int dx = -1; dx <= 1 && !adj; ++dx)
        {
          const int xx = cx + dx, yy = cy + dy;
          if (xx < 0 || yy < 0 || xx >= truth.width || yy >= truth.height) continue;
          const int8_t gn = truth.data[static_cast<size_t>(yy) * truth.width + xx];
          adj = gn == 100 || gn == 50;
        }
      (adj ? fp_adjacent : fp_isolated)++;
      if (std::getenv("OBST_DEBUG") && reader_.size() == static_cast<size_t>(frames))
      {
        const int gx = static_cast<int>(std::floor(x / est.resolution)), gy = static_cast<int>(std::floor(y / est.resolution));
        const CellCounters* cc = map.temporal().find(gx, gy);
        if (cc)
          std::fprintf(stderr, "FP adj=%d %d %d r=%.2f o=%d s=%d votes=%d flips=%d perm=%d\n", int(adj), gx, gy,
                       (Eigen::Vector2d(x, y) - wearer).norm(), cc->o, cc->s, cc->votes, cc->flips, int(cc->permanent));
      }
    }
}

void ObstaclesRun::scoreGlass(const eval::OccupancyGrid& est)
{
  for (size_t k = 0; k < t_.glass_cells.size(); ++k)
  {
    const Eigen::Vector2d& c = t_.glass_cells[k];
    const int gx = static_cast<int>(std::floor(c.x() / params.cell_size)), gy = static_cast<int>(std::floor(c.y() / params.cell_size));
    if (map.sonar().held(gx, gy)) ranger_hit_glass.insert(k);
    if (!ranger_hit_glass.count(k)) continue;
    const int ex = static_cast<int>(std::floor((c.x() - est.origin_x) / est.resolution));
    const int ey = static_cast<int>(std::floor((c.y() - est.origin_y) / est.resolution));
    if (ex >= 0 && ey >= 0 && ex < est.width && ey < est.height && est.data[static_cast<size_t>(ey) * est.width + ex] == 0)
      freed_after_hit.insert(k);
  }
}

void ObstaclesRun::printBands() const
{
  // Column clearance diagnostics: per band, how many truth-free cells within 3 m lack that
  // band's clear bit (summed over frames), and how many lack only it.
  static std::vector<size_t> lack(8, 0), only(8, 0);
  static size_t cells = 0, full = 0;
  const uint8_t all = static_cast<uint8_t>((1u << params.column_bands) - 1u);
  for (int cy = 0; cy < truth.height; ++cy)
    for (int cx = 0; cx < truth.width; ++cx)
    {
      if (truth.data[static_cast<size_t>(cy) * truth.width + cx] != 0) continue;
      const double x = truth.origin_x + (cx + 0.5) * truth.resolution, y = truth.origin_y + (cy + 0.5) * truth.resolution;
      if ((Eigen::Vector2d(x, y) - wearer).squaredNorm() > 9.0) continue;
      const CellCounters* cc = map.temporal().find(static_cast<int>(std::floor(x / grid.resolution)),
                                                   static_cast<int>(std::floor(y / grid.resolution)));
      ++cells;
      const uint8_t b = cc ? (cc->clear & all) : 0;
      if (b == all) ++full;
      for (int i = 0; i < params.column_bands; ++i)
        if (!(b >> i & 1u))
        {
          ++lack[i];
          if ((b | (1u << i)) == all) ++only[i];
        }
    }
  if (static_cast<size_t>(frames) == total || (opt_.max_frames > 0 && used == opt_.max_frames))
  {
    std::fprintf(stderr, "BANDS cells %zu full %.3f;", cells, double(full) / cells);
    for (int i = 0; i < params.column_bands; ++i)
      std::fprintf(stderr, " band %d lacks %.3f only %.3f;", i, double(lack[i]) / cells, double(only[i]) / cells);
    std::fprintf(stderr, "\n");
  }
}

void ObstaclesRun::plotMap()
{
  if (!t_.has_truth) return;
  map.grid(grid);
  const cv::Mat img = eval::plotMapScore(truth, grid, wearer, 3.0, Eigen::Isometry2d::Identity(), 0,
                                         "obstacles: " + opt_.bag + " (last frame, 3 m)");
  std::string err;
  if (!eval::writePng(opt_.png, img, &err)) std::cerr << "obstacles_benchmark: " << err << "\n";
}

// timings: nearest-rank percentiles (no interpolation)
double percentile(const std::vector<double>& v, double q)
{
  return eval::percentileNearestRank(v, q);
}

double ratio(long a, long b)
{
  return b > 0 ? static_cast<double>(a) / b : NAN;
}

void ObstaclesRun::printReport() const
{
  using eval::mean;
  const double p95_map = percentile(ms_map, 0.95), p95_disp = percentile(ms_disp, 0.95);
  std::printf("bag %s: %d frames read, %d used (%d without gt pose, %d without depth), image %dx%d\n", opt_.bag.c_str(), frames,
              used, no_pose, no_depth_frames,
              f.calib.width, f.calib.height);
  std::printf("%-34s %10s %10s\n", "timing (ms)", "median", "p95");
  std::printf("%-34s %10.2f %10.2f\n", "disparity + points", percentile(ms_disp, 0.5), p95_disp);
  std::printf("%-34s %10.2f %10.2f\n", "elevation + MLS + temporal", percentile(ms_map, 0.5), p95_map);
  const double p95_movers = ms_movers.empty() ? NAN : percentile(ms_movers, 0.95);
  if (!ms_movers.empty())
  {
    std::printf("%-34s %10.2f %10.2f\n", "movers: flow + segment + track", percentile(ms_movers, 0.5), p95_movers);
    std::printf("%-34s %10.2f %10.2f\n", "movers: tracker + predictor", percentile(ms_tracking, 0.5),
                ms_tracking.empty() ? NAN : percentile(ms_tracking, 0.95));
    std::printf("movers: confirmed tracks per frame (mean) %.3f, cells kept out of the votes per frame %.2f\n",
                confirmed_sum / used, mover_cells_sum / used);
  }
  std::printf("points per frame (mean) %.0f\n", mean(npts));
  std::printf("%-10s %9s %9s %13s %9s  (counts summed over frames)\n", "radius", "recall", "precision", "misclassified",
              "coverage");
  std::printf("%-10s %9.3f %9.3f %13.3f %9.3f\n", "3 m", s3.recall(), s3.precision(), s3.misclassified(), s3.coverage());
  std::printf("%-10s %9.3f %9.3f %13.3f %9.3f\n", "5 m", s5.recall(), s5.precision(), s5.misclassified(), s5.coverage());
  std::printf("false positives 3 m: %zu next to a true obstacle, %zu isolated, %zu of them STEP\n", fp_adjacent,
              fp_isolated, fp_step);
  const bool partial_scoring = t_.partial_scoring;
  std::printf("ground-truth obstacle cells ever reported free (5 m): %zu (glass %zu)%s\n", free_where_obstacle.size(),
              free_where_glass.size(), partial_scoring ? "" : " [no world: partial cells scored as the truth codes]");
  if (partial_scoring)
    std::printf("partial cells (an obstacle within %.0f cm of the border) scored neither way; of them reported free: %zu;\n"
                "  strict truth (any overlap = obstacle): 3 m recall %.3f precision %.3f, cells reported free %zu\n",
                opt_.partial_depth * 100, free_where_partial.size(), s3_strict.recall(), s3_strict.precision(),
                free_where_obstacle.size() + free_where_partial.size());
  if (partial_scoring)
    std::printf("glass-pane cells hit by the ranger: %zu, reported free after the hit: %zu\n", ranger_hit_glass.size(),
                freed_after_hit.size());
  const long ranges_used = proc.counters().ranges_echo, ranges_no_echo = proc.counters().ranges_no_echo;
  const long ranges_rejected = proc.counters().ranges_rejected;
  std::printf("ranger: %s, %ld echoes fused, %ld no echo, %ld rejected\n",
              opt_.no_sonar ? "off (--no-sonar)" : (ranges.empty() ? "none in the bag" : "on"), ranges_used, ranges_no_echo,
              ranges_rejected);
  if (t_.has_truth) std::printf("map plot: %s\n", opt_.png.c_str());
  if (std::getenv("OBST_FPMAP")) printFpCells();
  printPeople();
}

void ObstaclesRun::printFpCells() const
{
  std::vector<std::pair<int, std::pair<int, int>>> top;
  for (const auto& kv : fp_cells)
    if (kv.second[0] + kv.second[1] > 0) top.push_back({kv.second[0] + kv.second[1], kv.first});
  std::sort(top.rbegin(), top.rend());
  for (size_t i = 0; i < std::min<size_t>(top.size(), 60); ++i)
  {
    const auto& c = top[i].second;
    std::fprintf(stderr, "FPCELL x %.2f y %.2f frames %d (step %d)\n", truth.origin_x + (c.first + 0.5) * truth.resolution,
                 truth.origin_y + (c.second + 0.5) * truth.resolution, top[i].first, fp_cells.at(c)[1]);
  }
  top.clear();
  for (const auto& kv : fp_cells)
    if (kv.second[2] > 0) top.push_back({kv.second[2], kv.first});
  std::sort(top.rbegin(), top.rend());
  for (size_t i = 0; i < std::min<size_t>(top.size(), 60); ++i)
    std::fprintf(stderr, "FNCELL x %.2f y %.2f frames %d\n", truth.origin_x + (top[i].second.first + 0.5) * truth.resolution,
                 truth.origin_y + (top[i].second.second + 0.5) * truth.resolution, top[i].first);
}

void ObstaclesRun::printPeople() const
{
  if (has_people)
  {
    std::printf("people (truth within 5 m, confirmed tracks, matched within %.1f m): recall %.3f (%ld/%ld) precision %.3f "
                "(%ld/%ld), velocity error %.3f m/s over %ld track-frames older than %.1f s\n",
                pscore.gate, ratio(people_truth_matched, people_truth), people_truth_matched, people_truth,
                ratio(people_tracks_matched, people_tracks), people_tracks_matched, people_tracks,
                vel_n ? vel_sum / vel_n : NAN, vel_n, pscore.min_age);
    std::printf("people walking (truth >= 0.3 m/s) within 5 m: recall %.3f (%ld/%ld); of them in the camera's view: %.3f "
                "(%ld/%ld)\n",
                ratio(moving_matched, moving_truth), moving_matched, moving_truth, ratio(view_matched, view_truth),
                view_matched, view_truth);
    std::printf("people standing (truth < 0.3 m/s) in the camera's view within 5 m: held by the map %.3f (%ld/%ld); "
                "within its obstacle evidence range (%.2f m): %.3f (%ld/%ld)\n",
                ratio(standing_held, standing_truth), standing_held, standing_truth, evidence_range_m,
                ratio(standing_near_held, standing_near_truth), standing_near_held, standing_near_truth);
    std::printf("crossings (closest truth approach < 0.5 m): %d, warned >= 1.5 s ahead: %d; false warnings (people never "
                "within 1 m, or no one): %d in %.2f min\n",
                crossing.crossings(), crossing.crossingsWarned(), crossing.falseWarnings(), crossing.minutes());
    std::printf("  the camera's floor: %d of them walked where the camera could see and match them (right of the left "
                "image's first max_disparity columns, within max_depth) in >= %d frames before the 1.5 s; of those, "
                "warned in time: %d\n",
                crossing.crossingsVisible(), CrossingScoreParams().min_visible_frames, crossing.crossingsWarnedVisible());
    for (const CrossingScore::CrossingDetail& d : crossing.details())
      std::printf("  crossing: person %d closest %.2f m at t %.2f; %s; walking in view from %.2f s before, tracked from "
                  "%.2f s before, warned from %.2f s before\n",
                  d.id, d.d_closest, d.t_closest, d.visible ? "visible in time" : "NOT visible in time",
                  d.t_closest - d.first_visible, d.t_closest - d.first_tracked, d.t_closest - d.first_warned);
    std::printf("ghosts: %ld of %ld truth-free known cells within 5 m (not under a person) marked obstacle; "
                "cells on people's paths marked obstacle after they left: %zu; truth-free cells locked: %zu "
                "(on people's paths: %zu)\n",
                ghosts.ghost, ghosts.free_known, ghost_people_path.size(), locked_free.size(),
                static_cast<size_t>(std::count_if(locked_free.begin(), locked_free.end(),
                                                  [&](const auto& c) { return people_path.count(c) > 0; })));
  }
  if (!has_people && params.movers)
    std::printf("movers on a world without people (all false): %.3f confirmed a frame; crossing warnings: %d in %.2f min\n",
                confirmed_sum / std::max(1, used), crossing.falseWarnings(), crossing.minutes());
}

eval::JsonLine ObstaclesRun::jsonLine() const
{
  using eval::mean;
  auto num = [](double v, int decimals = 4) { return eval::jsonFixed(v, decimals); };
  const double p95_map = percentile(ms_map, 0.95), p95_disp = percentile(ms_disp, 0.95);
  const double p95_movers = ms_movers.empty() ? NAN : percentile(ms_movers, 0.95);
  const double p95_tracking = ms_tracking.empty() ? NAN : percentile(ms_tracking, 0.95);
  const bool scored_people = has_people && params.movers;
  const bool scored_ghosts = has_people && t_.has_truth;
  const bool has_truth = t_.has_truth, partial_scoring = t_.partial_scoring;
  const size_t locked_on_paths = static_cast<size_t>(
      std::count_if(locked_free.begin(), locked_free.end(), [&](const auto& c) { return people_path.count(c) > 0; }));
  eval::JsonLine js;
  js.add("ms_p95_map", num(p95_map, 3)).add("ms_p95_disparity", num(p95_disp, 3))
      .add("points_per_frame", num(mean(npts), 0)).add("recall_3m", num(s3.recall()))
      .add("precision_3m", num(s3.precision())).add("misclassified_3m", num(s3.misclassified()))
      .add("recall_5m", num(s5.recall())).add("precision_5m", num(s5.precision()))
      .add("free_where_obstacle_cells", has_truth ? std::to_string(free_where_obstacle.size()) : "null")
      .add("free_where_glass_cells", partial_scoring ? std::to_string(free_where_glass.size()) : "null")
      .add("free_where_obstacle_cells_strict",
           has_truth ? std::to_string(free_where_obstacle.size() + free_where_partial.size()) : "null")
      .add("recall_3m_strict", num(s3_strict.recall())).add("precision_3m_strict", num(s3_strict.precision()))
      .add("partial_scoring", partial_scoring)
      .add("ranger_hit_glass_cells", partial_scoring ? std::to_string(ranger_hit_glass.size()) : "null")
      .add("free_after_ranger_hit_glass_cells", partial_scoring ? std::to_string(freed_after_hit.size()) : "null")
      .add("sonar_readings_fused", proc.counters().ranges_echo).add("sonar", !opt_.no_sonar && !ranges.empty())
      .add("frames", used).add("no_depth_frames", no_depth_frames).add("ms_median_map", num(percentile(ms_map, 0.5), 3))
      .add("ms_median_disparity", num(percentile(ms_disp, 0.5), 3))
      .add("misclassified_5m", num(s5.misclassified())).add("coverage_3m", num(s3.coverage()))
      .add("coverage_5m", num(s5.coverage())).add("fp_adjacent_3m", fp_adjacent)
      .add("fp_isolated_3m", fp_isolated).add("fp_step_3m", fp_step).add("gt_depth", opt_.gt_depth).add("projected", opt_.projected)
      .add("movers", params.movers)
      .add("ms_p95_movers", num(p95_movers, 3)).add("ms_p95_tracking", num(p95_tracking, 3))
      .add("movers_confirmed_per_frame", params.movers ? num(confirmed_sum / used, 3) : "null")
      .add("ghost_cell_pct", scored_ghosts ? num(100.0 * ratio(ghosts.ghost, ghosts.free_known), 3) : "null")
      .add("locked_free_cells", scored_ghosts ? std::to_string(locked_free.size()) : "null")
      .add("locked_people_path_cells", scored_ghosts ? std::to_string(locked_on_paths) : "null")
      .add("ghost_people_path_cells", scored_ghosts ? std::to_string(ghost_people_path.size()) : "null")
      .add("people_recall_5m", scored_people ? num(ratio(people_truth_matched, people_truth)) : "null")
      .add("people_precision_5m", scored_people ? num(ratio(people_tracks_matched, people_tracks)) : "null")
      .add("people_recall_5m_walking", scored_people ? num(ratio(moving_matched, moving_truth)) : "null")
      .add("people_recall_5m_walking_in_view", scored_people ? num(ratio(view_matched, view_truth)) : "null")
      .add("people_recall_5m_standing_in_view", scored_people ? num(ratio(standing_held, standing_truth)) : "null")
      .add("people_recall_standing_in_evidence_range",
           scored_people ? num(ratio(standing_near_held, standing_near_truth)) : "null")
      .add("people_velocity_err_mps", scored_people && vel_n ? num(vel_sum / vel_n) : "null")
      .add("crossing_warned_pct", scored_people ? num(crossing.warnedPct(), 1) : "null")
      .add("crossings", scored_people ? std::to_string(crossing.crossings()) : "null")
      .add("crossings_visible", scored_people ? std::to_string(crossing.crossingsVisible()) : "null")
      .add("crossing_warned_pct_visible",
           scored_people && crossing.crossingsVisible() > 0
               ? num(100.0 * crossing.crossingsWarnedVisible() / crossing.crossingsVisible(), 1)
               : "null")
      .add("false_crossing_warnings_per_min", params.movers ? num(crossing.falseWarningsPerMin(), 2) : "null");
  return js;
}
}  // namespace

int main(int argc, char** argv)
{
  Options opt;
  eval::CommandLine cl("obstacles_benchmark", kUsage);
  eval::SetOptions set_options;
  set_options.addTo(cl);
  opt.addTo(cl);
  const auto run_set = [&] { return runSet(cl, argc, argv, set_options, opt); };
  if (const int rc = set_options.parse(cl, argc, argv, run_set, opt.bag); rc >= 0)
    return rc;
  const std::string& bag = opt.bag;
  if (opt.png.empty())
    opt.png = bag.size() > 4 && bag.substr(bag.size() - 4) == ".bag" ? bag.substr(0, bag.size() - 4) + "_obstacles_map.png"
                                                                     : bag + "_obstacles_map.png";

  // An active camera's bag: the map from the emitter-on pairs (the true depth goes with the others)
  const eval::StereoBagTopics topics;
  opt.projected = !opt.passive && !opt.gt_depth && eval::bagHasTopic(bag, topics.projected_left_image);
  const std::unique_ptr<eval::StereoBagReader> reader =
      eval::openStereoBag("obstacles_benchmark", bag, opt.projected ? topics.projected() : topics);
  if (!reader)
    return 1;
  const Truth truth = readTruth(opt, *reader);
  const Ranger ranger = readRanger(opt, *reader);

  ObstaclesParams params;  // defaults
  // The wearer's camera height: the nodelet takes it from the URDF; here from the world's walk
  // (generated walks have eye heights of 1.55-1.75 m), unless --set gives it.
  if (std::isfinite(truth.eye_height)) params.camera_height = truth.eye_height;
  params.projected = opt.projected;  // the emitter-on pairs are read
  if (!eval::applySets(cl, opt.overrides, params))  // --set: the node's parameter names (params.h table)
    return 2;
  for (const std::string& w : clampParams(params)) std::cerr << "obstacles_benchmark: " << w << "\n";
  std::map<long, Eigen::Isometry3d> mover_poses;
  if (!opt.mover_poses_path.empty())
  {
    mover_poses = readMoverPoses(opt.mover_poses_path);
    if (mover_poses.empty()) return cl.usageError("no pose rows in " + opt.mover_poses_path);
  }
  // One estimate for both of an active camera's streams (the same two cameras), fed by the pairs mapped.
  std::shared_ptr<assistive_description::StereoSelfCalibration> self_cal;
  auto selfCalibrate = [&self_cal](eval::StereoBagReader& r, bool estimate) {
    r.setFrameFilter([self_cal, estimate](eval::StereoFrame& f) {
      self_cal->correctAndEstimate(f.left, f.right, {f.calib.fx, f.calib.fy, f.calib.cx, f.calib.cy}, estimate);
    });
  };
  if (opt.self_calibrate)
  {
    self_cal = std::make_shared<assistive_description::StereoSelfCalibration>();
    selfCalibrate(*reader, true);
  }
  ObstaclesRun run(opt, params, truth, ranger, std::move(mover_poses), *reader);
  if (opt.projected && params.movers)
  {
    auto track_reader = eval::openStereoBag("obstacles_benchmark", bag, topics);
    if (track_reader && self_cal)
      selfCalibrate(*track_reader, false);
    run.setTrackReader(std::move(track_reader));
  }
  if (!run.run())
    return 1;
  if (self_cal)
  {
    const cv::Vec3d a = self_cal->applied() * (180.0 / M_PI);
    std::cout << self_cal->describe() << eval::rightRotationAgainstTruth(eval::readBagString(bag), a.val) << "\n";
  }
  run.plotMap();
  run.printReport();
  std::cout << run.jsonLine().str() << std::endl;
  return 0;
}
