// System replay test (see replay_chain.test): the whole chain keeps publishing while a generated
// bag plays, and what comes out is consistent with the bag's ground truth.
#include <assistive_msgs/NavigationState.h>
#include <assistive_msgs/TactileCue.h>
#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace
{
// A stage may pause this long (simulated time) between outputs while the bag plays.
constexpr double MAX_GAP_S = 1.0;

struct Stream
{
  std::vector<double> stamps;  // receive times (simulated clock)
  /// The longest time without a message within [t0, t1]; *from: when it began.
  double maxGapWithin(double t0, double t1, double* from) const
  {
    std::vector<double> s{ t0 };
    for (double t : stamps)
      if (t >= t0 && t <= t1) s.push_back(t);
    s.push_back(t1);
    double gap = 0.0;
    for (size_t i = 1; i < s.size(); ++i)
      if (s[i] - s[i - 1] > gap)
      {
        gap = s[i] - s[i - 1];
        *from = s[i - 1];
      }
    return gap;
  }
};

/// How far the simulated clock jumped within [t0, t1]: the steps of /clock over 0.1 s. rosbag play
/// stalled on its disk (another test reading a large bag) catches up by jumping its clock, and
/// every stream then shows that jump as a gap that no stage caused.
double clockJumpsWithin(const std::vector<double>& clock, double t0, double t1)
{
  double jumps = 0.0;
  for (size_t i = 1; i < clock.size(); ++i)
    if (clock[i - 1] >= t0 - 1e-6 && clock[i] <= t1 + 1e-6 && clock[i] - clock[i - 1] > 0.1)
      jumps += clock[i] - clock[i - 1];
  return jumps;
}

struct Recorder
{
  std::vector<double> clock;  // /clock as the player published it
  std::map<std::string, Stream> streams;
  std::vector<nav_msgs::Odometry> vo;
  std::vector<assistive_msgs::TactileCue> cues;
  void mark(const std::string& name) { streams[name].stamps.push_back(ros::Time::now().toSec()); }
};
}  // namespace

