// rosrun assistive_eval evaluate_trajectory GT [EST] [options]
// Trajectory error of an estimate against ground truth: APE/ATE after alignment, evo-style RPE,
// KITTI-style segment drift, end-point drift, largest error jump, yaw error per head-rotation band.
// GT / EST: a bag (nav_msgs/Odometry topics) or a TUM / KITTI text file. With one bag, both come
// from it (--gt-topic, --est-topic). Writes PNG plots; prints a table, then one JSON line.
#include <assistive_eval/metrics.h>
#include <assistive_eval/plots.h>
#include <assistive_eval/trajectory.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli_common.h"
#include "eval_ros.h"

using namespace assistive_eval;

namespace
{
const char* USAGE =
    "usage: evaluate_trajectory GT [EST] [options]\n"
    "       evaluate_trajectory --live [--duration S] [options]   (subscribes to --gt-topic and --est-topic)\n"
    "  GT, EST            a .bag (nav_msgs/Odometry) or a TUM ('t x y z qx qy qz qw') / KITTI (12 numbers) file;\n"
    "                     with a single bag both trajectories are read from it\n"
    "  --gt-topic T       ground-truth topic in a bag (default /ground_truth/odom)\n"
    "  --est-topic T      estimate topic in a bag (default /vo/odom)\n"
    "  --gt-format F, --est-format F   auto|tum|kitti for text files (default auto)\n"
    "  --gt-times FILE, --est-times FILE   stamps for KITTI files (one per line)\n"
    "  --gt-body B, --est-body B       auto|link|optical: body frame of the poses; link poses are turned into\n"
    "                     the optical frame (auto: bags by child_frame_id, text files as given)\n"
    "  --assoc A          auto|tum|evo|index (auto: index for two KITTI files without stamps, else tum)\n"
    "  --max-diff S       association tolerance in s (default 0.02)\n"
    "  --align A          se3|sim3|first|none for the ATE (default se3)\n"
    "  --rpe-delta M      RPE segment in m (default 10)\n"
    "  --drift-lengths L  segment lengths in m for drift, comma separated (default 1,2,5,10)\n"
    "  --up AX            world up axis x|y|z|-x|-y|-z|auto (default: z for bags, auto for text files)\n"
    "  --forward AX       body forward axis (default z: optical / KITTI camera frame)\n"
    "  --plot PREFIX      write PREFIX_topdown.png and PREFIX_side.png (default ./<EST name>)\n"
    "  --no-plot          no PNG\n"
    "  --live             read the two topics from a running ROS graph instead of files (needs a master);\n"
    "                     stops --duration S (wall clock) after the first message, else on Ctrl-C\n";

bool isBag(const std::string& p) { return p.size() > 4 && p.substr(p.size() - 4) == ".bag"; }

std::string guessFormat(const std::string& path)
{
  std::ifstream f(path);
  if (!f)
    throw std::runtime_error("cannot open '" + path + "'");
  std::string line;
  while (std::getline(f, line))
  {
    const auto p = line.find_first_not_of(" \t\r");
    if (p == std::string::npos || line[p] == '#')
      continue;
    for (char& c : line)
      if (c == ',' || c == '\t')
        c = ' ';
    std::istringstream is(line);
    std::string tok;
    int n = 0;
    while (is >> tok)
      ++n;
    if (n == 12)
      return "kitti";
    if (n == 8)
      return "tum";
    throw std::runtime_error(path + ": " + std::to_string(n) + " values per line: neither TUM (8) nor KITTI (12)");
  }
  throw std::runtime_error(path + ": empty");
}

Eigen::Vector3d axisOf(const std::string& s)
{
  const double sign = (!s.empty() && s[0] == '-') ? -1.0 : 1.0;
  const char c = s.empty() ? 'z' : s.back();
  if (c == 'x')
    return sign * Eigen::Vector3d::UnitX();
  if (c == 'y')
    return sign * Eigen::Vector3d::UnitY();
  if (c == 'z')
    return sign * Eigen::Vector3d::UnitZ();
  throw std::runtime_error("axis '" + s + "' is not one of x y z -x -y -z");
}

struct Source
{
  Trajectory traj;
  std::string description;
  bool kitti_without_times = false;
};

Source load(const std::string& path, const std::string& topic, const std::string& format, const std::string& times,
            const std::string& body)
{
  Source s;
  if (isBag(path))
  {
    std::string child;
    s.traj = cli::readOdometry(path, topic, &child);
    const bool link = body == "link" || (body == "auto" && child.find("optical") == std::string::npos);
    if (link)
      for (auto& sp : s.traj)
        sp.pose = sp.pose * linkToOptical();
    s.description = path + " " + topic + " (child " + child + (link ? ", camera_link -> optical" : "") + ")";
    return s;
  }
  const std::string f = format == "auto" ? guessFormat(path) : format;
  if (f == "kitti")
  {
    s.traj = readKitti(path, times);
    s.kitti_without_times = times.empty();
  }
  else if (f == "tum")
    s.traj = readTum(path);
  else
    throw std::runtime_error("format '" + f + "' is not tum or kitti");
  if (body == "link")
    for (auto& sp : s.traj)
      sp.pose = sp.pose * linkToOptical();
  s.description = path + " (" + f + ")";
  return s;
}

std::vector<double> parseList(const std::string& s)
{
  std::vector<double> v;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ','))
    v.push_back(std::stod(tok));
  return v;
}
}  // namespace

