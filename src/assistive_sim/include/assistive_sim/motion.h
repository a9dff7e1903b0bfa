#pragma once
// The simulated wearer: a C2 walk along the world's waypoint script (arc-length parametrised
// cubic B-spline, smooth speed profile), gait bob and sway, head yaw scans, pitch down, scripted
// and seeded head turns; and an IMU derived from that motion. ROS-free.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include <assistive_sim/types.h>
#include <assistive_sim/world.h>

namespace assistive_sim
{
class WearerMotion
{
public:
  /// `seed` chooses the automatic head turns and phases.
  WearerMotion(const TrajectoryScript& script, uint32_t seed);

  /// Time (s) at which the walk reaches the last waypoint.
  double duration() const { return t_end_; }
  /// Pose of camera_link (x forward, y left, z up) in the world at time t (s, 0 = start).
  Eigen::Isometry3d linkPose(double t) const;
  /// Pose of the left optical frame in the world (= linkPose * linkToLeftOptical()).
  Eigen::Isometry3d leftOpticalPose(double t) const { return linkPose(t) * linkToLeftOptical(); }
  /// Velocity / acceleration of camera_link's origin in the world (m/s, m/s^2).
  Eigen::Vector3d velocity(double t) const;
  Eigen::Vector3d acceleration(double t) const;
  /// Angular velocity of camera_link, expressed in camera_link (rad/s).
  Eigen::Vector3d angularVelocity(double t) const;
  /// Noise-free IMU reading (gyro, specific force in camera_link; +9.81 z when level at rest).
  ImuSample idealImu(double t) const;

  /// Distance walked at time t (m) and the walking speed (m/s).
  double distance(double t) const;
  double speed(double t) const;
  /// Total path length (m) and the path's floor point at arc length s.
  double pathLength() const { return length_; }
  Eigen::Vector2d pathPoint(double s) const;
  /// Head turns in effect (scripted + automatic), times relative to t = 0.
  const std::vector<HeadTurn>& headTurns() const { return turns_; }

private:
  /// One stretch walked without stopping: a B-spline through its waypoints, then (unless it is the
  /// last) a stop and a turn on the spot towards the next leg.
  struct Leg
  {
    std::vector<Eigen::Vector2d> ctrl;  ///< B-spline control points
    std::vector<double> span_s;         ///< arc length at the start of each span
    double length = 0.0;
    double heading_in = 0.0, heading_out = 0.0;  ///< rad, tangent at the start / end
    double s0 = 0.0;       ///< distance walked before this leg
    double t0 = 0.0;       ///< s, the leg starts moving
    double t1 = 0.0;       ///< s, the leg reaches its end point
    double t_ramp = 1.5;   ///< s, acceleration (and deceleration) time
    double t_cruise = 0.0; ///< s, cruise time of a leg that stops
    bool stops = false;    ///< ends in a stop and a turn on the spot
    double turn = 0.0, turn_at = 0.0, turn_duration = 0.0;  ///< rad, s, s
  };
  static Leg buildLeg(const std::vector<Eigen::Vector2d>& poly, double corner_radius);
  static Eigen::Vector2d spline(const Leg& leg, double u, int deriv);
  static double uOfS(const Leg& leg, double s);
  static double spanLength(const Leg& leg, int j, double u0, double u1);
  double legDistance(const Leg& leg, double tau) const;
  size_t legAt(double t) const;
  double headYawOffset(double t) const;

  TrajectoryScript script_;
  std::vector<Leg> legs_;
  double length_ = 0.0;
  double t_walk_ = 0.0;  ///< walking starts
  double t_ramp_ = 1.5;  ///< acceleration phase
  double t_end_ = 0.0;
  double phase_pitch_ = 0.0, phase_scan_ = 0.0;
  std::vector<HeadTurn> turns_;
};

/// IMU noise model (defaults: EuRoC's ADIS16448 figures).
struct ImuParams
{
  double rate = 200.0;                      ///< Hz
  double gyro_noise_density = 1.7e-4;       ///< rad/s/sqrt(Hz)
  double accel_noise_density = 2.0e-3;      ///< m/s^2/sqrt(Hz)
  double gyro_bias_walk = 1.9e-5;           ///< rad/s^2/sqrt(Hz)
  double accel_bias_walk = 3.0e-3;          ///< m/s^3/sqrt(Hz)
  double gyro_bias_initial = 3.0e-3;        ///< rad/s, sigma per axis
  double accel_bias_initial = 5.0e-2;       ///< m/s^2, sigma per axis
};

/// Noisy, biased IMU samples at a fixed rate from a WearerMotion (deterministic in the seed).
class ImuSimulator
{
public:
  ImuSimulator(const ImuParams& p, uint32_t seed);
  /// Next sample (stamps 0, 1/rate, 2/rate, ...; `t0` is added to the stamp). `motion_time` >= 0
  /// reads the motion at that time instead of the sample's own (a looping online walk).
  ImuSample next(const WearerMotion& motion, double t0 = 0.0, double motion_time = -1.0);
  /// Time of the next sample (relative).
  double nextTime() const { return k_ / p_.rate; }
  /// Skip samples so the next one is the first at or after time t (s).
  void skipTo(double t) { k_ = std::max<uint64_t>(k_, static_cast<uint64_t>(std::ceil(t * p_.rate))); }
  const Eigen::Vector3d& gyroBias() const { return bg_; }
  const Eigen::Vector3d& accelBias() const { return ba_; }

private:
  ImuParams p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> n_{0.0, 1.0};
  Eigen::Vector3d bg_, ba_;
  uint64_t k_ = 0;
};

}  // namespace assistive_sim
