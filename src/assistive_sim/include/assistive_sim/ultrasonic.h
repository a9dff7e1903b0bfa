#pragma once
// A forward ultrasonic ranger (HC-SR04 class) cast into the world (issue 20): a cone of rays, the
// first surface along each ray (glass is solid to sound), a specular echo model (a surface hit
// beyond max_incidence from its normal sends the echo away: no return), range noise and dropouts.
// The nearest returning ray is the range. ROS-free.
#include <cstdint>
#include <limits>
#include <optional>
#include <random>

#include <Eigen/Geometry>

#include <assistive_sim/world.h>

namespace assistive_sim
{
struct UltrasonicParams
{
  double beam_width = 15.0 * M_PI / 180.0;   ///< rad, full cone angle
  double min_range = 0.2;                    ///< m
  double max_range = 4.0;                    ///< m
  double rate = 20.0;                        ///< Hz
  double max_incidence = 40.0 * M_PI / 180.0;  ///< rad, from the surface normal; beyond: no echo
  double noise_sigma = 0.01;                 ///< m, plus noise_relative * range
  double noise_relative = 0.005;
  double dropout = 0.02;                     ///< probability a ping returns nothing
  int rings = 3;                             ///< rings of rays around the axis (rays: 1 + 8 per ring)
};

/// The first surface a ray meets: distance along the unit direction and the surface normal
/// (facing the ray). Glass panels are solid; the floor (z = 0) counts.
struct RayHit
{
  double t = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  int solid = -1;  ///< index into World::solids, -1 = the floor (or a person)
  int person = -1; ///< index into World::people when a person's body was hit
};
/// `time` (s, personAt's clock): the world's people are bodies at that time too (their cylinders,
/// as rendered); NaN leaves them out (the static world).
std::optional<RayHit> castRay(const World& w, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                              double time = std::numeric_limits<double>::quiet_NaN());

/// camera_link -> sonar_front, as src/assistive_description/urdf/wearer.urdf mounts it (neck_joint
/// to the torso, then the ranger on the chest's front, looking along x). The URDF models the torso
/// as rigid to the head, so the ranger follows the head's pitch and yaw.
inline Eigen::Isometry3d linkToSonar()
{
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(-0.1 + 0.12, -0.06, -0.45 + 0.05);
  return t;
}

class UltrasonicRanger
{
public:
  UltrasonicRanger(const World& world, const UltrasonicParams& p, uint32_t seed);
  /// Noise-free echo range from a sensor pose (x forward along the cone's axis): the nearest ray
  /// whose first surface returns an echo, within [min_range, max_range]; nothing otherwise.
  /// `time` (s): the people are where they are then (NaN: no people; see castRay).
  std::optional<double> idealRange(const Eigen::Isometry3d& sensor,
                                   double time = std::numeric_limits<double>::quiet_NaN()) const;
  /// One ping: idealRange with noise and dropouts (deterministic in the seed).
  std::optional<double> ping(const Eigen::Isometry3d& sensor, double time = std::numeric_limits<double>::quiet_NaN());
  const UltrasonicParams& params() const { return p_; }

private:
  const World& world_;
  UltrasonicParams p_;
  std::mt19937_64 rng_;
};
}  // namespace assistive_sim
