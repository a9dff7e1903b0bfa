#ifndef ASSISTIVE_TACTILE_VEST_GYRO_H
#define ASSISTIVE_TACTILE_VEST_GYRO_H

#include <array>
#include <cmath>
#include <string>

#include <Eigen/Core>

namespace assistive_tactile
{
/// The torso's turn about the vertical from the vest's IMU (sensor_msgs/Imu on `vest_imu`), for
/// `NavInput::body_yaw_rate`. The vest sits on the torso at whatever tilt the wearer's posture
/// gives it, so the yaw rate is the gyro's rate along the measured "up" (the accelerometer's
/// mean: gravity, the gait's swings averaged out over `up_tau_s`), not its z axis alone.
///
/// Its offset is captured whenever the vest is still: over any `still_window_s` of samples (the
/// window sliding by a quarter of it), an accelerometer steady within `kStillAccelSd` (no step: a
/// gait shakes it by metres per s^2) and a yaw rate steady within `kStillRateSd` and under
/// `kMaxOffset` (no turn on the spot, which takes steps) make the window's mean rate the offset,
/// taken out of every rate after. An MPU-6050's offset is up to +-20 deg/s at power-up
/// (datasheet), where the cue logic learns only what is left within 2 deg/s standing; a 3 deg/s
/// sigma left to it took trials on homes from 0.2 to 0.9 collisions a trial.
class VestGyro
{
public:
  static constexpr double kStillAccelSd = 0.15;               ///< m/s^2 (standing sway: about 0.05)
  static constexpr double kStillRateSd = 1.0 * M_PI / 180.0;  ///< rad/s
  static constexpr double kMaxOffset = 25.0 * M_PI / 180.0;   ///< rad/s (the MPU-6050's +-20, and some)

  explicit VestGyro(double up_tau_s = 1.0, double max_gap_s = 0.5, double still_window_s = 1.0)
    : up_tau_s_(up_tau_s), max_gap_s_(max_gap_s), still_window_s_(still_window_s)
  {
  }

  /// One IMU sample at time t (s): rate (rad/s) and specific force (m/s^2) in the vest's frame.
  void add(double t, const Eigen::Vector3d& rate, const Eigen::Vector3d& accel);

  /// The mean yaw rate (rad/s, + = left) since the last take, over `now - last`: the turn the
  /// samples carry, less the offset, divided by the time since the last take. NaN when no sample
  /// came within `max_gap_s` of now or the samples have gaps longer than that (no gyro: the caller
  /// falls back to the head) or no "up" is known yet.
  double take(double now);

  /// The offset taken out (rad/s about up) and how many still windows set it.
  double offset() const { return offset_; }
  int offsetCaptures() const { return captures_; }
  /// Start from an offset kept from an earlier run (`loadOffset`), until a still second captures
  /// one; ignored beyond `kMaxOffset` or not finite.
  void setOffset(double offset)
  {
    if (std::isfinite(offset) && std::fabs(offset) < kMaxOffset)
      offset_ = offset;
  }

private:
  /// Time-weighted sums over samples: time, rate, rate^2, |accel|, |accel|^2.
  struct Sums
  {
    double t = 0.0, r = 0.0, rr = 0.0, a = 0.0, aa = 0.0;
    void add(double rate_up, double accel_norm, double dt);
    Sums& operator+=(const Sums& o);
  };
  /// The window slides by a quarter: a still second is found wherever it begins.
  static constexpr int kStillParts = 4;

  void watchStill(double rate_up, double accel_norm, double dt);

  double up_tau_s_, max_gap_s_, still_window_s_;
  double offset_ = 0.0;
  int captures_ = 0;
  Sums part_;                          ///< the quarter of a window being filled
  std::array<Sums, kStillParts> parts_;  ///< the last quarters, oldest overwritten
  int parts_filled_ = 0, next_part_ = 0;
  Eigen::Vector3d up_ = Eigen::Vector3d::Zero();
  bool have_up_ = false;
  double last_sample_ = -1e300;
  double turn_ = 0.0;       ///< rad about up since the last take
  bool gap_ = true;         ///< a gap in the samples since the last take
  double last_take_ = -1e300;
};

/// The vest gyro's offset kept across runs, so a vest walked on before its first still second does
/// not start from zero (an MPU-6050's offset spreads +-20 deg/s over parts and temperatures; the
/// same part's at body temperature is likely far nearer its last value: not measured here): a file
/// with a line `offset_rad_s: X`. false with `why`: no file, unreadable, or an offset beyond
/// `VestGyro::kMaxOffset`.
bool loadOffset(const std::string& path, double* offset, std::string* why);
/// Writes it (replacing the file); false with `why`.
bool saveOffset(const std::string& path, double offset, std::string* why);

}  // namespace assistive_tactile

#endif
