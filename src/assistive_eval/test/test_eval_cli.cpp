// The evaluation CLIs end to end on a generated bag (no roscore): a walk with a known 4 % scale
// drift in the pipeline's odometry (camera_link in odom, rotated 90 deg from gt_world), and
// obstacle grids in the odom frame with one known false positive and one known miss.
#include <assistive_eval/bench_set.h>
#include <assistive_eval/map_score.h>
#include <assistive_eval/trajectory.h>
#include <assistive_eval/stereo_bag.h>

#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "real_data.h"

using namespace assistive_eval;

namespace
{
std::string exeDir()
{
  char buf[4096];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  std::string p(buf, n > 0 ? static_cast<size_t>(n) : 0);
  return p.substr(0, p.find_last_of('/'));
}

/// Runs a command; returns its exit code and stdout.
int run(const std::string& cmd, std::string& out)
{
  out.clear();
  FILE* f = ::popen((cmd + " 2>/dev/null").c_str(), "r");
  if (!f)
    return -1;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0)
    out.append(buf.data(), n);
  const int rc = ::pclose(f);
  return WEXITSTATUS(rc);
}

/// How a command ended: exit code (or the signal that killed it), stdout and stderr.
struct Outcome
{
  bool exited = false;  ///< false: killed by a signal (abort, segfault)
  int code = -1;        ///< exit code, or the signal number
  std::string out, err;
};
Outcome runCapture(const std::string& cmd)
{
  Outcome o;
  const std::string err_file = testing::TempDir() + "/cli_stderr_" + std::to_string(::getpid()) + ".txt";
  // exec: the shell becomes the command, so a signal reaches pclose as a signal, not as 128 + n
  FILE* f = ::popen(("exec " + cmd + " 2>" + err_file).c_str(), "r");
  if (!f)
    return o;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0)
    o.out.append(buf.data(), n);
  const int st = ::pclose(f);
  o.exited = WIFEXITED(st);
  o.code = o.exited ? WEXITSTATUS(st) : (WIFSIGNALED(st) ? WTERMSIG(st) : -1);
  std::ifstream e(err_file);
  std::stringstream ss;
  ss << e.rdbuf();
  o.err = ss.str();
  std::remove(err_file.c_str());
  return o;
}
/// A clean failure: a normal exit with a non-zero code below 128 (no abort, no signal).
::testing::AssertionResult cleanFailure(const Outcome& o)
{
  if (!o.exited)
    return ::testing::AssertionFailure() << "killed by signal " << o.code << "; stderr: " << o.err;
  if (o.code == 0 || o.code >= 128)
    return ::testing::AssertionFailure() << "exit code " << o.code << "; stderr: " << o.err;
  return ::testing::AssertionSuccess();
}
bool fileExists(const std::string& p)
{
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

std::string lastLine(const std::string& s)
{
  std::string t = s;
  while (!t.empty() && t.back() == '\n')
    t.pop_back();
  const auto p = t.find_last_of('\n');
  return p == std::string::npos ? t : t.substr(p + 1);
}

/// A number of a JSON line; NaN for null / missing.
double jsonValue(const std::string& json, const std::string& key)
{
  return assistive_eval::jsonNumber(json, key, std::nan(""));
}

Eigen::Isometry3d gtPose(double s)  // optical frame, walking along +y of gt_world
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(2.0, 3.0 + s, 1.6);
  T.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix() * linkToOptical().linear();
  return T;
}
Eigen::Isometry3d voPose(double s)  // camera_link in odom, 4 % too far
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(1.04 * s, 0.0, 1.6);
  return T;
}

bool inBox(const Eigen::Vector2d& p) { return p.x() > 3.0 && p.x() < 3.6 && p.y() > 4.0 && p.y() < 4.6; }

nav_msgs::Odometry odom(const Eigen::Isometry3d& T, double t, const std::string& frame, const std::string& child)
{
  nav_msgs::Odometry m;
  m.header.stamp = ros::Time(t);
  m.header.frame_id = frame;
  m.child_frame_id = child;
  m.pose.pose = tf2::toMsg(T);
  return m;
}

