// Each shipped world renders to a bag from one command (render_bag), with the README topics.
#include <assistive_eval/stereo_bag.h>
#include <assistive_msgs/MoverArray.h>
#include <assistive_sim/world.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

using namespace assistive_eval;  // render_bag writes the evaluation package's stereo bag layout

class RenderBagCli : public ::testing::TestWithParam<const char*>
{
};

TEST_P(RenderBagCli, WorldRendersToBag)
{
  const std::string world = GetParam();
  const std::string bag = std::string(::testing::TempDir()) + "assistive_sim_cli_" + world + ".bag";
  const std::string log = bag + ".log";
  const std::string cmd = std::string(RENDER_BAG_EXE) + " --world " + world + " --out " + bag +
                          " --frames 3 --width 160 --height 120 --seed 2 > " + log + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  // Last stdout line: JSON with frames and render_fps.
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  EXPECT_EQ(last.front(), '{');
  EXPECT_NE(last.find("\"frames\": 3"), std::string::npos) << last;
  EXPECT_NE(last.find("\"render_fps\": "), std::string::npos) << last;

  rosbag::Bag b(bag, rosbag::bagmode::Read);
  auto count = [&](const std::string& topic) {
    rosbag::View v(b, rosbag::TopicQuery(topic));
    return v.size();
  };
  EXPECT_EQ(count("/stereo/left/image_rect"), 3u);
  EXPECT_EQ(count("/stereo/right/image_rect"), 3u);
  EXPECT_EQ(count("/stereo/left/camera_info"), 3u);
  EXPECT_EQ(count("/stereo/right/camera_info"), 3u);
  // the reference camera: its emitter-on pairs beside the emitter-off ones (issue 35)
  EXPECT_EQ(count("/stereo/projected/left/image_rect"), 3u);
  EXPECT_EQ(count("/stereo/projected/right/image_rect"), 3u);
  EXPECT_EQ(count("/stereo/projected/left/camera_info"), 3u);
  EXPECT_EQ(count("/stereo/projected/right/camera_info"), 3u);
  EXPECT_EQ(count("/ground_truth/odom"), 3u);
  EXPECT_EQ(count("/ground_truth/occupancy"), 1u);
  EXPECT_EQ(count("/tf"), 3u);
  EXPECT_EQ(count("/imu/data"), 1u + 2u * 200u / 15u);  // samples up to t = 2/15 s at 200 Hz
  // People truth: one message per frame in the busy worlds, none in the static ones.
  EXPECT_EQ(count("/ground_truth/people"), world.find("_busy") != std::string::npos ? 3u : 0u);
  b.close();

  StereoBagReader r(bag);
  StereoFrame f;
  ASSERT_TRUE(r.next(f));
  EXPECT_EQ(f.left.cols, 160);
  EXPECT_NEAR(f.calib.baseline, 0.12, 1e-9);
  EXPECT_NEAR(f.calib.fx, 125.0, 1e-9);
  EXPECT_TRUE(f.has_gt_pose);
  EXPECT_TRUE(f.gt_depth.empty());  // only with --depth
  std::remove(bag.c_str());
  std::remove(log.c_str());
}

INSTANTIATE_TEST_SUITE_P(Worlds, RenderBagCli,
                         ::testing::Values("course", "corridor", "parking", "glass", "plaza", "plaza_busy", "corridor_busy"));

TEST(RenderBagCliPeople, PeopleTruthMatchesPersonAt)
{
  // /ground_truth/people: one MoverArray per camera frame at the frame's stamp (100 s + k / 15),
  // frame gt_world, id = index + 1, exactly personAt's position and velocity, zero covariance.
  const std::string bag = std::string(::testing::TempDir()) + "assistive_sim_cli_people.bag";
  const std::string cmd = std::string(RENDER_BAG_EXE) + " --world plaza_busy --out " + bag +
                          " --frames 40 --width 64 --height 48 > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const assistive_sim::World w = assistive_sim::World::load(std::string(ASSISTIVE_SIM_SOURCE_WORLDS) + "/plaza_busy.yaml");
  ASSERT_GE(w.people.size(), 10u);
  rosbag::Bag b(bag, rosbag::bagmode::Read);
  rosbag::View v(b, rosbag::TopicQuery("/ground_truth/people"));
  int k = 0;
  for (const rosbag::MessageInstance& mi : v)
  {
    const auto m = mi.instantiate<assistive_msgs::MoverArray>();
    ASSERT_TRUE(m);
    const double t = k / 15.0;
    EXPECT_NEAR(m->header.stamp.toSec(), 100.0 + t, 1e-6);
    EXPECT_NEAR(mi.getTime().toSec(), 100.0 + t, 1e-6);
    EXPECT_EQ(m->header.frame_id, "gt_world");
    ASSERT_EQ(m->movers.size(), w.people.size());
    for (size_t i = 0; i < w.people.size(); ++i)
    {
      const auto& mv = m->movers[i];
      const assistive_sim::PersonState s = assistive_sim::personAt(w, i, t);
      EXPECT_EQ(mv.id, i + 1);
      EXPECT_DOUBLE_EQ(mv.position.x, s.position.x());
      EXPECT_DOUBLE_EQ(mv.position.y, s.position.y());
      EXPECT_DOUBLE_EQ(mv.position.z, 0.0);
      EXPECT_DOUBLE_EQ(mv.velocity.x, s.velocity.x());
      EXPECT_DOUBLE_EQ(mv.velocity.y, s.velocity.y());
      EXPECT_FLOAT_EQ(mv.radius, static_cast<float>(w.people[i].radius));
      EXPECT_FLOAT_EQ(mv.height, static_cast<float>(w.people[i].height));
      for (double c : mv.covariance) EXPECT_EQ(c, 0.0);
    }
    ++k;
  }
  EXPECT_EQ(k, 40);
  // The first crosser walks at 1.2 m/s from t = 2.54 s: moving in the last frames.
  b.close();
  EXPECT_NEAR(assistive_sim::personAt(w, 0, 39 / 15.0).velocity.norm(), 1.2, 1e-9);
  std::remove(bag.c_str());
}

