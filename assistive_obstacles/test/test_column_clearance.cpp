// Column clearance (issue 17): which height bands of a column one frame saw clear, and the rule
// that frees a cell only when every band was seen clear. Exact answers on a synthetic depth image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <assistive_obstacles/column_clearance.h>
#include <assistive_obstacles/obstacle_map.h>
#include <assistive_obstacles/temporal_filter.h>

#include "synthetic.h"

using namespace assistive_obstacles;

namespace
{
// The default rig (640x480, fx 500, B 0.12 m) and its matcher-scale (0.5) disparity of a
// fronto-parallel depth `z` everywhere: d = fx * 0.5 * B / z.
cv::Mat flatDisparity(float z) { return cv::Mat(240, 320, CV_32F, cv::Scalar(500.f * 0.5f * 0.12f / z)); }

/// The map's code of the cell holding (x, y).
int8_t cellCode(const ObstacleMap& map, double x, double y)
{
  GridData g;
  map.grid(g);
  const int ix = static_cast<int>(std::floor((x - g.origin_x) / g.resolution));
  const int iy = static_cast<int>(std::floor((y - g.origin_y) / g.resolution));
  return g.data[iy * g.width + ix];
}
}  // namespace

TEST(ColumnClearance, BandHeightsEvenlySpacedBelowTheEye)
{
  ObstaclesParams p;
  const std::vector<float> h = columnBandHeights(p);
  ASSERT_EQ(h.size(), 5u);
  const float want[5] = {0.3f, 0.6625f, 1.025f, 1.3875f, 1.75f};
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(h[i], want[i], 1e-6f);
  p.column_bands = 0;
  EXPECT_TRUE(columnBandHeights(p).empty());
  EXPECT_EQ(allBands(0), 0);
  EXPECT_EQ(allBands(5), 31);
}

TEST(ColumnClearance, BandsSeenClearOnlyInViewAndWithDepthBeyond)
{
  ObstaclesParams p;
  const StereoModel m;
  const Eigen::Isometry3f T = synthetic::cameraAt(0, 0, 1.6);  // looking along +x, feet at z = 0
  const cv::Mat far = flatDisparity(10.f);
  const ColumnClearance cc(p, m, far, T, 0.f);
  // 3 m ahead every test height is in view (|1.6 - h| / 3 * 500 px < 240 px) and depth 10 m lies beyond.
  EXPECT_EQ(cc.clearBits(3.1f, 0.f), 31);
  // 1.1 m ahead only 1.3875 and 1.75 m are in view (1.025 m is 261 px below the centre row).
  EXPECT_EQ(cc.clearBits(1.1f, 0.f), 8 + 16);
  // Behind the camera: nothing.
  EXPECT_EQ(cc.clearBits(-2.f, 0.f), 0);
  // A surface 3.15 m away, the cell's centre 3.1 m: 5 cm beyond is not more than
  // max(margin 0.05, 2 sigma_Z = 2 * 3.1^2 * 0.3 / 60 = 0.096): not clear. At 3.3 m: clear.
  const cv::Mat wall = flatDisparity(3.15f), behind = flatDisparity(3.3f);
  EXPECT_EQ(ColumnClearance(p, m, wall, T, 0.f).clearBits(3.1f, 0.f), 0);
  EXPECT_EQ(ColumnClearance(p, m, behind, T, 0.f).clearBits(3.1f, 0.f), 31);
  // No depth at all: nothing seen clear.
  const cv::Mat none(240, 320, CV_32F, cv::Scalar(-1.f));
  EXPECT_EQ(ColumnClearance(p, m, none, T, 0.f).clearBits(3.1f, 0.f), 0);
}

