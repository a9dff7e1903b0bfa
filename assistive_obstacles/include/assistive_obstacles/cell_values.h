#pragma once
// Cell codes of the traversability grid (README "Grid cell codes"), and per-frame labels.
#include <cstdint>

namespace assistive_obstacles
{
/// Output codes (nav_msgs/OccupancyGrid data values).
constexpr int8_t UNKNOWN = -1;   ///< never observed (or not yet decided)
constexpr int8_t FREE = 0;       ///< traversable floor
constexpr int8_t STEP = 50;      ///< step or curb: traversable with care
constexpr int8_t OBSTACLE = 100; ///< anything between the floor and head height plus a margin

/// Per-frame label of one cell (before the temporal filter).
enum class FrameLabel : uint8_t
{
  NONE = 0,      ///< no vote this frame (not observed, too few points, or undecidable)
  FREE = 1,
  STEP = 2,
  OBSTACLE = 3,
};
}  // namespace assistive_obstacles
