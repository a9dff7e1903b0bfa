#include <assistive_obstacles/params.h>

#include <algorithm>
#include <sstream>

namespace assistive_obstacles
{
namespace
{
template <typename T>
void clampField(std::vector<std::string>& msgs, const char* name, T& v, T lo, T hi)
{
  const T c = std::min(std::max(v, lo), hi);
  if (c != v)
  {
    std::ostringstream s;
    s << name << " = " << v << " out of [" << lo << ", " << hi << "], using " << c;
    msgs.push_back(s.str());
    v = c;
  }
}
}  // namespace

std::vector<std::string> clampParams(ObstaclesParams& p)
{
  std::vector<std::string> m;
  if (p.disparity_method != "sgbm3way" && p.disparity_method != "sgbm" && p.disparity_method != "hh" && p.disparity_method != "hh4" &&
      p.disparity_method != "bm")
  {
    m.push_back("disparity_method '" + p.disparity_method + "' unknown, using sgbm3way");
    p.disparity_method = "sgbm3way";
  }
  clampField(m, "disparity_scale", p.disparity_scale, 0.125, 1.0);
  clampField(m, "max_disparity", p.max_disparity, 16, 512);
  if (p.block_size % 2 == 0)
  {
    m.push_back("block_size must be odd, using " + std::to_string(p.block_size + 1));
    ++p.block_size;
  }
  clampField(m, "block_size", p.block_size, 1, 21);
  clampField(m, "uniqueness_ratio", p.uniqueness_ratio, 0, 100);
  clampField(m, "speckle_window_size", p.speckle_window_size, 0, 1000);
  clampField(m, "speckle_range", p.speckle_range, 0, 64);
  clampField(m, "disp12_max_diff", p.disp12_max_diff, -1, 64);
  clampField(m, "sgbm_p1", p.sgbm_p1, 0, 1000);
  clampField(m, "sgbm_p2", p.sgbm_p2, p.sgbm_p1 + 1, 10000);
  clampField(m, "min_depth", p.min_depth, 0.05, 10.0);
  clampField(m, "max_depth", p.max_depth, p.min_depth + 0.1, 50.0);
  clampField(m, "point_stride", p.point_stride, 1, 16);
  clampField(m, "edge_filter", p.edge_filter, 0.0, 1000.0);
  clampField(m, "texture_max_depth_sigma", p.texture_max_depth_sigma, 0.0, 100.0);
  clampField(m, "image_noise_sigma", p.image_noise_sigma, 0.01, 100.0);
  clampField(m, "cell_size", p.cell_size, 0.02, 2.0);
  clampField(m, "window_radius", p.window_radius, 2 * p.cell_size, 50.0);
  clampField(m, "min_points_per_cell", p.min_points_per_cell, 1, 100000);
  clampField(m, "gap_height", p.gap_height, 0.5, 5.0);
  clampField(m, "step_height", p.step_height, 0.01, 1.0);
  clampField(m, "min_step", p.min_step, 0.0, p.step_height);
  clampField(m, "head_clearance", p.head_clearance, 0.0, 3.0);
  clampField(m, "camera_height", p.camera_height, 0.0, 3.0);
  clampField(m, "max_surface_rise", p.max_surface_rise, 0.0, 5.0);
  clampField(m, "max_surface_drop", p.max_surface_drop, 0.0, 5.0);
  clampField(m, "cluster_gap", p.cluster_gap, 0.0, 1.0);
  clampField(m, "min_cluster_points", p.min_cluster_points, 1, 1000);
  clampField(m, "surface_push", p.surface_push, 0.0, 0.5);
  clampField(m, "ground_quantile", p.ground_quantile, 0.0, 1.0);
  clampField(m, "thickness_trim", p.thickness_trim, 0.0, 0.45);
  clampField(m, "min_traversable_edges", p.min_traversable_edges, 0, 8);
  clampField(m, "closing_radius", p.closing_radius, 0, 5);
  clampField(m, "closing_weight", p.closing_weight, 1, 4);
  clampField(m, "fine_factor", p.fine_factor, 1, 10);
  clampField(m, "peak_fraction", p.peak_fraction, 0.0, 1.0);
  clampField(m, "min_observations", p.min_observations, 1, 1000);
  clampField(m, "obstacle_ratio", p.obstacle_ratio, 0.0, 1.0);
  clampField(m, "permanent_flips", p.permanent_flips, 1, 60000);
  clampField(m, "max_count", p.max_count, p.min_observations, 60000);
  clampField(m, "full_weight_range", p.full_weight_range, 0.0, 50.0);
  clampField(m, "dropout_max_range", p.dropout_max_range, 0.0, 50.0);
  clampField(m, "vote_max_range", p.vote_max_range, 0.0, 50.0);
  clampField(m, "disparity_sigma", p.disparity_sigma, 0.0, 100.0);
  clampField(m, "obstacle_max_sigma", p.obstacle_max_sigma, 0.0, 100.0);
  clampField(m, "dropout_free_weight", p.dropout_free_weight, 0, 4);
  clampField(m, "max_frame_gap_s", p.max_frame_gap_s, 0.05, 60.0);
  clampField(m, "rebuild_frames", p.rebuild_frames, 1, 1000);
  clampField(m, "min_fresh_points", p.min_fresh_points, 0, 10000000);
  clampField(m, "octomap_resolution", p.octomap_resolution, 0.01, 2.0);
  clampField(m, "octomap_max_range", p.octomap_max_range, 0.1, 50.0);
  clampField(m, "octomap_point_stride", p.octomap_point_stride, 1, 1000);
  return m;
}

}  // namespace assistive_obstacles
