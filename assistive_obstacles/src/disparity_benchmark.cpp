// rosrun assistive_obstacles disparity_benchmark DIR
// Scores the obstacle stage's DEFAULT disparity configuration on the real stereo pairs of DIR
// (default $ASSISTIVE_REAL_DATA/stereo_disparity, else the folder beside the workspace,
// ../shared/data/real/stereo_disparity: items 3-5 of its README) beside the peer,
// full-resolution OpenCV SGBM, in the same run. KITTI D1 = % of valid GT px with |err| > 3 px and
// > 5 % of GT; Middlebury bad-2.0 = % of valid GT px with |err| > 2 px. Pixels without an
// estimate count as errors (no interpolation). Last stdout line: one JSON object.
#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <assistive_eval/benchmark.h>
#include <assistive_eval/disparity_eval.h>
#include <assistive_obstacles/disparity.h>

#ifndef ASSISTIVE_REAL_DATA_DIR  // set by CMake: the folder beside the workspace
#define ASSISTIVE_REAL_DATA_DIR "../shared/data/real"
#endif

using namespace assistive_obstacles;

namespace ev = assistive_eval;

int main(int argc, char** argv)
{
  std::string dir;
  int reps = 5;
  const char* usage =
      "usage: disparity_benchmark [DIR] [--reps N]\n"
      "  Scores the default disparity configuration on the real stereo pairs of DIR (default\n"
      "  $ASSISTIVE_REAL_DATA/stereo_disparity, else " ASSISTIVE_REAL_DATA_DIR "/stereo_disparity)\n"
      "  beside OpenCV SGBM; --reps timing repetitions (default 5).\n"
      "  Last stdout line: JSON.\n";
  ev::CommandLine cl("disparity_benchmark", usage);
  cl.positional(&dir, "DIR", false).count("--reps", &reps, 1);
  if (const int rc = cl.parse(argc, argv); rc >= 0)
    return rc;
  if (dir.empty())
  {
    const char* env = std::getenv("ASSISTIVE_REAL_DATA");
    dir = ((env && *env) ? std::string(env) : std::string(ASSISTIVE_REAL_DATA_DIR)) + "/stereo_disparity";
  }
  const ObstaclesParams defaults;  // the stage's default configuration
  DisparityEstimator ours(defaults);
  const int peer_nd = defaults.max_disparity;

  struct Row
  {
    std::string name;
    ev::DisparityScore ours, peer;
    double ms = NAN, peer_ms = NAN;
    int w = 0, h = 0;
  };
  std::vector<Row> rows;
  std::vector<std::string> skipped;
  const std::vector<ev::RealPair> pairs = ev::loadRealPairs(dir, &skipped);
  for (const std::string& m : skipped) std::cerr << "[disparity_benchmark] skipped " << m << "\n";
  for (const ev::RealPair& it : pairs)
  {
    const cv::Mat &l = it.left, &r = it.right;
    std::cerr << "[disparity_benchmark] " << it.name << " " << l.cols << "x" << l.rows << " ...\n";
    Row row;
    row.name = it.name;
    row.w = l.cols;
    row.h = l.rows;
    cv::Mat d_ours, d_peer;
    ours.computeFullRes(l, r, d_ours);  // warm-up
    row.ms = ev::medianWallMs([&] { ours.computeFullRes(l, r, d_ours); }, reps);
    row.peer_ms = ev::medianWallMs([&] { d_peer = ev::peerSgbm(l, r, peer_nd); }, reps);
    row.ours = ev::scoreDisparity(d_ours, it.gt);
    row.peer = ev::scoreDisparity(d_peer, it.gt);
    rows.push_back(row);
  }
  if (rows.empty())
  {
    std::cout << "disparity_benchmark: no dataset found under " << dir << " (skipped)\n";
    std::cout << "{\"d1_pct\": null, \"bad2_pct\": null, \"ms\": null, \"peer_d1_pct\": null, "
                 "\"peer_bad2_pct\": null, \"peer_ms\": null, \"skipped\": true}"
              << std::endl;
    return 0;
  }

  std::printf("default configuration: %s, scale %.2f, %d disparities at that scale (max %d px full res), block %d\n",
              defaults.disparity_method.c_str(), defaults.disparity_scale, ours.numDisparities(),
              defaults.max_disparity, defaults.block_size);
  std::printf("peer: OpenCV SGBM (MODE_SGBM), full resolution, %d disparities, block 5\n", peer_nd);
  std::printf("%-30s %10s | %8s %8s %8s %8s | %8s %8s %8s %8s\n", "pair", "size", "D1 %", "bad2 %", "dens %", "ms",
              "peer D1", "bad2", "dens", "ms");
  double ms_sum = 0, pms_sum = 0;
  std::vector<double> b2, pb2;
  double d1 = NAN, pd1 = NAN;
  for (const Row& r : rows)
  {
    std::printf("%-30s %4dx%-5d | %8.2f %8.2f %8.1f %8.1f | %8.2f %8.2f %8.1f %8.1f\n", r.name.c_str(), r.w, r.h,
                r.ours.d1_pct, r.ours.bad2_pct, r.ours.density_pct, r.ms, r.peer.d1_pct, r.peer.bad2_pct, r.peer.density_pct, r.peer_ms);
    ms_sum += r.ms;
    pms_sum += r.peer_ms;
    if (r.name.rfind("kitti", 0) == 0)
    {
      d1 = r.ours.d1_pct;
      pd1 = r.peer.d1_pct;
    }
    else
    {
      b2.push_back(r.ours.bad2_pct);
      pb2.push_back(r.peer.bad2_pct);
    }
  }
  const double bad2 = ev::mean(b2), pbad2 = ev::mean(pb2);
  const double ms = ms_sum / rows.size(), pms = pms_sum / rows.size();
  std::printf("\nd1_pct (KITTI) %.2f vs peer %.2f (ratio %.2f, target <= 1.5)\n", d1, pd1, d1 / pd1);
  std::printf("bad2_pct (Middlebury mean) %.2f vs peer %.2f (ratio %.2f, target <= 1.5)\n", bad2, pbad2, bad2 / pbad2);
  std::printf("ms per pair (mean) %.1f vs peer %.1f (speed-up %.1fx, target >= 3)\n", ms, pms, pms / ms);
  auto num = [](double v) { return ev::jsonFixed(v, 3); };
  ev::JsonLine js;
  js.add("d1_pct", num(d1)).add("bad2_pct", num(bad2)).add("ms", num(ms)).add("peer_d1_pct", num(pd1))
      .add("peer_bad2_pct", num(pbad2)).add("peer_ms", num(pms)).add("speedup", num(pms / ms));
  for (const Row& r : rows)
    js.add(r.name + "_d1_pct", num(r.ours.d1_pct)).add(r.name + "_bad2_pct", num(r.ours.bad2_pct))
        .add(r.name + "_ms", num(r.ms)).add(r.name + "_peer_d1_pct", num(r.peer.d1_pct))
        .add(r.name + "_peer_bad2_pct", num(r.peer.bad2_pct)).add(r.name + "_peer_ms", num(r.peer_ms));
  std::cout << js.str() << std::endl;
  return 0;
}
