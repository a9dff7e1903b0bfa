#pragma once
// Voxelised elevation map of one frame (seed 4.2.1): world points (z up) binned into 20 cm
// cells of a square window around the wearer, each cell keeping the sorted heights of its points.
// Flat arrays indexed by window-local cell (counting sort): no per-point allocation, no hashing
// into a tree. Cells with fewer than min_points_per_cell points are dropped as noise.
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include <assistive_obstacles/params.h>

namespace assistive_obstacles
{
/// A square window of n x n cells whose lower-left cell has global integer index (ox, oy);
/// global cell (gx, gy) covers x in [gx*res, (gx+1)*res). It follows the wearer in whole cells.
struct Window
{
  int ox = 0, oy = 0;  ///< global index of local cell (0, 0)
  int n = 0;           ///< cells per side
  double res = 0.2;    ///< m
  double cx = 0.0, cy = 0.0;  ///< m, wearer position (circle centre)
  double radius = 5.0;        ///< m

  /// Window of radius r centred on (x, y).
  static Window around(double x, double y, double r, double res);
  int index(int lx, int ly) const { return ly * n + lx; }
  bool localOf(double x, double y, int& lx, int& ly) const;
  /// Whether the centre of local cell (lx, ly) lies inside the processing circle.
  bool inCircle(int lx, int ly) const;
  double centerX(int lx) const { return (ox + lx + 0.5) * res; }
  double centerY(int ly) const { return (oy + ly + 0.5) * res; }
};

class ElevationMap
{
public:
  explicit ElevationMap(const ObstaclesParams& p = ObstaclesParams()) : params_(p) {}
  void setParams(const ObstaclesParams& p) { params_ = p; }

  /// Bins `points` (world frame, z up) into `window`; points outside the circle or above
  /// `z_max` are ignored. Replaces the previous frame's content.
  /// Points above `z_elevated` are also counted on a grid fine_factor times finer.
  void build(const std::vector<Eigen::Vector3f>& points, const Window& window, float z_max,
             float z_elevated = std::numeric_limits<float>::infinity());

  const Window& window() const { return window_; }
  /// Points binned into local cell `idx` this frame before the noise cut.
  int rawCount(int idx) const { return raw_count_[idx]; }
  /// Points kept in the cell (0 when the cell was dropped as noise).
  int count(int idx) const { return raw_count_[idx] >= params_.min_points_per_cell ? raw_count_[idx] : 0; }
  /// Sorted (ascending) heights of the cell's points; valid for count(idx) entries.
  const float* heights(int idx) const { return heights_.data() + offset_[idx]; }
  /// Fine grid of elevated-point counts: (n * fine) cells per side, index fy * n * fine + fx.
  int fineSide() const { return window_.n * fine_; }
  int fine() const { return fine_; }
  const std::vector<uint16_t>& fineCounts() const { return fine_count_; }
  /// Points binned this frame (all cells, before the noise cut).
  size_t binnedPoints() const { return binned_; }

private:
  ObstaclesParams params_;
  Window window_;
  std::vector<int32_t> cell_of_point_;
  std::vector<int32_t> raw_count_, offset_, fill_;
  std::vector<float> heights_;
  std::vector<uint16_t> fine_count_;
  int fine_ = 1;
  size_t binned_ = 0;
};

}  // namespace assistive_obstacles
