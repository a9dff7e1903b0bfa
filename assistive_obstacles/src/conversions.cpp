#include <assistive_obstacles/conversions.h>

#include <cstdint>
#include "assistive_obstacles/cell_values.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

namespace assistive_obstacles
{
bool fromMsg(const sensor_msgs::CameraInfo& l, const sensor_msgs::CameraInfo& r, StereoModel& m)
{
  const double fx = l.P[0], fy = l.P[5];
  if (!(fx > 0.0) || !(fy > 0.0) || l.width == 0 || l.height == 0 || l.width != r.width || l.height != r.height)
    return false;
  const double b = -r.P[3] / r.P[0];
  if (!(b > 0.0) || !std::isfinite(b)) return false;
  m.width = static_cast<int>(l.width);
  m.height = static_cast<int>(l.height);
  m.fx = fx;
  m.fy = fy;
  m.cx = l.P[2];
  m.cy = l.P[6];
  m.baseline = b;
  return true;
}

stereo_msgs::DisparityImage toDisparityMsg(const cv::Mat& disp, const StereoModel& model, int nd,
                                           const std_msgs::Header& header)
{
  stereo_msgs::DisparityImage d;
  d.header = header;
  const double s = model.width > 0 ? static_cast<double>(disp.cols) / model.width : 1.0;
  d.f = static_cast<float>(model.fx * s);
  d.T = static_cast<float>(model.baseline);
  d.min_disparity = 0.f;
  d.max_disparity = static_cast<float>(nd - 1);
  d.delta_d = 1.f / 16.f;
  d.valid_window.x_offset = 0;
  d.valid_window.y_offset = 0;
  d.valid_window.width = static_cast<uint32_t>(disp.cols);
  d.valid_window.height = static_cast<uint32_t>(disp.rows);
  cv_bridge::CvImage img(header, sensor_msgs::image_encodings::TYPE_32FC1, disp);
  img.toImageMsg(d.image);
  return d;
}

sensor_msgs::PointCloud2 toCloudMsg(const std::vector<Eigen::Vector3f>& pts, const std_msgs::Header& header)
{
  sensor_msgs::PointCloud2 c;
  c.header = header;
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2FieldsByString(1, "xyz");
  mod.resize(pts.size());
  c.height = 1;
  c.width = static_cast<uint32_t>(pts.size());
  c.is_dense = true;
  sensor_msgs::PointCloud2Iterator<float> x(c, "x"), y(c, "y"), z(c, "z");
  for (const auto& p : pts)
  {
    *x = p.x();
    *y = p.y();
    *z = p.z();
    ++x;
    ++y;
    ++z;
  }
  return c;
}

std::vector<Eigen::Vector3f> fromCloudMsg(const sensor_msgs::PointCloud2& c)
{
  std::vector<Eigen::Vector3f> out;
  out.reserve(static_cast<size_t>(c.width) * c.height);
  sensor_msgs::PointCloud2ConstIterator<float> x(c, "x"), y(c, "y"), z(c, "z");
  for (; x != x.end(); ++x, ++y, ++z) out.emplace_back(*x, *y, *z);
  return out;
}

visualization_msgs::MarkerArray toMarkers(const std::vector<Eigen::Vector3f>& centers, const std::vector<float>& sizes,
                                          const std::string& frame, const ros::Time& stamp)
{
  visualization_msgs::MarkerArray arr;
  std::map<int, size_t> by_size;  // leaf size in mm -> marker index
  float zmin = 0.f, zmax = 2.f;
  for (size_t i = 0; i < centers.size(); ++i)
  {
    const int key = static_cast<int>(std::lround(sizes[i] * 1000.f));
    auto it = by_size.find(key);
    if (it == by_size.end())
    {
      visualization_msgs::Marker m;
      m.header.frame_id = frame;
      m.header.stamp = stamp;
      m.ns = "octomap";
      m.id = static_cast<int>(arr.markers.size());
      m.type = visualization_msgs::Marker::CUBE_LIST;
      m.action = visualization_msgs::Marker::ADD;
      m.pose.orientation.w = 1.0;
      m.scale.x = m.scale.y = m.scale.z = sizes[i];
      m.color.a = 1.0f;
      arr.markers.push_back(m);
      it = by_size.emplace(key, arr.markers.size() - 1).first;
    }
    visualization_msgs::Marker& m = arr.markers[it->second];
    geometry_msgs::Point p;
    p.x = centers[i].x();
    p.y = centers[i].y();
    p.z = centers[i].z();
    m.points.push_back(p);
    const float t = std::min(1.f, std::max(0.f, (centers[i].z() - zmin) / (zmax - zmin)));
    std_msgs::ColorRGBA c;
    c.r = t;
    c.g = 1.f - std::abs(2.f * t - 1.f);
    c.b = 1.f - t;
    c.a = 1.f;
    m.colors.push_back(c);
  }
  return arr;
}

assistive_msgs::MoverArray toMoverArray(const std::vector<ReportedMover>& movers, double floor_z,
                                        const std::string& frame, const ros::Time& stamp)
{
  assistive_msgs::MoverArray a;
  a.header.frame_id = frame;
  a.header.stamp = stamp;
  for (const ReportedMover& r : movers)
  {
    assistive_msgs::Mover m;
    m.id = static_cast<uint32_t>(r.track.id);
    m.position.x = r.track.x(0);
    m.position.y = r.track.x(1);
    m.position.z = floor_z;
    m.velocity.x = r.track.x(2);
    m.velocity.y = r.track.x(3);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) m.covariance[static_cast<size_t>(4 * i + j)] = r.track.P(i, j);
    m.radius = static_cast<float>(r.radius);
    m.height = static_cast<float>(r.height);
    a.movers.push_back(m);
  }
  return a;
}

