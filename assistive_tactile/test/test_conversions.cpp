#include <gtest/gtest.h>

#include <cmath>

#include "assistive_tactile/conversions.h"

using namespace assistive_tactile;

TEST(Conversions, CueRoundTrip)
{
  Cue c;
  c.mode = CueMode::PROXIMITY;
  c.intensity = { { 0.f, 0.f, 0.7f, 0.f } };
  c.reason = "obstacle 0.80 m ahead: step left";
  const ros::Time stamp(12.5), source(12.25);
  const assistive_msgs::TactileCue m = toMsg(c, stamp, source, "torso");
  EXPECT_EQ(m.header.stamp, stamp);
  EXPECT_EQ(m.source_stamp, source);
  EXPECT_EQ(m.header.frame_id, "torso");
  EXPECT_EQ(m.mode, assistive_msgs::TactileCue::PROXIMITY);
  EXPECT_FLOAT_EQ(m.intensity[assistive_msgs::TactileCue::LEFT_WAIST], 0.7f);
  const Cue back = fromMsg(m);
  EXPECT_EQ(back.mode, c.mode);
  EXPECT_EQ(back.intensity, c.intensity);
  EXPECT_EQ(back.reason, c.reason);
}

TEST(Conversions, EnumsMatchTheMessage)
{
  EXPECT_EQ(static_cast<int>(CueMode::IDLE), assistive_msgs::TactileCue::IDLE);
  EXPECT_EQ(static_cast<int>(CueMode::GUIDANCE), assistive_msgs::TactileCue::GUIDANCE);
  EXPECT_EQ(static_cast<int>(CueMode::PROXIMITY), assistive_msgs::TactileCue::PROXIMITY);
  EXPECT_EQ(static_cast<int>(CueMode::ALERT), assistive_msgs::TactileCue::ALERT);
  EXPECT_EQ(static_cast<int>(CueMode::UNSURE), assistive_msgs::TactileCue::UNSURE);
  EXPECT_EQ(LEFT_SHOULDER, assistive_msgs::TactileCue::LEFT_SHOULDER);
  EXPECT_EQ(RIGHT_SHOULDER, assistive_msgs::TactileCue::RIGHT_SHOULDER);
  EXPECT_EQ(LEFT_WAIST, assistive_msgs::TactileCue::LEFT_WAIST);
  EXPECT_EQ(RIGHT_WAIST, assistive_msgs::TactileCue::RIGHT_WAIST);
  EXPECT_EQ(static_cast<int>(NavStatus::NO_WAYPOINT), assistive_msgs::NavigationState::NO_WAYPOINT);
  EXPECT_EQ(static_cast<int>(NavStatus::IN_UNKNOWN), assistive_msgs::NavigationState::IN_UNKNOWN);
}

TEST(Conversions, BadIntensitiesAreClamped)
{
  assistive_msgs::TactileCue m;
  m.mode = 77;
  m.intensity = { { std::nanf(""), -0.5f, 3.f, 0.5f } };
  const Cue c = fromMsg(m);
  EXPECT_EQ(c.mode, CueMode::UNSURE);
  EXPECT_EQ(c.intensity[0], 0.f);
  EXPECT_EQ(c.intensity[1], 0.f);
  EXPECT_EQ(c.intensity[2], 1.f);
  EXPECT_EQ(c.intensity[3], 0.5f);
}

// The pulse pattern through TactileCue (ms in the message, 10 ms units on the vest).
TEST(Conversions, CuePatternRoundTrip)
{
  Cue c;
  c.mode = CueMode::GUIDANCE;
  c.instruction = Instruction::VEER;
  c.level = 2;
  c.intensity = { { 0.7f, 0.f, 0.f, 0.f } };
  c.pattern = vest_pattern_t{ 17, 15, 15, 2 };
  const assistive_msgs::TactileCue m = toMsg(c, ros::Time(1.0), ros::Time(0.9), "torso");
  EXPECT_EQ(m.pattern_id, 17);
  EXPECT_EQ(m.pulse_on_ms, 150);
  EXPECT_EQ(m.pulse_off_ms, 150);
  EXPECT_EQ(m.pulse_count, 2);
  EXPECT_EQ(m.instruction, assistive_msgs::TactileCue::VEER);
  const Cue back = fromMsg(m);
  EXPECT_TRUE(vest_pattern_equal(&back.pattern, &c.pattern));
  EXPECT_EQ(back.level, 2);
  // Rounded to 10 ms; a pulse that is on never becomes 0 (which would mean steady: a buzz), and
  // a long one saturates at 2550 ms.
  assistive_msgs::TactileCue r;
  r.pulse_on_ms = 3;
  r.pulse_off_ms = 4;
  EXPECT_EQ(fromMsg(r).pattern.on_10ms, 1);
  EXPECT_EQ(fromMsg(r).pattern.off_10ms, 0);
  r.pulse_on_ms = 104;
  EXPECT_EQ(fromMsg(r).pattern.on_10ms, 10);
  r.pulse_on_ms = 105;
  EXPECT_EQ(fromMsg(r).pattern.on_10ms, 11);
  r.pulse_on_ms = 60000;
  EXPECT_EQ(fromMsg(r).pattern.on_10ms, 255);
  r.pulse_on_ms = 0;
  EXPECT_EQ(fromMsg(r).pattern.on_10ms, 0);  // steady
}

