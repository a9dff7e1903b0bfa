#pragma once
// Obstacle-map scoring against a ground-truth grid (codes of the interface contract:
// -1 unknown, 0 free, 50 step, 100 obstacle). ROS-free: Eigen only.
#include <assistive_eval/types.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <vector>

namespace assistive_eval
{
/// The grid type and cell codes are the shared ones of <assistive_eval/types.h>
/// (assistive_eval::OccupancyGrid, CELL_UNKNOWN/FREE/STEP/OBSTACLE).
using Grid = assistive_eval::OccupancyGrid;

/// An obstacle is any "not walkable" code: step or obstacle (>= 50).
inline bool isObstacle(int8_t v) { return v >= CELL_STEP; }

struct MapScoreParams
{
  double radius_m = 3.0;  ///< only ground-truth cells whose centre is within this of the wearer
  /// Optional, one entry per gt cell (row-major): non-zero = scored neither way (a cell an
  /// obstacle covers only in part, or a free cell with an obstacle just past its border: below
  /// what a 20 cm grid can resolve; the planner's clearance covers it). Such cells count only in
  /// `excluded`; an obstacle one reported free goes to `free_where_partial_cells`.
  const std::vector<uint8_t>* exclude = nullptr;
  /// Optional, one entry per gt cell: non-zero = glass panel (for `free_where_glass`).
  const std::vector<uint8_t>* glass = nullptr;
};

/// Scored over ground-truth cells within the radius whose truth is known (not -1). The estimate is
/// looked up at each such cell's centre. Cells unknown in the estimate are neither free nor
/// obstacle: they count only in `est_unknown` (and lower `coverage`).
struct MapScore
{
  double radius_m = 0.0;
  size_t gt_known = 0;     ///< gt cells known within the radius (not excluded)
  size_t scored = 0;       ///< of those, known in the estimate too
  size_t est_unknown = 0;  ///< gt known, estimate unknown / outside the estimate
  size_t tp = 0, fp = 0, fn = 0, tn = 0;
  size_t free_where_obstacle = 0;                   ///< estimate exactly FREE, truth obstacle/step
  std::vector<size_t> free_where_obstacle_cells;    ///< their gt cell indices (y * width + x)
  size_t excluded = 0;                              ///< gt known cells scored neither way (params.exclude)
  std::vector<size_t> free_where_partial_cells;     ///< excluded obstacle cells reported exactly FREE
  std::vector<size_t> free_where_glass_cells;       ///< of free_where_obstacle_cells, glass (params.glass)
  double precision = std::numeric_limits<double>::quiet_NaN();      ///< tp / (tp + fp)
  double recall = std::numeric_limits<double>::quiet_NaN();         ///< tp / (tp + fn)
  double misclassified = std::numeric_limits<double>::quiet_NaN();  ///< (fp + fn) / scored
  double coverage = std::numeric_limits<double>::quiet_NaN();       ///< scored / gt_known
};

/// `T_est_gt` maps points of the ground-truth grid frame into the estimate grid's frame (identity
/// when both grids share a frame). `wearer_gt` is the wearer's position in the gt frame.
MapScore scoreMap(const Grid& gt, const Grid& est, const Eigen::Vector2d& wearer_gt,
                  const MapScoreParams& p = MapScoreParams(),
                  const Eigen::Isometry2d& T_est_gt = Eigen::Isometry2d::Identity());

/// Sums scores over many grids / frames (micro-average) and keeps the distinct truth cells ever
/// reported free while obstacle (benchmark key `free_where_obstacle_cells`, docs/design.md).
class MapScoreAccumulator
{
public:
  void add(const MapScore& s);
  /// Totals with precision / recall / misclassified / coverage recomputed from the summed counts.
  MapScore total() const;
  size_t freeWhereObstacleCells() const { return fwo_cells_.size(); }
  size_t grids() const { return grids_; }

private:
  MapScore sum_;
  std::vector<size_t> fwo_cells_;  ///< sorted, unique
  size_t grids_ = 0;
};

/// Planar pose (x, y, heading of the body's `forward` axis) of a 3D pose in a z-up world. To score
/// a grid kept in the pipeline's `odom` frame: T_gt_odom = planarPose(gt_cam, z) *
/// planarPose(odom_cam_link, x).inverse(), and T_est_gt = T_gt_odom.inverse() (shift it by the
/// grid origin when the estimate grid's cells are indexed from an origin, as Grid does).
Eigen::Isometry2d planarPose(const Eigen::Isometry3d& pose, const Eigen::Vector3d& forward);

}  // namespace assistive_eval
