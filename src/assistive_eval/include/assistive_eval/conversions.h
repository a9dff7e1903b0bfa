#pragma once
// Message conversions of the stereo bag topics (library assistive_eval_bag; not for ROS-free code).
#include <string>

#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/Range.h>

#include <assistive_common/code_grid_msg.h>
#include <assistive_eval/types.h>

namespace assistive_eval
{
/// mono8 image message from a CV_8UC1 image (throws std::invalid_argument for other types).
sensor_msgs::Image toImageMsg(const cv::Mat& mono8, const std::string& frame, const ros::Time& stamp);
/// CV_32FC1 depth image message (encoding 32FC1, metres).
sensor_msgs::Image toDepthMsg(const cv::Mat& depth, const std::string& frame, const ros::Time& stamp);
/// Rectified camera info: D = 0, R = I, P = [f 0 cx Tx; 0 f cy 0; 0 0 1 0], Tx = 0 (left) or
/// -fx * baseline (right).
sensor_msgs::CameraInfo toCameraInfo(const StereoCalib& calib, bool right, const std::string& frame,
                                     const ros::Time& stamp);
/// Stereo calibration from the left (and right, for the baseline; may be null) camera infos.
StereoCalib fromCameraInfos(const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo* right);

/// Ground-truth occupancy <-> nav_msgs/OccupancyGrid: the one conversion of the shared grid
/// (code_grid_msg.h): toMsg(grid, frame, stamp), fromMsg(msg).
using assistive_common::fromMsg;
using assistive_common::toMsg;

sensor_msgs::Imu toMsg(const ImuSample& sample, const std::string& frame);
ImuSample fromMsg(const sensor_msgs::Imu& msg);

/// An ultrasonic ranger's ping: `range` in m, +Inf for "no echo within max_range" (REP-117);
/// field of view in rad, limits in m.
sensor_msgs::Range toRangeMsg(double range, double field_of_view, double min_range, double max_range,
                              const std::string& frame, const ros::Time& stamp);

}  // namespace assistive_eval
