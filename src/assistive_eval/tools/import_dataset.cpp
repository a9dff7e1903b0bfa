// rosrun assistive_eval import_dataset {kitti|euroc|pairs} SRC --out FILE.bag [--max-frames N]
//     [--truth image_stamp|devkit]
// Turns a real stereo dataset into a stereo bag with the layout of render_bag (README
// "Topics of a stereo bag"): rectified mono8 images + camera_info, and /ground_truth/odom + gt tf
// where the dataset has truth. Progress on stderr; a table, then one JSON line on stdout.
#include <assistive_eval/datasets.h>
#include <assistive_eval/stereo_bag.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "cli_common.h"

namespace
{
const char* USAGE =
    "usage: import_dataset {kitti|euroc|pairs} SRC --out FILE.bag [--max-frames N] [--truth image_stamp|devkit]\n"
    "  kitti: a KITTI raw 'sync' drive folder (image_00, image_01, oxts, calib_*.txt here or in the parent)\n"
    "         --truth image_stamp (default): the OXTS pose moved to each image's stamp with the OXTS\n"
    "         velocity and rates; devkit: OXTS sample i as it is for image i (up to 5 ms off)\n"
    "  euroc: an EuRoC MAV folder (mav0/cam0, mav0/cam1 with sensor.yaml, state_groundtruth_estimate0)\n"
    "  pairs: left/ and right/ rectified images + stereo_left.yaml / stereo_right.yaml (ROS camera_info)\n";
}

int main(int argc, char** argv)
{
  using namespace assistive_eval;
  std::string created;  // the output bag once this run has opened (truncated) it
  // On an error the writer is closed by now (stack unwinding): remove the partial bag rather than
  // leave a bag that looks complete.
  auto removePartial = [&] {
    std::cerr << "\n";  // after the progress bar
    if (!created.empty() && std::remove(created.c_str()) == 0)
      std::cerr << "import_dataset: removed the partial output " << created << "\n";
  };
  return cli::runMain("import_dataset", USAGE, [&]() -> int {
    const cli::Args args(argc, argv, {"out", "max-frames", "truth"}, {"help"});
    if (args.has("help"))
    {
      std::cout << USAGE;
      return 0;
    }
    if (args.positional.size() != 2 || !args.has("out"))
      throw cli::UsageError(!args.has("out") ? "--out FILE.bag is required" : "need a dataset kind and a source folder");
    const std::string kind = args.positional[0], src_dir = args.positional[1], out = args.get("out");
    DatasetOptions options;
    if (args.has("truth"))
    {
      const std::string t = args.get("truth");
      if (t != "image_stamp" && t != "devkit")
        throw cli::UsageError("option --truth: image_stamp or devkit, got '" + t + "'");
      if (kind != "kitti")
        throw cli::UsageError("option --truth applies to kitti only");
      options.kitti_truth = parseKittiTruth(t);
    }
    auto src = openDataset(kind, src_dir, options);
    size_t n = src->size();
    if (args.has("max-frames"))
    {
      const double m = args.getDouble("max-frames", 0);
      if (m < 1 || m != std::floor(m))
        throw cli::UsageError("option --max-frames: need a whole number >= 1, got '" + args.get("max-frames") + "'");
      n = std::min(n, static_cast<size_t>(m));
    }
    StereoBagWriter writer(out);
    created = out;
    size_t gt_frames = 0;
    double path = 0.0;
    Eigen::Vector3d prev = Eigen::Vector3d::Zero();
    StereoCalib calib;
    double t0 = 0.0, t1 = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
      const StereoFrame f = src->frame(i);
      writer.writeFrame(f);
      if (i == 0)
      {
        calib = f.calib;
        t0 = f.stamp;
      }
      t1 = f.stamp;
      if (f.has_gt_pose)
      {
        if (gt_frames > 0)
          path += (f.gt_pose.translation() - prev).norm();
        prev = f.gt_pose.translation();
        ++gt_frames;
      }
      cli::progress(i + 1, n, "frames -> " + out);
    }
    writer.close();
    const bool has_gt = gt_frames > 0;
    std::printf("dataset           %s (%s)\n", kind.c_str(), src_dir.c_str());
    std::printf("bag               %s\n", out.c_str());
    std::printf("frames            %zu (%.3f s)\n", n, t1 - t0);
    std::printf("image size        %d x %d\n", calib.width, calib.height);
    std::printf("rectified calib   fx %.4f fy %.4f cx %.4f cy %.4f px, baseline %.5f m\n", calib.fx, calib.fy,
                calib.cx, calib.cy, calib.baseline);
    std::printf("ground truth      %s (%zu frames, path %.3f m)\n", has_gt ? "yes" : "no", gt_frames, path);
    if (!src->truthNote().empty())
      std::printf("truth             %s\n", src->truthNote().c_str());
    const std::string truth_key =
        kind == "kitti" && has_gt ? std::string("\"") + toString(options.kitti_truth) + "\"" : "null";
    std::printf("{\"frames\": %zu, \"has_ground_truth\": %s, \"kind\": \"%s\", \"width\": %d, \"height\": %d, "
                "\"fx_px\": %.4f, \"baseline_m\": %.5f, \"gt_path_m\": %s, \"kitti_truth\": %s}\n",
                n, has_gt ? "true" : "false", kind.c_str(), calib.width, calib.height, calib.fx, calib.baseline,
                has_gt ? std::to_string(path).c_str() : "null", truth_key.c_str());
    return 0;
  }, removePartial);
}
