#include <assistive_eval/conversions.h>

#include <cstdint>
#include <type_traits>
#include <nav_msgs/OccupancyGrid.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <sensor_msgs/image_encodings.h>
#include <std_msgs/Header.h>
#include <tf2_eigen/tf2_eigen.h>

namespace assistive_eval
{
namespace
{
std_msgs::Header header(const std::string& frame, const ros::Time& stamp)
{
  std_msgs::Header h;
  h.stamp = stamp;
  h.frame_id = frame;
  return h;
}

/// An image message of `img` (rows copied; `bytes_per_px` bytes per pixel, one channel).
sensor_msgs::Image imageMsg(const cv::Mat& img, const char* encoding, size_t bytes_per_px, const std::string& frame,
                            const ros::Time& stamp)
{
  sensor_msgs::Image m;
  m.header = header(frame, stamp);
  m.height = img.rows;
  m.width = img.cols;
  m.encoding = encoding;
  m.is_bigendian = 0;
  m.step = static_cast<uint32_t>(img.cols * bytes_per_px);
  m.data.resize(static_cast<size_t>(img.rows) * m.step);
  for (int r = 0; r < img.rows; ++r) std::memcpy(&m.data[static_cast<size_t>(r) * m.step], img.ptr(r), m.step);
  return m;
}
}  // namespace

sensor_msgs::Image toImageMsg(const cv::Mat& img, const std::string& frame, const ros::Time& stamp)
{
  if (img.type() != CV_8UC1) throw std::invalid_argument("toImageMsg: image must be CV_8UC1");
  return imageMsg(img, sensor_msgs::image_encodings::MONO8.c_str(), 1, frame, stamp);
}

sensor_msgs::Image toDepthMsg(const cv::Mat& depth, const std::string& frame, const ros::Time& stamp)
{
  if (depth.type() != CV_32FC1) throw std::invalid_argument("toDepthMsg: depth must be CV_32FC1");
  return imageMsg(depth, sensor_msgs::image_encodings::TYPE_32FC1.c_str(), 4, frame, stamp);
}

sensor_msgs::CameraInfo toCameraInfo(const StereoCalib& c, bool right, const std::string& frame,
                                     const ros::Time& stamp)
{
  sensor_msgs::CameraInfo info;
  info.header = header(frame, stamp);
  info.width = c.width;
  info.height = c.height;
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {c.fx, 0, c.cx, right ? -c.fx * c.baseline : 0.0, 0, c.fy, c.cy, 0, 0, 0, 1, 0};
  return info;
}

StereoCalib fromCameraInfos(const sensor_msgs::CameraInfo& l, const sensor_msgs::CameraInfo* r)
{
  StereoCalib c;
  c.width = l.width;
  c.height = l.height;
  // Rectified images: the projection matrix P holds the intrinsics of the rectified camera.
  const bool has_p = l.P[0] > 0.0;
  c.fx = has_p ? l.P[0] : l.K[0];
  c.fy = has_p ? l.P[5] : l.K[4];
  c.cx = has_p ? l.P[2] : l.K[2];
  c.cy = has_p ? l.P[6] : l.K[5];
  if (r && r->P[0] > 0.0) c.baseline = -r->P[3] / r->P[0];
  return c;
}

sensor_msgs::Imu toMsg(const ImuSample& s, const std::string& frame)
{
  sensor_msgs::Imu m;
  m.header = header(frame, ros::Time(std::max(s.stamp, 1e-9)));
  m.angular_velocity.x = s.gyro.x();
  m.angular_velocity.y = s.gyro.y();
  m.angular_velocity.z = s.gyro.z();
  m.linear_acceleration.x = s.accel.x();
  m.linear_acceleration.y = s.accel.y();
  m.linear_acceleration.z = s.accel.z();
  if (s.has_orientation)
  {
    m.orientation = tf2::toMsg(s.orientation);
  }
  else
  {
    m.orientation.w = 1.0;
    m.orientation_covariance[0] = -1.0;  // orientation unknown (sensor_msgs/Imu convention)
  }
  return m;
}

ImuSample fromMsg(const sensor_msgs::Imu& m)
{
  ImuSample s;
  s.stamp = m.header.stamp.toSec();
  s.gyro = {m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z};
  s.accel = {m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z};
  s.has_orientation = m.orientation_covariance[0] >= 0.0;
  tf2::fromMsg(m.orientation, s.orientation);
  return s;
}

sensor_msgs::Range toRangeMsg(double range, double field_of_view, double min_range, double max_range,
                              const std::string& frame, const ros::Time& stamp)
{
  sensor_msgs::Range m;
  m.header = header(frame, stamp);
  m.radiation_type = sensor_msgs::Range::ULTRASOUND;
  m.field_of_view = static_cast<float>(field_of_view);
  m.min_range = static_cast<float>(min_range);
  m.max_range = static_cast<float>(max_range);
  m.range = static_cast<float>(range);
  return m;
}

}  // namespace assistive_eval
