#pragma once
// sensor_msgs/CameraInfo <-> CameraCalibration (nodelet target only; the core is ROS-free).
#include <assistive_description/camera_calibration.h>
#include <sensor_msgs/CameraInfo.h>

namespace assistive_description
{
sensor_msgs::CameraInfo toMsg(const CameraCalibration& c);
CameraCalibration fromMsg(const sensor_msgs::CameraInfo& m);

}  // namespace assistive_description
