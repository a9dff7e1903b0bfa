#include "assistive_vo/conversions.h"
#include <cmath>
#include <tf2_eigen/tf2_eigen.h>

namespace assistive_vo
{
bool fromMsg(const sensor_msgs::CameraInfo& l, const sensor_msgs::CameraInfo& r, StereoCamera& cam,
             std::string* error)
{
  auto fail = [&](const std::string& e) {
    if (error)
      *error = e;
    return false;
  };
  const double fx = l.P[0], fy = l.P[5], cx = l.P[2], cy = l.P[6];
  if (!(fx > 0 && fy > 0 && std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) && std::isfinite(cy)))
    return fail("left camera_info has no valid projection matrix P");
  if (l.width == 0 || l.height == 0 || l.width != r.width || l.height != r.height)
    return fail("left/right camera_info sizes are zero or differ");
  if (std::abs(r.P[0] - fx) > 1e-3 * fx || std::abs(r.P[5] - fy) > 1e-3 * fy || std::abs(r.P[2] - cx) > 1.0 ||
      std::abs(r.P[6] - cy) > 1.0)
    return fail("left/right camera_info intrinsics differ: images are not rectified as a pair");
  const double baseline = -r.P[3] / r.P[0];
  if (!(baseline > 1e-3 && baseline < 10.0))
    return fail("right camera_info P[3] must be -fx * baseline with a positive baseline");
  cam.fx = fx;
  cam.fy = fy;
  cam.cx = cx;
  cam.cy = cy;
  cam.baseline = baseline;
  cam.width = static_cast<int>(l.width);
  cam.height = static_cast<int>(l.height);
  return true;
}

void toMsg(const StereoCamera& cam, sensor_msgs::CameraInfo& l, sensor_msgs::CameraInfo& r)
{
  for (sensor_msgs::CameraInfo* m : {&l, &r})
  {
    m->width = static_cast<uint32_t>(cam.width);
    m->height = static_cast<uint32_t>(cam.height);
    m->distortion_model = "plumb_bob";
    m->D.assign(5, 0.0);
    m->K = {cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1};
    m->R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    m->P = {cam.fx, 0, cam.cx, 0, 0, cam.fy, cam.cy, 0, 0, 0, 1, 0};
  }
  r.P[3] = -cam.fx * cam.baseline;
}

nav_msgs::Odometry toOdometryMsg(const VoOutput& o, const ros::Time& stamp, const std::string& odom_frame,
                                 const std::string& base_frame)
{
  nav_msgs::Odometry m;
  m.header.stamp = stamp;
  m.header.frame_id = odom_frame;
  m.child_frame_id = base_frame;
  const PublishedOdometry p = published(o);
  m.pose.pose = tf2::toMsg(p.T_odom_link);
  tf2::toMsg(p.linear_velocity, m.twist.twist.linear);
  tf2::toMsg(p.angular_velocity, m.twist.twist.angular);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
    {
      m.pose.covariance[static_cast<size_t>(i * 6 + j)] = p.pose_covariance(i, j);
      m.twist.covariance[static_cast<size_t>(i * 6 + j)] = p.twist_covariance(i, j);
    }
  return m;
}

geometry_msgs::TransformStamped toTransformMsg(const Eigen::Isometry3d& T, const ros::Time& stamp,
                                               const std::string& parent, const std::string& child)
{
  geometry_msgs::TransformStamped t = tf2::eigenToTransform(T);
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  return t;
}

Eigen::Isometry3d poseFromMsg(const geometry_msgs::Pose& p)
{
  Eigen::Isometry3d T;
  tf2::fromMsg(p, T);
  return T;
}
}  // namespace assistive_vo
