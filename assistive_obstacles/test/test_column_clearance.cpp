// Column clearance (issue 17): which height bands of a column one frame saw clear, and the rule
// that frees a cell only when every band was seen clear. Exact answers on a synthetic depth image.
#include <gtest/gtest.h>

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
}  // namespace

TEST(ColumnClearance, BandHeightsEvenlySpacedBelowTheEye)
{
  ObstaclesParams p;
  const std::vector<float> h = columnBandHeights(p);
  ASSERT_EQ(h.size(), 5u);
  const float want[5] = {0.3f, 0.6125f, 0.925f, 1.2375f, 1.55f};
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
  // 1.1 m ahead only 1.2375 and 1.55 m are in view (0.925 m is 334 px below the centre row).
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

TEST(ColumnClearance, TemporalBitsGatherOverFramesAndObstacleEvidenceClearsThem)
{
  TemporalFilter f;
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
}

TEST(ColumnClearance, ShelfAtHeadHeightIsNotFreedByTheFloorUnderIt)
{
  // A 0.2 m cell at x 1.0-1.2 under a shelf at 1.4-1.8 m. Seen up close only its floor is in view
  // (the shelf is above the image): the floor alone never frees it. Seen from 3 m with nothing in
  // the way it is freed; then the shelf seen from 3 m (too far for an obstacle vote) withdraws the
  // clearance, and the floor up close does not give it back.
  ObstaclesParams p;
  const StereoModel m;
  ObstacleMap map(p);
  synthetic::Points floor;
  synthetic::patch(floor, 0.4, 2.0, -0.6, 0.6, 0.0);
  synthetic::Points shelf = floor;
  for (double x = 1.01; x < 1.2; x += 0.02)
    for (double y = -0.09; y < 0.1; y += 0.02)
      for (double z = 1.4; z <= 1.8; z += 0.05) shelf.emplace_back(x, y, z);
  const Eigen::Isometry3f near = synthetic::cameraAt(0, 0, 1.6), far = synthetic::cameraAt(-2, 0, 1.6);
  const cv::Mat disp = flatDisparity(10.f);
  GridData g;
  auto code = [&]() {
    map.grid(g);
    const int ix = static_cast<int>(std::floor((1.1 - g.origin_x) / g.resolution));
    const int iy = static_cast<int>(std::floor((0.0 - g.origin_y) / g.resolution));
    return g.data[iy * g.width + ix];
  };
  for (int i = 0; i < 10; ++i) map.update(synthetic::toCamera(floor, near), near, &m, &disp);
  EXPECT_EQ(code(), CELL_UNKNOWN);  // bands 0.3-0.925 m never in view from 1.1 m
  for (int i = 0; i < 5; ++i) map.update(synthetic::toCamera(floor, far), far, &m, &disp);
  EXPECT_EQ(code(), CELL_FREE);  // every band seen clear from 3.1 m
  map.update(synthetic::toCamera(shelf, far), far, &m, &disp);
  EXPECT_EQ(code(), CELL_UNKNOWN);  // obstacle evidence (no vote from 3.1 m) withdraws it
  for (int i = 0; i < 10; ++i) map.update(synthetic::toCamera(floor, near), near, &m, &disp);
  EXPECT_EQ(code(), CELL_UNKNOWN);
  // The seed's rule (column_bands 0): the floor up close frees it at once.
  p.column_bands = 0;
  ObstacleMap seed(p);
  for (int i = 0; i < 5; ++i) seed.update(synthetic::toCamera(floor, near), near, &m, &disp);
  seed.grid(g);
  const int ix = static_cast<int>(std::floor((1.1 - g.origin_x) / g.resolution));
  const int iy = static_cast<int>(std::floor((0.0 - g.origin_y) / g.resolution));
  EXPECT_EQ(g.data[iy * g.width + ix], CELL_FREE);
}
