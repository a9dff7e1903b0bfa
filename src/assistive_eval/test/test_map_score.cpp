// Obstacle-map scoring on hand-made grids with exact counts.
#include <assistive_eval/map_score.h>

#include <gtest/gtest.h>

#include <tuple>
#include <utility>
#include <vector>

using namespace assistive_eval;

namespace
{
/// 10 x 10 cells of 1 m, origin (0, 0): cell (x, y) covers [x, x+1) x [y, y+1).
Grid makeGrid(int8_t fill)
{
  Grid g;
  g.resolution = 1.0;
  g.width = g.height = 10;
  g.data.assign(100, fill);
  return g;
}
void set(Grid& g, int x, int y, int8_t v) { g.data[static_cast<size_t>(y) * g.width + x] = v; }
}  // namespace

TEST(MapScore, ExactCountsOnHandMadeGrids)
{
  // Wearer at (5, 5) (a cell corner); radius 1.5 m takes the cells with centres within 1.5 m:
  // centres (4.5|5.5, 4.5|5.5) at 0.71 m and (3.5|6.5, 4.5|5.5), (4.5|5.5, 3.5|6.5) at 1.58 m -> only 4
  // cells. Use radius 2.0: + the 8 cells at 1.58 m = 12 cells.
  Grid gt = makeGrid(CELL_FREE);
  Grid est = makeGrid(CELL_FREE);
  // truth: obstacles at (4,4), (5,4), step at (6,5); unknown at (4,6)
  set(gt, 4, 4, CELL_OBSTACLE);
  set(gt, 5, 4, CELL_OBSTACLE);
  set(gt, 6, 5, CELL_STEP);
  set(gt, 4, 6, CELL_UNKNOWN);
  // estimate: (4,4) obstacle (TP), (5,4) free (FN, free_where_obstacle), (6,5) unknown (not scored),
  // (3,5) obstacle (FP), (5,6) step (FP), (4,6) obstacle (truth unknown: ignored);
  // (9,9) obstacle far outside the radius (ignored)
  set(est, 4, 4, CELL_OBSTACLE);
  set(est, 5, 4, CELL_FREE);
  set(est, 6, 5, CELL_UNKNOWN);
  set(est, 3, 5, CELL_OBSTACLE);
  set(est, 5, 6, CELL_STEP);
  set(est, 4, 6, CELL_OBSTACLE);
  set(est, 9, 9, CELL_OBSTACLE);

  MapScoreParams p;
  p.radius_m = 2.0;
  const MapScore s = scoreMap(gt, est, Eigen::Vector2d(5.0, 5.0), p);
  EXPECT_EQ(s.gt_known, 11u);  // 12 cells in the radius, one unknown in the truth
  EXPECT_EQ(s.est_unknown, 1u);
  EXPECT_EQ(s.scored, 10u);
  EXPECT_EQ(s.tp, 1u);
  EXPECT_EQ(s.fn, 1u);
  EXPECT_EQ(s.fp, 2u);
  EXPECT_EQ(s.tn, 6u);
  EXPECT_EQ(s.free_where_obstacle, 1u);
  ASSERT_EQ(s.free_where_obstacle_cells.size(), 1u);
  EXPECT_EQ(s.free_where_obstacle_cells[0], 4u * 10u + 5u);
  EXPECT_DOUBLE_EQ(s.precision, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.recall, 0.5);
  EXPECT_DOUBLE_EQ(s.misclassified, 3.0 / 10.0);
  EXPECT_DOUBLE_EQ(s.coverage, 10.0 / 11.0);
}

TEST(MapScore, UnknownEstimateIsNotFreeAndRatiosAreUndefined)
{
  Grid gt = makeGrid(CELL_OBSTACLE);
  Grid est = makeGrid(CELL_UNKNOWN);
  MapScoreParams p;
  p.radius_m = 5.0;
  const MapScore s = scoreMap(gt, est, Eigen::Vector2d(5.0, 5.0), p);
  EXPECT_GT(s.gt_known, 0u);
  EXPECT_EQ(s.est_unknown, s.gt_known);
  EXPECT_EQ(s.scored, 0u);
  EXPECT_EQ(s.free_where_obstacle, 0u);
  EXPECT_TRUE(std::isnan(s.precision));
  EXPECT_TRUE(std::isnan(s.recall));
  EXPECT_TRUE(std::isnan(s.misclassified));
  EXPECT_DOUBLE_EQ(s.coverage, 0.0);
}

TEST(MapScore, EstimateInAnotherFrameIsLookedUpThroughTheTransform)
{
  // The estimate grid is the truth shifted: est frame = gt frame moved by (+3, +2) m and the
  // estimate grid is 0.5 m cells. Same content -> perfect score.
  Grid gt = makeGrid(CELL_FREE);
  set(gt, 2, 2, CELL_OBSTACLE);
  set(gt, 3, 2, CELL_OBSTACLE);
  set(gt, 7, 8, CELL_STEP);
  Grid est;
  est.resolution = 0.5;
  est.width = est.height = 20;
  est.origin_x = -3.0;
  est.origin_y = -2.0;
  est.data.assign(400, CELL_FREE);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x)
    {
      const Eigen::Vector2d c = est.cellCenter(x, y) + Eigen::Vector2d(3.0, 2.0);  // into gt frame
      est.data[static_cast<size_t>(y) * 20 + x] = gt.atWorld(c.x(), c.y());
    }
  Eigen::Isometry2d T_est_gt = Eigen::Isometry2d::Identity();
  T_est_gt.translation() = Eigen::Vector2d(-3.0, -2.0);
  MapScoreParams p;
  p.radius_m = 5.0;
  const MapScore s = scoreMap(gt, est, Eigen::Vector2d(5.0, 5.0), p, T_est_gt);
  EXPECT_EQ(s.fp + s.fn, 0u);
  EXPECT_EQ(s.tp, 3u);
  EXPECT_DOUBLE_EQ(s.precision, 1.0);
  EXPECT_DOUBLE_EQ(s.recall, 1.0);
  EXPECT_DOUBLE_EQ(s.misclassified, 0.0);
  // Without the transform the shifted content misses.
  const MapScore w = scoreMap(gt, est, Eigen::Vector2d(5.0, 5.0), p);
  EXPECT_GT(w.fp + w.fn, 0u);
}

