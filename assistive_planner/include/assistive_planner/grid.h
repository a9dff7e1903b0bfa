#pragma once

#include <cmath>
#include <cstdint>
#include <vector>
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

/// ROS-free copy of an OccupancyGrid: row-major, cell (x, y) at data[y * width + x],
/// cell centre at origin + (x + 0.5, y + 0.5) * resolution. The grid is axis aligned with the world frame.
struct Grid
{
  int width = 0;
  int height = 0;
  double resolution = 0.2;
  double origin_x = 0.0;
  double origin_y = 0.0;
  std::vector<int8_t> data;

  bool empty() const { return width <= 0 || height <= 0 || data.size() != size_t(width) * size_t(height); }
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  int index(int x, int y) const { return y * width + x; }
  int8_t at(int x, int y) const { return data[size_t(index(x, y))]; }
  bool worldToCell(double wx, double wy, int& x, int& y) const
  {
    x = int(std::floor((wx - origin_x) / resolution));
    y = int(std::floor((wy - origin_y) / resolution));
    return inside(x, y);
  }
  double cellX(int x) const { return origin_x + (x + 0.5) * resolution; }
  double cellY(int y) const { return origin_y + (y + 0.5) * resolution; }
};

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
