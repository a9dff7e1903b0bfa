// planner_benchmark: D* Lite replanning against A* from scratch on synthetic grids (no roscore, no args).
// Prints a table, then one JSON line (docs/design.md, "Benchmarks").
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <assistive_eval/benchmark.h>

#include "assistive_planner/cost_model.h"
#include "assistive_planner/dstar_lite.h"
#include "assistive_planner/grid.h"

using namespace assistive_planner;
using assistive_eval::median;
using assistive_eval::Stopwatch;

namespace
{
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
  std::vector<double> first_ms_v, first_exp_v, first_astar_ms_v, first_astar_exp_v;
  std::vector<double> r1_5m_exp, a1_5m_exp, r1_ms, r1_exp, r1_near_ms, r1_near_exp, a1_exp, a1_near_exp, a1_ms, r50_ms, r50_exp, a50_exp,
      scroll_ms, scroll_exp, ascroll_exp;
  int mismatches = 0, checks = 0;
};

void runGrid(SizeResult& R, int n, int trials, std::mt19937& rng, int done, int total);

SizeResult runSize(int n, int trials, int grids, unsigned seed)
{
  SizeResult R;
  R.n = n;
  std::mt19937 rng(seed);
  const int per_grid = std::max(1, trials / grids);
  for (int k = 0; k < grids; ++k)
    runGrid(R, n, per_grid, rng, k * per_grid, grids * per_grid);
  fprintf(stderr, "\n");
  return R;
}

/// D* Lite against A* from scratch on the same costs and cells: counts a check, and a mismatch
/// when the costs differ; returns A*'s result (its expansions are the comparison figure).
SearchResult checkAgainstAstar(SizeResult& R, const DStarLite& d)
{
  const SearchResult a = astar(d.costs(), d.startX(), d.startY(), d.goalX(), d.goalY());
  ++R.checks;
  if (!same(d.startCost(), a.cost))
    ++R.mismatches;
  return a;
}

/// A grid whose corners are connected (at most 50 tries), planned from corner to corner into
/// `base`: the first plan's time and expansions, and A*'s, go into R.
void planFirst(SizeResult& R, int n, std::mt19937& rng, DStarLite& base)
{
  PlannerParams p;
  Grid grid;
  CostGrid cg;
  double first_ms = 0.0;
  size_t first_exp = 0;
  for (int attempt = 0; attempt < 50; ++attempt)
  {
    grid = makeGrid(n, rng);
    cg = CostGrid(n, n);
    cg.w = cellWeights(grid, p);
    base.reset(cg);
    base.setStart(1, 1);
    base.setGoal(n - 2, n - 2);
    base.resetExpansions();
    const Stopwatch t0;
    const bool ok = base.plan();
    first_ms = t0.wallMs();
    first_exp = base.expansions();
    if (ok)
      break;
  }
  R.first_ms_v.push_back(first_ms);
  R.first_exp_v.push_back(double(first_exp));
  const Stopwatch t1;
  const SearchResult a0 = astar(cg, 1, 1, n - 2, n - 2);
  R.first_astar_ms_v.push_back(t1.wallMs());
  R.first_astar_exp_v.push_back(double(a0.expansions));
  ++R.checks;
  R.mismatches += !same(base.startCost(), a0.cost);
}

/// (a) one cell on the current path, anywhere between start and goal, becomes an obstacle.
/// variant 0: anywhere on the path; 1: within 10 cells (2 m) of the wearer; 2: within 25 cells (5 m,
/// the obstacle window's radius: where the camera adds and removes obstacles)
void blockOnePathCell(SizeResult& R, const DStarLite& base, const std::vector<int>& path0, std::mt19937& rng)
{
  for (int variant = 0; variant < 3; ++variant)
  {
    DStarLite d = base;
    const size_t lo = 1;
    const size_t hi = variant == 0 ? path0.size() - 2 : std::min<size_t>(path0.size() - 2, variant == 1 ? 10 : 25);
    std::uniform_int_distribution<size_t> pick(lo, hi);
    const int cell = path0[pick(rng)];
    d.resetExpansions();
    const Stopwatch s;
    d.updateCells({ { cell, COST_INF } });
    d.plan();
    const double t_ms = s.wallMs();
    const Stopwatch a0s;
    const SearchResult a = checkAgainstAstar(R, d);
    const double a_ms = a0s.wallMs();
    if (variant == 0)
    {
      R.r1_ms.push_back(t_ms);
      R.r1_exp.push_back(double(d.expansions()));
      R.a1_exp.push_back(double(a.expansions));
      R.a1_ms.push_back(a_ms);
    }
    else if (variant == 2)
    {
      R.r1_5m_exp.push_back(double(d.expansions()));
      R.a1_5m_exp.push_back(double(a.expansions));
    }
    else
    {
      R.r1_near_ms.push_back(t_ms);
      R.r1_near_exp.push_back(double(d.expansions()));
      R.a1_near_exp.push_back(double(a.expansions));
    }
  }
}

