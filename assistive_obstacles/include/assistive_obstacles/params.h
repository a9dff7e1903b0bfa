#pragma once
// All parameters of the obstacle stage. The initializers are the only defaults (STYLE.md 4);
// the nodelet reads every field as a ROS parameter of the same name and clamps it with clampParams().
#include <string>
#include <vector>

namespace assistive_obstacles
{
struct ObstaclesParams
{
  // --- dense disparity -------------------------------------------------------------------
  std::string disparity_method = "sgbm3way";  ///< "sgbm3way", "sgbm", "hh", "hh4" or "bm" (hh/hh4: fewer
                                              ///< errors, but 10x slower than sgbm3way on 450x375 inputs)
  double disparity_scale = 0.5;     ///< image scale the matcher runs at (1 = full resolution)
  int max_disparity = 128;          ///< px at FULL resolution (min depth = fx*B/max_disparity)
  int block_size = 5;               ///< px at the matcher's scale, odd
  int uniqueness_ratio = 10;        ///< %
  int speckle_window_size = 100;    ///< px^2 at the matcher's scale (0 disables)
  int speckle_range = 2;            ///< disparity levels
  int disp12_max_diff = 1;          ///< left-right check, px at the matcher's scale (<0 disables)
  int sgbm_p1 = 4;                  ///< SGBM smoothness penalty P1 (disparity change of 1) per pixel of the block:
                                    ///< P1 = sgbm_p1 * block_size^2 (OpenCV's sample uses 8; 4 keeps slanted floors
                                    ///< and walls from being pulled onto fronto-parallel planes)
  int sgbm_p2 = 64;                 ///< P2 (larger disparity jumps) = sgbm_p2 * block_size^2 (must exceed sgbm_p1)

  // --- points ----------------------------------------------------------------------------
  double min_depth = 0.3;           ///< m, closer points are dropped
  double max_depth = 6.0;           ///< m, farther points are dropped (disparity noise grows as z^2)
  int point_stride = 1;             ///< take every n-th pixel of the scaled disparity in u and v
  double edge_filter = 0.5;         ///< px at the matcher's scale: pixels whose 3x3 disparity range exceeds this
                                    ///< lie on a depth discontinuity ("flying pixels") and give no point (0 disables)
  double texture_max_depth_sigma = 0.15;  ///< m: pixels whose depth is less precise than this by the Cramer-Rao bound
                                         ///< of their block's horizontal texture give no point (0 disables): a
                                         ///< near-textureless wall matches at +-1-2 px and scatters points in front of it
  double image_noise_sigma = 2.0;   ///< grey levels: the camera's pixel noise, for that bound

  // --- elevation map / MLS (wearer-tied, not scene-tied) ----------------------------------
  double cell_size = 0.2;           ///< m, elevation cell edge
  double window_radius = 5.0;       ///< m, processed circle around the wearer (scrolls)
  int min_points_per_cell = 10;     ///< cells with fewer points are dropped as noise
  double gap_height = 1.9;          ///< G, m: intervals split at vertical gaps larger than this (wearer height + margin)
  double step_height = 0.2;         ///< T, m: thicker intervals are vertical (obstacle); also max climbable height difference
  double min_step = 0.065;          ///< m: a traversable cell whose neighbour differs by more is a step/curb
  double head_clearance = 0.3;      ///< m above the camera: higher points cannot touch the wearer
  double camera_height = 1.6;       ///< m, camera above the wearer's feet (feet level = camera z - this)
  double max_surface_rise = 0.45;   ///< m: walkable surfaces lie at most this far above the feet ...
  double max_surface_drop = 0.6;    ///< m: ... or this far below them (else obstacle / drop-off)
  double cluster_gap = 0.1;         ///< m: heights closer than this form one sub-cluster (outlier rejection)
  int min_cluster_points = 3;       ///< sub-clusters with fewer points are noise
  double surface_push = 0.04;       ///< m: elevated points are moved this far away from the camera along the horizontal
                                    ///< ray: a camera sees the front face of a solid, the solid lies behind it, so a face
                                    ///< on a cell border (depth noise splits its points) lands in the solid's cell; keep it
                                    ///< below the thinnest obstacle (0 disables)
  bool surface_push_normal = true;  ///< push along the surface's horizontal normal (from the disparity gradient) where
                                    ///< the surface is steep, instead of the viewing ray
  double ground_quantile = 0.7;     ///< quantile of the lowest interval's heights taken as the cell's ground height:
                                    ///< above the median, so a cell holding a curb edge takes the curb's height as
                                    ///< the ground truth does (highest walkable surface in the cell)
  double thickness_trim = 0.05;     ///< fraction of an interval's heights trimmed at each end for its thickness
  int min_traversable_edges = 5;    ///< compatible 8-neighbours needed to be traversable
  int closing_radius = 1;           ///< cells, morphological closing of the obstacle mask, filling cells without a vote (0 disables)
  int closing_weight = 1;           ///< vote weight (1..4) of a cell the closing filled; such votes never decide a cell
                                    ///< on their own (a cell never seen itself stays unknown)
  int fine_factor = 4;              ///< elevated points are also counted on a grid this many times finer (5 cm) ...
  double peak_fraction = 0.5;       ///< ... and a vertical cell stays an obstacle only if one of its fine bins holds at
                                    ///< least this fraction of the densest fine bin within 2 fine bins (suppresses the
                                    ///< depth-noise spill of a wall into the cell in front of it; 0 disables)