std::string makeBag()
{
  const std::string path = testing::TempDir() + "/eval_cli_test.bag";
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  const double t0 = 100.0;
  // truth grid: 40 x 40 m of 0.2 m cells from (-10, -10), free with a 3 x 3 cell box
  nav_msgs::OccupancyGrid gt;
  gt.header.stamp = ros::Time(t0);
  gt.header.frame_id = "gt_world";
  gt.info.resolution = 0.2f;
  gt.info.width = gt.info.height = 200;
  gt.info.origin.position.x = gt.info.origin.position.y = -10.0;
  gt.info.origin.orientation.w = 1.0;
  gt.data.assign(200 * 200, 0);
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x)
      if (inBox(Eigen::Vector2d(-10.0 + 0.2 * x + 0.1, -10.0 + 0.2 * y + 0.1)))
        gt.data[static_cast<size_t>(y) * 200 + x] = 100;
  bag.write("/ground_truth/occupancy", ros::Time(t0), gt);
  for (int i = 0; i <= 100; ++i)
  {
    const double s = 0.1 * i, t = t0 + s;
    bag.write("/ground_truth/odom", ros::Time(t), odom(gtPose(s), t, "gt_world", "gt_camera_left_optical_frame"));
    bag.write("/vo/odom", ros::Time(t), odom(voPose(s), t, "odom", "camera_link"));
    if (i != 0 && i != 50)
      continue;
    // a perfect local map in odom, as seen from the drifting VO pose: odom point -> gt_world
    const double yaw_gt = M_PI / 2;
    const Eigen::Isometry2d T_gt_odom = (Eigen::Translation2d(2.0, 3.0 + s) * Eigen::Rotation2Dd(yaw_gt)) *
                                        Eigen::Translation2d(1.04 * s, 0.0).inverse();
    nav_msgs::OccupancyGrid e;
    e.header.stamp = ros::Time(t);
    e.header.frame_id = "odom";
    e.info.resolution = 0.2f;
    e.info.width = 90;
    e.info.height = 60;
    e.info.origin.position.x = -6.0;
    e.info.origin.position.y = -6.0;
    e.info.origin.orientation.w = 1.0;
    e.data.assign(90 * 60, 0);
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 90; ++x)
      {
        const Eigen::Vector2d g = T_gt_odom * Eigen::Vector2d(-6.0 + 0.2 * x + 0.1, -6.0 + 0.2 * y + 0.1);
        int8_t v = inBox(g) ? 100 : 0;
        if (i == 0 && std::abs(g.x() - 3.1) < 0.05 && std::abs(g.y() - 4.1) < 0.05)
          v = 0;  // the miss: a truth obstacle reported free
        if (i == 0 && std::abs(g.x() - 1.1) < 0.05 && std::abs(g.y() - 3.1) < 0.05)
          v = 100;  // the false positive
        e.data[static_cast<size_t>(y) * 90 + x] = v;
      }
    bag.write("/obstacles/traversability", ros::Time(t), e);
  }
  bag.close();
  return path;
}
}  // namespace

TEST(EvalCli, EvaluateTrajectoryReportsTheKnownScaleDrift)
{
  const std::string bag = makeBag();
  std::string out;
  ASSERT_EQ(run(exeDir() + "/evaluate_trajectory " + bag + " --plot " + testing::TempDir() + "/cli_traj", out), 0)
      << out;
  const std::string j = lastLine(out);
  ASSERT_EQ(j.front(), '{') << out;
  EXPECT_NEAR(jsonValue(j, "frames"), 101, 1e-9);
  EXPECT_NEAR(jsonValue(j, "drift_pct"), 4.0, 1e-4);
  EXPECT_NEAR(jsonValue(j, "endpoint_drift_pct"), 4.0, 1e-4);
  EXPECT_NEAR(jsonValue(j, "drift_deg_per_m"), 0.0, 1e-4);
  EXPECT_NEAR(jsonValue(j, "max_jump_m"), 0.004, 1e-5);
  EXPECT_NEAR(jsonValue(j, "yaw_err_deg_lt5"), 0.0, 1e-4);
  EXPECT_GT(jsonValue(j, "ate_rmse_m"), 0.01);
  std::ifstream png(testing::TempDir() + "/cli_traj_topdown.png");
  EXPECT_TRUE(png.good());
  // a missing topic is a clear error with a non-zero exit
  EXPECT_NE(run(exeDir() + "/evaluate_trajectory " + bag + " --est-topic /nope", out), 0);
}

