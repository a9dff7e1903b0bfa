#pragma once
// Message conversions of the obstacle stage (nodelet target only; the core stays ROS-free).
#include <string>
#include <vector>

#include <assistive_msgs/MoverArray.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/PointCloud2.h>
#include <stereo_msgs/DisparityImage.h>
#include <visualization_msgs/MarkerArray.h>

#include <assistive_common/code_grid_msg.h>
#include <assistive_obstacles/disparity.h>
#include <assistive_obstacles/mover_pipeline.h>
#include <assistive_obstacles/obstacle_map.h>

namespace assistive_obstacles
{
/// Grid <-> nav_msgs/OccupancyGrid: the one conversion of the shared grid (code_grid_msg.h):
/// toMsg(grid, frame, stamp) (identity orientation, z = 0), fromMsg(msg) (orientation ignored:
/// our grids are axis-aligned).
using assistive_common::fromMsg;
using assistive_common::toMsg;

/// Rectified left + right camera_info -> stereo model; false when the infos are unusable
/// (fx <= 0, no baseline, size mismatch).
bool fromMsg(const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo& right, StereoModel& model);

/// Matcher-scale disparity (CV_32F, invalid < 0) -> stereo_msgs/DisparityImage (f and T at that
/// scale, invalid = -1, min/max from the matcher's range).
stereo_msgs::DisparityImage toDisparityMsg(const cv::Mat& disp, const StereoModel& model, int num_disparities,
                                           const std_msgs::Header& header);

/// Points -> sensor_msgs/PointCloud2 with float32 x, y, z (unorganised).
sensor_msgs::PointCloud2 toCloudMsg(const std::vector<Eigen::Vector3f>& points, const std_msgs::Header& header);
/// PointCloud2 with float32 x, y, z -> points (for the round-trip test and tools).
std::vector<Eigen::Vector3f> fromCloudMsg(const sensor_msgs::PointCloud2& msg);

/// Occupied OctoMap leaves -> one CUBE_LIST marker per leaf size, coloured by height.
visualization_msgs::MarkerArray toMarkers(const std::vector<Eigen::Vector3f>& centers, const std::vector<float>& sizes,
                                          const std::string& frame, const ros::Time& stamp);

/// Confirmed movers -> assistive_msgs/MoverArray (position z = `floor_z`, the wearer's feet;
/// covariance row-major 4x4 of x, y, vx, vy). An empty list gives an empty array ("no one").
assistive_msgs::MoverArray toMoverArray(const std::vector<ReportedMover>& movers, double floor_z,
                                        const std::string& frame, const ros::Time& stamp);
/// rviz: per mover a CYLINDER (radius, height), an ARROW of its velocity (1 s long) and a LINE_STRIP
/// of its predicted path over `horizon` s; a DELETEALL first, so that movers that ended vanish.
visualization_msgs::MarkerArray toMoverMarkers(const std::vector<ReportedMover>& movers, double floor_z, double horizon,
                                               const std::string& frame, const ros::Time& stamp);
}  // namespace assistive_obstacles
