#pragma once

#include <cmath>
#include <cstdint>
#include <vector>
#include <assistive_common/code_grid.h>
#include <assistive_common/codes.h>

namespace assistive_planner
{
/// Cell codes of the traversability grid (README "Grid cell codes"; one definition for every
/// stage in assistive_common/codes.h).
using assistive_common::CELL_FREE;
using assistive_common::CELL_OBSTACLE;
using assistive_common::CELL_STEP;
using assistive_common::CELL_UNKNOWN;
using assistive_common::isObstacleCode;
using assistive_common::isTraversableCode;
using assistive_common::isUnknownCode;

/// ROS-free copy of an OccupancyGrid: the one grid of cell codes (assistive_common/code_grid.h),
/// axis aligned with the world frame; at() is CELL_UNKNOWN outside.
using Grid = assistive_common::CodeGrid;

struct Point2
{
  double x = 0.0;
  double y = 0.0;
};

inline double wrapAngle(double a)
{
  return std::atan2(std::sin(a), std::cos(a));
}
}  // namespace assistive_planner
