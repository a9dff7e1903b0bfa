#pragma once
// Standing still known from the IMU: no gait in the accelerometer. A zero-velocity detector of the
// kind pedestrian inertial navigation uses (Skog, Haendel, Nilsson, Rantakokko, "Zero-velocity
// detection - an algorithm evaluation", IEEE TBME 57(11), 2010: the acceleration-moving-variance
// detector, a likelihood ratio test of "stationary" against "moving" over a window of samples).
// Head-mounted, not foot-mounted: a walking head bobs with every step (vertical, 2-4 m/s^2 at a
// normal pace), a head that only turns on the spot does not. The angular-rate energy detector
// (their best) is not usable here: turning on the spot is exactly what must count as standing.
#include <deque>
#include <Eigen/Core>

namespace assistive_vo
{
class StandingDetector
{
public:
  struct Options
  {
    double window_s = 0.8;          ///< longer than one step at the slowest pace (0.72 s at 0.9 m/s)
    double max_accel_sigma = 0.25;  ///< m/s^2: rms deviation of the specific force from its window mean
  };
  StandingDetector() = default;
  explicit StandingDetector(const Options& o) : o_(o) {}
  void setOptions(const Options& o) { o_ = o; }
  void clear() { s_.clear(); }
  /// The mean specific force over one frame interval [stamp - dt, stamp] (the accelerometer's
  /// integral over it / dt), in the gravity-aligned odom axes (so a head that only turns does not
  /// turn gravity through it). An older stamp restarts the window.
  void add(double stamp, double dt, const Eigen::Vector3d& f_odom);
  /// Rms deviation of the specific force from its mean over the window (m/s^2); -1 while the
  /// samples do not span window_s.
  double statistic() const;
  /// The same over the samples there are, however short their span (-1: none): what a hold carried
  /// over a gap goes on with while the window refills.
  double partialStatistic() const;
  /// The same over the samples of the window whose interval starts at or after `t0` (-1: none):
  /// a hold that started at t0 (a stop) goes on while what came since shows no gait, before the
  /// window has cleared the deceleration that came before it.
  double statisticSince(double t0) const;
  /// No gait over a full window: statistic() within max_accel_sigma.
  bool quiet() const
  {
    const double t = statistic();
    return t >= 0.0 && t <= o_.max_accel_sigma;
  }

private:
  struct Sample
  {
    double t, dt;
    Eigen::Vector3d f;
  };
  Options o_;
  std::deque<Sample> s_;
};
}  // namespace assistive_vo