TEST(EvalCli, EvaluateMapPlacesOdomGridsAndCountsTheKnownErrors)
{
  const std::string bag = makeBag();
  std::string out;
  ASSERT_EQ(run(exeDir() + "/evaluate_map " + bag + " --plot " + testing::TempDir() + "/cli_map", out), 0) << out;
  const std::string j = lastLine(out);
  ASSERT_EQ(j.front(), '{') << out;
  EXPECT_NEAR(jsonValue(j, "grids"), 2, 1e-9);
  // 3 m: only the first grid sees the box: 8 TP, 1 FN, 1 FP
  EXPECT_NEAR(jsonValue(j, "precision_3m"), 8.0 / 9.0, 1e-5);
  EXPECT_NEAR(jsonValue(j, "recall_3m"), 8.0 / 9.0, 1e-5);
  // 5 m: the second grid sees the whole box too: 17 TP
  EXPECT_NEAR(jsonValue(j, "precision_5m"), 17.0 / 18.0, 1e-5);
  EXPECT_NEAR(jsonValue(j, "recall_5m"), 17.0 / 18.0, 1e-5);
  EXPECT_NEAR(jsonValue(j, "coverage_5m"), 1.0, 1e-9);
  EXPECT_NEAR(jsonValue(j, "free_where_obstacle_cells"), 1, 1e-9);
  EXPECT_GT(jsonValue(j, "misclassified_3m"), 0.0);
  std::ifstream png(testing::TempDir() + "/cli_map_map.png");
  EXPECT_TRUE(png.good());
}

TEST(ImportDataset, KittiBagHasTheRenderBagLayoutAndReadsBack)
{
  const std::string rel = "stereo_sequence/kitti_raw_2011_09_26_drive_0001_sync_f000-059";
  REQUIRE_REAL_DATA(rel);
  const std::string bag = testing::TempDir() + "/import_kitti_test.bag";
  std::string out;
  // the devkit truth (OXTS sample i for image i) is the one the data README's figures describe
  ASSERT_EQ(run(exeDir() + "/import_dataset kitti " + realDataDir() + "/" + rel + " --out " + bag +
                    " --max-frames 20 --truth devkit",
                out),
            0)
      << out;
  const std::string j = lastLine(out);
  EXPECT_NE(j.find("\"frames\": 20"), std::string::npos) << j;
  EXPECT_NE(j.find("\"has_ground_truth\": true"), std::string::npos) << j;
  EXPECT_NE(j.find("\"kitti_truth\": \"devkit\""), std::string::npos) << j;
  // the renderer engineer's reader sees rectified mono8 pairs, the calibration and the truth
  StereoBagReader reader(bag);
  EXPECT_TRUE(reader.hasGroundTruth());
  EXPECT_EQ(reader.groundTruth().size(), 20u);
  StereoFrame f;
  size_t n = 0;
  Eigen::Isometry3d first = Eigen::Isometry3d::Identity(), last = first;
  while (reader.next(f))
  {
    if (n == 0)
    {
      EXPECT_EQ(f.left.cols, 1242);
      EXPECT_EQ(f.left.type(), CV_8UC1);
      EXPECT_NEAR(f.calib.fx, 721.5377, 1e-3);
      EXPECT_NEAR(f.calib.baseline, 0.53715, 1e-5);
      first = f.gt_pose;
    }
    ASSERT_TRUE(f.has_gt_pose) << n;
    last = f.gt_pose;
    ++n;
  }
  EXPECT_EQ(n, 20u);
  // README: frame 19 is 24.48 m ahead of frame 0 along the camera axis, 0.53 m to the right
  const Eigen::Isometry3d rel19 = first.inverse() * last;
  EXPECT_NEAR(rel19.translation().z(), 24.48, 0.01);
  EXPECT_NEAR(rel19.translation().x(), 0.53, 0.01);
  // and evaluate_trajectory reads the imported truth (against itself: zero error)
  ASSERT_EQ(run(exeDir() + "/evaluate_trajectory " + bag + " --est-topic /ground_truth/odom --no-plot", out), 0);
  EXPECT_NEAR(jsonValue(lastLine(out), "ate_rmse_m"), 0.0, 1e-6);
  EXPECT_NEAR(jsonValue(lastLine(out), "path_length_m"), 24.49, 0.01);
  // the default: the truth at the image stamps (frame 0's image is 3.4 ms after its OXTS sample,
  // frame 19's 1.95 ms: about 2 cm less path)
  ASSERT_EQ(run(exeDir() + "/import_dataset kitti " + realDataDir() + "/" + rel + " --out " + bag +
                    " --max-frames 20",
                out),
            0)
      << out;
  EXPECT_NE(lastLine(out).find("\"kitti_truth\": \"image_stamp\""), std::string::npos) << lastLine(out);
  EXPECT_NEAR(jsonValue(lastLine(out), "gt_path_m"), 24.4686, 0.001);
  // an unknown truth, or --truth for another kind, is a usage error
  EXPECT_EQ(run(exeDir() + "/import_dataset kitti " + realDataDir() + "/" + rel + " --out " + bag + " --truth nearest",
                out),
            2);
  EXPECT_EQ(run(exeDir() + "/import_dataset euroc " + realDataDir() + "/" + rel + " --out " + bag + " --truth devkit",
                out),
            2);
  std::remove(bag.c_str());
}