  // --- temporal filter ---------------------------------------------------------------------
  int min_observations = 5;         ///< O+S before a cell is decided
  double obstacle_ratio = 0.5;      ///< obstacle if O/(O+S) > this
  int permanent_flips = 15;         ///< I at which a cell becomes an obstacle for good
  int max_count = 40;               ///< O+S are halved above this many full-weight votes (keeps the filter responsive)
  double vote_max_range = 3.5;      ///< m: cells farther than this from the wearer take no vote (0 = whole window):
                                    ///< depth error grows as Z^2; a cell behind a wall is otherwise only ever voted
                                    ///< on from afar (by noise) and never corrected up close
  double full_weight_range = 2.5;   ///< m: votes of cells nearer than this weigh 4, farther ones 4*(r0/r)^2 (>= 1),
                                    ///< as stereo depth noise grows with r^2 (0: every vote weighs 1, as in the seed)

  double disparity_sigma = 0.3;     ///< px at FULL resolution: stereo disparity noise assumed for the depth error
  double obstacle_max_sigma = 0.03; ///< m: cells take obstacle votes only within the range where the depth error
                                    ///< sigma_Z = Z^2 * disparity_sigma / (fx * baseline) is at most this (2.45 m for
                                    ///< the 12 cm, 500 px rig); free votes reach vote_max_range (0 disables; needs the
                                    ///< camera model passed to ObstacleMap::update)

  // --- dropout / glass policy ----------------------------------------------------------------
  double dropout_max_range = 4.0;   ///< m: obstacle cells in view this close but without depth are reported
  int dropout_free_weight = 1;      ///< vote weight (0..4) of the free label such a cell still gets: 0 locks the cell
                                    ///< (a false obstacle in front of the floor could then never be cleared), 1 lets
                                    ///< seen-through cells fade after ~4x as many frames as made them obstacles

  // --- trust in the input ("never guide on a guess", FrameGate) ---------------------------
  double max_frame_gap_s = 0.5;     ///< s: a longer gap between frames, or time going back, clears the map
  int rebuild_frames = 5;           ///< fresh frames after a clear before the grid is published again
  int min_fresh_points = 500;       ///< a frame with fewer 3D points yields no depth: it neither updates the map nor
                                    ///< refreshes the grid's stamp (black, saturated, covered or textureless view)

  // --- OctoMap of what was seen ------------------------------------------------------------
  bool octomap_enabled = true;
  double octomap_resolution = 0.1;  ///< m
  double octomap_max_range = 5.0;   ///< m, ray length for insertion
  int octomap_point_stride = 8;     ///< insert every n-th point (ray casting cost)
  std::string octomap_save_path = "/tmp/assistive_obstacles.bt";
};

/// Clamps `p` into valid ranges; returns one message per changed field (for NODELET_WARN).
std::vector<std::string> clampParams(ObstaclesParams& p);

}  // namespace assistive_obstacles
