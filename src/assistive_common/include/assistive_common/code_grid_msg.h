#pragma once
// The one conversion between the shared grid (code_grid.h: assistive_obstacles::GridData,
// assistive_planner::Grid, assistive_eval::OccupancyGrid) and its message, nav_msgs/OccupancyGrid
// with an identity origin orientation (rtabmap's MsgConversion.h, tf2_eigen: toMsg / fromMsg).
// For the nodelets, tools and benchmarks: it includes ROS messages, so no core library includes it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>

#include <nav_msgs/OccupancyGrid.h>
#include <ros/time.h>
#include <std_msgs/Header.h>

#include <assistive_common/code_grid.h>

namespace assistive_common
{
// The grid codes (codes.h) are nav_msgs/OccupancyGrid values: int8 cells, -1 unknown, occupancy
// 0..100 with the step code in between.
static_assert(std::is_same<nav_msgs::OccupancyGrid::_data_type::value_type, int8_t>::value,
              "nav_msgs/OccupancyGrid cells are int8");
static_assert(CELL_UNKNOWN == -1, "nav_msgs/OccupancyGrid: -1 is unknown");
static_assert(CELL_FREE == 0 && CELL_OBSTACLE == 100, "nav_msgs/OccupancyGrid: occupancy 0 (free) .. 100 (occupied)");
static_assert(CELL_FREE < CELL_STEP && CELL_STEP < CELL_OBSTACLE, "the step code lies between free and obstacle");

/// Grid -> message (identity orientation, z = 0; map_load_time = the header's stamp).
inline nav_msgs::OccupancyGrid toMsg(const CodeGrid& grid, const std_msgs::Header& header)
{
  nav_msgs::OccupancyGrid m;
  m.header = header;
  m.info.map_load_time = header.stamp;
  m.info.resolution = static_cast<float>(grid.resolution);
  m.info.width = static_cast<uint32_t>(std::max(0, grid.width));
  m.info.height = static_cast<uint32_t>(std::max(0, grid.height));
  m.info.origin.position.x = grid.origin_x;
  m.info.origin.position.y = grid.origin_y;
  m.info.origin.orientation.w = 1.0;
  m.data = grid.data;
  return m;
}

/// Grid -> message with a header of `frame` and `stamp`.
inline nav_msgs::OccupancyGrid toMsg(const CodeGrid& grid, const std::string& frame, const ros::Time& stamp)
{
  std_msgs::Header h;
  h.stamp = stamp;
  h.frame_id = frame;
  return toMsg(grid, h);
}

/// Message -> grid, checked: false (and `out` empty) when the grid is malformed (no cells, a
/// resolution that is not positive and finite, data of another size, an origin not finite) or
/// rotated (our grids are axis-aligned).
inline bool fromMsg(const nav_msgs::OccupancyGrid& msg, CodeGrid& out)
{
  out = CodeGrid();
  const auto& info = msg.info;
  const auto& q = info.origin.orientation;
  const bool identity = std::abs(q.x) < 1e-6 && std::abs(q.y) < 1e-6 && std::abs(q.z) < 1e-6;
  if (info.width == 0 || info.height == 0 || !(info.resolution > 0.0f) || !std::isfinite(info.resolution) ||
      msg.data.size() != size_t(info.width) * size_t(info.height) || !identity ||
      !std::isfinite(info.origin.position.x) || !std::isfinite(info.origin.position.y))
    return false;
  out.width = int(info.width);
  out.height = int(info.height);
  out.resolution = info.resolution;
  out.origin_x = info.origin.position.x;
  out.origin_y = info.origin.position.y;
  out.data = msg.data;
  return true;
}

/// Message -> grid as it comes (orientation ignored): the size and origin copied, data missing at
/// the end unknown (CELL_UNKNOWN), extra data dropped.
inline CodeGrid fromMsg(const nav_msgs::OccupancyGrid& msg)
{
  CodeGrid g;
  g.origin_x = msg.info.origin.position.x;
  g.origin_y = msg.info.origin.position.y;
  g.resolution = msg.info.resolution;
  g.width = static_cast<int>(msg.info.width);
  g.height = static_cast<int>(msg.info.height);
  g.data = msg.data;
  const size_t n = static_cast<size_t>(g.width) * static_cast<size_t>(g.height);
  if (g.data.size() != n)
    g.data.resize(n, CELL_UNKNOWN);
  return g;
}
}  // namespace assistive_common
