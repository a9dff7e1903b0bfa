#pragma once
// Synthetic data for the core tests: random 3D points seen by a stereo rig with a known motion,
// and a tiny ray caster rendering textured planes (a wall and a floor) into rectified stereo pairs.
#include <random>
#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>
#include "assistive_vo/p3p_ransac.h"
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
namespace test
{
inline StereoCamera makeCamera()
{
  StereoCamera c;
  c.fx = c.fy = 500.0;
  c.cx = 319.5;
  c.cy = 239.5;
  c.baseline = 0.12;
  c.width = 640;
  c.height = 480;
  return c;
}

inline Eigen::Isometry3d makePose(double rx, double ry, double rz, double tx, double ty, double tz)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(tx, ty, tz);
  return T;
}

/// Points in the reference frame, visible in both frames (inside the image, in front).
inline Vec3List randomVisiblePoints(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur, int n,
                                    std::mt19937& rng)
{
  std::uniform_real_distribution<double> ux(-4, 4), uy(-3, 3), uz(2, 15);
  Vec3List out;
  const Eigen::Isometry3d T_cur_ref = T_ref_cur.inverse();
  while (static_cast<int>(out.size()) < n)
  {
    const Eigen::Vector3d X(ux(rng), uy(rng), uz(rng));
    const Eigen::Vector3d Xc = T_cur_ref * X;
    if (Xc.z() < 1.0)
      continue;
    const Eigen::Vector2d a = cam.projectLeft(X), b = cam.projectLeft(Xc);
    if (a.x() < 0 || a.y() < 0 || a.x() >= cam.width || a.y() >= cam.height || b.x() < 0 || b.y() < 0 ||
        b.x() >= cam.width || b.y() >= cam.height)
      continue;
    out.push_back(X);
  }
  return out;
}

/// Smooth random texture (blob-like), values 0..255, CV_8UC1, size n x n.
inline cv::Mat randomTexture(int n, unsigned seed)
{
  cv::Mat t(n, n, CV_32F);
  cv::RNG rng(seed);
  rng.fill(t, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::Mat s1, s2;
  cv::GaussianBlur(t, s1, cv::Size(0, 0), 1.5);
  cv::GaussianBlur(t, s2, cv::Size(0, 0), 6.0);
  cv::Mat m = s1 * 0.6 + s2 * 0.4;
  cv::normalize(m, m, 0, 255, cv::NORM_MINMAX);
  cv::Mat out;
  m.convertTo(out, CV_8U);
  return out;
}

/// A wall at world z = wall_z (optical frame of the first camera: z forward) and a floor at
/// world y = floor_y (y down), both textured at `res` m/texel. Renders the left or right image of
/// a camera whose left optical frame has pose T_w_c.
struct PlaneWorld
{
  double wall_z = 6.0, floor_y = 1.5, res = 0.01;
  cv::Mat wall_tex = randomTexture(1600, 1), floor_tex = randomTexture(1600, 2);

  cv::Mat render(const StereoCamera& cam, const Eigen::Isometry3d& T_w_c, bool right) const
  {
    return renderRows(cam, [&T_w_c](int) { return T_w_c; }, right);
  }

  /// A rolling shutter: image row v seen from the pose `pose_of_row(v)` (the pose at its exposure).
  template <class PoseOfRow>
  cv::Mat renderRows(const StereoCamera& cam, const PoseOfRow& pose_of_row, bool right) const
  {
    cv::Mat mx_w(cam.height, cam.width, CV_32F), my_w(cam.height, cam.width, CV_32F);
    cv::Mat mx_f(cam.height, cam.width, CV_32F), my_f(cam.height, cam.width, CV_32F);
    cv::Mat use_wall(cam.height, cam.width, CV_8U);
    const double half = wall_tex.cols * res / 2;
    for (int v = 0; v < cam.height; ++v)
    {
      const Eigen::Isometry3d T_w_c = pose_of_row(v);
      const Eigen::Matrix3d R = T_w_c.linear();
      const Eigen::Vector3d o = T_w_c * Eigen::Vector3d(right ? cam.baseline : 0.0, 0, 0);
      for (int u = 0; u < cam.width; ++u)
      {
        const Eigen::Vector3d d = R * Eigen::Vector3d((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
        double sw = d.z() > 1e-9 ? (wall_z - o.z()) / d.z() : 1e9;
        double sf = d.y() > 1e-9 ? (floor_y - o.y()) / d.y() : 1e9;
        if (sw <= 0) sw = 1e9;
        if (sf <= 0) sf = 1e9;
        const bool wall = sw < sf;
        use_wall.at<uint8_t>(v, u) = wall;
        const Eigen::Vector3d p = o + (wall ? sw : sf) * d;
        mx_w.at<float>(v, u) = static_cast<float>((p.x() + half) / res);
        my_w.at<float>(v, u) = static_cast<float>((p.y() + half) / res);
        mx_f.at<float>(v, u) = static_cast<float>((p.x() + half) / res);
        my_f.at<float>(v, u) = static_cast<float>((p.z() + 2.0) / res);
      }
    }
    cv::Mat a, b;
    cv::remap(wall_tex, a, mx_w, my_w, cv::INTER_LINEAR, cv::BORDER_REFLECT);
    cv::remap(floor_tex, b, mx_f, my_f, cv::INTER_LINEAR, cv::BORDER_REFLECT);
    b.copyTo(a, use_wall == 0);
    return a;
  }
};
}  // namespace test
}  // namespace assistive_vo