/// (b) 50 changed cells: obstacles appear and vanish in a 5 m (25 cell) patch around a path point
void change50Cells(SizeResult& R, const DStarLite& base, const std::vector<int>& path0, int n, std::mt19937& rng)
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
  const Stopwatch s;
  d.updateCells(ch);
  d.plan();
  R.r50_ms.push_back(s.wallMs());
  R.r50_exp.push_back(double(d.expansions()));
  R.a50_exp.push_back(double(checkAgainstAstar(R, d).expansions));
}

/// (c) the window scrolls one cell with the wearer (a new column of random cells enters); the first
/// scroll of the copied planner warms its reusable buffers and is not timed (the nodelet keeps one planner)
void scrollOneCell(SizeResult& R, const DStarLite& base, int n, std::mt19937& rng)
{
  DStarLite d = base;
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 2; ++k)
  {
    std::vector<double> w(d.costs().w.size());
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        w[size_t(y * n + x)] = (x + 1 < n) ? d.costs().w[size_t(y * n + x + 1)] : (u(rng) < 0.2 ? COST_INF : 1.0);
    d.resetExpansions();
    const Stopwatch s;
    d.scroll(1, 0, w);  // new (x, y) = old (x + 1, y): the wearer moved one cell in +x
    d.setStart(d.startX() + 1, d.startY());
    d.plan();
    if (k == 0)
      continue;
    R.scroll_ms.push_back(s.wallMs());
    R.scroll_exp.push_back(double(d.expansions()));
    if (d.hasGoal())
      R.ascroll_exp.push_back(double(checkAgainstAstar(R, d).expansions));
  }
}

void runGrid(SizeResult& R, int n, int trials, std::mt19937& rng, int done, int total)
{
  DStarLite base;
  planFirst(R, n, rng, base);
  const std::vector<int> path0 = base.path();
  for (int t = 0; t < trials; ++t)
  {
    fprintf(stderr, "\r%dx%d trial %d/%d", n, n, done + t + 1, total);
    blockOnePathCell(R, base, path0, rng);
    change50Cells(R, base, path0, n, rng);
    scrollOneCell(R, base, n, rng);
  }
}

/// Fixed decimals; "null" for a missing figure (negative or not finite).
std::string num(double v, int prec = 4)
{
  return v >= 0.0 ? assistive_eval::jsonFixed(v, prec) : "null";
}
}  // namespace

