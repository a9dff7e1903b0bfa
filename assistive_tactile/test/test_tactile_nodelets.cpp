// rostest: planner/state -> cue_logic -> tactile/cue -> vest_bridge -> pty -> simulated vest,
// checked through tactile/cue and the bridge's diagnostics (which carry the vest's STATUS reply).
#include <gtest/gtest.h>

#include <assistive_msgs/NavigationState.h>
#include <assistive_msgs/TactileCue.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include <functional>

namespace
{
assistive_msgs::TactileCue::ConstPtr g_cue;
std::string g_vest_reports, g_link_message;
int g_link_level = -1;
visualization_msgs::MarkerArray::ConstPtr g_markers;

void cueCb(const assistive_msgs::TactileCue::ConstPtr& m)
{
  g_cue = m;
}
void markerCb(const visualization_msgs::MarkerArray::ConstPtr& m)
{
  g_markers = m;
}
void diagCb(const diagnostic_msgs::DiagnosticArray::ConstPtr& m)
{
  for (const auto& s : m->status)
    if (s.name.find("vest link") != std::string::npos)
    {
      g_link_level = s.level;
      g_link_message = s.message;
      for (const auto& kv : s.values)
        if (kv.key == "vest reports")
          g_vest_reports = kv.value;
    }
}

assistive_msgs::NavigationState state(uint8_t status, float dev, float ahead, float left, float right)
{
  assistive_msgs::NavigationState s;
  s.header.stamp = ros::Time::now();
  s.header.frame_id = "odom";
  s.source_stamp = ros::Time::now() - ros::Duration(0.05);
  s.status = status;
  s.heading = 0.2f;
  s.path_heading = 0.2f + dev;
  s.waypoint_distance = 3.0f;
  s.free_distance_ahead = ahead;
  s.free_distance_left = left;
  s.free_distance_right = right;
  return s;
}

/// Publishes `s` at 10 Hz until pred() holds or timeout; returns pred().
bool publishUntil(ros::Publisher& pub, const std::function<assistive_msgs::NavigationState()>& s,
                  const std::function<bool()>& pred, double timeout)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  ros::WallTime next;
  while (ros::ok() && ros::WallTime::now() < end)
  {
    if (s && ros::WallTime::now() >= next)
    {
      pub.publish(s());
      next = ros::WallTime::now() + ros::WallDuration(0.1);
    }
    ros::spinOnce();
    if (pred())
      return true;
    ros::WallDuration(0.01).sleep();
  }
  return pred();
}
}  // namespace

TEST(TactileNodelets, EndToEndOnTheSimulatedVest)
{
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<assistive_msgs::NavigationState>("/planner/state", 1);
  ros::Subscriber cs = nh.subscribe("/tactile/cue", 10, cueCb);
  ros::Subscriber ds = nh.subscribe("/diagnostics", 50, diagCb);
  ros::Subscriber ms = nh.subscribe("/tactile/markers", 1, markerCb);

  // 1. The bridge finds the simulated vest (link up = the vest answers).
  ASSERT_TRUE(publishUntil(pub, nullptr, [] { return g_link_level >= 0 && g_vest_reports != "-" &&
                                                     !g_vest_reports.empty(); }, 30.0))
      << "link: " << g_link_message;

  // 2. Path 45 deg to the left: left shoulder, source_stamp carried through, vest drives it.
  assistive_msgs::NavigationState last;
  auto left = [&] { return last = state(assistive_msgs::NavigationState::OK, 0.785f, 4.f, 2.f, 2.f); };
  ASSERT_TRUE(publishUntil(pub, left, [] {
    return g_cue && g_cue->mode == assistive_msgs::TactileCue::GUIDANCE && g_vest_reports.rfind("L-sh   0", 0) != 0 &&
           g_vest_reports.find("R-sh   0  L-w   0  R-w   0") != std::string::npos;
  }, 15.0)) << "vest reports: " << g_vest_reports;
  EXPECT_GT(g_cue->intensity[assistive_msgs::TactileCue::LEFT_SHOULDER], 0.f);
  EXPECT_EQ(g_cue->intensity[assistive_msgs::TactileCue::RIGHT_SHOULDER], 0.f);
  EXPECT_EQ(g_cue->header.frame_id, "torso");
  EXPECT_NE(g_cue->reason.find("turn left"), std::string::npos);

  // 3. Obstacle 0.8 m ahead, room on the right: right waist on the vest.
  ASSERT_TRUE(publishUntil(pub, [] { return state(assistive_msgs::NavigationState::OK, 0.f, 0.8f, 0.1f, 1.5f); },
                           [] {
                             return g_cue && g_cue->mode == assistive_msgs::TactileCue::PROXIMITY &&
                                    g_vest_reports.rfind("L-sh   0  R-sh   0  L-w   0  R-w ", 0) == 0 &&
                                    g_vest_reports.find("R-w   0") == std::string::npos;
                           }, 15.0)) << "vest reports: " << g_vest_reports;

  // 4. No pose: UNSURE, vest quiet.
  ASSERT_TRUE(publishUntil(pub, [] { return state(assistive_msgs::NavigationState::NO_POSE, 0.785f, 0.3f, 0, 0); },
                           [] {
                             return g_cue && g_cue->mode == assistive_msgs::TactileCue::UNSURE &&
                                    g_vest_reports.rfind("L-sh   0  R-sh   0  L-w   0  R-w   0", 0) == 0;
                           }, 15.0)) << "vest reports: " << g_vest_reports;
  EXPECT_NE(g_cue->reason.find("no pose"), std::string::npos);

  // 5. Drive a turn again, then stop publishing: the cue logic goes UNSURE (stale), vest quiet.
  ASSERT_TRUE(publishUntil(pub, left, [] {
    return g_cue && g_cue->mode == assistive_msgs::TactileCue::GUIDANCE && g_vest_reports.rfind("L-sh   0", 0) != 0;
  }, 15.0));
  ASSERT_TRUE(publishUntil(pub, nullptr, [] {
    return g_cue && g_cue->mode == assistive_msgs::TactileCue::UNSURE &&
           g_cue->reason.find("stale") != std::string::npos &&
           g_vest_reports.rfind("L-sh   0  R-sh   0  L-w   0  R-w   0", 0) == 0;
  }, 15.0)) << "cue: " << (g_cue ? g_cue->reason : "none") << " vest: " << g_vest_reports;

  // 6. Markers for the four motors when someone listens.
  EXPECT_TRUE(publishUntil(pub, left, [] { return g_markers && g_markers->markers.size() == 5u; }, 10.0));
  if (g_markers)
  {
    EXPECT_EQ(g_markers->markers[0].header.frame_id, "motor_left_shoulder");
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_tactile_nodelets");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