TEST(ImportDataset, MissingFolderIsAClearErrorWithNonZeroExit)
{
  std::string out;
  EXPECT_EQ(run(exeDir() + "/import_dataset euroc /nonexistent/euroc --out " + testing::TempDir() + "/x.bag", out), 1);
  EXPECT_EQ(run(exeDir() + "/import_dataset kitti", out), 2);  // usage
}

// ------------------------------------------------------------------ every CLI: --help, -h, unknown options
namespace
{
/// The repository's CLIs: this package's next to this test, the stage packages' in their devel
/// lib folders (devel/lib/<package>/<name>; built by .ci/build before the tests run).
std::vector<std::string> allClis()
{
  const std::string lib = exeDir() + "/..";
  return {exeDir() + "/import_dataset",
          exeDir() + "/evaluate_trajectory",
          exeDir() + "/evaluate_map",
          lib + "/assistive_sim/render_bag",
          lib + "/assistive_vo/vo_benchmark",
          lib + "/assistive_obstacles/obstacles_benchmark",
          lib + "/assistive_obstacles/disparity_benchmark",
          lib + "/assistive_planner/planner_benchmark",
          lib + "/assistive_tactile/tactile_benchmark",
          lib + "/assistive_tactile/sim_vest",
          lib + "/assistive_bringup/chain_benchmark"};
}
bool hasUsage(const std::string& s) { return s.find("usage:") != std::string::npos; }
}  // namespace

TEST(CliContract, HelpPrintsUsageAndExitsZeroUnknownOptionsFail)
{
  int checked = 0;
  for (const std::string& exe : allClis())
  {
    if (!fileExists(exe))
    {
      std::printf("[ SKIPPED  ] %s is not built\n", exe.c_str());
      continue;
    }
    ++checked;
    for (const char* h : {"--help", "-h"})
    {
      const Outcome o = runCapture(exe + " " + h);
      EXPECT_TRUE(o.exited && o.code == 0) << exe << " " << h << ": exit " << o.code << "\n" << o.err;
      EXPECT_TRUE(hasUsage(o.out)) << exe << " " << h << " stdout: " << o.out;
    }
    for (const char* bad : {"--no-such-option", "-q"})
    {
      const Outcome o = runCapture(exe + " " + bad);
      EXPECT_TRUE(cleanFailure(o)) << exe << " " << bad;
      EXPECT_EQ(o.out.find('{'), std::string::npos) << exe << " " << bad << " ran: " << o.out;
      if (exe.find("sim_vest") == std::string::npos)  // sim_vest names the argument, without usage
      {
        EXPECT_TRUE(hasUsage(o.err)) << exe << " " << bad << " stderr: " << o.err;
      }
    }
  }
  EXPECT_GE(checked, 3);  // this package's CLIs at least
}

