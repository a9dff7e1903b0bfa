#pragma once
#include <Eigen/Core>

namespace assistive_vo
{
/// Rectified stereo pinhole model: left camera is the reference, right = left + baseline along +x
/// of the left optical frame (so u_right = u_left - d, d = fx * baseline / Z).
struct StereoCamera
{
  double fx = 0, fy = 0, cx = 0, cy = 0, baseline = 0;
  int width = 0, height = 0;

  bool valid() const
  {
    return fx > 0 && fy > 0 && baseline > 0 && width > 0 && height > 0 && cx > 0 && cy > 0;
  }
  /// 3D point (left optical frame) from pixel and disparity, eq. 2.22.
  Eigen::Vector3d triangulate(double u, double v, double d) const
  {
    const double z = fx * baseline / d;
    return Eigen::Vector3d((u - cx) * z / fx, (v - cy) * z / fy, z);
  }
  Eigen::Vector2d projectLeft(const Eigen::Vector3d& p) const
  {
    return Eigen::Vector2d(fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy);
  }
  double projectRightU(const Eigen::Vector3d& p) const
  {
    return fx * (p.x() - baseline) / p.z() + cx;
  }
  Eigen::Vector3d bearing(double u, double v) const
  {
    return Eigen::Vector3d((u - cx) / fx, (v - cy) / fy, 1.0).normalized();
  }
  /// From any calibration record with the same field names (e.g. assistive_eval::StereoCalib, as
  /// read from bags and datasets) without depending on its package.
  template <class Calib>
  static StereoCamera from(const Calib& c)
  {
    StereoCamera cam;
    cam.fx = c.fx;
    cam.fy = c.fy;
    cam.cx = c.cx;
    cam.cy = c.cy;
    cam.baseline = c.baseline;
    cam.width = c.width;
    cam.height = c.height;
    return cam;
  }
};
}  // namespace assistive_vo
