#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "assistive_planner/cost_grid.h"

namespace assistive_planner
{
/// D* Lite (Koenig & Likhachev 2005, the optimised version of their figure 4) on an 8-connected
/// CostGrid. The search runs backwards from the goal, so moves of the start and cost changes near it
/// are repaired with few expansions. Priority queue: an indexed binary heap (decrease/increase/remove
/// in O(log n)). The window may scroll: `scroll()` keeps g/rhs of the overlap and repairs the border.
class DStarLite
{
public:
  struct Key
  {
    double k1 = COST_INF;
    double k2 = COST_INF;
    bool operator<(const Key& o) const { return k1 < o.k1 || (k1 == o.k1 && k2 < o.k2); }
  };

  /// New grid: all search state is dropped (call setGoal, setStart, plan).
  void reset(const CostGrid& costs);
  /// Goal cell. A different goal restarts the search cleanly (g = rhs = inf, empty queue, km = 0).
  void setGoal(int gx, int gy);
  /// Current start (wearer) cell; km grows by h(last start, start).
  void setStart(int sx, int sy);
  /// Changed cell weights (index, new weight). Repairs rhs of each cell and its 8 neighbours.
  void updateCells(const std::vector<std::pair<int, double>>& changes);
  /// Diffs a full weight array of the same size against the current one and applies the changes.
  size_t setCosts(const std::vector<double>& w);
  /// Window scroll: new cell (x, y) is old cell (x + dx, y + dy). `w` is the full new weight array.
  /// Cells leaving the window are dropped, entering cells start at g = rhs = inf, the border is repaired.
  /// If the goal leaves the window the search state is cleared (hasGoal() false).
  void scroll(int dx, int dy, const std::vector<double>& w);
  /// ComputeShortestPath. Returns true if the start has a finite cost.
  bool plan();

  bool hasGoal() const { return has_goal_; }
  bool hasStart() const { return has_start_; }
  int goalX() const { return goal_x_; }
  int goalY() const { return goal_y_; }
  int startX() const { return start_x_; }
  int startY() const { return start_y_; }
  double startCost() const;
  /// Greedy descent from the start on g; cell indices start..goal, empty if no path.
  std::vector<int> path() const;
  const CostGrid& costs() const { return grid_; }
  double g(int idx) const { return g_[size_t(idx)]; }
  size_t expansions() const { return expansions_; }
  void resetExpansions() { expansions_ = 0; }

private:
  double h(int x, int y) const { return octile(x - start_x_, y - start_y_); }
  Key calcKey(int u) const;
  void updateVertex(int u);
  double minSucc(int u) const;
  void repairCell(int u);  // recompute rhs of u and its neighbours
  // indexed heap
  void heapPush(int u, const Key& k);
  void heapUpdate(int u, const Key& k);
  void heapRemove(int u);
  void siftUp(size_t i);
  void siftDown(size_t i);
  bool inHeap(int u) const { return pos_[size_t(u)] >= 0; }
  void clearSearch();

  CostGrid grid_;
  std::vector<double> g_, rhs_;
  std::vector<Key> key_;
  std::vector<int> pos_;   // heap position, -1 = not queued
  std::vector<int> heap_;  // cell indices
  double km_ = 0.0;
  bool has_goal_ = false, has_start_ = false;
  int goal_x_ = 0, goal_y_ = 0, start_x_ = 0, start_y_ = 0, last_x_ = 0, last_y_ = 0;
  size_t expansions_ = 0;
  std::vector<double> scratch_g_, scratch_rhs_, scratch_w_;  // scroll buffers, reused
  std::vector<char> scratch_fresh_;
};
}  // namespace assistive_planner