TEST(MapScore, AccumulatorSumsCountsAndKeepsDistinctFreeWhereObstacleCells)
{
  // counts of two grids: tp fp fn tn, scored of gt_known, free-where-obstacle cells
  auto grid = [](size_t tp, size_t fp, size_t fn, size_t tn, size_t gt_known, std::vector<size_t> cells) {
    MapScore s;
    std::tie(s.tp, s.fp, s.fn, s.tn) = std::make_tuple(tp, fp, fn, tn);
    s.scored = tp + fp + fn + tn;
    s.gt_known = gt_known;
    s.free_where_obstacle_cells = std::move(cells);
    return s;
  };
  const MapScore a = grid(3, 1, 1, 5, 12, {7, 3}), b = grid(1, 0, 1, 8, 10, {3, 9});
  MapScoreAccumulator acc;
  acc.add(a);
  acc.add(b);
  const MapScore t = acc.total();
  EXPECT_EQ(acc.grids(), 2u);
  EXPECT_EQ(t.tp, 4u);
  EXPECT_DOUBLE_EQ(t.precision, 4.0 / 5.0);
  EXPECT_DOUBLE_EQ(t.recall, 4.0 / 6.0);
  EXPECT_DOUBLE_EQ(t.misclassified, 3.0 / 20.0);
  EXPECT_DOUBLE_EQ(t.coverage, 20.0 / 22.0);
  EXPECT_EQ(acc.freeWhereObstacleCells(), 3u);  // {3, 7, 9}
}

TEST(MapScore, PlanarPoseOfAnOpticalFrame)
{
  // optical frame looking along +y of the world (heading 90 deg), at (1, 2, 1.6)
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 1, 0, 0,  //
      0, 0, 1,            //
      0, -1, 0;           // columns: x (right) = +x, y (down) = -z, z (forward) = +y
  T.translation() = Eigen::Vector3d(1.0, 2.0, 1.6);
  const Eigen::Isometry2d p = planarPose(T, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(p.translation().x(), 1.0, 1e-12);
  EXPECT_NEAR(p.translation().y(), 2.0, 1e-12);
  EXPECT_NEAR(std::atan2(p.linear()(1, 0), p.linear()(0, 0)), M_PI / 2, 1e-12);
}

TEST(MapScore, ExcludedCellsScoredNeitherWayGlassCounted)
{
  // Wearer at (5, 5), radius 2: the 12 cells of ExactCountsOnHandMadeGrids. Truth obstacles at
  // (4,4) (glass) and (5,4) (partly covered: excluded); a free cell (3,5) beside an obstacle
  // (excluded). The estimate says free at (4,4) and (5,4), obstacle at (3,5).
  Grid gt = makeGrid(CELL_FREE), est = makeGrid(CELL_FREE);
  set(gt, 4, 4, CELL_OBSTACLE);
  set(gt, 5, 4, CELL_OBSTACLE);
  set(est, 3, 5, CELL_OBSTACLE);
  std::vector<uint8_t> exclude(100, 0), glass(100, 0);
  exclude[4 * 10 + 5] = 1;
  exclude[5 * 10 + 3] = 1;
  glass[4 * 10 + 4] = 1;
  MapScoreParams p;
  p.radius_m = 2.0;
  const MapScore strict = scoreMap(gt, est, {5.0, 5.0}, p);
  EXPECT_EQ(strict.gt_known, 12u);
  EXPECT_EQ(strict.fn, 2u);
  EXPECT_EQ(strict.fp, 1u);
  EXPECT_EQ(strict.free_where_obstacle_cells.size(), 2u);
  EXPECT_TRUE(strict.free_where_glass_cells.empty());  // no glass mask given
  p.exclude = &exclude;
  p.glass = &glass;
  const MapScore s = scoreMap(gt, est, {5.0, 5.0}, p);
  EXPECT_EQ(s.excluded, 2u);
  EXPECT_EQ(s.gt_known, 10u);
  EXPECT_EQ(s.tp, 0u);
  EXPECT_EQ(s.fn, 1u);
  EXPECT_EQ(s.fp, 0u);
  EXPECT_EQ(s.tn, 9u);
  EXPECT_NEAR(s.coverage, 1.0, 1e-12);
  ASSERT_EQ(s.free_where_obstacle_cells.size(), 1u);
  EXPECT_EQ(s.free_where_obstacle_cells[0], 44u);
  ASSERT_EQ(s.free_where_glass_cells.size(), 1u);
  EXPECT_EQ(s.free_where_glass_cells[0], 44u);
  ASSERT_EQ(s.free_where_partial_cells.size(), 1u);
  EXPECT_EQ(s.free_where_partial_cells[0], 45u);
}
