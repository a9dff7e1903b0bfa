#pragma once
#include <deque>
#include <Eigen/Geometry>

namespace assistive_vo
{
/// Recent IMU samples (camera_link axes): integrates the gyro between two frame stamps (the
/// rotation prior for fast head turns) and averages the accelerometer for the initial gravity.
class ImuBuffer
{
public:
  explicit ImuBuffer(double keep_s = 2.0) : keep_s_(keep_s) {}
  /// Samples must come in stamp order; an older one (bag loop) clears the buffer first.
  void add(double stamp, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel);
  void clear() { s_.clear(); }
  bool empty() const { return s_.empty(); }
  /// Stamp of the newest sample (-1: none).
  double latest() const { return s_.empty() ? -1.0 : s_.back().t; }
  /// Rotation R_t0_t1 of camera_link (maps t1 coords to t0 coords) from the gyro, trapezoidal
  /// per sample interval. False when the samples do not cover [t0, t1] (to within `slack` s).
  bool integrate(double t0, double t1, Eigen::Quaterniond& R, double slack = 0.02) const;
  /// The same, and the accelerometer integrated over [t0, t1] in camera_link axes at t0:
  /// dv = sum R_t0_s a_s ds (the velocity increment of IMU preintegration; specific force, so it
  /// holds gravity's +g * dt as well as the motion).
  bool integrate(double t0, double t1, Eigen::Quaterniond& R, Eigen::Vector3d& dv, double slack = 0.02) const;
  /// The same, and the position increment of IMU preintegration: dp = sum (dv_s ds + R_t0_s a_s ds^2 / 2),
  /// the double integral of the specific force in camera_link axes at t0. With the velocity v and
  /// the pose (R, p) at t0 in a frame where gravity is g: p1 = p + v T + g T^2 / 2 + R dp,
  /// v1 = v + g T + R dv, R1 = R * R_t0_t1 (T = t1 - t0). The gyro is integrated as measured: the
  /// VO removes its bias estimate from the frame-to-frame rotation; inside one frame interval the
  /// bias turns the accelerometer by < 1e-3 rad, which is neglected.
  bool integrate(double t0, double t1, Eigen::Quaterniond& R, Eigen::Vector3d& dv, Eigen::Vector3d& dp,
                 double slack = 0.02) const;
  /// Mean gyro reading (rad/s, as measured) over the samples in [t - window / 2, t + window / 2];
  /// false without any there.
  bool meanRate(double t, double window, Eigen::Vector3d& w) const;
  /// Mean accelerometer reading over the samples up to `t` (at most `window` s back);
  /// false without samples. `span` (optional): the time those samples cover.
  bool meanAccel(double t, double window, Eigen::Vector3d& a, double* span = nullptr) const;

private:
  struct Sample
  {
    double t;
    Eigen::Vector3d w, a;
  };
  std::deque<Sample> s_;
  double keep_s_;
};
}  // namespace assistive_vo