TEST(ColumnClearance, OccupiedBandsFromTheCellsHeights)
{
  // Bands (feet 0): [0.2, 0.481), [0.481, 0.844), [0.844, 1.206), [1.206, 1.569), [1.569, top].
  ObstaclesParams p;
  std::vector<float> h(10, 0.f);  // floor
  h.push_back(0.7f);              // two stray points: fewer than min_cluster_points (3)
  h.push_back(0.71f);
  for (int i = 0; i <= 8; ++i) h.push_back(1.4f + 0.05f * i);  // shelf 1.4-1.8: 4 in band 3, 5 in band 4
  std::sort(h.begin(), h.end());
  EXPECT_EQ(columnOccupiedBits(p, 0.f, h.data(), static_cast<int>(h.size())), 8 + 16);
  // Feet at 1 m: band 0 [1.2, 1.481) holds 2 shelf points, band 1 [1.481, 1.844) the other 7.
  EXPECT_EQ(columnOccupiedBits(p, 1.0f, h.data(), static_cast<int>(h.size())), 2);
  h.push_back(0.72f);
  std::sort(h.begin(), h.end());
  EXPECT_EQ(columnOccupiedBits(p, 0.f, h.data(), static_cast<int>(h.size())), 2 + 8 + 16);
}

TEST(ColumnClearance, TemporalBitsGatherOverFramesAndObstacleEvidenceClearsThem)
{
  ObstaclesParams strict;
  strict.column_strict_from = 0.0;  // every band must be seen clear
  TemporalFilter f(strict);
  f.resize(20);
  EXPECT_FALSE(f.columnClear(2, 3));  // never seen
  f.observeColumn(2, 3, 8 + 16, 0);
  EXPECT_FALSE(f.columnClear(2, 3));
  f.observeColumn(2, 3, 1 + 2 + 4, 0);
  EXPECT_TRUE(f.columnClear(2, 3));  // gathered over two frames
  f.observeColumn(2, 3, 31, 16);     // an obstacle in the top band this frame: that band withdrawn
  EXPECT_FALSE(f.columnClear(2, 3));
  f.observeColumn(2, 3, 16, 0);
  EXPECT_TRUE(f.columnClear(2, 3));
  ObstaclesParams off;
  off.column_bands = 0;
  TemporalFilter g(off);
  g.resize(20);
  EXPECT_TRUE(g.columnClear(2, 3));  // rule off
  // Default: every band (test points below 2 m) is presumed clear until an obstacle is seen in it.
  TemporalFilter d;
  d.resize(20);
  EXPECT_TRUE(d.columnClear(5, 5));
  d.observeColumn(5, 5, 0, 16);
  EXPECT_FALSE(d.columnClear(5, 5));
  d.observeColumn(5, 5, 16, 0);
  EXPECT_TRUE(d.columnClear(5, 5));
}

TEST(ColumnClearance, ShelfAtHeadHeightIsNotFreedByTheFloorUnderIt)
{
  // A 0.2 m cell at x 1.0-1.2 under a shelf at 1.4-1.8 m. Seen from 3.1 m (too far for an obstacle
  // vote) the shelf withdraws the clearance of the bands its points are in (1.3875 and 1.75 m).
  // Up close, the head pitched down 30 deg, only the floor is in view and the 1.75 m band is not:
  // the floor alone does not free the cell. Seen clear from 3.1 m (the shelf gone) it is freed.
  // With the seed's rule (column_bands 0) the floor up close frees it at once.
  ObstaclesParams p;
  const StereoModel m;
  synthetic::Points floor;
  synthetic::patch(floor, 0.4, 2.0, -0.6, 0.6, 0.0);
  synthetic::Points shelf = floor;
  for (double x = 1.01; x < 1.2; x += 0.02)
    for (double y = -0.09; y < 0.1; y += 0.02)
      for (double z = 1.4; z <= 1.8; z += 0.05) shelf.emplace_back(x, y, z);
  Eigen::Isometry3f near = synthetic::cameraAt(0, 0, 1.6);
  near.linear() = near.linear() * Eigen::AngleAxisf(static_cast<float>(-30.0 * M_PI / 180.0), Eigen::Vector3f::UnitX());
  const Eigen::Isometry3f far = synthetic::cameraAt(-2, 0, 1.6);
  const cv::Mat disp = flatDisparity(10.f);
  EXPECT_EQ(ColumnClearance(p, m, disp, near, 0.f).clearBits(1.1f, 0.f), 15);  // all but 1.75 m in view
  auto code = [](const ObstacleMap& map) { return cellCode(map, 1.1, 0.0); };
  ObstacleMap map(p);
  map.update(synthetic::toCamera(shelf, far), far, &m, &disp);
  EXPECT_EQ(code(map), CELL_UNKNOWN);
  for (int i = 0; i < 10; ++i) map.update(synthetic::toCamera(floor, near), near, &m, &disp);
  EXPECT_EQ(code(map), CELL_UNKNOWN);  // the floor alone: no free vote
  for (int i = 0; i < 5; ++i) map.update(synthetic::toCamera(floor, far), far, &m, &disp);
  EXPECT_EQ(code(map), CELL_FREE);  // every band seen clear from 3.1 m
  p.column_bands = 0;
  ObstacleMap seed(p);
  seed.update(synthetic::toCamera(shelf, far), far, &m, &disp);
  for (int i = 0; i < 10; ++i) seed.update(synthetic::toCamera(floor, near), near, &m, &disp);
  EXPECT_EQ(code(seed), CELL_FREE);
}

