#include "assistive_planner/cost_grid.h"

#include <algorithm>
#include <functional>
#include <queue>
#include <utility>

namespace assistive_planner
{
namespace
{
using QItem = std::pair<double, int>;
using MinQueue = std::priority_queue<QItem, std::vector<QItem>, std::greater<QItem>>;
}  // namespace

std::vector<double> dijkstraCostToGoal(const CostGrid& g, int goal_x, int goal_y, size_t* expansions)
{
  std::vector<double> dist(g.w.size(), COST_INF);
  size_t n_exp = 0;
  if (!g.inside(goal_x, goal_y))
    return dist;
  MinQueue q;
  const int gi = g.index(goal_x, goal_y);
  dist[size_t(gi)] = 0.0;
  q.push({ 0.0, gi });
  while (!q.empty())
  {
    const auto [d, u] = q.top();
    q.pop();
    if (d > dist[size_t(u)])
      continue;
    ++n_exp;
    const int x = u % g.width, y = u / g.width;
    for (int k = 0; k < 8; ++k)
    {
      const double c = g.edgeCost(x, y, k);  // symmetric
      if (c == COST_INF)
        continue;
      const int v = g.index(x + NB_DX[k], y + NB_DY[k]);
      if (d + c < dist[size_t(v)])
      {
        dist[size_t(v)] = d + c;
        q.push({ d + c, v });
      }
    }
  }
  if (expansions)
    *expansions = n_exp;
  return dist;
}

SearchResult astar(const CostGrid& g, int sx, int sy, int gx, int gy)
{
  SearchResult r;
  if (!g.inside(sx, sy) || !g.inside(gx, gy))
    return r;
  const size_t n = g.w.size();
  std::vector<double> dist(n, COST_INF);
  std::vector<int> parent(n, -1);
  std::vector<char> closed(n, 0);
  MinQueue q;
  const int s = g.index(sx, sy), t = g.index(gx, gy);
  dist[size_t(s)] = 0.0;
  q.push({ octile(gx - sx, gy - sy), s });
  while (!q.empty())
  {
    const int u = q.top().second;
    q.pop();
    if (closed[size_t(u)])
      continue;
    closed[size_t(u)] = 1;
    ++r.expansions;
    if (u == t)
      break;
    const int x = u % g.width, y = u / g.width;
    for (int k = 0; k < 8; ++k)
    {
      const double c = g.edgeCost(x, y, k);
      if (c == COST_INF)
        continue;
      const int nx = x + NB_DX[k], ny = y + NB_DY[k];
      const int v = g.index(nx, ny);
      if (closed[size_t(v)])
        continue;
      const double nd = dist[size_t(u)] + c;
      if (nd < dist[size_t(v)])
      {
        dist[size_t(v)] = nd;
        parent[size_t(v)] = u;
        q.push({ nd + octile(gx - nx, gy - ny), v });
      }
    }
  }
  r.cost = dist[size_t(t)];
  if (r.cost < COST_INF)
  {
    for (int v = t; v != -1; v = parent[size_t(v)])
      r.path.push_back(v);
    std::reverse(r.path.begin(), r.path.end());
  }
  return r;
}

double pathCost(const CostGrid& g, const std::vector<int>& path)
{
  if (path.empty())
    return COST_INF;
  double c = 0.0;
  for (size_t i = 1; i < path.size(); ++i)
  {
    const int x = path[i - 1] % g.width, y = path[i - 1] / g.width;
    const int dx = path[i] % g.width - x, dy = path[i] / g.width - y;
    int k = -1;
    for (int j = 0; j < 8; ++j)
      if (NB_DX[j] == dx && NB_DY[j] == dy)
        k = j;
    if (k < 0)
      return COST_INF;
    c += g.edgeCost(x, y, k);
  }
  return c;
}
}  // namespace assistive_planner