int main(int argc, char** argv)
{
  int trials100 = 1000, trials400 = 60;
  const char* usage =
      "usage: planner_benchmark [--trials N]\n"
      "  D* Lite vs A* from scratch on synthetic 100x100 and 400x400 grids; --trials change trials on the\n"
      "  100x100 grids (default 1000; the 400x400 grids get N/16). Last stdout line: JSON.\n";
  long trials = -1;
  assistive_eval::CommandLine cl("planner_benchmark", usage);
  cl.count("--trials", &trials, 1L);
  if (const int rc = cl.parse(argc, argv); rc >= 0)
    return rc;
  if (trials > 0)
  {
    trials100 = static_cast<int>(std::min<long>(trials, std::numeric_limits<int>::max()));
    trials400 = std::max(1, trials100 / 16);
  }
  const SizeResult a = runSize(100, trials100, 50, 7);
  const SizeResult b = runSize(400, trials400, 20, 11);
  printf("D* Lite vs A* from scratch (synthetic grids, ~20%% obstacles, clearance + step costs, 8-connected)\n");
  printf("%-34s %14s %14s\n", "", "100x100", "400x400");
  auto row = [](const char* name, const std::string& x, const std::string& y) {
    printf("%-34s %14s %14s\n", name, x.c_str(), y.c_str());
  };
  row("grids / change trials", std::to_string(a.first_ms_v.size()) + " / " + std::to_string(a.r1_ms.size()),
      std::to_string(b.first_ms_v.size()) + " / " + std::to_string(b.r1_ms.size()));
  row("first plan ms median", num(median(a.first_ms_v)), num(median(b.first_ms_v)));
  row("first plan expansions median", num(median(a.first_exp_v), 0), num(median(b.first_exp_v), 0));
  row("A* from scratch ms median (first)", num(median(a.first_astar_ms_v)), num(median(b.first_astar_ms_v)));
  row("A* from scratch expansions median", num(median(a.first_astar_exp_v), 0), num(median(b.first_astar_exp_v), 0));
  row("replan 1 cell on path ms median", num(median(a.r1_ms)), num(median(b.r1_ms)));
  row("replan 1 cell expansions median", num(median(a.r1_exp), 0), num(median(b.r1_exp), 0));
  row("A* after 1 cell expansions median", num(median(a.a1_exp), 0), num(median(b.a1_exp), 0));
  row("A* after 1 cell ms median", num(median(a.a1_ms)), num(median(b.a1_ms)));
 row("replan 1 cell <= 5 m ahead exp med", num(median(a.r1_5m_exp), 0), num(median(b.r1_5m_exp), 0));
  row("replan 1 cell <= 2 m ahead ms med", num(median(a.r1_near_ms)), num(median(b.r1_near_ms)));
  row("  expansions median", num(median(a.r1_near_exp), 0), num(median(b.r1_near_exp), 0));
  row("replan 50 cells ms median", num(median(a.r50_ms)), num(median(b.r50_ms)));
  row("replan 50 cells expansions median", num(median(a.r50_exp), 0), num(median(b.r50_exp), 0));
  row("A* after 50 cells expansions med", num(median(a.a50_exp), 0), num(median(b.a50_exp), 0));
  row("scroll 1 cell + replan ms median", num(median(a.scroll_ms)), num(median(b.scroll_ms)));
  row("scroll 1 cell expansions median", num(median(a.scroll_exp), 0), num(median(b.scroll_exp), 0));
  const double ratio100 = median(a.a1_exp) / std::max(1.0, median(a.r1_exp));
  const double ratio400 = median(b.a1_exp) / std::max(1.0, median(b.r1_exp));
  const double near100 = median(a.a1_near_exp) / std::max(1.0, median(a.r1_near_exp));
  const double r5m100 = median(a.a1_5m_exp) / std::max(1.0, median(a.r1_5m_exp));
  const double r5m400 = median(b.a1_5m_exp) / std::max(1.0, median(b.r1_5m_exp));
  row("expansion ratio A*/D* (1 cell on path)", num(ratio100, 2), num(ratio400, 2));
  row("  same, cell <= 5 m ahead", num(r5m100, 2), num(r5m400, 2));
  row("  same, cell <= 2 m ahead", num(near100, 2),
      num(median(b.a1_near_exp) / std::max(1.0, median(b.r1_near_exp)), 2));
  auto share10 = [](const SizeResult& r) {
    size_t k = 0;
    for (size_t i = 0; i < r.r1_exp.size(); ++i)
      k += r.a1_exp[i] >= 10.0 * std::max(1.0, r.r1_exp[i]);
    return r.r1_exp.empty() ? -1.0 : 100.0 * double(k) / double(r.r1_exp.size());
  };
  row("  trials with ratio >= 10 (%)", num(share10(a), 1), num(share10(b), 1));
  row("optimal cost mismatches", std::to_string(a.mismatches) + "/" + std::to_string(a.checks),
      std::to_string(b.mismatches) + "/" + std::to_string(b.checks));
  assistive_eval::JsonLine js;
  js.add("optimal_mismatches", a.mismatches + b.mismatches).add("optimal_checks", a.checks + b.checks)
      .add("replan1_ms_median_100", num(median(a.r1_ms))).add("replan1_ms_median_400", num(median(b.r1_ms)))
      .add("expansion_ratio_100", num(ratio100, 2)).add("expansion_ratio_400", num(ratio400, 2))
      .add("expansion_ratio_near_100", num(near100, 2)).add("expansion_ratio_5m_100", num(r5m100, 2))
      .add("expansion_ratio_5m_400", num(r5m400, 2)).add("first_plan_ms_100", num(median(a.first_ms_v)))
      .add("first_plan_ms_400", num(median(b.first_ms_v))).add("replan50_ms_median_100", num(median(a.r50_ms)))
      .add("replan50_ms_median_400", num(median(b.r50_ms))).add("astar_ms_median_100", num(median(a.a1_ms)))
      .add("astar_ms_median_400", num(median(b.a1_ms))).add("scroll1_ms_median_100", num(median(a.scroll_ms)))
      .add("scroll1_ms_median_400", num(median(b.scroll_ms))).add("ratio_ge10_pct_100", num(share10(a), 1));
  printf("%s\n", js.str().c_str());
  return 0;
}