// ------------------------------------------------------------------ broken stereo bags
namespace
{
/// A small stereo bag the benchmarks can run on: 4 frames of 160x120 random texture, the right
/// image 8 px shifted, ground-truth poses and an occupancy grid.
std::string goodStereoBag()
{
  const std::string path = testing::TempDir() + "/cli_good_stereo.bag";
  StereoBagWriter w(path);
  OccupancyGrid g;
  g.origin_x = g.origin_y = -5.0;
  g.resolution = 0.2;
  g.width = g.height = 50;
  g.data.assign(50 * 50, 0);
  w.writeOccupancy(g, 100.0);
  cv::RNG rng(7);
  cv::Mat noise(60, 84, CV_8UC1), big;  // blobs of about 2 px
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::resize(noise, big, cv::Size(168, 120), 0, 0, cv::INTER_LINEAR);
  for (int i = 0; i < 4; ++i)
  {
    StereoFrame f;
    f.stamp = 100.0 + i / 15.0;
    f.calib = StereoCalib{160, 120, 125.0, 125.0, 79.5, 59.5, 0.12};  // width height fx fy cx cy baseline
    f.left = big(cv::Rect(8, 0, 160, 120)).clone();
    f.right = big(cv::Rect(0, 0, 160, 120)).clone();
    f.has_gt_pose = true;
    f.gt_pose = Eigen::Translation3d(0.05 * i, 0.0, 1.6) * linkToLeftOptical();
    w.writeFrame(f);
  }
  w.close();
  return path;
}

/// A copy of `good` with images / camera_infos edited in place (return false to drop a message).
std::string editBag(const std::string& good, const std::string& name,
                    const std::function<bool(const std::string&, sensor_msgs::Image*, sensor_msgs::CameraInfo*)>& edit)
{
  const std::string path = testing::TempDir() + "/cli_" + name + ".bag";
  rosbag::Bag in(good, rosbag::bagmode::Read), out(path, rosbag::bagmode::Write);
  for (const rosbag::MessageInstance& m : rosbag::View(in))
  {
    if (auto img = m.instantiate<sensor_msgs::Image>())
    {
      sensor_msgs::Image c = *img;
      if (edit(m.getTopic(), &c, nullptr))
        out.write(m.getTopic(), m.getTime(), c);
    }
    else if (auto info = m.instantiate<sensor_msgs::CameraInfo>())
    {
      sensor_msgs::CameraInfo c = *info;
      if (edit(m.getTopic(), nullptr, &c))
        out.write(m.getTopic(), m.getTime(), c);
    }
    else if (edit(m.getTopic(), nullptr, nullptr))
      out.write(m.getTopic(), m.getTime(), m);
  }
  return path;
}

bool isStereoImage(const std::string& t) { return t == "/stereo/left/image_rect" || t == "/stereo/right/image_rect"; }
}  // namespace