TEST(ColumnClearance, BandsHiddenJustInFrontAreBlocked)
{
  // The cell's centre 3.1 m ahead; tolerance max(margin 0.05, 2 sigma_Z = 0.096 m).
  ObstaclesParams p;
  const StereoModel m;
  const Eigen::Isometry3f T = synthetic::cameraAt(0, 0, 1.6);
  p.column_block_depth = 0.5;  // the rule on (off by default)
  // A surface at 2.9 m: 0.2 m in front of every band, within column_block_depth (0.5): blocked, not clear.
  const ColumnClearance::Bits near = ColumnClearance(p, m, flatDisparity(2.9f), T, 0.f).bits(3.1f, 0.f);
  EXPECT_EQ(near.clear, 0);
  EXPECT_EQ(near.blocked, 31);
  // 3.05 m: within the tolerance, neither; 2.4 m: hidden from farther than 0.5 m in front, neither.
  EXPECT_EQ(ColumnClearance(p, m, flatDisparity(3.05f), T, 0.f).bits(3.1f, 0.f).blocked, 0);
  EXPECT_EQ(ColumnClearance(p, m, flatDisparity(2.4f), T, 0.f).bits(3.1f, 0.f).blocked, 0);
  // Beyond: clear, not blocked.
  const ColumnClearance::Bits far = ColumnClearance(p, m, flatDisparity(10.f), T, 0.f).bits(3.1f, 0.f);
  EXPECT_EQ(far.clear, 31);
  EXPECT_EQ(far.blocked, 0);
  p.column_block_depth = 0.0;  // rule off
  EXPECT_EQ(ColumnClearance(p, m, flatDisparity(2.9f), T, 0.f).bits(3.1f, 0.f).blocked, 0);
}

TEST(ColumnClearance, FloorUnderAShelfsFrontFaceIsNotFreed)
{
  // A 0.2 m cell at x 2.0-2.2 behind a shelf's front face at x = 2.0 (1.4-1.8 m high): the camera
  // sees the floor under the shelf, and every band in view over the cell ends on the face 0.1 m in
  // front of the cell's centre (the depth image: 2.0 m everywhere; the shelf's own points fall in
  // the cell in front). The floor's free votes do not count: the cell stays unknown. With the rule
  // off (column_block_depth 0) the presumed-clear bands let the floor free it. A floor seen with
  // depth beyond the bands frees it either way.
  const StereoModel m;
  synthetic::Points floor;
  synthetic::patch(floor, 0.4, 3.0, -0.6, 0.6, 0.0);
  const Eigen::Isometry3f T = synthetic::cameraAt(0, 0, 1.6);
  const cv::Mat face = flatDisparity(2.0f), open = flatDisparity(10.f);
  auto code = [](const ObstacleMap& map) { return cellCode(map, 2.1, 0.0); };
  ObstaclesParams p;
  p.column_block_depth = 0.5;  // the rule on (off by default)
  ObstacleMap map(p);
  for (int i = 0; i < 10; ++i) map.update(synthetic::toCamera(floor, T), T, &m, &face);
  EXPECT_EQ(code(map), CELL_UNKNOWN);
  for (int i = 0; i < 10; ++i) map.update(synthetic::toCamera(floor, T), T, &m, &open);
  EXPECT_EQ(code(map), CELL_FREE);  // seen clear: the shelf is gone
  p.column_block_depth = 0.0;
  ObstacleMap off(p);
  for (int i = 0; i < 10; ++i) off.update(synthetic::toCamera(floor, T), T, &m, &face);
  EXPECT_EQ(code(off), CELL_FREE);
}
