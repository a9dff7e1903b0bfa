#pragma once
// The obstacle stage's map: per frame, camera-frame points -> world -> elevation cells -> MLS
// labels -> temporal filter, in a window that scrolls with the wearer; plus the dropout / glass
// report and the OctoMap of what was seen. ROS-free.
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include <assistive_common/code_grid.h>

#include <assistive_obstacles/cell_values.h>
#include <assistive_obstacles/disparity.h>
#include <assistive_obstacles/elevation_map.h>
#include <assistive_obstacles/mls_classifier.h>
#include <assistive_obstacles/params.h>
#include <assistive_obstacles/seen_octree.h>
#include <assistive_obstacles/sonar_fusion.h>
#include <assistive_obstacles/temporal_filter.h>

namespace assistive_obstacles
{
/// A square grid of output codes (row-major, index = iy * width + ix), axis-aligned in the world:
/// the one grid of cell codes (assistive_common/code_grid.h).
using GridData = assistive_common::CodeGrid;

struct FrameStats
{
  size_t points_in = 0;      ///< points handed to update()
  size_t points_binned = 0;  ///< points inside the window and below head clearance
  int cells_observed = 0;    ///< cells with >= min_points_per_cell points
  int obstacle_votes = 0, free_votes = 0;
  int dropout_cells = 0;     ///< obstacle cells in view without depth this frame
  int mover_cells = 0;       ///< cells in the vote circle skipped as covered by a mover (setMovers)
};

/// A mover's ground footprint (world, m): a disc; every cell it overlaps takes no vote.
struct MoverFootprint
{
  double x = 0.0, y = 0.0;
  double radius = 0.0;
};

/// Range (m) within which a cell may take an obstacle vote: where the stereo depth error
/// sigma_Z = Z^2 * disparity_sigma / (fx * baseline) stays below obstacle_max_sigma (0 = no limit).
double obstacleEvidenceRange(const ObstaclesParams& p, const StereoModel& m);

class ObstacleMap
{
public:
  explicit ObstacleMap(const ObstaclesParams& p = ObstaclesParams());
  void setParams(const ObstaclesParams& p);
  const ObstaclesParams& params() const { return params_; }
  /// Whether update() uses surface normals (surface_push along the normal): compute them then.
  bool usesNormals() const { return params_.surface_push > 0.0 && params_.surface_push_normal; }

  /// One frame: `points_cam` in the left optical frame, `T_world_cam` its pose in the world
  /// (z up). `camera` + `disparity` (the matcher-scale CV_32F disparity the points came from;
  /// both may be null) enable the dropout / glass policy: a cell mapped as obstacle whose depth
  /// vanished or passes through it this frame is reported and takes no free vote.
  /// `normals_cam` (optional, one per point, facing the camera): elevated points are pushed into
  /// the solid along the surface normal instead of the viewing ray (see surface_push).
  /// Elevation + MLS + temporal only; the OctoMap is updated by insertOctomap().
  void update(const std::vector<Eigen::Vector3f>& points_cam, const Eigen::Isometry3f& T_world_cam,
              const StereoModel* camera = nullptr, const cv::Mat* disparity = nullptr,
              const std::vector<Eigen::Vector3f>* normals_cam = nullptr);
  /// Ghost-free hook (issue 22): the movers of the NEXT update() only (their detections are of that
  /// frame). Cells a footprint overlaps take no vote and no column observation in it (the temporal
  /// filter's mover cells), so people walking by leave no ghost and lock no cell. None given
  /// (the default): update() is unchanged. Footprints that are not finite, or wider than
  /// window_radius, are ignored.
  void setMovers(const std::vector<MoverFootprint>& movers) { movers_ = movers; }
  /// One forward-ranger reading (sonar_fusion.h) into the current window (after the first
  /// update()); its pose in the same world frame. Returns its check (only ECHO adds evidence).
  RangeCheck addRange(const RangeReading& r);
  const SonarFusion& sonar() const { return sonar_; }
  /// Inserts the last frame's world points into the OctoMap.
  void insertOctomap();

  /// Traversability codes of the current window.
  void grid(GridData& out) const;
  /// Dropout / glass report of the last frame: CELL_OBSTACLE where a mapped obstacle is in view but
  /// had no depth, CELL_UNKNOWN elsewhere (same geometry as grid()).
  const GridData& dropout() const { return dropout_; }
  const FrameStats& stats() const { return stats_; }
  const Window& window() const { return window_; }
  const std::vector<FrameLabel>& frameLabels() const { return labels_; }
  const std::vector<Eigen::Vector3f>& worldPoints() const { return world_; }
  const TemporalFilter& temporal() const { return temporal_; }
  SeenOctree& octree() { return *octree_; }
  void reset();

private:
  // The steps of update() after the points are in the world frame.
  /// Moves the points of steep or elevated surfaces surface_push into the solid behind them.
  void pushIntoSurfaces(const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                        const std::vector<Eigen::Vector3f>* normals_cam, float elevated);
  /// This frame's votes of every cell of the window (and the dropout grid, the frame's stats).
  void voteCells(const Eigen::Isometry3f& T_world_cam, const StereoModel* camera, const cv::Mat* disparity,
                 float feet);

  ObstaclesParams params_;
  ElevationMap elevation_;
  MlsClassifier mls_;
  TemporalFilter temporal_;
  SonarFusion sonar_;
  float last_feet_ = 0.f;
  std::unique_ptr<SeenOctree> octree_;
  Window window_;
  std::vector<Eigen::Vector3f> world_;
  Eigen::Vector3f last_origin_ = Eigen::Vector3f::Zero();
  std::vector<FrameLabel> labels_;
  GridData dropout_;
  FrameStats stats_;
  std::vector<MoverFootprint> movers_;  ///< for the next update()
};

}  // namespace assistive_obstacles
