#pragma once
// Multi-level surface classification of one frame's elevation map (seed 4.2.2-4.2.3, Triebel 2006):
// heights -> intervals split at gaps > G; an interval thicker than T is vertical -> obstacle;
// horizontal cells form an 8-neighbour graph, cells with >= 5 compatible edges are traversable;
// then a morphological closing of the obstacle mask.
#include <vector>

#include <assistive_obstacles/cell_values.h>
#include <assistive_obstacles/elevation_map.h>
#include <assistive_obstacles/params.h>

namespace assistive_obstacles
{
/// One height interval of a cell.
struct HeightInterval
{
  float bottom = 0.f, top = 0.f;  ///< m (trimmed extent)
  float median = 0.f;             ///< m
  float ground = 0.f;             ///< m, the ground_quantile of the heights
  /// m, the standard errors of `median` and `ground` (from the heights' density about each)
  float median_se = 0.f, ground_se = 0.f;
  int points = 0;
};

/// What one cell's heights say on their own.
enum class CellKind : uint8_t
{
  EMPTY = 0,     ///< no (or only noise) points
  HORIZONTAL,    ///< the lowest interval is thinner than T: a surface at height `ground`
  VERTICAL,      ///< the lowest interval is thicker than T (within the wearer's height): obstacle
};

class MlsClassifier
{
public:
  explicit MlsClassifier(const ObstaclesParams& p = ObstaclesParams()) : params_(p) {}
  void setParams(const ObstaclesParams& p) { params_ = p; }

  /// Splits sorted heights into intervals: sub-clusters at gaps > cluster_gap, sub-clusters with
  /// fewer than min_cluster_points dropped, the rest merged while gaps are < G (gap_height).
  void intervals(const float* h, int n, std::vector<HeightInterval>& out) const;
  /// Kind of a cell from its sorted heights; `ground` = the ground_quantile (or, with `median`,
  /// the median) of the lowest interval. Intervals more than G above the lowest one's top are
  /// overhead (the wearer fits under).
  /// `ground_se` (optional): its standard error (HeightInterval).
  CellKind analyse(const float* h, int n, float& ground, bool median = false, float* ground_se = nullptr) const;

  /// Labels every cell of `map` (index = window-local); `feet_z` is the wearer's feet level.
  void classify(const ElevationMap& map, float feet_z, std::vector<FrameLabel>& labels);

  const std::vector<CellKind>& kinds() const { return kind_; }
  const std::vector<float>& ground() const { return ground_; }
  /// 1 where the last classify() labelled a cell OBSTACLE only because the closing filled it.
  const std::vector<uint8_t>& filled() const { return filled_; }
  /// 1 where the last classify() found elevated points but no density peak of them (a neighbour's
  /// depth spill) and labelled the cell by its floor alone.
  const std::vector<uint8_t>& spill() const { return spill_; }

private:
  // The steps of classify(), in order.
  void analyseCells(const ElevationMap& map, float feet_z);  ///< kind_ and ground_ of every cell
  void dropSpill(const ElevationMap& map, float feet_z);     ///< vertical cells without a density peak
  bool holdsDensityPeak(const ElevationMap& map, int lx, int ly) const;
  void labelByEdges(const Window& w, std::vector<FrameLabel>& labels) const;  ///< the graph pass
  FrameLabel edgeLabel(const Window& w, int lx, int ly) const;                ///< a horizontal cell's
  void closeObstacles(int n, std::vector<FrameLabel>& labels);                ///< the closing, filled_

  ObstaclesParams params_;
  std::vector<CellKind> kind_;
  std::vector<float> ground_;
  std::vector<float> ground_se_;
  mutable std::vector<HeightInterval> scratch_;
  std::vector<uint8_t> mask_;
  std::vector<uint8_t> filled_;
  std::vector<uint8_t> spill_;
};

}  // namespace assistive_obstacles
