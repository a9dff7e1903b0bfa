#include <gtest/gtest.h>

#include <cmath>

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
  // motion vector, search triangle, waypoint, and the crossing warning's arrow and text (deleted: none)
  const auto ma = toMarkers(o, h);
  ASSERT_EQ(ma.markers.size(), 6u);
  EXPECT_EQ(ma.markers[3].ns, "crossing");
  EXPECT_EQ(ma.markers[3].action, visualization_msgs::Marker::DELETE);
  EXPECT_EQ(ma.markers[4].action, visualization_msgs::Marker::DELETE);
  EXPECT_EQ(ma.markers[5].ns, "passage");
  EXPECT_EQ(ma.markers[5].action, visualization_msgs::Marker::DELETE);  // no passage ahead
  EXPECT_EQ(s.crossing, assistive_msgs::NavigationState::CROSSING_NONE);
  EXPECT_EQ(s.crossing_id, 0u);
  EXPECT_EQ(s.crossing_time, 0.0f);
  EXPECT_EQ(s.crossing_distance, 0.0f);
  // no passage ahead: -1; a doorway 1.5 m ahead: distance, heading, width; not OK: none
  EXPECT_FLOAT_EQ(s.passage_distance, -1.0f);
  o.passage_distance = 1.5;
  o.passage_heading = 0.2;
  o.passage_width = 0.8;
  o.passage_point = { 2.5, -0.5 };
  o.passage_axis = 1.2;
  const auto d = toMsg(o, h, ros::Time(9.5));
  EXPECT_FLOAT_EQ(d.passage_distance, 1.5f);
  EXPECT_FLOAT_EQ(d.passage_heading, 0.2f);
  EXPECT_FLOAT_EQ(d.passage_width, 0.8f);
  EXPECT_DOUBLE_EQ(d.passage_point.x, 2.5);
  EXPECT_DOUBLE_EQ(d.passage_point.y, -0.5);
  EXPECT_FLOAT_EQ(d.passage_axis, 1.2f);
  // rviz: the axis through the middle, 0.6 m either side
  const auto pm = toMarkers(o, h).markers[5];
  EXPECT_EQ(pm.action, visualization_msgs::Marker::ADD);
  ASSERT_EQ(pm.points.size(), 2u);
  EXPECT_NEAR(pm.points[0].x, 2.5 - 0.6 * std::cos(1.2), 1e-9);
  EXPECT_NEAR(pm.points[1].y, -0.5 + 0.6 * std::sin(1.2), 1e-9);
  // the steering path's first 8 m, for the corners taken walking (none unless OK)
  EXPECT_TRUE(d.path_ahead.empty());
  o.steer_path = { { 1, 2 }, { 4, 2 }, { 4, 8 }, { 4, 12 } };  // 3 + 6 m: the third point ends it
  const auto pa = toMsg(o, h, ros::Time(9.5)).path_ahead;
  ASSERT_EQ(pa.size(), 3u);
  EXPECT_DOUBLE_EQ(pa[1].x, 4.0);
  EXPECT_DOUBLE_EQ(pa[2].y, 8.0);
  o.status = PlanStatus::NO_PATH;
  EXPECT_TRUE(toMsg(o, h, ros::Time(9.5)).path_ahead.empty());
  EXPECT_FLOAT_EQ(toMsg(o, h, ros::Time(9.5)).passage_distance, -1.0f);
  o.status = PlanStatus::OK;
  // status values match the message constants
  EXPECT_EQ(uint8_t(PlanStatus::IN_UNKNOWN), assistive_msgs::NavigationState::IN_UNKNOWN);
  EXPECT_EQ(uint8_t(PlanStatus::NO_WAYPOINT), assistive_msgs::NavigationState::NO_WAYPOINT);
  EXPECT_EQ(uint8_t(PlanStatus::NO_PATH), assistive_msgs::NavigationState::NO_PATH);
}

// The crossing advice goes out in NavigationState (and as markers); MoverArray comes in as tracks.
TEST(Conversions, CrossingAndMovers)
{
  PlanOutput o;
  o.status = PlanStatus::OK;
  o.crossing.advice = CrossingAdvice::STOP;
  o.crossing.id = 12;
  o.crossing.time = 0.75;
  o.crossing.distance = 0.25;
  o.crossing.mover = { 1.0, -1.0 };
  o.crossing.mover_at_closest = { 1.0, 0.0 };
  o.crossing.wearer_at_closest = { 1.0, 0.0 };
  std_msgs::Header h;
  h.frame_id = "odom";
  const auto s = toMsg(o, h, ros::Time(1.0));
  EXPECT_EQ(s.crossing, assistive_msgs::NavigationState::CROSSING_STOP);
  EXPECT_EQ(s.crossing_id, 12u);
  EXPECT_FLOAT_EQ(s.crossing_time, 0.75f);
  EXPECT_FLOAT_EQ(s.crossing_distance, 0.25f);
  const auto ma = toMarkers(o, h);
  ASSERT_EQ(ma.markers.size(), 6u);
  EXPECT_EQ(ma.markers[3].action, visualization_msgs::Marker::ADD);
  ASSERT_EQ(ma.markers[3].points.size(), 2u);
  EXPECT_DOUBLE_EQ(ma.markers[3].points[1].y, 0.0);
  EXPECT_EQ(ma.markers[4].text, "person 12: STOP in 0.8 s (0.25 m)");
  o.crossing.time = std::nan("");  // never out as NaN: no advice
  EXPECT_EQ(toMsg(o, h, ros::Time(1.0)).crossing, assistive_msgs::NavigationState::CROSSING_NONE);
  EXPECT_EQ(uint8_t(CrossingAdvice::LEFT), assistive_msgs::NavigationState::CROSSING_LEFT);
  EXPECT_EQ(uint8_t(CrossingAdvice::RIGHT), assistive_msgs::NavigationState::CROSSING_RIGHT);

  assistive_msgs::MoverArray movers;
  assistive_msgs::Mover m;
  m.id = 4;
  m.position.x = 1.5;
  m.position.y = -2.0;
  m.velocity.x = 0.1;
  m.velocity.y = 1.2;
  for (int i = 0; i < 16; ++i)
    m.covariance[size_t(i)] = i == 0 ? 0.01 : i == 5 ? 0.02 : i == 2 ? 0.003 : 0.0;
  movers.movers.push_back(m);
  m.id = 5;
  m.velocity.x = std::nan("");  // dropped
  movers.movers.push_back(m);
  const std::vector<MoverState> t = fromMsg(movers);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].id, 4);
  EXPECT_DOUBLE_EQ(t[0].position().x(), 1.5);
  EXPECT_DOUBLE_EQ(t[0].position().y(), -2.0);
  EXPECT_DOUBLE_EQ(t[0].velocity().x(), 0.1);
  EXPECT_DOUBLE_EQ(t[0].velocity().y(), 1.2);
  EXPECT_DOUBLE_EQ(t[0].P(0, 0), 0.01);
  EXPECT_DOUBLE_EQ(t[0].P(1, 1), 0.02);
  EXPECT_DOUBLE_EQ(t[0].P(0, 2), 0.003);  // row-major
  EXPECT_DOUBLE_EQ(t[0].P(2, 0), 0.0);
}
