#pragma once
// Message <-> core conversions (nodelet target only; the core never sees ROS types).
#include <string>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include "assistive_vo/published_odometry.h"
#include "assistive_vo/stereo_camera.h"
#include "assistive_vo/visual_odometry.h"

namespace assistive_vo
{
/// Rectified stereo calibration from the two camera_infos (README: D = 0, R = I,
/// right P[3] = -fx * baseline). False with a reason in `error` when they are unusable.
bool fromMsg(const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo& right, StereoCamera& cam,
             std::string* error = nullptr);
/// CameraInfo pair of a StereoCamera (for tests and tools).
void toMsg(const StereoCamera& cam, sensor_msgs::CameraInfo& left, sensor_msgs::CameraInfo& right);

/// nav_msgs/Odometry of camera_link in odom, covariance row-major (x y z rotx roty rotz), of
/// published(o) (published_odometry.h): an untrusted output gets kUntrustedVariance diagonals and
/// zero twist (its pose is the last trusted one).
nav_msgs::Odometry toOdometryMsg(const VoOutput& o, const ros::Time& stamp, const std::string& odom_frame,
                                 const std::string& base_frame);
geometry_msgs::TransformStamped toTransformMsg(const Eigen::Isometry3d& T, const ros::Time& stamp,
                                               const std::string& parent, const std::string& child);
/// Pose of a nav_msgs/Odometry as an Isometry3d (inverse of the pose part of toOdometryMsg).
Eigen::Isometry3d poseFromMsg(const geometry_msgs::Pose& p);
}  // namespace assistive_vo
