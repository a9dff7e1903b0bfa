#pragma once
// Hand-built world point sets for the core tests (world frame: x/y ground plane, z up, floor z = 0).
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

namespace synthetic
{
using Points = std::vector<Eigen::Vector3f>;

/// Horizontal patch [x0,x1) x [y0,y1) at height z, `per_cell` points per 0.2 m cell (grid jittered).
inline void patch(Points& p, double x0, double x1, double y0, double y1, double z, int per_side = 5,
                  double noise = 0.0, unsigned seed = 1)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise > 0 ? noise : 1e-9);
  const double step = 0.2 / per_side;
  for (double x = x0 + step / 2; x < x1; x += step)
    for (double y = y0 + step / 2; y < y1; y += step)
      p.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z + (noise > 0 ? n(rng) : 0.0)));
}

/// Vertical wall along y at x, from y0 to y1, heights z0..z1.
inline void wallX(Points& p, double x, double y0, double y1, double z0, double z1, double step = 0.04)
{
  for (double y = y0 + step / 2; y < y1; y += step)
    for (double z = z0; z <= z1 + 1e-9; z += step)
      p.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
}

/// Thin vertical pole at (x, y), radius r, heights 0..h.
inline void pole(Points& p, double x, double y, double r, double h, double step = 0.03)
{
  for (double z = step; z <= h; z += step)
    for (int k = 0; k < 4; ++k)
    {
      const double a = k * M_PI / 2;
      p.emplace_back(static_cast<float>(x + r * std::cos(a)), static_cast<float>(y + r * std::sin(a)), static_cast<float>(z));
    }
}

/// Camera pose for tests: camera at (x, y, z) looking along +x (optical z = world x,
/// optical x = world -y, optical y = world -z).
inline Eigen::Isometry3f cameraAt(double x, double y, double z)
{
  Eigen::Matrix3f r;
  r << 0, 0, 1,
      -1, 0, 0,
       0, -1, 0;
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.linear() = r;
  t.translation() = Eigen::Vector3f(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  return t;
}

/// World points -> camera frame for pose `T_world_cam`.
inline Points toCamera(const Points& world, const Eigen::Isometry3f& T_world_cam)
{
  Points out;
  out.reserve(world.size());
  const Eigen::Isometry3f inv = T_world_cam.inverse();
  for (const auto& w : world) out.push_back(inv * w);
  return out;
}
}  // namespace synthetic
