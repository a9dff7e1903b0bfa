#pragma once
#include <deque>
#include <Eigen/Geometry>

namespace assistive_vo
{
/// Keeps the odom frame level over long walks. Vision and gyro leave the tilt (roll / pitch) of
/// the odom frame to drift; gravity does not. Over a window of tracked frames, the accelerometer
/// rotated into odom and summed, minus the velocity change the odometry measured over the same
/// window, is gravity as the odometry sees it:
///   sum_i w_i R_i a_i dt_i = vbar_B - vbar_A + g z T,
/// with vbar_A, vbar_B the mean velocities over the window's first and last `velocity_intervals`
/// frame intervals (from the positions), R_i a_i dt_i the accelerometer (specific force)
/// integrated over interval i in odom axes (the IMU preintegration increment rotated by the
/// orientation at the interval's start), w_i the weights that make the equation exact for an
/// acceleration linear within each interval (ramping over A and B, 1 in between), and T the time
/// between the middles of A and B. The angle between that vector and odom's z is the tilt the
/// odometry has accumulated (plus what the accelerometer bias adds, a constant in the head frame).
/// A fraction T / time_constant of it is returned as a correction, so one window's noise moves the
/// frame little and the tilt cannot run away. Yaw is not touched.
class GravityAligner
{
public:
  struct Options
  {
    double window_s = 4.0;           ///< length of one gravity measurement, s
    double time_constant_s = 120.0;  ///< correction = tilt * window / time_constant (<= 0: off)
    double gravity = 9.81;           ///< m/s^2
    double max_residual = 0.3;       ///< | |g measured| - gravity | above this: window rejected, m/s^2
    double max_frame_gap_s = 0.2;    ///< a longer interval between frames restarts the window
    int velocity_intervals = 4;      ///< frame intervals per end velocity (fewer: noisier velocities)
  };
  GravityAligner() = default;
  explicit GravityAligner(const Options& o) : o_(o) {}
  void setOptions(const Options& o) { o_ = o; }
  /// Forget the window (after a reset, a lost frame or a gap: the velocities would be wrong).
  void clear() { f_.clear(); }

  /// One tracked frame: the camera_link pose in odom and `dv_prev`, the accelerometer integrated
  /// over the interval since the previous frame in the previous frame's camera_link axes (m/s;
  /// ImuBuffer::integrate). True when a window closed and `correction` (odom axes, to apply about
  /// the current position) is set; it is the identity when the window was rejected.
  bool add(double stamp, const Eigen::Isometry3d& T_odom_link, const Eigen::Vector3d& dv_prev,
           Eigen::Matrix3d& correction);

  /// The last accepted window: tilt of the odom frame against gravity (deg), and the number of
  /// windows accepted / rejected since construction.
  double lastTiltDeg() const { return last_tilt_deg_; }
  int accepted() const { return accepted_; }
  int rejected() const { return rejected_; }

private:
  struct Frame
  {
    double t;
    Eigen::Vector3d p;
    Eigen::Matrix3d R;   ///< orientation at the frame
    Eigen::Vector3d dv;  ///< accelerometer integrated over the interval ending here, odom axes
  };
  Options o_;
  std::deque<Frame> f_;
  double last_tilt_deg_ = 0.0;
  int accepted_ = 0, rejected_ = 0;
};
}  // namespace assistive_vo
