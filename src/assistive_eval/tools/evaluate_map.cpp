// rosrun assistive_eval evaluate_map BAG [options]
// Scores estimated obstacle grids (nav_msgs/OccupancyGrid, default /obstacles/traversability)
// against the bag's ground-truth occupancy within 3 m and 5 m of the wearer: precision, recall,
// misclassified fraction, coverage, and the cells ever reported free that are obstacles in the
// truth. Writes a colour-coded PNG of the last scored grid; a table, then one JSON line.
#include <assistive_eval/map_score.h>
#include <assistive_eval/metrics.h>
#include <assistive_eval/plots.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "cli_common.h"
#include "eval_ros.h"

using namespace assistive_eval;

namespace
{
const char* USAGE =
    "usage: evaluate_map BAG [options]\n"
    "  --est-topic T       estimated grid topic (default /obstacles/traversability)\n"
    "  --est-bag FILE      read the estimated grids (and --est-odom-topic) from another bag\n"
    "  --gt-topic T        ground-truth grid (default /ground_truth/occupancy)\n"
    "  --gt-odom-topic T   ground-truth pose of the wearer's camera (default /ground_truth/odom)\n"
    "  --est-odom-topic T  the pipeline's pose (default /vo/odom): places odom-frame grids in gt_world at each\n"
    "                      grid's stamp; without it, odom = the floor under the first true camera pose, x = its heading\n"
    "  --radii R           comma-separated radii in m (default 3,5)\n"
    "  --max-grids N       score at most N evenly spaced grids (default all)\n"
    "  --plot PREFIX       PNG of the last grid scored at the largest radius: PREFIX_map.png (default ./<BAG name>)\n"
    "  --no-plot           no PNG\n";

std::string radiusKey(double r)
{
  std::ostringstream os;
  if (std::abs(r - std::round(r)) < 1e-9)
    os << static_cast<long>(std::lround(r));
  else
    os << r;
  return os.str();
}

/// Nearest pose in time (binary search); false when further than `tol` seconds.
bool nearestPose(const Trajectory& t, double stamp, double tol, Eigen::Isometry3d& out)
{
  if (t.empty())
    return false;
  auto it = std::lower_bound(t.begin(), t.end(), stamp, [](const StampedPose& a, double s) { return a.t < s; });
  double best = 1e300;
  for (auto c : {it, it == t.begin() ? it : it - 1})
    if (c != t.end() && std::abs(c->t - stamp) < best)
    {
      best = std::abs(c->t - stamp);
      out = c->pose;
    }
  return best <= tol;
}

}  // namespace