visualization_msgs::MarkerArray toMoverMarkers(const std::vector<ReportedMover>& movers, double floor_z, double horizon,
                                               const std::string& frame, const ros::Time& stamp)
{
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker clear;
  clear.header.frame_id = frame;
  clear.header.stamp = stamp;
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);
  for (const ReportedMover& r : movers)
  {
    const double h = r.height > 0.0 ? r.height : 1.7;
    visualization_msgs::Marker base;
    base.header = clear.header;
    base.id = r.track.id;
    base.action = visualization_msgs::Marker::ADD;
    base.pose.orientation.w = 1.0;
    base.color.r = 1.0f;  // magenta: apart from the octomap's height colours and the orange path
    base.color.b = 1.0f;
    base.color.a = 0.8f;
    visualization_msgs::Marker c = base;
    c.ns = "movers";
    c.type = visualization_msgs::Marker::CYLINDER;
    c.pose.position.x = r.track.x(0);
    c.pose.position.y = r.track.x(1);
    c.pose.position.z = floor_z + 0.5 * h;
    c.scale.x = c.scale.y = 2.0 * std::max(0.05, r.radius);
    c.scale.z = h;
    c.color.a = 0.5f;
    out.markers.push_back(c);
    visualization_msgs::Marker v = base;
    v.ns = "mover_velocity";
    v.type = visualization_msgs::Marker::ARROW;
    v.scale.x = 0.05;  // shaft diameter
    v.scale.y = 0.1;   // head diameter
    v.scale.z = 0.1;
    geometry_msgs::Point p0, p1;
    p0.x = r.track.x(0);
    p0.y = r.track.x(1);
    p0.z = p1.z = floor_z + 1.0;
    p1.x = p0.x + r.track.x(2);
    p1.y = p0.y + r.track.x(3);
    v.points = {p0, p1};
    out.markers.push_back(v);
    visualization_msgs::Marker path = base;
    path.ns = "mover_path";
    path.type = visualization_msgs::Marker::LINE_STRIP;
    path.scale.x = 0.03;
    for (int k = 0; k <= 6; ++k)
    {
      const double t = horizon * k / 6.0;
      geometry_msgs::Point q;
      q.x = r.track.x(0) + r.track.x(2) * t;
      q.y = r.track.x(1) + r.track.x(3) * t;
      q.z = floor_z + 0.05;
      path.points.push_back(q);
    }
    out.markers.push_back(path);
  }
  return out;
}

}  // namespace assistive_obstacles
