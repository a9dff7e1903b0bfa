// planner_benchmark: D* Lite replanning against A* from scratch on synthetic grids (no roscore, no args).
// Prints a table, then one JSON line (SPEC.md "Benchmarks").
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "assistive_planner/cost_model.h"
#include "assistive_planner/dstar_lite.h"
#include "assistive_planner/grid.h"

using namespace assistive_planner;
using Clock = std::chrono::steady_clock;

namespace
{
double ms(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double, std::milli>(b - a).count();
}
double median(std::vector<double> v)
{
  if (v.empty())
    return -1.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
bool same(double a, double b)
{
  if (a == COST_INF || b == COST_INF)
    return a == b;
  return std::abs(a - b) <= 1e-9 * (1.0 + std::abs(b));
}

// Random rectangular obstacles (about 20 % of the cells), some step cells, costs from the planner's cost
// model (clearance cost on); start and goal in opposite corners, kept free.
Grid makeGrid(int n, std::mt19937& rng)
{
  Grid g;
  g.width = g.height = n;
  g.resolution = 0.2;
  g.data.assign(size_t(n) * size_t(n), CELL_FREE);
  std::uniform_int_distribution<int> pos(0, n - 1), len(1, std::max(2, n / 12));
  long blocked = 0;
  while (blocked < long(n) * n / 5)
  {
    const int x0 = pos(rng), y0 = pos(rng), w = len(rng), h = len(rng);
    const int8_t code = (rng() % 10 == 0) ? CELL_STEP : CELL_OBSTACLE;
    for (int y = y0; y < std::min(n, y0 + h); ++y)
      for (int x = x0; x < std::min(n, x0 + w); ++x)
        if (g.data[size_t(y * n + x)] == CELL_FREE)
        {
          g.data[size_t(y * n + x)] = code;
          blocked += code == CELL_OBSTACLE;
        }
  }
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
    {
      g.data[size_t(y * n + x)] = CELL_FREE;
      g.data[size_t((n - 1 - y) * n + (n - 1 - x))] = CELL_FREE;
    }
  return g;
}

struct SizeResult
{
  int n = 0;
  double first_ms = 0, first_astar_ms = 0;
  size_t first_exp = 0, first_astar_exp = 0;
  std::vector<double> r1_ms, r1_exp, r1_near_ms, r1_near_exp, a1_exp, a1_near_exp, a1_ms, r50_ms, r50_exp, a50_exp,
      scroll_ms, scroll_exp, ascroll_exp;
  int mismatches = 0, checks = 0;
};

SizeResult runSize(int n, int trials, unsigned seed)
{
  SizeResult R;
  R.n = n;
  std::mt19937 rng(seed);
  PlannerParams p;
  Grid grid;
  CostGrid cg;
  DStarLite base;
  // a grid whose corners are connected
  for (int attempt = 0; attempt < 50; ++attempt)
  {
    grid = makeGrid(n, rng);
    cg = CostGrid(n, n);
    cg.w = cellWeights(grid, p);
    base.reset(cg);
    base.setStart(1, 1);
    base.setGoal(n - 2, n - 2);
    base.resetExpansions();
    const auto t0 = Clock::now();
    const bool ok = base.plan();
    R.first_ms = ms(t0, Clock::now());
    R.first_exp = base.expansions();
    if (ok)
      break;
  }
  const auto t1 = Clock::now();
  const SearchResult a0 = astar(cg, 1, 1, n - 2, n - 2);
  R.first_astar_ms = ms(t1, Clock::now());
  R.first_astar_exp = a0.expansions;
  ++R.checks;
  R.mismatches += !same(base.startCost(), a0.cost);
  const std::vector<int> path0 = base.path();

  auto check = [&](const DStarLite& d) {
    const SearchResult a = astar(d.costs(), d.startX(), d.startY(), d.goalX(), d.goalY());
    ++R.checks;
    if (!same(d.startCost(), a.cost))
      ++R.mismatches;
    return a;
  };

  for (int t = 0; t < trials; ++t)
  {
    fprintf(stderr, "\r%dx%d trial %d/%d", n, n, t + 1, trials);
    // (a) one cell on the current path, anywhere between start and goal, becomes an obstacle
    for (int variant = 0; variant < 2; ++variant)
    {
      DStarLite d = base;
      const size_t lo = 1, hi = variant == 0 ? path0.size() - 2 : std::min<size_t>(path0.size() - 2, 10);
      std::uniform_int_distribution<size_t> pick(lo, hi);
      const int cell = path0[pick(rng)];
      d.resetExpansions();
      const auto s = Clock::now();
      d.updateCells({ { cell, COST_INF } });
      d.plan();
      const double t_ms = ms(s, Clock::now());
      const auto a0s = Clock::now();
      const SearchResult a = check(d);
      const double a_ms = ms(a0s, Clock::now());
      if (variant == 0)
      {
        R.r1_ms.push_back(t_ms);
        R.r1_exp.push_back(double(d.expansions()));
        R.a1_exp.push_back(double(a.expansions));
        R.a1_ms.push_back(a_ms);
      }
      else
      {
        R.r1_near_ms.push_back(t_ms);
        R.r1_near_exp.push_back(double(d.expansions()));
        R.a1_near_exp.push_back(double(a.expansions));
      }
    }
    // (b) 50 changed cells: obstacles appear and vanish in a 5 m (25 cell) patch around a path point
    {
      DStarLite d = base;
      std::uniform_int_distribution<size_t> pick(1, path0.size() - 2);
      const int c = path0[pick(rng)];
      const int cx = c % n, cy = c / n;
      std::uniform_int_distribution<int> off(-12, 12);
      std::vector<std::pair<int, double>> ch;
      std::vector<double> w = d.costs().w;
      while (ch.size() < 50)
      {
        const int x = std::clamp(cx + off(rng), 0, n - 1), y = std::clamp(cy + off(rng), 0, n - 1);
        const int i = y * n + x;
        if ((x <= 1 && y <= 1) || (x >= n - 2 && y >= n - 2))
          continue;
        w[size_t(i)] = (w[size_t(i)] == COST_INF) ? 1.0 : COST_INF;
        ch.emplace_back(i, w[size_t(i)]);
      }
      d.resetExpansions();
      const auto s = Clock::now();
      d.updateCells(ch);
      d.plan();
      R.r50_ms.push_back(ms(s, Clock::now()));
      R.r50_exp.push_back(double(d.expansions()));
      R.a50_exp.push_back(double(check(d).expansions));
    }
    // (c) the window scrolls one cell with the wearer (new row of random cells enters)
    {
      DStarLite d = base;
      std::vector<double> w(d.costs().w.size());
      std::uniform_real_distribution<double> u(0, 1);
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
          w[size_t(y * n + x)] =
              (x + 1 < n) ? d.costs().w[size_t(y * n + x + 1)] : (u(rng) < 0.2 ? COST_INF : 1.0);
      d.resetExpansions();
      const auto s = Clock::now();
      d.scroll(1, 0, w);  // new (x, y) = old (x + 1, y): the wearer moved one cell in +x
      d.setStart(d.startX() + 1, d.startY());
      d.plan();
      R.scroll_ms.push_back(ms(s, Clock::now()));
      R.scroll_exp.push_back(double(d.expansions()));
      if (d.hasGoal())
        R.ascroll_exp.push_back(double(check(d).expansions));
    }
  }
  fprintf(stderr, "\n");
  return R;
}

std::string num(double v, int prec = 4)
{
  if (!(v >= 0.0) || !std::isfinite(v))
    return "null";
  char b[64];
  snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}
}  // namespace

int main(int argc, char** argv)
{
  int trials100 = 200, trials400 = 40;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--trials")
    {
      trials100 = std::max(1, std::atoi(argv[i + 1]));
      trials400 = std::max(1, trials100 / 5);
    }
  const SizeResult a = runSize(100, trials100, 7);
  const SizeResult b = runSize(400, trials400, 11);
  printf("D* Lite vs A* from scratch (synthetic grids, ~20%% obstacles, clearance + step costs, 8-connected)\n");
  printf("%-34s %14s %14s\n", "", "100x100", "400x400");
  auto row = [](const char* name, const std::string& x, const std::string& y) {
    printf("%-34s %14s %14s\n", name, x.c_str(), y.c_str());
  };
  row("trials", std::to_string(a.r1_ms.size()), std::to_string(b.r1_ms.size()));
  row("first plan ms", num(a.first_ms), num(b.first_ms));
  row("first plan expansions", std::to_string(a.first_exp), std::to_string(b.first_exp));
  row("A* from scratch ms (first)", num(a.first_astar_ms), num(b.first_astar_ms));
  row("A* from scratch expansions", std::to_string(a.first_astar_exp), std::to_string(b.first_astar_exp));
  row("replan 1 cell on path ms median", num(median(a.r1_ms)), num(median(b.r1_ms)));
  row("replan 1 cell expansions median", num(median(a.r1_exp), 0), num(median(b.r1_exp), 0));
  row("A* after 1 cell expansions median", num(median(a.a1_exp), 0), num(median(b.a1_exp), 0));
  row("A* after 1 cell ms median", num(median(a.a1_ms)), num(median(b.a1_ms)));
  row("replan 1 cell near wearer ms med", num(median(a.r1_near_ms)), num(median(b.r1_near_ms)));
  row("  expansions median", num(median(a.r1_near_exp), 0), num(median(b.r1_near_exp), 0));
  row("replan 50 cells ms median", num(median(a.r50_ms)), num(median(b.r50_ms)));
  row("replan 50 cells expansions median", num(median(a.r50_exp), 0), num(median(b.r50_exp), 0));
  row("A* after 50 cells expansions med", num(median(a.a50_exp), 0), num(median(b.a50_exp), 0));
  row("scroll 1 cell + replan ms median", num(median(a.scroll_ms)), num(median(b.scroll_ms)));
  row("scroll 1 cell expansions median", num(median(a.scroll_exp), 0), num(median(b.scroll_exp), 0));
  const double ratio100 = median(a.a1_exp) / std::max(1.0, median(a.r1_exp));
  const double ratio400 = median(b.a1_exp) / std::max(1.0, median(b.r1_exp));
  const double near100 = median(a.a1_near_exp) / std::max(1.0, median(a.r1_near_exp));
  row("expansion ratio A*/D* (1 cell)", num(ratio100, 2), num(ratio400, 2));
  row("  same, cell near the wearer", num(near100, 2),
      num(median(b.a1_near_exp) / std::max(1.0, median(b.r1_near_exp)), 2));
  row("optimal cost mismatches", std::to_string(a.mismatches) + "/" + std::to_string(a.checks),
      std::to_string(b.mismatches) + "/" + std::to_string(b.checks));
  printf("{\"optimal_mismatches\": %d, \"optimal_checks\": %d, \"replan1_ms_median_100\": %s, "
         "\"replan1_ms_median_400\": %s, \"expansion_ratio_100\": %s, \"expansion_ratio_400\": %s, "
         "\"expansion_ratio_near_100\": %s, \"first_plan_ms_100\": %s, \"first_plan_ms_400\": %s, "
         "\"replan50_ms_median_100\": %s, \"replan50_ms_median_400\": %s, \"astar_ms_median_100\": %s, "
         "\"astar_ms_median_400\": %s, \"scroll1_ms_median_100\": %s, \"scroll1_ms_median_400\": %s}\n",
         a.mismatches + b.mismatches, a.checks + b.checks, num(median(a.r1_ms)).c_str(), num(median(b.r1_ms)).c_str(),
         num(ratio100, 2).c_str(), num(ratio400, 2).c_str(), num(near100, 2).c_str(), num(a.first_ms).c_str(),
         num(b.first_ms).c_str(), num(median(a.r50_ms)).c_str(), num(median(b.r50_ms)).c_str(),
         num(median(a.a1_ms)).c_str(), num(median(b.a1_ms)).c_str(), num(median(a.scroll_ms)).c_str(),
         num(median(b.scroll_ms)).c_str());
  return 0;
}
