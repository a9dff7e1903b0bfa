// The evaluation CLIs end to end on a generated bag (no roscore): a walk with a known 4 % scale
// drift in the pipeline's odometry (camera_link in odom, rotated 90 deg from gt_world), and
// obstacle grids in the odom frame with one known false positive and one known miss.
#include <assistive_sim/eval/map_score.h>
#include <assistive_sim/eval/trajectory.h>
#include <assistive_sim/stereo_bag.h>

#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <tf2_eigen/tf2_eigen.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <memory>
#include <unistd.h>

#include "real_data.h"

using namespace assistive_sim;
using namespace assistive_sim::eval;

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

std::string lastLine(const std::string& s)
{
  std::string t = s;
  while (!t.empty() && t.back() == '\n')
    t.pop_back();
  const auto p = t.find_last_of('\n');
  return p == std::string::npos ? t : t.substr(p + 1);
}

/// Number after "\"key\": " in a flat JSON object; NaN for null / missing.
double jsonValue(const std::string& json, const std::string& key)
{
  const auto p = json.find("\"" + key + "\": ");
  if (p == std::string::npos)
    return std::nan("");
  const std::string rest = json.substr(p + key.size() + 4);
  if (rest.rfind("null", 0) == 0)
    return std::nan("");
  return std::stod(rest);
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
  ASSERT_EQ(run(exeDir() + "/import_dataset kitti " + realDataDir() + "/" + rel + " --out " + bag +
                    " --max-frames 20",
                out),
            0)
      << out;
  const std::string j = lastLine(out);
  EXPECT_NE(j.find("\"frames\": 20"), std::string::npos) << j;
  EXPECT_NE(j.find("\"has_ground_truth\": true"), std::string::npos) << j;
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
  std::remove(bag.c_str());
}

TEST(ImportDataset, MissingFolderIsAClearErrorWithNonZeroExit)
{
  std::string out;
  EXPECT_EQ(run(exeDir() + "/import_dataset euroc /nonexistent/euroc --out " + testing::TempDir() + "/x.bag", out), 1);
  EXPECT_EQ(run(exeDir() + "/import_dataset kitti", out), 2);  // usage
}
