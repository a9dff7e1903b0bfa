#pragma once
// The codes the stages exchange, in one place (README "Grid cell codes", docs/design.md
// "Topics"): the traversability grid's cell values, the planner's navigation status and the cue
// logic's modes. ROS-free on purpose (every stage's core includes it); each package's
// conversions.cpp checks them against the message constants with static_assert.
#include <cstdint>

namespace assistive_common
{
/// Cell codes of the traversability grid and of the simulator's ground-truth occupancy
/// (nav_msgs/OccupancyGrid data values).
constexpr int8_t CELL_UNKNOWN = -1;   ///< never observed (or not yet decided)
constexpr int8_t CELL_FREE = 0;       ///< traversable floor
constexpr int8_t CELL_STEP = 50;      ///< step or curb: traversable with care
constexpr int8_t CELL_OBSTACLE = 100; ///< anything between the floor and head height plus a margin

inline bool isTraversableCode(int8_t c) { return c == CELL_FREE || c == CELL_STEP; }
inline bool isObstacleCode(int8_t c) { return c > CELL_STEP; }  // 51..100: obstacle
inline bool isUnknownCode(int8_t c) { return c < 0; }

/// Navigation status of the planner (assistive_msgs/NavigationState.status).
enum class NavStatus : uint8_t
{
  OK = 0,          ///< a path to the waypoint exists
  NO_POSE = 1,     ///< no trusted wearer pose
  NO_MAP = 2,      ///< no traversability grid yet, or it is stale
  IN_UNKNOWN = 3,  ///< the wearer stands in unmapped space: no path is invented
  NO_PATH = 4,     ///< no free path to any waypoint
  NO_WAYPOINT = 5  ///< nothing traversable inside the search triangle
};

/// The planner's advice about a person whose predicted path crosses the wearer's
/// (assistive_msgs/NavigationState.crossing): what the wearer should do about the most urgent one.
enum class CrossingAdvice : uint8_t
{
  NONE = 0,   ///< nobody crossing, or no fresh mover news
  LEFT = 1,   ///< step / veer left to let them pass
  RIGHT = 2,  ///< step / veer right
  STOP = 3    ///< stop: too close in time, or the avoiding side is blocked
};

/// "NONE", "LEFT", "RIGHT", "STOP" (logs, diagnostics, markers).
inline const char* crossingName(CrossingAdvice a)
{
  switch (a)
  {
    case CrossingAdvice::NONE:
      return "NONE";
    case CrossingAdvice::LEFT:
      return "LEFT";
    case CrossingAdvice::RIGHT:
      return "RIGHT";
    case CrossingAdvice::STOP:
      return "STOP";
  }
  return "?";
}

/// Cue mode of the cue logic (assistive_msgs/TactileCue.mode).
enum class CueMode : uint8_t
{
  IDLE = 0,       ///< on course, motors off
  GUIDANCE = 1,   ///< turn: a shoulder motor
  PROXIMITY = 2,  ///< obstacle near: a waist motor toward free space
  ALERT = 3,      ///< obstacle very near or nothing free: all four motors
  UNSURE = 4      ///< the system cannot decide: motors off
};
}  // namespace assistive_common
