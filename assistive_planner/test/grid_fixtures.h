// Test support for the planner's gtests: a free 0.2 m grid, a rectangle of one cell code in it and
// a cell of the planner's published grid (one copy for test_planner, test_waypoint and test_blind_zone).
#pragma once

#include <cstddef>
#include <cstdint>

#include "assistive_planner/planner.h"

namespace planner_test
{
/// An n x n grid of free 0.2 m cells, its lower-left corner at (ox, oy).
inline assistive_planner::Grid freeGrid(double ox, double oy, int n)
{
  assistive_planner::Grid g;
  g.width = g.height = n;
  g.resolution = 0.2;
  g.origin_x = ox;
  g.origin_y = oy;
  g.data.assign(size_t(n * n), assistive_planner::CELL_FREE);
  return g;
}
/// Sets every cell whose centre lies in [x0, x1] x [y0, y1] to `code`.
inline void fillRect(assistive_planner::Grid& g, double x0, double y0, double x1, double y1, int8_t code)
{
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x)
      if (g.cellX(x) >= x0 && g.cellX(x) <= x1 && g.cellY(y) >= y0 && g.cellY(y) <= y1)
        g.data[size_t(g.index(x, y))] = code;
}
/// No grid in the planner's output, or the point lies outside it (no cell code).
constexpr int kNoCell = 1000;
/// The code of the cell of the planner's published grid (`PlanOutput::grid`) holding (x, y); kNoCell
/// when there is none.
inline int plannedCell(const assistive_planner::PlanOutput& o, double x, double y)
{
  int cx, cy;
  if (!o.grid || !o.grid->worldToCell(x, y, cx, cy))
    return kNoCell;
  return o.grid->at(cx, cy);
}
}  // namespace planner_test
