#pragma once

#include <cmath>
#include <limits>
#include <vector>

namespace assistive_planner
{
constexpr double COST_INF = std::numeric_limits<double>::infinity();
constexpr double SQRT2 = 1.4142135623730951;
/// Edge costs are rounded to multiples of 1/COST_SCALE (a power of two): sums of them are exact in double,
/// so D* Lite's key comparisons and rhs == c + g tests are exact, with no round-off ties.
constexpr double COST_SCALE = 1024.0;
inline double quantizeCost(double c) { return std::round(c * COST_SCALE) / COST_SCALE; }
/// The diagonal step at unit weight after quantisation (1448 / 1024), used by the heuristic.
inline const double DIAG_UNIT = quantizeCost(SQRT2);

/// The 8 neighbour offsets: 0..3 straight, 4..7 diagonal.
constexpr int NB_DX[8] = { 1, -1, 0, 0, 1, 1, -1, -1 };
constexpr int NB_DY[8] = { 0, 0, 1, -1, 1, -1, 1, -1 };

/// Per-cell traversal weights (>= 1 per metre of cell length; COST_INF = blocked), row-major.
/// Edge cost between 8-neighbours u, v: length (1 or sqrt 2 cells) * (w[u] + w[v]) / 2; infinite if either
/// end is blocked or, for a diagonal, if either of the two cells it passes between is blocked (no corner cutting).
/// Symmetric, so predecessors = successors. The heuristic octile distance (weights >= 1) is consistent.
struct CostGrid
{
  int width = 0;
  int height = 0;
  std::vector<double> w;

  CostGrid() = default;
  CostGrid(int wd, int ht, double fill = 1.0) : width(wd), height(ht), w(size_t(wd) * size_t(ht), fill) {}
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  int index(int x, int y) const { return y * width + x; }

  /// Cost from cell (x, y) to its neighbour k (see NB_DX); COST_INF if blocked or outside.
  double edgeCost(int x, int y, int k) const
  {
    const int nx = x + NB_DX[k], ny = y + NB_DY[k];
    if (!inside(nx, ny))
      return COST_INF;
    const double a = w[size_t(index(x, y))], b = w[size_t(index(nx, ny))];
    if (a == COST_INF || b == COST_INF)
      return COST_INF;
    if (k < 4)
      return quantizeCost(0.5 * (a + b));
    if (w[size_t(index(nx, y))] == COST_INF || w[size_t(index(x, ny))] == COST_INF)
      return COST_INF;
    return quantizeCost(SQRT2 * 0.5 * (a + b));
  }
};

/// Octile distance in cells with the quantised diagonal (admissible and consistent for weights >= 1).
inline double octile(int dx, int dy)
{
  dx = std::abs(dx);
  dy = std::abs(dy);
  const int mn = dx < dy ? dx : dy, mx = dx < dy ? dy : dx;
  return (mx - mn) + DIAG_UNIT * mn;
}

/// Reference searches (tests and benchmark): plain Dijkstra and A* from scratch.
struct SearchResult
{
  double cost = COST_INF;
  size_t expansions = 0;
  std::vector<int> path;  ///< cell indices start..goal (A* only)
};
/// Dijkstra from goal over the whole grid; returns the cost-to-goal of every cell.
std::vector<double> dijkstraCostToGoal(const CostGrid& g, int goal_x, int goal_y, size_t* expansions = nullptr);
/// A* start -> goal with the octile heuristic.
SearchResult astar(const CostGrid& g, int sx, int sy, int gx, int gy);
/// Cost of a path given as cell indices (COST_INF if a step is not an allowed edge).
double pathCost(const CostGrid& g, const std::vector<int>& path);
}  // namespace assistive_planner
