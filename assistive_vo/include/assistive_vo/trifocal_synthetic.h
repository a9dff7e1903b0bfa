#pragma once
// Synthetic four-view data for the trifocal solvers (seed 2.3.1: baseline 7.5 cm, a random stereo
// pair displaced by a random motion, random 3D points and lines projected into the four cameras,
// Gaussian noise on the image coordinates). Shared by the gtests and pointline_benchmark.
// ROS-free, header only.
#include <cmath>
#include <random>
#include <Eigen/Geometry>
#include "assistive_vo/trifocal_solver.h"

namespace assistive_vo
{
struct TrifocalSceneOptions
{
  double baseline = 0.075;      ///< m (the seed's simulations)
  bool random_rig = false;      ///< false: rectified (R0 = I, t0 = (-b, 0, 0)); true: R0 up to 5 deg, t0 any direction
  double focal = 500.0;         ///< px, for the noise and the field of view
  double half_width = 320.0;    ///< px: the image is 640 x 480
  double half_height = 240.0;   ///< px
  double depth_min = 1.0;       ///< m (view 1)
  double depth_max = 6.0;       ///< m
  double max_rotation_deg = 15; ///< random motion: angle up to this about a random axis
  double max_translation = 0.5; ///< m, uniform in a ball
  double noise_px = 0.0;        ///< Gaussian sigma on every image coordinate
  double min_plane_angle_deg = 10; ///< lines: views 1 and 2 back-project to planes at least this far apart
};

struct TrifocalScene
{
  StereoRig rig;
  StereoMotion motion;
  PointQuads points;
  LineQuads lines;
};

namespace synthetic_detail
{
inline Eigen::Matrix3d randomRotation(std::mt19937& rng, double max_deg)
{
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::Vector3d axis(n(rng), n(rng), n(rng));
  axis.normalize();
  return Eigen::AngleAxisd(u(rng) * max_deg * M_PI / 180.0, axis).toRotationMatrix();
}

/// Camera i's coordinates of a view-1 point.
inline Eigen::Vector3d inView(const TrifocalScene& s, int v, const Eigen::Vector3d& X)
{
  switch (v)
  {
    case 0:
      return X;
    case 1:
      return s.rig.R0 * X + s.rig.t0;
    case 2:
      return s.motion.R * X + s.motion.t;
    default:
      return s.rig.R0 * (s.motion.R * X + s.motion.t) + s.rig.t0;
  }
}

inline bool visible(const TrifocalScene& s, const TrifocalSceneOptions& o, const Eigen::Vector3d& X,
                    Eigen::Vector2d x[4])
{
  for (int v = 0; v < 4; ++v)
  {
    const Eigen::Vector3d c = inView(s, v, X);
    if (c.z() < 0.3)
      return false;
    x[v] = c.head<2>() / c.z();
    if (std::abs(x[v].x()) * o.focal > o.half_width || std::abs(x[v].y()) * o.focal > o.half_height)
      return false;
  }
  return true;
}

inline Eigen::Vector3d randomPoint(std::mt19937& rng, const TrifocalSceneOptions& o)
{
  std::uniform_real_distribution<double> z(o.depth_min, o.depth_max), u(-1, 1);
  const double d = z(rng);
  return Eigen::Vector3d(u(rng) * d * o.half_width / o.focal, u(rng) * d * o.half_height / o.focal, d);
}
}  // namespace synthetic_detail

/// A random scene with `n_points` points and `n_lines` lines visible in all four views. Exact
/// observations when o.noise_px == 0. The segments of views 2-4 cover different parts of the
/// 3D line than view 1's (lines are not point correspondences).
inline TrifocalScene makeTrifocalScene(std::mt19937& rng, int n_points, int n_lines, const TrifocalSceneOptions& o)
{
  using namespace synthetic_detail;
  TrifocalScene s;
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  if (o.random_rig)
  {
    s.rig.R0 = randomRotation(rng, 5.0);
    Eigen::Vector3d dir(-1.0 + 0.2 * n(rng), 0.2 * n(rng), 0.2 * n(rng));
    s.rig.t0 = o.baseline * dir.normalized();
  }
  else
  {
    s.rig.R0.setIdentity();
    s.rig.t0 = Eigen::Vector3d(-o.baseline, 0, 0);
  }
  // a motion that keeps a reasonable share of the view-1 frustum visible
  for (int attempt = 0; attempt < 1000; ++attempt)
  {
    s.motion.R = randomRotation(rng, o.max_rotation_deg);
    Eigen::Vector3d t;
    do
      t = Eigen::Vector3d(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1);
    while (t.norm() > 1.0);
    s.motion.t = o.max_translation * t;
    if (s.motion.t.norm() < 0.05 * o.max_translation)
      continue;
    int ok = 0;
    Eigen::Vector2d x[4];
    for (int i = 0; i < 50; ++i)
      ok += visible(s, o, randomPoint(rng, o), x) ? 1 : 0;
    if (ok >= 10)
      break;
  }
  std::normal_distribution<double> noise(0.0, o.noise_px / o.focal);
  auto jitter = [&](Eigen::Vector2d& v) {
    if (o.noise_px > 0)
      v += Eigen::Vector2d(noise(rng), noise(rng));
  };
  for (int guard = 0; static_cast<int>(s.points.size()) < n_points && guard < 100000; ++guard)
  {
    PointQuad q;
    if (!visible(s, o, randomPoint(rng, o), q.x))
      continue;
    for (auto& v : q.x)
      jitter(v);
    s.points.push_back(q);
  }
  for (int guard = 0; static_cast<int>(s.lines.size()) < n_lines && guard < 100000; ++guard)
  {
    const Eigen::Vector3d A = randomPoint(rng, o), B = randomPoint(rng, o);
    if ((A - B).norm() < 0.5)
      continue;
    Eigen::Vector2d xa[4], xb[4];
    if (!visible(s, o, A, xa) || !visible(s, o, B, xb))
      continue;
    // planes of views 1 and 2 apart (a line in the epipolar plane cannot be triangulated)
    const Eigen::Vector3d n1 = A.cross(B).normalized();
    const Eigen::Vector3d C2 = -s.rig.R0.transpose() * s.rig.t0;  // right camera centre
    const Eigen::Vector3d n2 = (A - C2).cross(B - C2).normalized();
    if (std::abs(n1.dot(n2)) > std::cos(o.min_plane_angle_deg * M_PI / 180.0))
      continue;
    LineQuad l;
    l.p[0] = xa[0];
    l.q[0] = xb[0];
    bool ok = true;
    for (int v = 1; v < 4 && ok; ++v)
    {
      // another part of the same 3D line
      const Eigen::Vector3d P = A + (0.3 * u(rng)) * (B - A), Q = A + (0.7 + 0.3 * u(rng)) * (B - A);
      Eigen::Vector2d xp[4], xq[4];
      ok = visible(s, o, P, xp) && visible(s, o, Q, xq);
      l.p[v] = xp[v];
      l.q[v] = xq[v];
      ok = ok && (l.p[v] - l.q[v]).norm() * o.focal > 20.0;
    }
    if (!ok || (l.p[0] - l.q[0]).norm() * o.focal < 20.0)
      continue;
    for (int v = 0; v < 4; ++v)
    {
      jitter(l.p[v]);
      jitter(l.q[v]);
    }
    s.lines.push_back(l);
  }
  return s;
}

/// Rotation error (deg) and translation error (relative to |t|, %) of a hypothesis.
inline double rotationErrorDeg(const Eigen::Matrix3d& R_est, const Eigen::Matrix3d& R_true)
{
  const double c = std::max(-1.0, std::min(1.0, ((R_est * R_true.transpose()).trace() - 1.0) / 2.0));
  return std::acos(c) * 180.0 / M_PI;
}
inline double translationErrorPct(const Eigen::Vector3d& t_est, const Eigen::Vector3d& t_true)
{
  return 100.0 * (t_est - t_true).norm() / std::max(t_true.norm(), 1e-12);
}

}  // namespace assistive_vo