TEST(CliContract, StereoBagClisFailCleanlyOnBrokenBags)
{
  const std::string lib = exeDir() + "/..";
  std::vector<std::string> clis;
  for (const std::string& e : {lib + "/assistive_vo/vo_benchmark", lib + "/assistive_obstacles/obstacles_benchmark"})
    if (fileExists(e))
      clis.push_back(e);
    else
      std::printf("[ SKIPPED  ] %s is not built\n", e.c_str());
  if (clis.empty())
    GTEST_SKIP() << "no stereo bag benchmark built";

  const std::string good = goodStereoBag();
  const std::string rgb8 = editBag(good, "rgb8", [](const std::string& t, sensor_msgs::Image* img, sensor_msgs::CameraInfo*) {
    if (img && isStereoImage(t))
    {
      std::vector<uint8_t> d;
      for (uint8_t v : img->data)
        d.insert(d.end(), {v, v, v});
      img->data = d;
      img->encoding = sensor_msgs::image_encodings::RGB8;
      img->step = img->width * 3;
    }
    return true;
  });
  const std::string depth = editBag(good, "32fc1", [](const std::string& t, sensor_msgs::Image* img, sensor_msgs::CameraInfo*) {
    if (img && isStereoImage(t))
    {
      img->encoding = sensor_msgs::image_encodings::TYPE_32FC1;
      img->step = img->width * 4;
      img->data.assign(img->step * img->height, 0);
    }
    return true;
  });
  const std::string noinfo = editBag(good, "noinfo", [](const std::string&, sensor_msgs::Image*, sensor_msgs::CameraInfo* c) {
    return c == nullptr;
  });
  const std::string nan = editBag(good, "naninfo", [](const std::string&, sensor_msgs::Image*, sensor_msgs::CameraInfo* c) {
    if (c)
      c->K[0] = c->P[0] = std::nan("");
    return true;
  });
  const std::string sizes = editBag(good, "sizes", [](const std::string& t, sensor_msgs::Image* img, sensor_msgs::CameraInfo*) {
    if (img && t == "/stereo/right/image_rect")
    {
      img->height /= 2;
      img->data.resize(img->step * img->height);
    }
    return true;
  });
  for (const std::string& exe : clis)
  {
    const std::string args = " --frames 3 " + std::string(exe.find("vo_") != std::string::npos ? "--no-peer --plot " : "--png ") +
                             testing::TempDir() + "/cli_broken_plot.png";
    // rgb8: converted to mono8 with a one-line warning, the run completes with its JSON line
    Outcome o = runCapture(exe + " " + rgb8 + args);
    EXPECT_TRUE(o.exited && o.code == 0) << exe << " rgb8: exit " << o.code << "\n" << o.err;
    EXPECT_NE(o.err.find("warning: rgb8 images"), std::string::npos) << o.err;
    EXPECT_EQ(lastLine(o.out).front(), '{') << o.out;
    // 32FC1 images: an error naming the encoding
    o = runCapture(exe + " " + depth + args);
    EXPECT_TRUE(cleanFailure(o)) << exe << " 32FC1";
    EXPECT_NE(o.err.find("'32FC1' is not supported"), std::string::npos) << o.err;
    // no camera_info / NaN camera_info: an error, never the default calibration
    o = runCapture(exe + " " + noinfo + args);
    EXPECT_TRUE(cleanFailure(o)) << exe << " no camera_info";
    EXPECT_NE(o.err.find("has no /stereo/left/camera_info"), std::string::npos) << o.err;
    o = runCapture(exe + " " + nan + args);
    EXPECT_TRUE(cleanFailure(o)) << exe << " NaN camera_info";
    EXPECT_NE(o.err.find("invalid intrinsics fx nan"), std::string::npos) << o.err;
    // left and right images of different sizes
    o = runCapture(exe + " " + sizes + args);
    EXPECT_TRUE(cleanFailure(o)) << exe << " sizes";
    EXPECT_NE(o.err.find("/stereo/left/image_rect is 160x120 but /stereo/right/image_rect is 160x60"),
              std::string::npos)
        << o.err;
  }
  for (const auto& p : {good, rgb8, depth, noinfo, nan, sizes})
    std::remove(p.c_str());
}

