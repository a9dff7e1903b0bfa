#include "assistive_planner/dstar_lite.h"

#include <algorithm>
#include <cmath>

namespace assistive_planner
{
void DStarLite::reset(const CostGrid& costs)
{
  grid_ = costs;
  has_goal_ = false;
  has_start_ = false;
  clearSearch();
}

void DStarLite::clearSearch()
{
  const size_t n = grid_.w.size();
  g_.assign(n, COST_INF);
  rhs_.assign(n, COST_INF);
  key_.assign(n, Key());
  pos_.assign(n, -1);
  heap_.clear();
  km_ = 0.0;
}

void DStarLite::setGoal(int gx, int gy)
{
  if (has_goal_ && gx == goal_x_ && gy == goal_y_)
    return;
  clearSearch();
  if (!grid_.inside(gx, gy))
  {
    has_goal_ = false;
    return;
  }
  has_goal_ = true;
  goal_x_ = gx;
  goal_y_ = gy;
  last_x_ = start_x_;
  last_y_ = start_y_;
  const int gi = grid_.index(gx, gy);
  rhs_[size_t(gi)] = 0.0;
  heapPush(gi, calcKey(gi));
}

void DStarLite::setStart(int sx, int sy)
{
  if (has_start_)
  {
    // lower bounds of the queued keys stay valid if km grows by the start's move (paper, line 38')
    km_ += octile(sx - last_x_, sy - last_y_);
  }
  has_start_ = true;
  start_x_ = last_x_ = sx;
  start_y_ = last_y_ = sy;
}

DStarLite::Key DStarLite::calcKey(int u) const
{
  const double m = std::min(g_[size_t(u)], rhs_[size_t(u)]);
  if (m == COST_INF)
    return Key{ COST_INF, COST_INF };
  return Key{ m + h(u % grid_.width, u / grid_.width) + km_, m };
}

double DStarLite::minSucc(int u) const
{
  const int x = u % grid_.width, y = u / grid_.width;
  double best = COST_INF;
  for (int k = 0; k < 8; ++k)
  {
    const double c = grid_.edgeCost(x, y, k);
    if (c == COST_INF)
      continue;
    const double v = c + g_[size_t(grid_.index(x + NB_DX[k], y + NB_DY[k]))];
    if (v < best)
      best = v;
  }
  return best;
}

void DStarLite::updateVertex(int u)
{
  const bool inconsistent = g_[size_t(u)] != rhs_[size_t(u)];
  if (inconsistent && inHeap(u))
    heapUpdate(u, calcKey(u));
  else if (inconsistent)
    heapPush(u, calcKey(u));
  else if (inHeap(u))
    heapRemove(u);
}

void DStarLite::repairCell(int u)
{
  if (!has_goal_)
    return;
  const int x = u % grid_.width, y = u / grid_.width;
  const int gi = grid_.index(goal_x_, goal_y_);
  for (int k = -1; k < 8; ++k)
  {
    const int nx = k < 0 ? x : x + NB_DX[k], ny = k < 0 ? y : y + NB_DY[k];
    if (!grid_.inside(nx, ny))
      continue;
    const int v = grid_.index(nx, ny);
    if (v != gi)
      rhs_[size_t(v)] = minSucc(v);
    updateVertex(v);
  }
}

void DStarLite::updateCells(const std::vector<std::pair<int, double>>& changes)
{
  for (const auto& [idx, w] : changes)
    grid_.w[size_t(idx)] = w;
  // km already follows the start in setStart(); cells are repaired after all weights are in
  for (const auto& ch : changes)
    repairCell(ch.first);
}

size_t DStarLite::setCosts(const std::vector<double>& w)
{
  std::vector<std::pair<int, double>> changes;
  const size_t n = std::min(w.size(), grid_.w.size());
  for (size_t i = 0; i < n; ++i)
    if (w[i] != grid_.w[i])
      changes.emplace_back(int(i), w[i]);
  updateCells(changes);
  return changes.size();
}

void DStarLite::scroll(int dx, int dy, const std::vector<double>& w)
{
  const int W = grid_.width, H = grid_.height;
  if (dx == 0 && dy == 0)
  {
    setCosts(w);
    return;
  }
  const size_t n = size_t(W) * size_t(H);
  // shift into scratch buffers kept between calls (fresh allocations cost page faults on every scroll)
  scratch_g_.resize(n);
  scratch_rhs_.resize(n);
  scratch_w_.resize(n);
  scratch_fresh_.resize(n);
  const int x_lo = std::max(0, -dx), x_hi = std::min(W, W - dx);  // new x whose old x + dx is inside
  for (int y = 0; y < H; ++y)
  {
    const size_t row = size_t(y) * size_t(W);
    const int oy = y + dy;
    if (oy < 0 || oy >= H || x_lo >= x_hi)
    {
      std::fill_n(scratch_g_.begin() + long(row), W, COST_INF);
      std::fill_n(scratch_rhs_.begin() + long(row), W, COST_INF);
      std::fill_n(scratch_w_.begin() + long(row), W, COST_INF);
      std::fill_n(scratch_fresh_.begin() + long(row), W, char(1));
      continue;
    }
    const size_t orow = size_t(oy) * size_t(W) + size_t(x_lo + dx);
    const size_t lo = row + size_t(x_lo), len = size_t(x_hi - x_lo);
    std::fill(scratch_g_.begin() + long(row), scratch_g_.begin() + long(lo), COST_INF);
    std::fill(scratch_rhs_.begin() + long(row), scratch_rhs_.begin() + long(lo), COST_INF);
    std::fill(scratch_w_.begin() + long(row), scratch_w_.begin() + long(lo), COST_INF);
    std::fill(scratch_fresh_.begin() + long(row), scratch_fresh_.begin() + long(lo), char(1));
    std::copy_n(g_.begin() + long(orow), len, scratch_g_.begin() + long(lo));
    std::copy_n(rhs_.begin() + long(orow), len, scratch_rhs_.begin() + long(lo));
    std::copy_n(grid_.w.begin() + long(orow), len, scratch_w_.begin() + long(lo));
    std::fill_n(scratch_fresh_.begin() + long(lo), len, char(0));
    std::fill(scratch_g_.begin() + long(lo + len), scratch_g_.begin() + long(row + size_t(W)), COST_INF);
    std::fill(scratch_rhs_.begin() + long(lo + len), scratch_rhs_.begin() + long(row + size_t(W)), COST_INF);
    std::fill(scratch_w_.begin() + long(lo + len), scratch_w_.begin() + long(row + size_t(W)), COST_INF);
    std::fill(scratch_fresh_.begin() + long(lo + len), scratch_fresh_.begin() + long(row + size_t(W)), char(1));
  }
  // queued cells that stay in the window, in new indices
  std::vector<int> queued;
  queued.reserve(heap_.size());
  for (int o : heap_)
  {
    const int x = o % W - dx, y = o / W - dy;
    if (grid_.inside(x, y))
      queued.push_back(y * W + x);
  }
  for (int o : heap_)
    pos_[size_t(o)] = -1;
  heap_.clear();
  g_.swap(scratch_g_);
  rhs_.swap(scratch_rhs_);
  // the start shifts with the window, so h and the keys of the overlap are unchanged
  start_x_ -= dx;
  start_y_ -= dy;
  last_x_ -= dx;
  last_y_ -= dy;
  goal_x_ -= dx;
  goal_y_ -= dy;
  if (has_goal_ && !grid_.inside(goal_x_, goal_y_))
  {
    grid_.w = w;
    has_goal_ = false;
    clearSearch();
    return;
  }
  for (int u : queued)
    heapPush(u, calcKey(u));
  // first the geometry change: the overlap with its old weights, entering cells blocked until they arrive
  grid_.w.swap(scratch_w_);
  // overlap cells at the window border lost neighbours that left the window
  std::vector<std::pair<int, double>> changes;
  for (int x = 0; x < W; ++x)
    for (int y : { 0, H - 1 })
      if (!scratch_fresh_[size_t(y * W + x)])
        repairCell(y * W + x);
  for (int y = 1; y + 1 < H; ++y)
    for (int x : { 0, W - 1 })
      if (!scratch_fresh_[size_t(y * W + x)])
        repairCell(y * W + x);
  // then the entering cells and the changed weights of the overlap
  for (size_t i = 0; i < n; ++i)
    if (scratch_fresh_[i] || w[i] != grid_.w[i])
      changes.emplace_back(int(i), w[i]);
  updateCells(changes);
}

bool DStarLite::plan()
{
  if (!has_goal_ || !has_start_ || !grid_.inside(start_x_, start_y_))
    return false;
  const int s = grid_.index(start_x_, start_y_);
  while (!heap_.empty())
  {
    const int u = heap_.front();
    const Key k_old = key_[size_t(u)];
    const Key k_start = calcKey(s);
    // exact: costs are quantised (cost_grid.h), so ties between h and summed edge costs are real ties
    if (!(k_old < k_start) && !(rhs_[size_t(s)] > g_[size_t(s)]))
      break;
    ++expansions_;
    const Key k_new = calcKey(u);
    const int x = u % grid_.width, y = u / grid_.width;
    if (k_old < k_new)
    {
      heapUpdate(u, k_new);
    }
    else if (g_[size_t(u)] > rhs_[size_t(u)])
    {
      g_[size_t(u)] = rhs_[size_t(u)];
      heapRemove(u);
      const int gi = grid_.index(goal_x_, goal_y_);
      for (int k = 0; k < 8; ++k)
      {
        const double c = grid_.edgeCost(x, y, k);
        if (c == COST_INF)
          continue;
        const int v = grid_.index(x + NB_DX[k], y + NB_DY[k]);
        if (v != gi)
        {
          const double cand = c + g_[size_t(u)];
          if (cand < rhs_[size_t(v)])
            rhs_[size_t(v)] = cand;
        }
        updateVertex(v);
      }
    }
    else
    {
      const double g_old = g_[size_t(u)];
      g_[size_t(u)] = COST_INF;
      const int gi = grid_.index(goal_x_, goal_y_);
      for (int k = -1; k < 8; ++k)
      {
        int v;
        if (k < 0)
        {
          v = u;
        }
        else
        {
          const double c = grid_.edgeCost(x, y, k);
          if (c == COST_INF)
            continue;
          v = grid_.index(x + NB_DX[k], y + NB_DY[k]);
          if (rhs_[size_t(v)] != c + g_old)  // rhs(v) was not supported by u
            continue;
        }
        if (v != gi)
          rhs_[size_t(v)] = minSucc(v);
        updateVertex(v);
      }
    }
  }
  return rhs_[size_t(s)] < COST_INF;
}

double DStarLite::startCost() const
{
  if (!has_goal_ || !has_start_ || !grid_.inside(start_x_, start_y_))
    return COST_INF;
  return rhs_[size_t(grid_.index(start_x_, start_y_))];
}

std::vector<int> DStarLite::path() const
{
  std::vector<int> p;
  if (startCost() == COST_INF)
    return p;
  const int gi = grid_.index(goal_x_, goal_y_);
  int u = grid_.index(start_x_, start_y_);
  p.push_back(u);
  const size_t max_len = grid_.w.size();
  while (u != gi && p.size() <= max_len)
  {
    const int x = u % grid_.width, y = u / grid_.width;
    double best = COST_INF;
    int next = -1;
    for (int k = 0; k < 8; ++k)
    {
      const double c = grid_.edgeCost(x, y, k);
      if (c == COST_INF)
        continue;
      const int v = grid_.index(x + NB_DX[k], y + NB_DY[k]);
      const double val = c + g_[size_t(v)];
      if (val < best)
      {
        best = val;
        next = v;
      }
    }
    if (next < 0)
      return {};
    u = next;
    p.push_back(u);
  }
  if (u != gi)
    return {};
  return p;
}

// ---- indexed binary heap ----
void DStarLite::heapPush(int u, const Key& k)
{
  key_[size_t(u)] = k;
  pos_[size_t(u)] = int(heap_.size());
  heap_.push_back(u);
  siftUp(heap_.size() - 1);
}

void DStarLite::heapUpdate(int u, const Key& k)
{
  const Key old = key_[size_t(u)];
  key_[size_t(u)] = k;
  if (k < old)
    siftUp(size_t(pos_[size_t(u)]));
  else
    siftDown(size_t(pos_[size_t(u)]));
}

void DStarLite::heapRemove(int u)
{
  const size_t i = size_t(pos_[size_t(u)]);
  const int last = heap_.back();
  heap_.pop_back();
  pos_[size_t(u)] = -1;
  if (i < heap_.size())
  {
    heap_[i] = last;
    pos_[size_t(last)] = int(i);
    siftUp(i);
    siftDown(size_t(pos_[size_t(last)]));
  }
}

void DStarLite::siftUp(size_t i)
{
  const int u = heap_[i];
  const Key k = key_[size_t(u)];
  while (i > 0)
  {
    const size_t p = (i - 1) / 2;
    if (!(k < key_[size_t(heap_[p])]))
      break;
    heap_[i] = heap_[p];
    pos_[size_t(heap_[i])] = int(i);
    i = p;
  }
  heap_[i] = u;
  pos_[size_t(u)] = int(i);
}

void DStarLite::siftDown(size_t i)
{
  const size_t n = heap_.size();
  const int u = heap_[i];
  const Key k = key_[size_t(u)];
  while (true)
  {
    size_t c = 2 * i + 1;
    if (c >= n)
      break;
    if (c + 1 < n && key_[size_t(heap_[c + 1])] < key_[size_t(heap_[c])])
      ++c;
    if (!(key_[size_t(heap_[c])] < k))
      break;
    heap_[i] = heap_[c];
    pos_[size_t(heap_[i])] = int(i);
    i = c;
  }
  heap_[i] = u;
  pos_[size_t(u)] = int(i);
}
}  // namespace assistive_planner