int main(int argc, char** argv)
{
  return cli::runMain("evaluate_map", USAGE, [&]() -> int {
    const cli::Args args(argc, argv,
                         {"est-topic", "est-bag", "gt-topic", "gt-odom-topic", "est-odom-topic", "radii", "max-grids",
                          "plot"},
                         {"no-plot", "help"});
    if (args.has("help"))
    {
      std::cout << USAGE;
      return 0;
    }
    if (args.positional.size() != 1)
    {
      std::cerr << USAGE;
      return 2;
    }
    const std::string bag = args.positional[0], est_bag = args.get("est-bag", bag);
    const std::string est_topic = args.get("est-topic", "/obstacles/traversability");
    std::vector<double> radii;
    {
      std::stringstream ss(args.get("radii", "3,5"));
      std::string tok;
      while (std::getline(ss, tok, ','))
        radii.push_back(std::stod(tok));
    }
    if (radii.empty())
      throw std::runtime_error("--radii is empty");

    const auto gts = cli::readGrids(bag, args.get("gt-topic", "/ground_truth/occupancy"));
    const cli::StampedGrid& gtg = gts.back();
    if (std::abs(std::atan2(gtg.origin.linear()(1, 0), gtg.origin.linear()(0, 0))) > 1e-9)
      throw std::runtime_error("the ground-truth grid has a rotated origin; expected an axis-aligned gt_world grid");
    Grid gt = gtg.grid;
    gt.origin_x = gtg.origin.translation().x();
    gt.origin_y = gtg.origin.translation().y();

    std::string gt_child;
    Trajectory gt_odom = cli::readOdometry(bag, args.get("gt-odom-topic", "/ground_truth/odom"), &gt_child);
    const Eigen::Vector3d gt_forward =
        gt_child.find("optical") != std::string::npos ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
    Trajectory est_odom;
    Eigen::Vector3d est_forward = Eigen::Vector3d::UnitX();
    try
    {
      std::string child;
      est_odom = cli::readOdometry(est_bag, args.get("est-odom-topic", "/vo/odom"), &child);
      if (child.find("optical") != std::string::npos)
        est_forward = Eigen::Vector3d::UnitZ();
    }
    catch (const std::exception&)
    {
      est_odom.clear();  // optional: fall back to the first-pose convention
    }
    // odom per the README: floor under the camera's start, x = the initial heading
    const Eigen::Isometry2d T_gt_odom0 = planarPose(gt_odom.front().pose, gt_forward);

    const size_t max_grids = static_cast<size_t>(std::max(0.0, args.getDouble("max-grids", 0)));
    const auto grids = cli::readGrids(est_bag, est_topic, max_grids);

    std::vector<MapScoreAccumulator> acc(radii.size());
    size_t scored_grids = 0, skipped = 0;
    MapScore last_plot_score;
    Eigen::Vector2d last_wearer = Eigen::Vector2d::Zero();
    Eigen::Isometry2d last_T = Eigen::Isometry2d::Identity();
    const cli::StampedGrid* last_grid = nullptr;
    for (size_t k = 0; k < grids.size(); ++k)
    {
      const cli::StampedGrid& g = grids[k];
      cli::progress(k + 1, grids.size(), "grids");
      Eigen::Isometry3d wearer3;
      if (!nearestPose(gt_odom, g.stamp, 0.1, wearer3))
      {
        ++skipped;
        continue;
      }
      Eigen::Isometry2d T_gt_frame = Eigen::Isometry2d::Identity();
      if (g.frame_id.rfind("gt_", 0) == 0 || g.frame_id == gtg.frame_id)
        T_gt_frame = Eigen::Isometry2d::Identity();
      else if (!est_odom.empty())
      {
        Eigen::Isometry3d est3;
        if (!nearestPose(est_odom, g.stamp, 0.1, est3))
        {
          ++skipped;
          continue;
        }
        T_gt_frame = planarPose(wearer3, gt_forward) * planarPose(est3, est_forward).inverse();
      }
      else
        T_gt_frame = T_gt_odom0;
      const Eigen::Isometry2d T_est_gt = g.origin.inverse() * T_gt_frame.inverse();
      const Eigen::Vector2d wearer = wearer3.translation().head<2>();
      for (size_t i = 0; i < radii.size(); ++i)
      {
        MapScoreParams p;
        p.radius_m = radii[i];
        const MapScore s = scoreMap(gt, g.grid, wearer, p, T_est_gt);
        acc[i].add(s);
        if (i + 1 == radii.size())
          last_plot_score = s;
      }
      last_wearer = wearer;
      last_T = T_est_gt;
      last_grid = &g;
      ++scored_grids;
    }
    if (scored_grids == 0)
      throw std::runtime_error("no estimated grid could be placed: no ground-truth pose within 0.1 s of any grid stamp");
    std::ostringstream js;
    js << "{\"grids\": " << scored_grids;
    std::printf("ground truth   %s %s (%dx%d cells of %.2f m)\n", bag.c_str(), gtg.frame_id.c_str(), gt.width,
                gt.height, gt.resolution);
    std::printf("estimate       %s %s: %zu grids scored, %zu skipped (frame %s, %s)\n", est_bag.c_str(),
                est_topic.c_str(), scored_grids, skipped, grids.front().frame_id.c_str(),
                est_odom.empty() ? "placed by the first true pose" : "placed by the estimated pose per grid");
    std::printf("radius   precision   recall   misclassified   coverage        tp        fp        fn        tn  "
                "est_unknown\n");
    for (size_t i = 0; i < radii.size(); ++i)
    {
      const MapScore t = acc[i].total();
      std::printf("%4.1f m  %10s %8s %15s %10s %9zu %9zu %9zu %9zu %12zu\n", radii[i], jsonNumber(t.precision, 4).c_str(),
                  jsonNumber(t.recall, 4).c_str(), jsonNumber(t.misclassified, 4).c_str(),
                  jsonNumber(t.coverage, 4).c_str(), t.tp, t.fp, t.fn, t.tn, t.est_unknown);
      const std::string r = radiusKey(radii[i]);
      js << ", \"precision_" << r << "m\": " << jsonNumber(t.precision) << ", \"recall_" << r
         << "m\": " << jsonNumber(t.recall) << ", \"misclassified_" << r << "m\": " << jsonNumber(t.misclassified)
         << ", \"coverage_" << r << "m\": " << jsonNumber(t.coverage);
    }
    std::printf("free_where_obstacle_cells  %zu (distinct truth cells ever reported free within %.1f m)\n",
                acc.back().freeWhereObstacleCells(), radii.back());
    js << ", \"free_where_obstacle_cells\": " << acc.back().freeWhereObstacleCells();
    std::string plot;
    if (!args.has("no-plot") && last_grid)
    {
      plot = args.get("plot", "./" + cli::baseName(est_bag)) + "_map.png";
      std::string err;
      const cv::Mat img = plotMapScore(gt, last_grid->grid, last_wearer, radii.back(), last_T, 0,
                                       "last grid, " + radiusKey(radii.back()) + " m: precision " +
                                           jsonNumber(last_plot_score.precision, 3) + " recall " +
                                           jsonNumber(last_plot_score.recall, 3));
      if (!writePng(plot, img, &err))
      {
        std::cerr << "evaluate_map: warning: " << err << "\n";
        plot.clear();
      }
      else
        std::printf("plot           %s\n", plot.c_str());
    }
    js << ", \"plot_map\": " << (plot.empty() ? "null" : "\"" + plot + "\"") << "}";
    std::printf("%s\n", js.str().c_str());
    return 0;
  });
}