TEST(RenderBagCliDeterminism, SameSeedSameBag)
{
  auto run = [](const std::string& out, int seed) {
    const std::string cmd = std::string(RENDER_BAG_EXE) + " --world course --out " + out +
                            " --frames 2 --width 96 --height 72 --seed " + std::to_string(seed) +
                            " > /dev/null 2>&1";
    return std::system(cmd.c_str());
  };
  const std::string a = std::string(::testing::TempDir()) + "assistive_sim_det_a.bag";
  const std::string b = std::string(::testing::TempDir()) + "assistive_sim_det_b.bag";
  const std::string c = std::string(::testing::TempDir()) + "assistive_sim_det_c.bag";
  ASSERT_EQ(run(a, 3), 0);
  ASSERT_EQ(run(b, 3), 0);
  ASSERT_EQ(run(c, 4), 0);
  StereoBagReader ra(a), rb(b), rc(c);
  StereoFrame fa, fb, fc;
  while (ra.next(fa))
  {
    ASSERT_TRUE(rb.next(fb));
    ASSERT_TRUE(rc.next(fc));
    EXPECT_EQ(cv::norm(fa.left, fb.left, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(fa.right, fb.right, cv::NORM_INF), 0.0);
    EXPECT_TRUE(fa.gt_pose.isApprox(fb.gt_pose, 1e-12));
    ASSERT_EQ(fa.imu.size(), fb.imu.size());
    for (size_t i = 0; i < fa.imu.size(); ++i) EXPECT_EQ(fa.imu[i].gyro, fb.imu[i].gyro);
    EXPECT_GT(cv::norm(fa.left, fc.left, cv::NORM_L1), 0.0);
  }
  for (const auto& p : {a, b, c}) std::remove(p.c_str());
}

TEST(RenderBagCliProjector, EmitterOnPairsHalfAFrameAfterEachAndNoneWhenPassive)
{
  const std::string dir = ::testing::TempDir();
  const std::string active = dir + "assistive_sim_cli_active.bag", passive = dir + "assistive_sim_cli_passive.bag";
  const std::string base = std::string(RENDER_BAG_EXE) + " --world corridor --frames 3 --width 160 --height 120";
  ASSERT_EQ(std::system((base + " --out " + active + " > /dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(std::system((base + " --passive --out " + passive + " > /dev/null 2>&1").c_str()), 0);
  EXPECT_TRUE(bagHasTopic(active, StereoBagTopics().projected_left_image));
  EXPECT_FALSE(bagHasTopic(passive, StereoBagTopics().projected_left_image));
  // The emitter-off pairs are the passive camera's, bit for bit; the emitter-on pairs come half a
  // frame (1/30 s) after each and differ from them (the dots, the corridor's floor a metre or two on).
  StereoBagReader off_a(active), off_p(passive), on(active, StereoBagTopics().projected());
  StereoFrame a, p, o;
  int n = 0;
  while (off_a.next(a))
  {
    ASSERT_TRUE(off_p.next(p));
    ASSERT_TRUE(on.next(o));
    EXPECT_EQ(cv::norm(a.left, p.left, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(a.right, p.right, cv::NORM_INF), 0.0);
    EXPECT_NEAR(o.stamp - a.stamp, 1.0 / 30.0, 1e-6);
    EXPECT_FALSE(o.has_gt_pose);  // (the truth runs on the emitter-off clock: interpolate)
    cv::Mat d;
    cv::absdiff(o.left(cv::Rect(0, 100, 160, 20)), a.left(cv::Rect(0, 100, 160, 20)), d);
    EXPECT_GT(cv::mean(d)[0], 2.0);
    ++n;
  }
  EXPECT_FALSE(on.next(o));
  EXPECT_EQ(n, 3);
  std::remove(active.c_str());
  std::remove(passive.c_str());
}

TEST(RenderBagCliDepth, DepthOptionWritesTrueDepth)
{
  const std::string bag = std::string(::testing::TempDir()) + "assistive_sim_cli_depth.bag";
  const std::string cmd = std::string(RENDER_BAG_EXE) + " --world corridor --out " + bag +
                          " --frames 2 --width 160 --height 120 --depth > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  StereoBagReader r(bag);
  EXPECT_TRUE(r.hasDepth());
  StereoFrame f;
  int n = 0;
  while (r.next(f))
  {
    ASSERT_EQ(f.gt_depth.type(), CV_32FC1);
    ASSERT_EQ(f.gt_depth.size(), f.left.size());
    // Looking down the corridor: the bottom row sees the floor ~1.6 m below at a few metres, the
    // centre sees far away (the corridor is 28 m long).
    double mn, mx;
    cv::minMaxLoc(f.gt_depth, &mn, &mx);
    EXPECT_GT(mx, 5.0);
    EXPECT_GE(mn, 0.0);
    // Indoors nearly every pixel hits a surface (only the far door opening shows the sky).
    EXPECT_LT(cv::countNonZero(f.gt_depth <= 0.f), f.gt_depth.total() / 20);
    EXPECT_LT(f.gt_depth.at<float>(119, 80), 5.0f);
    ++n;
  }
  EXPECT_EQ(n, 2);
  std::remove(bag.c_str());
}

TEST(RenderBagCliErrors, MalformedWorldNamesLine)
{
  const std::string yaml = std::string(::testing::TempDir()) + "assistive_sim_bad_world.yaml";
  {
    std::ofstream o(yaml);
    o << "name: bad\nfloor: {min: [0, 0], max: [5, 5]}\nelements:\n  - {type: box, center: [1, 1], size: [1, 1]}\n"
         "trajectory: {waypoints: [[0, 0], [1, 1]]}\n";
  }
  const std::string log = yaml + ".log";
  const std::string cmd = std::string(RENDER_BAG_EXE) + " --world " + yaml + " --out /tmp/never.bag 2> " + log +
                          " > /dev/null";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  std::ifstream in(log);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find(":4: field 'elements[0](box).size'"), std::string::npos) << ss.str();
  std::remove(yaml.c_str());
  std::remove(log.c_str());
}

TEST(RenderBagCliErrors, HelpExitsZeroUnknownOptionGivesUsage)
{
  const std::string log = std::string(::testing::TempDir()) + "assistive_sim_render_help.log";
  auto read = [&]() {
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  for (const char* h : {"--help", "-h"})
  {
    EXPECT_EQ(std::system((std::string(RENDER_BAG_EXE) + " " + h + " > " + log + " 2>/dev/null").c_str()), 0) << h;
    EXPECT_NE(read().find("usage: render_bag"), std::string::npos) << read();
  }
  const int st = std::system((std::string(RENDER_BAG_EXE) + " --no-such-option 2> " + log + " > /dev/null").c_str());
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 2);
  EXPECT_NE(read().find("usage: render_bag"), std::string::npos) << read();
  std::remove(log.c_str());
}

TEST(RenderBagCliTruth, TruthGridAtTheAskedCell)
{
  // --truth-resolution: the truth grid at the cell a map run at another cell_size is scored against
  const std::string base = std::string(RENDER_BAG_EXE) + " --world course --frames 1 --width 96 --height 72 --seed 2";
  const std::string a = std::string(::testing::TempDir()) + "assistive_sim_truth_a.bag";
  const std::string b = std::string(::testing::TempDir()) + "assistive_sim_truth_b.bag";
  ASSERT_EQ(std::system((base + " --out " + a + " > /dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(std::system((base + " --out " + b + " --truth-resolution 0.1 > /dev/null 2>&1").c_str()), 0);
  OccupancyGrid ga, gb;
  ASSERT_TRUE(StereoBagReader(a).readOccupancy(ga));
  ASSERT_TRUE(StereoBagReader(b).readOccupancy(gb));
  EXPECT_NEAR(ga.resolution, 0.2, 1e-6);  // float32 in nav_msgs/MapMetaData
  EXPECT_NEAR(gb.resolution, 0.1, 1e-6);
  EXPECT_NEAR(gb.width * gb.resolution, ga.width * ga.resolution, 0.2);  // the same floor, finer cells
  EXPECT_NEAR(gb.height * gb.resolution, ga.height * ga.resolution, 0.2);
  const int refused = std::system((base + " --out " + b + " --truth-resolution 0 > /dev/null 2>&1").c_str());
  EXPECT_TRUE(WIFEXITED(refused) && WEXITSTATUS(refused) == 2);
  std::remove(a.c_str());
  std::remove(b.c_str());
}
