#include <gtest/gtest.h>

#include <assistive_obstacles/elevation_map.h>

#include "synthetic.h"

using namespace assistive_obstacles;

TEST(Window, CentredAndCellAligned)
{
  const Window w = Window::around(1.05, -2.3, 5.0, 0.2);
  EXPECT_EQ(w.n, 52);
  int lx, ly;
  ASSERT_TRUE(w.localOf(1.05, -2.3, lx, ly));
  EXPECT_NEAR(w.centerX(lx), 1.1, 1e-9);
  EXPECT_NEAR(w.centerY(ly), -2.3, 1e-9);
  EXPECT_TRUE(w.inCircle(lx, ly));
  EXPECT_FALSE(w.inCircle(0, 0));  // corner of the square is outside the 5 m circle
  EXPECT_FALSE(w.localOf(1.05 + 6.0, -2.3, lx, ly));
}

TEST(ElevationMap, BinsSortsAndDropsSparseCells)
{
  ObstaclesParams p;  // min_points_per_cell = 10
  ElevationMap m(p);
  synthetic::Points pts;
  for (int i = 0; i < 12; ++i) pts.emplace_back(0.05f, 0.05f, 0.3f - 0.01f * i);  // cell (0,0): 12 pts
  for (int i = 0; i < 9; ++i) pts.emplace_back(0.45f, 0.05f, 0.0f);                // cell (2,0): 9 pts
  pts.emplace_back(0.05f, 0.05f, 5.0f);   // above z_max: ignored
  pts.emplace_back(7.0f, 0.05f, 0.0f);    // outside the circle
  const Window w = Window::around(0.0, 0.0, 5.0, 0.2);
  m.build(pts, w, 2.0f);
  int lx, ly;
  ASSERT_TRUE(w.localOf(0.05, 0.05, lx, ly));
  const int c = w.index(lx, ly);
  EXPECT_EQ(m.count(c), 12);
  const float* h = m.heights(c);
  for (int i = 1; i < 12; ++i) EXPECT_LE(h[i - 1], h[i]);
  EXPECT_NEAR(h[0], 0.19f, 1e-5);
  ASSERT_TRUE(w.localOf(0.45, 0.05, lx, ly));
  EXPECT_EQ(m.rawCount(w.index(lx, ly)), 9);
  EXPECT_EQ(m.count(w.index(lx, ly)), 0);  // noise-only cell dropped
  EXPECT_EQ(m.binnedPoints(), 21u);
}
