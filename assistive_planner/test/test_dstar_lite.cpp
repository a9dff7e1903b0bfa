// Randomized optimality test: D* Lite against a plain Dijkstra from scratch after every change.
#include <gtest/gtest.h>

#include <random>

#include "assistive_planner/dstar_lite.h"

using namespace assistive_planner;

namespace
{
double randomWeight(std::mt19937& rng)
{
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double r = u(rng);
  if (r < 0.25)
    return COST_INF;                   // obstacle
  if (r < 0.35)
    return 1.0 + 3.0 * u(rng);         // step / clearance cost
  if (r < 0.40)
    return 500.0;                      // unknown-like expensive cell
  return 1.0;                          // free
}

bool near(double a, double b)
{
  if (a == COST_INF || b == COST_INF)
    return a == b;
  return std::abs(a - b) <= 1e-7 * (1.0 + std::abs(b));
}

// Checks D* Lite's start cost and the extracted path's cost against Dijkstra; returns false on mismatch.
::testing::AssertionResult matchesDijkstra(const DStarLite& d)
{
  const CostGrid& g = d.costs();
  const auto dist = dijkstraCostToGoal(g, d.goalX(), d.goalY());
  const double ref = dist[size_t(g.index(d.startX(), d.startY()))];
  if (!near(d.startCost(), ref))
    return ::testing::AssertionFailure() << "start cost " << d.startCost() << " vs Dijkstra " << ref;
  if (ref < COST_INF)
  {
    const auto p = d.path();
    if (p.empty() || p.front() != g.index(d.startX(), d.startY()) || p.back() != g.index(d.goalX(), d.goalY()))
      return ::testing::AssertionFailure() << "no path extracted although cost is " << ref;
    if (!near(pathCost(g, p), ref))
      return ::testing::AssertionFailure() << "path cost " << pathCost(g, p) << " vs " << ref;
  }
  return ::testing::AssertionSuccess();
}
}  // namespace

TEST(DStarLite, StraightLineAndCornerCutting)
{
  CostGrid g(5, 5, 1.0);
  DStarLite d;
  d.reset(g);
  d.setStart(0, 0);
  d.setGoal(4, 4);
  ASSERT_TRUE(d.plan());
  EXPECT_NEAR(d.startCost(), 4 * DIAG_UNIT, 1e-12);
  // block (1,0) and (0,1): the diagonal (0,0)->(1,1) would cut both corners -> no path
  d.updateCells({ { g.index(1, 0), COST_INF }, { g.index(0, 1), COST_INF } });
  EXPECT_FALSE(d.plan());
  EXPECT_TRUE(d.path().empty());
  // one corner free again: still no diagonal (no cutting past the remaining obstacle), but a detour
  d.updateCells({ { g.index(1, 0), 1.0 } });
  ASSERT_TRUE(d.plan());
  EXPECT_NEAR(d.startCost(), 2.0 + 3 * DIAG_UNIT, 1e-12);  // (0,0)->(1,0)->(2,1) diag... length 1 + 3 diag + 1
}

TEST(DStarLite, GoalChangeRestartsCleanly)
{
  CostGrid g(10, 10, 1.0);
  DStarLite d;
  d.reset(g);
  d.setStart(0, 0);
  d.setGoal(9, 0);
  ASSERT_TRUE(d.plan());
  EXPECT_NEAR(d.startCost(), 9.0, 1e-12);
  d.setGoal(0, 9);
  ASSERT_TRUE(d.plan());
  EXPECT_NEAR(d.startCost(), 9.0, 1e-12);
  EXPECT_TRUE(matchesDijkstra(d));
}

TEST(DStarLite, RandomizedAgainstDijkstra)
{
  std::mt19937 rng(12345);
  const int kGrids = 1200;
  int mismatches = 0, checks = 0, scrolls = 0, changes = 0, moves = 0;
  for (int trial = 0; trial < kGrids; ++trial)
  {
    std::uniform_int_distribution<int> size_dist(4, 30);
    const int W = size_dist(rng), H = size_dist(rng);
    CostGrid g(W, H);
    for (auto& w : g.w)
      w = randomWeight(rng);
    std::uniform_int_distribution<int> rx(0, W - 1), ry(0, H - 1);
    DStarLite d;
    d.reset(g);
    d.setStart(rx(rng), ry(rng));
    d.setGoal(rx(rng), ry(rng));
    d.plan();
    ++checks;
    if (!matchesDijkstra(d))
      ++mismatches;
    const int steps = 12;
    for (int s = 0; s < steps; ++s)
    {
      std::uniform_int_distribution<int> op(0, 9);
      const int o = op(rng);
      if (o < 5)
      {
        // a batch of random cell changes
        std::uniform_int_distribution<int> nb(1, 15);
        std::vector<std::pair<int, double>> ch;
        const int n = nb(rng);
        for (int i = 0; i < n; ++i)
          ch.emplace_back(g.index(rx(rng), ry(rng)), randomWeight(rng));
        // duplicates in one batch: the last one wins, as in the grid
        d.updateCells(ch);
        changes += n;
      }
      else if (o < 8)
      {
        // window scroll by up to 3 cells, with the overlap also partly changed
        std::uniform_int_distribution<int> sh(-3, 3);
        const int dx = sh(rng), dy = sh(rng);
        const CostGrid& old = d.costs();
        std::vector<double> w(old.w.size());
        for (int y = 0; y < H; ++y)
          for (int x = 0; x < W; ++x)
          {
            const int ox = x + dx, oy = y + dy;
            const bool overlap = ox >= 0 && oy >= 0 && ox < W && oy < H;
            std::uniform_real_distribution<double> u(0, 1);
            w[size_t(y * W + x)] = (overlap && u(rng) > 0.05) ? old.w[size_t(oy * W + ox)] : randomWeight(rng);
          }
        d.scroll(dx, dy, w);
        ++scrolls;
        if (!d.hasGoal())
          d.setGoal(rx(rng), ry(rng));
        // keep the start inside the window
        int sx = std::min(std::max(d.startX(), 0), W - 1), sy = std::min(std::max(d.startY(), 0), H - 1);
        d.setStart(sx, sy);
      }
      else
      {
        // the wearer walks up to 2 cells (km grows)
        std::uniform_int_distribution<int> mv(-2, 2);
        int sx = std::min(std::max(d.startX() + mv(rng), 0), W - 1);
        int sy = std::min(std::max(d.startY() + mv(rng), 0), H - 1);
        d.setStart(sx, sy);
        ++moves;
        if (op(rng) == 0)
          d.setGoal(rx(rng), ry(rng));  // occasional goal change: clean restart
      }
      d.plan();
      ++checks;
      const auto r = matchesDijkstra(d);
      if (!r)
      {
        ++mismatches;
        ADD_FAILURE() << "trial " << trial << " step " << s << ": " << r.message();
      }
    }
  }
  RecordProperty("checks", checks);
  EXPECT_EQ(mismatches, 0) << "of " << checks << " checks";
  EXPECT_GE(checks, 1000 * 10);
  EXPECT_GT(scrolls, 1000);
  EXPECT_GT(changes, 1000);
  EXPECT_GT(moves, 1000);
}
