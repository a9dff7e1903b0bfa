#ifndef ASSISTIVE_TACTILE_VEST_GYRO_H
#define ASSISTIVE_TACTILE_VEST_GYRO_H

#include <Eigen/Core>

namespace assistive_tactile
{
/// The torso's turn about the vertical from the vest's IMU (sensor_msgs/Imu on `vest_imu`), for
/// `NavInput::body_yaw_rate`. The vest sits on the torso at whatever tilt the wearer's posture
/// gives it, so the yaw rate is the gyro's rate along the measured "up" (the accelerometer's
/// mean: gravity, the gait's swings averaged out over `up_tau_s`), not its z axis alone.
class VestGyro
{
public:
  explicit VestGyro(double up_tau_s = 1.0, double max_gap_s = 0.5) : up_tau_s_(up_tau_s), max_gap_s_(max_gap_s) {}

  /// One IMU sample at time t (s): rate (rad/s) and specific force (m/s^2) in the vest's frame.
  void add(double t, const Eigen::Vector3d& rate, const Eigen::Vector3d& accel);

  /// The mean yaw rate (rad/s, + = left) since the last take, over `now - last`: the turn the
  /// samples carry divided by the time since the last take. NaN when no sample came within
  /// `max_gap_s` of now or the samples have gaps longer than that (no gyro: the caller falls back
  /// to the head) or no "up" is known yet.
  double take(double now);

private:
  double up_tau_s_, max_gap_s_;
  Eigen::Vector3d up_ = Eigen::Vector3d::Zero();
  bool have_up_ = false;
  double last_sample_ = -1e300;
  double turn_ = 0.0;       ///< rad about up since the last take
  bool gap_ = true;         ///< a gap in the samples since the last take
  double last_take_ = -1e300;
};

}  // namespace assistive_tactile

#endif
