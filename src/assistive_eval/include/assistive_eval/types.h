#pragma once
// Plain data types shared by the simulator, the bag I/O and every stage's benchmark.
// ROS-free (OpenCV + Eigen only), so core libraries may include it.
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <assistive_common/code_grid.h>
#include <assistive_common/codes.h>

namespace assistive_eval
{
/// Rectified stereo intrinsics (identical for both cameras; right = left shifted by baseline
/// along +x of the left optical frame, i.e. along -y of camera_link).
struct StereoCalib
{
  int width = 640;
  int height = 480;
  double fx = 500.0;    ///< px
  double fy = 500.0;    ///< px
  double cx = 319.5;    ///< px
  double cy = 239.5;    ///< px
  double baseline = 0.12;  ///< m
};

/// One IMU sample in the camera_link frame (x forward, y left, z up).
struct ImuSample
{
  double stamp = 0.0;                              ///< s
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   ///< rad/s
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  ///< m/s^2, specific force (+9.81 z at rest)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< world->link, if known
  bool has_orientation = false;
};

/// One rectified stereo frame as read from / written to a stereo bag.
struct StereoFrame
{
  double stamp = 0.0;  ///< s
  cv::Mat left;        ///< CV_8UC1
  cv::Mat right;       ///< CV_8UC1
  StereoCalib calib;
  /// Ground-truth pose of the left optical frame (z forward, x right, y down) in gt_world.
  bool has_gt_pose = false;
  Eigen::Isometry3d gt_pose = Eigen::Isometry3d::Identity();
  /// Ground-truth velocity of the left optical frame in gt_world (m/s), if known.
  Eigen::Vector3d gt_velocity = Eigen::Vector3d::Zero();
  /// Optional ground-truth depth Z (m) of the left image, CV_32FC1, 0 = nothing (sky); empty when
  /// the bag has none (render_bag --depth writes it).
  cv::Mat gt_depth;
  /// IMU samples with stamp in (previous frame's stamp, this frame's stamp]; the first frame
  /// gets every sample up to its stamp.
  std::vector<ImuSample> imu;
};

/// Grid cell codes (README "Grid cell codes"; one definition for every stage in
/// assistive_common/codes.h).
using assistive_common::CELL_FREE;
using assistive_common::CELL_OBSTACLE;
using assistive_common::CELL_STEP;
using assistive_common::CELL_UNKNOWN;

/// 2D occupancy grid in gt_world (axis-aligned, like nav_msgs/OccupancyGrid with identity
/// origin orientation): the one grid of cell codes (assistive_common/code_grid.h).
using OccupancyGrid = assistive_common::CodeGrid;

/// Fixed transform camera_link -> left optical frame used by the simulator's ground truth:
/// same origin (camera_link sits at the left camera's centre), optical z = link x,
/// optical x = -link y, optical y = -link z.
inline Eigen::Isometry3d linkToLeftOptical()
{
  Eigen::Matrix3d r;
  r << 0, 0, 1,
      -1, 0, 0,
       0, -1, 0;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r;  // columns: optical axes expressed in link
  return t;
}

}  // namespace assistive_eval
