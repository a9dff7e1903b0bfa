#include "assistive_tactile/conversions.h"

#include <cstdint>
#include <assistive_msgs/NavigationState.h>
#include <assistive_msgs/TactileCue.h>

#include <algorithm>
#include <cmath>

namespace assistive_tactile
{
// The navigation status (assistive_common/codes.h) is assistive_msgs/NavigationState.status.
static_assert(static_cast<int>(NavStatus::OK) == static_cast<int>(assistive_msgs::NavigationState::OK), "NavigationState.OK");
static_assert(static_cast<int>(NavStatus::NO_POSE) == static_cast<int>(assistive_msgs::NavigationState::NO_POSE), "NavigationState.NO_POSE");
static_assert(static_cast<int>(NavStatus::NO_MAP) == static_cast<int>(assistive_msgs::NavigationState::NO_MAP), "NavigationState.NO_MAP");
static_assert(static_cast<int>(NavStatus::IN_UNKNOWN) == static_cast<int>(assistive_msgs::NavigationState::IN_UNKNOWN), "NavigationState.IN_UNKNOWN");
static_assert(static_cast<int>(NavStatus::NO_PATH) == static_cast<int>(assistive_msgs::NavigationState::NO_PATH), "NavigationState.NO_PATH");
static_assert(static_cast<int>(NavStatus::NO_WAYPOINT) == static_cast<int>(assistive_msgs::NavigationState::NO_WAYPOINT), "NavigationState.NO_WAYPOINT");
// The crossing advice (assistive_common/codes.h) is assistive_msgs/NavigationState.crossing.
static_assert(static_cast<int>(CrossingAdvice::NONE) == static_cast<int>(assistive_msgs::NavigationState::CROSSING_NONE), "NavigationState.CROSSING_NONE");
static_assert(static_cast<int>(CrossingAdvice::LEFT) == static_cast<int>(assistive_msgs::NavigationState::CROSSING_LEFT), "NavigationState.CROSSING_LEFT");
static_assert(static_cast<int>(CrossingAdvice::RIGHT) == static_cast<int>(assistive_msgs::NavigationState::CROSSING_RIGHT), "NavigationState.CROSSING_RIGHT");
static_assert(static_cast<int>(CrossingAdvice::STOP) == static_cast<int>(assistive_msgs::NavigationState::CROSSING_STOP), "NavigationState.CROSSING_STOP");
// The cue modes (assistive_common/codes.h) are assistive_msgs/TactileCue.mode.
static_assert(static_cast<int>(CueMode::IDLE) == static_cast<int>(assistive_msgs::TactileCue::IDLE), "TactileCue.IDLE");
static_assert(static_cast<int>(CueMode::GUIDANCE) == static_cast<int>(assistive_msgs::TactileCue::GUIDANCE), "TactileCue.GUIDANCE");
static_assert(static_cast<int>(CueMode::PROXIMITY) == static_cast<int>(assistive_msgs::TactileCue::PROXIMITY), "TactileCue.PROXIMITY");
static_assert(static_cast<int>(CueMode::ALERT) == static_cast<int>(assistive_msgs::TactileCue::ALERT), "TactileCue.ALERT");
static_assert(static_cast<int>(CueMode::UNSURE) == static_cast<int>(assistive_msgs::TactileCue::UNSURE), "TactileCue.UNSURE");
static_assert(static_cast<int>(Instruction::VEER) == static_cast<int>(assistive_msgs::TactileCue::VEER), "TactileCue.VEER");
static_assert(static_cast<int>(Instruction::UNSURE) == static_cast<int>(assistive_msgs::TactileCue::UNSURE_START), "TactileCue.UNSURE_START");
// Motor indices of the intensity array (TactileCue constants).
static_assert(static_cast<int>(LEFT_SHOULDER) == static_cast<int>(assistive_msgs::TactileCue::LEFT_SHOULDER), "TactileCue.LEFT_SHOULDER");
static_assert(static_cast<int>(RIGHT_SHOULDER) == static_cast<int>(assistive_msgs::TactileCue::RIGHT_SHOULDER), "TactileCue.RIGHT_SHOULDER");
static_assert(static_cast<int>(LEFT_WAIST) == static_cast<int>(assistive_msgs::TactileCue::LEFT_WAIST), "TactileCue.LEFT_WAIST");
static_assert(static_cast<int>(RIGHT_WAIST) == static_cast<int>(assistive_msgs::TactileCue::RIGHT_WAIST), "TactileCue.RIGHT_WAIST");

NavInput fromMsg(const assistive_msgs::NavigationState& msg)
{
  NavInput in;
  in.status = msg.status <= static_cast<uint8_t>(NavStatus::NO_WAYPOINT) ? static_cast<NavStatus>(msg.status) :
                                                                           NavStatus::NO_POSE;
  in.message = msg.message;
  if (msg.status > static_cast<uint8_t>(NavStatus::NO_WAYPOINT))
    in.message = "unknown planner status " + std::to_string(msg.status);
  in.heading = msg.heading;
  in.path_heading = msg.path_heading;
  in.waypoint_distance = msg.waypoint_distance;
  in.free_ahead = msg.free_distance_ahead;
  in.free_left = msg.free_distance_left;
  in.free_right = msg.free_distance_right;
  in.steer_heading = msg.steer_heading;
  in.walk_heading = msg.walk_heading;
  in.walking_speed = msg.walking_speed;
  in.head_yaw = msg.head_yaw;
  in.free_steer = msg.free_distance_steer;
  in.passage_distance = msg.passage_distance;
  in.passage_heading = msg.passage_heading;
  in.passage_width = msg.passage_width;
  in.passage_x = msg.passage_point.x;
  in.passage_y = msg.passage_point.y;
  in.passage_axis = msg.passage_axis;
  in.x = msg.wearer.x;  // in the state's frame (the planner's grid's)
  in.y = msg.wearer.y;
  for (const geometry_msgs::Point& q : msg.path_ahead)
    if (std::isfinite(q.x) && std::isfinite(q.y))
      in.path.push_back({ q.x, q.y });
  // an advice code this build does not know is no advice (the status still decides the rest)
  in.crossing = msg.crossing <= static_cast<uint8_t>(CrossingAdvice::STOP) ? static_cast<CrossingAdvice>(msg.crossing) :
                                                                            CrossingAdvice::NONE;
  in.crossing_id = static_cast<int>(std::min<uint32_t>(msg.crossing_id, 0x7fffffff));
  in.crossing_time = msg.crossing_time;
  in.crossing_distance = msg.crossing_distance;
  if (!msg.source_stamp.isZero())  // zero = unknown: stays NaN, never guided on
    in.source_time = msg.source_stamp.toSec();
  return in;
}

assistive_msgs::TactileCue toMsg(const Cue& cue, const ros::Time& stamp, const ros::Time& source_stamp,
                                 const std::string& frame_id)
{
  assistive_msgs::TactileCue m;
  m.header.stamp = stamp;
  m.header.frame_id = frame_id;
  m.source_stamp = source_stamp;
  m.mode = static_cast<uint8_t>(cue.mode);
  for (int i = 0; i < NUM_MOTORS; ++i)
    m.intensity[i] = cue.intensity[i];
  m.instruction = static_cast<uint8_t>(cue.instruction);
  m.level = static_cast<uint8_t>(cue.level);
  m.pattern_id = cue.pattern.id;
  m.pulse_on_ms = static_cast<uint16_t>(10u * cue.pattern.on_10ms);
  m.pulse_off_ms = static_cast<uint16_t>(10u * cue.pattern.off_10ms);
  m.pulse_count = cue.pattern.count;
  m.reason = cue.reason;
  return m;
}

Cue fromMsg(const assistive_msgs::TactileCue& msg)
{
  Cue c;
  c.mode = msg.mode <= static_cast<uint8_t>(CueMode::UNSURE) ? static_cast<CueMode>(msg.mode) : CueMode::UNSURE;
  for (int i = 0; i < NUM_MOTORS; ++i)
  {
    const float v = msg.intensity[i];
    c.intensity[i] = std::isfinite(v) ? std::min(1.f, std::max(0.f, v)) : 0.f;
  }
  c.instruction = msg.instruction <= static_cast<uint8_t>(Instruction::UNSURE) ? static_cast<Instruction>(msg.instruction)
                                                                              : Instruction::NONE;
  c.level = std::min<int>(msg.level, 3);
  c.pattern.id = msg.pattern_id;
  // 10 ms units; a pulse shorter than 5 ms still pulses (0 would mean steady, a buzz)
  c.pattern.on_10ms = static_cast<uint8_t>(msg.pulse_on_ms == 0 ? 0 : std::max(1, std::min(255, (msg.pulse_on_ms + 5) / 10)));
  c.pattern.off_10ms = static_cast<uint8_t>(std::min(255, (msg.pulse_off_ms + 5) / 10));
  c.pattern.count = msg.pulse_count;
  c.reason = msg.reason;
  return c;
}

}  // namespace assistive_tactile