TEST(Conversions, NavigationState)
{
  assistive_msgs::NavigationState s;
  s.status = assistive_msgs::NavigationState::OK;
  s.heading = 0.5f;
  s.path_heading = 1.0f;
  s.waypoint_distance = 2.5f;
  s.free_distance_ahead = 0.9f;
  s.free_distance_left = 1.2f;
  s.free_distance_right = 0.3f;
  s.message = "ok";
  s.passage_distance = 1.5f;
  s.passage_heading = 0.2f;
  s.passage_width = 0.8f;
  s.passage_point.x = 2.5;
  s.passage_point.y = -0.5;
  s.passage_axis = 1.2f;
  NavInput in = fromMsg(s);
  EXPECT_FLOAT_EQ(in.passage_distance, 1.5f);
  EXPECT_FLOAT_EQ(in.passage_heading, 0.2f);
  EXPECT_FLOAT_EQ(in.passage_width, 0.8f);
  EXPECT_DOUBLE_EQ(in.passage_x, 2.5);
  EXPECT_DOUBLE_EQ(in.passage_y, -0.5);
  EXPECT_FLOAT_EQ(float(in.passage_axis), 1.2f);
  EXPECT_TRUE(in.path.empty());
  geometry_msgs::Point q;
  q.x = 1.0;
  q.y = 2.0;
  s.path_ahead = { q, q };
  s.path_ahead[1].x = 4.0;
  s.path_ahead.push_back(q);
  s.path_ahead[2].y = std::nan("");  // a point that is no point is left out
  in = fromMsg(s);
  ASSERT_EQ(in.path.size(), 2u);
  EXPECT_DOUBLE_EQ(in.path[1][0], 4.0);
  EXPECT_DOUBLE_EQ(in.path[1][1], 2.0);
  EXPECT_EQ(in.status, NavStatus::OK);
  EXPECT_FLOAT_EQ(in.heading, 0.5f);
  EXPECT_FLOAT_EQ(in.path_heading, 1.0f);
  EXPECT_FLOAT_EQ(in.waypoint_distance, 2.5f);
  EXPECT_FLOAT_EQ(in.free_ahead, 0.9f);
  EXPECT_FLOAT_EQ(in.free_left, 1.2f);
  EXPECT_FLOAT_EQ(in.free_right, 0.3f);
  EXPECT_EQ(in.message, "ok");
  EXPECT_TRUE(std::isnan(in.source_time));  // no source_stamp: unknown, never guided on
  s.source_stamp = ros::Time(1234.5);
  EXPECT_DOUBLE_EQ(fromMsg(s).source_time, 1234.5);
  s.status = 42;  // a status this build does not know: treated as "cannot decide"
  in = fromMsg(s);
  EXPECT_EQ(in.status, NavStatus::NO_POSE);
  EXPECT_NE(in.message.find("42"), std::string::npos);
  CueLogic logic;
  EXPECT_EQ(logic.update(in, 0.0).mode, CueMode::UNSURE);
}

// The crossing advice comes through: code, mover, time, distance; an unknown code is no advice.
TEST(Conversions, NavigationStateCrossing)
{
  assistive_msgs::NavigationState s;
  s.status = assistive_msgs::NavigationState::OK;
  EXPECT_EQ(fromMsg(s).crossing, CrossingAdvice::NONE);
  s.crossing = assistive_msgs::NavigationState::CROSSING_RIGHT;
  s.crossing_id = 7;
  s.crossing_time = 1.75f;
  s.crossing_distance = 0.25f;
  NavInput in = fromMsg(s);
  EXPECT_EQ(in.crossing, CrossingAdvice::RIGHT);
  EXPECT_EQ(in.crossing_id, 7);
  EXPECT_DOUBLE_EQ(in.crossing_time, 1.75);
  EXPECT_DOUBLE_EQ(in.crossing_distance, 0.25);
  s.crossing = assistive_msgs::NavigationState::CROSSING_STOP;
  EXPECT_EQ(fromMsg(s).crossing, CrossingAdvice::STOP);
  s.crossing = assistive_msgs::NavigationState::CROSSING_LEFT;
  EXPECT_EQ(fromMsg(s).crossing, CrossingAdvice::LEFT);
  s.crossing = 9;
  EXPECT_EQ(fromMsg(s).crossing, CrossingAdvice::NONE);
}