TEST(ImportDataset, SizeMismatchNamesTheImageAndLeavesNoPartialBag)
{
  // a 'pairs' folder of 64x48 images whose third right image is 40x30
  const std::string dir = testing::TempDir() + "/cli_pairs_mismatch";
  for (const std::string& sub : {std::string(), std::string("/left"), std::string("/right")})
    ::mkdir((dir + sub).c_str(), 0755);
  cv::RNG rng(3);
  for (int i = 0; i < 4; ++i)
  {
    cv::Mat img(48, 64, CV_8UC1);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    const std::string name = "/000" + std::to_string(i) + ".png";
    ASSERT_TRUE(cv::imwrite(dir + "/left" + name, img));
    ASSERT_TRUE(cv::imwrite(dir + "/right" + name, i == 2 ? cv::Mat(img(cv::Rect(0, 0, 40, 30))) : img));
  }
  for (const std::string side : {"left", "right"})
  {
    std::ofstream y(dir + "/stereo_" + side + ".yaml");
    y << "image_width: 64\nimage_height: 48\n"
         "camera_matrix: {rows: 3, cols: 3, data: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]}\n"
         "projection_matrix: {rows: 3, cols: 4, data: [50, 0, 31.5, "
      << (side == "left" ? "0" : "-6") << ", 0, 50, 23.5, 0, 0, 0, 1, 0]}\n";
  }
  const std::string bag = testing::TempDir() + "/cli_pairs_mismatch.bag";
  std::remove(bag.c_str());
  const Outcome o = runCapture(exeDir() + "/import_dataset pairs " + dir + " --out " + bag);
  EXPECT_TRUE(cleanFailure(o));
  EXPECT_NE(o.err.find("right image '" + dir + "/right/0002.png' is 40x30"), std::string::npos) << o.err;
  EXPECT_FALSE(fileExists(bag)) << "partial output left behind";
  // the first two frames alone import fine
  const Outcome ok = runCapture(exeDir() + "/import_dataset pairs " + dir + " --out " + bag + " --max-frames 2");
  EXPECT_TRUE(ok.exited && ok.code == 0) << ok.err;
  EXPECT_NE(lastLine(ok.out).find("\"frames\": 2"), std::string::npos) << ok.out;
  std::remove(bag.c_str());
}

TEST(ObstaclesBenchmarkCli, MapAtAnotherCellScoredAgainstTheWorldAtThatCell)
{
  // --set cell_size=0.1 on a bag whose truth is at 0.2 m: the truth is rasterised again from the
  // world at 0.1 m, so the figures equal those against a bag rendered with its truth at 0.1 m
  const std::string lib = exeDir() + "/..";
  const std::string ob = lib + "/assistive_obstacles/obstacles_benchmark", rb = lib + "/assistive_sim/render_bag";
  for (const std::string& e : {ob, rb})
    if (!fileExists(e))
      GTEST_SKIP() << "SKIPPED: " << e << " is not built";
  const std::string dir = testing::TempDir() + "/cli_cell_" + std::to_string(::getpid());
  ASSERT_EQ(::mkdir(dir.c_str(), 0755), 0);
  const std::string render = rb + " --world course --frames 12 --seed 3 --out " + dir;
  ASSERT_EQ(runCapture(render + "/a.bag").code, 0);
  ASSERT_EQ(runCapture(render + "/b.bag --truth-resolution 0.1").code, 0);
  const std::string bench = " --world course --set cell_size=0.1 --png " + dir + "/map.png";
  const Outcome a = runCapture(ob + " " + dir + "/a.bag" + bench);
  const Outcome b = runCapture(ob + " " + dir + "/b.bag" + bench);
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_NE(a.err.find("truth rasterised from"), std::string::npos) << a.err;
  EXPECT_EQ(b.err.find("truth rasterised from"), std::string::npos) << b.err;  // already at the map's cell
  std::map<std::string, double> va, vb;
  ASSERT_TRUE(parseJsonNumbers(lastJsonLine(a.out), &va)) << a.out;
  ASSERT_TRUE(parseJsonNumbers(lastJsonLine(b.out), &vb)) << b.out;
  for (const char* k : {"recall_3m", "precision_3m", "free_where_obstacle_cells", "coverage_3m", "fp_adjacent_3m"})
    EXPECT_EQ(va.at(k), vb.at(k)) << k;
  EXPECT_GT(va.at("coverage_3m"), 0.0);  // something was scored
  // without a world to rasterise from, the bag's own truth stays and a warning says so
  const Outcome c = runCapture(ob + " " + dir + "/a.bag --world none --set cell_size=0.1 --png " + dir + "/map.png");
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_NE(c.err.find("no world gives the truth at it"), std::string::npos) << c.err;
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}