TEST(ReplayChain, EveryStageKeepsPublishingAndAgreesWithGroundTruth)
{
  ros::NodeHandle nh, pnh("~");
  std::string bag_path;
  ASSERT_TRUE(pnh.getParam("bag", bag_path));

  // What the bag holds: the camera stamps and the true poses of the left camera. Read beside the
  // spinning below, not before it: the bag plays on the wall clock from launch and the streams are
  // timed as they arrive, so a slow read (a cold disk) must not hold their callbacks back.
  struct BagTruth
  {
    std::vector<double> image_stamps;
    std::map<double, geometry_msgs::Point> truth;
  };
  double duration = 0;
  const bool has_duration = pnh.getParam("duration", duration);
  std::future<BagTruth> reading = std::async(std::launch::async, [bag_path, has_duration, duration] {
    BagTruth b;
    rosbag::Bag bag(bag_path);
    // the player stops `duration` seconds after the bag's start (a longer walk's first part)
    ros::Time end = ros::TIME_MAX;
    if (has_duration)
      end = rosbag::View(bag).getBeginTime() + ros::Duration(duration);
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/ground_truth/odom"}), ros::TIME_MIN, end);
    for (const auto& m : view)
    {
      auto odom = m.instantiate<nav_msgs::Odometry>();
      b.image_stamps.push_back(odom->header.stamp.toSec());
      b.truth[odom->header.stamp.toSec()] = odom->pose.pose.position;
    }
    return b;
  });

  Recorder rec;
  auto clock_sub = nh.subscribe<rosgraph_msgs::Clock>("/clock", 1000, [&](const rosgraph_msgs::Clock::ConstPtr& m) {
    rec.clock.push_back(m->clock.toSec());
  });
  auto vo_sub = nh.subscribe<nav_msgs::Odometry>("/vo/odom", 100, [&](const nav_msgs::Odometry::ConstPtr& m) {
    rec.mark("vo/odom");
    rec.vo.push_back(*m);
  });
  auto map_sub = nh.subscribe<nav_msgs::OccupancyGrid>("/obstacles/traversability", 10,
                                                       [&](const nav_msgs::OccupancyGrid::ConstPtr&) {
                                                         rec.mark("obstacles/traversability");
                                                       });
  auto state_sub = nh.subscribe<assistive_msgs::NavigationState>(
      "/planner/state", 100, [&](const assistive_msgs::NavigationState::ConstPtr&) { rec.mark("planner/state"); });
  auto cue_sub = nh.subscribe<assistive_msgs::TactileCue>("/tactile/cue", 100,
                                                          [&](const assistive_msgs::TactileCue::ConstPtr& m) {
                                                            rec.mark("tactile/cue");
                                                            rec.cues.push_back(*m);
                                                          });

  // Run until the bag is read and the simulated clock reaches its end (rosbag play's last clock tick
  // may fall a few ms short of the last message), with a wall-clock limit for a stuck player.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(300.0);
  while (ros::ok() && ros::WallTime::now() < deadline &&
         reading.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  const BagTruth bag_truth = reading.get();
  const std::vector<double>& image_stamps = bag_truth.image_stamps;
  const std::map<double, geometry_msgs::Point>& truth = bag_truth.truth;
  ASSERT_GT(image_stamps.size(), 30u);
  const double bag_t0 = image_stamps.front(), bag_t1 = image_stamps.back();
  std::set<double> image_stamp_set(image_stamps.begin(), image_stamps.end());
  const double end = bag_t1 - 0.1;
  while (ros::ok() && ros::WallTime::now() < deadline && ros::Time::now().toSec() < end)
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  for (int i = 0; i < 100; ++i)  // drain what is still in flight
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_GE(ros::Time::now().toSec(), end) << "the bag did not finish playing within 300 s";

  // 1. Liveness: each stage publishes throughout the bag (after a warm-up of 1.5 s: the first
  //    maps and paths need a few frames).
  const double warm = bag_t0 + 1.5;
  for (const char* name : {"vo/odom", "obstacles/traversability", "planner/state", "tactile/cue"})
  {
    double from = warm;
    const double gap = rec.streams[name].maxGapWithin(warm, end, &from);
    const double jumps = clockJumpsWithin(rec.clock, from, from + gap);
    const auto& st = rec.streams[name].stamps;
    std::printf("replay_chain: %s: %zu messages, the first %.2f s into the bag, longest gap %.2f s from %.2f s (the clock "
                "jumped %.2f s of it)\n",
                name, st.size(), st.empty() ? -1.0 : st.front() - bag_t0, gap, from - bag_t0, jumps);
    EXPECT_LT(gap - jumps, MAX_GAP_S) << name << " stopped publishing for " << gap << " s (simulated) while the bag played, from "
                                      << from - bag_t0 << " s into it (" << end - bag_t0 << " s judged; the player's clock "
                                      << "jumped " << jumps << " s of it)";
  }

  // 2. VO: a pose for most frames, no NaN, and the distance walked agrees with the ground truth.
  EXPECT_GE(rec.vo.size(), image_stamps.size() * 8 / 10);
  ASSERT_FALSE(rec.vo.empty());
  const auto& p0 = rec.vo.front().pose.pose.position;
  const auto& g0 = truth.begin()->second;
  double worst = 0.0;
  for (const auto& o : rec.vo)
  {
    const auto& p = o.pose.pose.position;
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    auto it = truth.find(o.header.stamp.toSec());
    if (it == truth.end()) continue;
    const double d_vo = std::hypot(p.x - p0.x, p.y - p0.y, p.z - p0.z);
    const auto& g = it->second;
    const double d_gt = std::hypot(g.x - g0.x, g.y - g0.y, g.z - g0.z);
    worst = std::max(worst, std::abs(d_vo - d_gt));
  }
  EXPECT_LT(worst, 0.15) << "VO displacement differs from the ground truth by up to " << worst << " m";

  // 3. Cues: valid intensities, and each decided from an image of the bag; the newest cue is
  //    never far behind the newest image (a frozen upstream stage shows up here).
  ASSERT_FALSE(rec.cues.empty());
  double lag_max = 0.0;
  for (const auto& c : rec.cues)
  {
    for (float v : c.intensity) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
    if (c.source_stamp.isZero()) continue;  // not decided from an image yet (start-up)
    EXPECT_TRUE(image_stamp_set.count(c.source_stamp.toSec())) << "cue stamped " << c.source_stamp << " matches no image";
    const double decided = c.header.stamp.toSec(), seen = c.source_stamp.toSec();
    if (decided > warm)  // the player's clock jumps are no stage's lag (clockJumpsWithin)
      lag_max = std::max(lag_max, decided - seen - clockJumpsWithin(rec.clock, seen, decided));
  }
  EXPECT_LT(lag_max, MAX_GAP_S) << "cues were decided from images up to " << lag_max
                                << " s old (not counting the player's clock jumps)";
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_replay_chain");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