int main(int argc, char** argv)
{
  return cli::runMain("evaluate_trajectory", USAGE, [&]() -> int {
    const cli::Args args(argc, argv,
                         {"gt-topic", "est-topic", "gt-format", "est-format", "gt-times", "est-times", "gt-body",
                          "est-body", "assoc", "max-diff", "align", "rpe-delta", "drift-lengths", "up", "forward",
                          "plot", "duration"},
                         {"no-plot", "help", "live"});
    if (args.has("help"))
    {
      std::cout << USAGE;
      return 0;
    }
    const bool live = args.has("live");
    if ((!live && (args.positional.empty() || args.positional.size() > 2)) || (live && !args.positional.empty()))
    {
      std::cerr << USAGE;
      return 2;
    }
    Source gt, est;
    std::string gt_path, est_path;
    if (live)
    {
      gt_path = "live";
      est_path = "live_" + cli::baseName(args.get("est-topic", "/vo/odom"));
      std::string gc, ec;
      cli::collectLive(argc, argv, args.get("gt-topic", "/ground_truth/odom"), args.get("est-topic", "/vo/odom"),
                       args.getDouble("duration", 0.0), gt.traj, est.traj, &gc, &ec);
      auto toOptical = [](Source& s, const std::string& body, const std::string& child, const std::string& topic) {
        const bool link = body == "link" || (body == "auto" && child.find("optical") == std::string::npos);
        if (link)
          for (auto& sp : s.traj)
            sp.pose = sp.pose * linkToOptical();
        s.description = "live " + topic + " (child " + child + (link ? ", camera_link -> optical" : "") + ")";
      };
      toOptical(gt, args.get("gt-body", "auto"), gc, args.get("gt-topic", "/ground_truth/odom"));
      toOptical(est, args.get("est-body", "auto"), ec, args.get("est-topic", "/vo/odom"));
      for (char& c : est_path)
        if (c == '/')
          c = '_';
    }
    else
    {
      gt_path = args.positional[0];
      est_path = args.positional.size() == 2 ? args.positional[1] : gt_path;
      if (args.positional.size() == 1 && !isBag(gt_path))
        throw std::runtime_error("with a single argument it must be a bag holding both trajectories");
      gt = load(gt_path, args.get("gt-topic", "/ground_truth/odom"), args.get("gt-format", "auto"),
                args.get("gt-times"), args.get("gt-body", "auto"));
      est = load(est_path, args.get("est-topic", "/vo/odom"), args.get("est-format", "auto"), args.get("est-times"),
                 args.get("est-body", "auto"));
    }

    // association
    std::string assoc = args.get("assoc", "auto");
    if (assoc == "auto")
      assoc = (gt.kitti_without_times && est.kitti_without_times) ? "index" : "tum";
    AssociationMethod am = AssociationMethod::TUM_GREEDY;
    if (assoc == "evo")
      am = AssociationMethod::EVO_NEAREST;
    else if (assoc == "index")
      am = AssociationMethod::INDEX;
    else if (assoc != "tum")
      throw std::runtime_error("--assoc must be auto, tum, evo or index");
    const double max_diff = args.getDouble("max-diff", 0.02);
    const MatchedTrajectories m = match(gt.traj, est.traj, max_diff, am);
    if (m.gt.size() < 2)
      throw std::runtime_error("only " + std::to_string(m.gt.size()) + " associated poses (gt " +
                               std::to_string(gt.traj.size()) + ", est " + std::to_string(est.traj.size()) +
                               "); check the stamps / --max-diff");

    TrajectoryEvalParams p;
    const std::string align = args.get("align", "se3");
    if (align == "se3")
      p.ate_align = AlignMode::SE3;
    else if (align == "sim3")
      p.ate_align = AlignMode::SIM3;
    else if (align == "first")
      p.ate_align = AlignMode::FIRST_POSE;
    else if (align == "none")
      p.ate_align = AlignMode::NONE;
    else
      throw std::runtime_error("--align must be se3, sim3, first or none");
    p.rpe_delta_m = args.getDouble("rpe-delta", 10.0);
    if (args.has("drift-lengths"))
      p.drift_lengths_m = parseList(args.get("drift-lengths"));
    // up axis: bags follow the README (gt_world z up); text files: the axis the truth moves least along
    std::string up = args.get("up", (live || isBag(gt_path)) ? "z" : "auto");
    if (up == "auto")
    {
      Eigen::Vector3d lo = m.gt[0].pose.translation(), hi = lo;
      for (const auto& sp : m.gt)
      {
        lo = lo.cwiseMin(sp.pose.translation());
        hi = hi.cwiseMax(sp.pose.translation());
      }
      Eigen::Index k = 0;
      (hi - lo).minCoeff(&k);
      up = k == 0 ? "x" : (k == 1 ? "-y" : "z");
    }
    p.yaw.up = axisOf(up);
    p.yaw.forward = axisOf(args.get("forward", "z"));

    const TrajectoryReport r = evaluateTrajectory(m.gt, m.est, p);

    // plots (estimate aligned as for the ATE)
    std::string plot_top, plot_side;
    if (!args.has("no-plot"))
    {
      const std::string prefix = args.get("plot", "./" + cli::baseName(est_path));
      const Trajectory aligned = applyAlignment(m.est, r.alignment);
      PlotOptions o;
      Eigen::Index upk = 0;
      p.yaw.up.cwiseAbs().maxCoeff(&upk);
      o.axis_up = static_cast<int>(upk);
      o.up_sign = p.yaw.up[upk] > 0 ? 1.0 : -1.0;
      o.axis_h = upk == 0 ? 1 : 0;
      o.axis_v = upk == 2 ? 1 : 2;
      o.title = cli::baseName(est_path) + " vs truth, ATE " + jsonNumber(r.ate.rmse, 4) + " m";
      std::vector<PlotSeries> series{{"truth", positions(m.gt), cv::Scalar(0, 150, 0)},
                                     {"estimate (" + align + " aligned)", positions(aligned), cv::Scalar(0, 0, 230)}};
      std::unique_ptr<Grid> floor;
      if (isBag(gt_path))
      {
        try
        {
          auto grids = cli::readGrids(gt_path, "/ground_truth/occupancy", 1);
          if (!grids.empty() && std::abs(std::atan2(grids[0].origin.linear()(1, 0), grids[0].origin.linear()(0, 0))) < 1e-9)
          {
            floor = std::make_unique<Grid>(grids[0].grid);
            floor->origin_x = grids[0].origin.translation().x();
            floor->origin_y = grids[0].origin.translation().y();
          }
        }
        catch (const std::exception&)
        {
          // no floor plan in this bag: plot the paths alone
        }
      }
      std::string err;
      plot_top = prefix + "_topdown.png";
      plot_side = prefix + "_side.png";
      if (!writePng(plot_top, plotTopDown(series, floor.get(), o), &err) ||
          !writePng(plot_side, plotSideView(series, o), &err))
      {
        std::cerr << "evaluate_trajectory: warning: " << err << "\n";
        plot_top = plot_side = "";
      }
    }

    std::printf("ground truth   %s, %zu poses\n", gt.description.c_str(), gt.traj.size());
    std::printf("estimate       %s, %zu poses\n", est.description.c_str(), est.traj.size());
    std::printf("association    %s, max diff %.4f s: %zu pairs\n", assoc.c_str(), max_diff, m.gt.size());
    std::printf("alignment      %s; RPE delta %.2f m; up axis %s\n", align.c_str(), p.rpe_delta_m, up.c_str());
    std::printf("%s", reportTable(r).c_str());
    if (!plot_top.empty())
      std::printf("plots          %s %s\n", plot_top.c_str(), plot_side.c_str());
    std::string j = reportJson(r);
    j.pop_back();
    std::ostringstream extra;
    extra << ", \"pairs\": " << m.gt.size() << ", \"association\": \"" << assoc << "\", \"align\": \"" << align
          << "\", \"ate_std_m\": " << jsonNumber(r.ate.std) << ", \"ate_min_m\": " << jsonNumber(r.ate.min)
          << ", \"ate_sse\": " << jsonNumber(r.ate.sse, 9) << ", \"rpe_delta_m\": " << jsonNumber(p.rpe_delta_m)
          << ", \"rpe_mean_m\": " << jsonNumber(r.rpe.mean) << ", \"rpe_median_m\": " << jsonNumber(r.rpe.median)
          << ", \"rpe_min_m\": " << jsonNumber(r.rpe.min) << ", \"rpe_max_m\": " << jsonNumber(r.rpe.max)
          << ", \"plot_topdown\": " << (plot_top.empty() ? "null" : "\"" + plot_top + "\"")
          << ", \"plot_side\": " << (plot_side.empty() ? "null" : "\"" + plot_side + "\"") << "}";
    std::printf("%s%s\n", j.c_str(), extra.str().c_str());
    return 0;
  });
}
