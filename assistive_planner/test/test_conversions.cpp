#include <gtest/gtest.h>

#include "assistive_planner/conversions.h"

using namespace assistive_planner;

TEST(Conversions, GridRoundTrip)
{
  Grid g;
  g.width = 3;
  g.height = 2;
  g.resolution = 0.2;
  g.origin_x = -1.0;
  g.origin_y = 2.0;
  g.data = { -1, 0, 50, 100, 0, 0 };
  std_msgs::Header h;
  h.frame_id = "odom";
  Grid back;
  ASSERT_TRUE(fromMsg(toMsg(g, h), back));
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_NEAR(back.resolution, 0.2, 1e-6);
  EXPECT_DOUBLE_EQ(back.origin_x, -1.0);
  EXPECT_DOUBLE_EQ(back.origin_y, 2.0);
  EXPECT_EQ(back.data, g.data);
}

TEST(Conversions, RejectsMalformedGrid)
{
  nav_msgs::OccupancyGrid m;
  m.info.width = 3;
  m.info.height = 3;
  m.info.resolution = 0.2f;
  m.info.origin.orientation.w = 1.0;
  m.data.assign(8, 0);  // one short
  Grid g;
  EXPECT_FALSE(fromMsg(m, g));
  m.data.assign(9, 0);
  EXPECT_TRUE(fromMsg(m, g));
  m.info.origin.orientation.z = 0.3826834;  // rotated 45 degrees
  m.info.origin.orientation.w = 0.9238795;
  EXPECT_FALSE(fromMsg(m, g));
}

TEST(Conversions, NavigationStateFieldsAndNoNaN)
{
  PlanOutput o;
  o.status = PlanStatus::OK;
  o.wearer = { 1, 2 };
  o.heading = 0.5;
  o.head_yaw = 0.6;
  o.has_waypoint = true;
  o.waypoint = { 4, 2 };
  o.waypoint_distance = 3.0;
  o.path_heading = 0.1;
  o.path_length = 3.2;
  o.free_ahead = 2.0;
  o.free_left = std::nan("");
  o.free_right = 0.4;
  o.path = { { 1, 2 }, { 2, 2 }, { 4, 2 } };
  std_msgs::Header h;
  h.frame_id = "odom";
  h.stamp = ros::Time(10.0);
  const auto s = toMsg(o, h, ros::Time(9.5));
  EXPECT_EQ(s.status, assistive_msgs::NavigationState::OK);
  EXPECT_EQ(s.source_stamp, ros::Time(9.5));
  EXPECT_FLOAT_EQ(s.heading, 0.5f);
  EXPECT_FLOAT_EQ(s.head_yaw, 0.6f);
  EXPECT_DOUBLE_EQ(s.waypoint.x, 4.0);
  EXPECT_FLOAT_EQ(s.waypoint_distance, 3.0f);
  EXPECT_FLOAT_EQ(s.path_heading, 0.1f);
  EXPECT_FLOAT_EQ(s.path_length, 3.2f);
  EXPECT_FLOAT_EQ(s.free_distance_ahead, 2.0f);
  EXPECT_FLOAT_EQ(s.free_distance_left, 0.0f);  // NaN never goes out
  EXPECT_FLOAT_EQ(s.free_distance_right, 0.4f);
  const auto p = toPathMsg(o, h);
  ASSERT_EQ(p.poses.size(), 3u);
  EXPECT_DOUBLE_EQ(p.poses[2].pose.position.x, 4.0);
  EXPECT_EQ(toMarkers(o, h).markers.size(), 3u);
  // status values match the message constants
  EXPECT_EQ(uint8_t(PlanStatus::IN_UNKNOWN), assistive_msgs::NavigationState::IN_UNKNOWN);
  EXPECT_EQ(uint8_t(PlanStatus::NO_WAYPOINT), assistive_msgs::NavigationState::NO_WAYPOINT);
  EXPECT_EQ(uint8_t(PlanStatus::NO_PATH), assistive_msgs::NavigationState::NO_PATH);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
