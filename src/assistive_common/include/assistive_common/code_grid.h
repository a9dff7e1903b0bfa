#pragma once
// The grid that carries the cell codes (codes.h), defined once: the obstacle stage's output, the
// planner's input, the simulator's ground-truth occupancy and the evaluation's maps are all this
// struct (assistive_obstacles::GridData, assistive_planner::Grid and assistive_eval::OccupancyGrid
// are its names there). ROS-free (Eigen only); nav_msgs/OccupancyGrid with an identity origin
// orientation is its message.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include <assistive_common/codes.h>

namespace assistive_common
{
/// A 2D grid of cell codes, axis-aligned in its world frame: row-major, cell (ix, iy) at
/// data[iy * width + ix], covering x in [origin_x + ix * resolution, origin_x + (ix + 1) * resolution)
/// (likewise y); its centre at origin + (ix + 0.5, iy + 0.5) * resolution.
struct CodeGrid
{
  double origin_x = 0.0;    ///< m, lower-left corner of cell (0, 0)
  double origin_y = 0.0;    ///< m
  double resolution = 0.2;  ///< m / cell
  int width = 0;            ///< cells along x
  int height = 0;           ///< cells along y
  std::vector<int8_t> data;  ///< row-major, index = iy * width + ix

  /// No cells to read: no size, or data that does not match the size.
  bool empty() const
  {
    return width <= 0 || height <= 0 || data.size() != static_cast<size_t>(width) * static_cast<size_t>(height);
  }
  bool inside(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < width && iy < height; }
  int index(int ix, int iy) const { return iy * width + ix; }
  /// Code of a cell; CELL_UNKNOWN outside the grid.
  int8_t at(int ix, int iy) const { return inside(ix, iy) ? data[static_cast<size_t>(index(ix, iy))] : CELL_UNKNOWN; }
  /// World coordinates -> cell index (also when outside); false when outside the grid.
  bool cellOf(double x, double y, int& ix, int& iy) const
  {
    ix = static_cast<int>(std::floor((x - origin_x) / resolution));
    iy = static_cast<int>(std::floor((y - origin_y) / resolution));
    return inside(ix, iy);
  }
  /// The planner's name for cellOf().
  bool worldToCell(double x, double y, int& ix, int& iy) const { return cellOf(x, y, ix, iy); }
  /// Code at a world point (CELL_UNKNOWN outside).
  int8_t atWorld(double x, double y) const
  {
    int ix, iy;
    return cellOf(x, y, ix, iy) ? data[static_cast<size_t>(index(ix, iy))] : CELL_UNKNOWN;
  }
  /// Centre of a cell in world coordinates.
  double cellX(int ix) const { return origin_x + (ix + 0.5) * resolution; }
  double cellY(int iy) const { return origin_y + (iy + 0.5) * resolution; }
  Eigen::Vector2d cellCenter(int ix, int iy) const { return {cellX(ix), cellY(iy)}; }
};
}  // namespace assistive_common
