#pragma once
// Cell codes of the traversability grid (README "Grid cell codes": one definition for every
// stage, assistive_common/codes.h), and per-frame labels.
#include <cstdint>
#include <assistive_common/codes.h>

namespace assistive_obstacles
{
/// Output codes (nav_msgs/OccupancyGrid data values).
using assistive_common::CELL_FREE;
using assistive_common::CELL_OBSTACLE;
using assistive_common::CELL_STEP;
using assistive_common::CELL_UNKNOWN;

/// Per-frame label of one cell (before the temporal filter).
enum class FrameLabel : uint8_t
{
  NONE = 0,      ///< no vote this frame (not observed, too few points, or undecidable)
  FREE = 1,
  STEP = 2,
  OBSTACLE = 3,
};
}  // namespace assistive_obstacles
