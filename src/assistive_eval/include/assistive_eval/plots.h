#pragma once
// PNG plots with OpenCV drawing: trajectories (top-down over the floor plan, side view) and the
// colour-coded scored obstacle map. ROS-free.
#include <assistive_eval/map_score.h>
#include <assistive_eval/trajectory.h>

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace assistive_eval
{
struct PlotSeries
{
  std::string name;
  std::vector<Eigen::Vector3d> points;  ///< in the world frame of the plot
  cv::Scalar color{0, 0, 255};          ///< BGR
};
std::vector<Eigen::Vector3d> positions(const Trajectory& traj);

struct PlotOptions
{
  int width = 900, height = 900;  ///< pixels
  int axis_h = 0;                 ///< world axis drawn to the right in the top-down view
  int axis_v = 1;                 ///< world axis drawn upwards in the top-down view
  int axis_up = 2;                ///< height axis (side view); KITTI camera frames: axis_h 0, axis_v 2, axis_up 1
  double up_sign = 1.0;           ///< -1 when the height axis points down (KITTI/optical: y down)
  std::string title;
};

/// Top-down view. `floor_plan` (may be null) is drawn under the paths: obstacles dark, steps
/// brown, free light, unknown white (only when axis_h/axis_v are the grid's x/y).
cv::Mat plotTopDown(const std::vector<PlotSeries>& series, const Grid* floor_plan, const PlotOptions& o);
/// Side view: distance along the first series' path (m) against height; series with as many
/// points as the first (index-aligned) are drawn at the first series' distances.
cv::Mat plotSideView(const std::vector<PlotSeries>& series, const PlotOptions& o);
/// Ground truth vs estimate within the radius around the wearer: TP green, FP orange, FN red,
/// TN light grey, estimate unknown pale blue, outside the radius the truth dimmed; the image
/// shows the window of radius + 2 m around the wearer.
cv::Mat plotMapScore(const Grid& gt, const Grid& est, const Eigen::Vector2d& wearer_gt, double radius_m,
                     const Eigen::Isometry2d& T_est_gt = Eigen::Isometry2d::Identity(), int cell_px = 0,
                     const std::string& title = "");
/// cv::imwrite with an error message instead of an exception; returns success.
bool writePng(const std::string& path, const cv::Mat& img, std::string* error = nullptr);

}  // namespace assistive_eval
