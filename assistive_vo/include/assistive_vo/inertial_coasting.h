#pragma once
// Carrying the pose over frames where vision fails (a plain wall filling the view, darkness,
// blur, dropped frames) on the IMU, the seed's recommendation in 6.2.1 ("employ a cheap
// accelerometer and gyroscope unit to provide motion estimates when visual odometry has failed").
#include <deque>
#include <Eigen/Geometry>

namespace assistive_vo
{
/// IMU preintegration between frames (ImuBuffer::integrate): the specific force integrated once
/// (dv) and twice (dp) over `dt`, in camera_link axes at the interval's start.
struct ImuDelta
{
  double dt = 0.0;
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  Eigen::Vector3d dp = Eigen::Vector3d::Zero();
};

/// The translation part of inertial coasting. The orientation comes from the VO's own chain (the
/// gyro with its estimated bias); this class gives the position and velocity:
///   v1 = v + (g + b) T + R (dv - T ba),   p1 = p + v T + (g + b) T^2 / 2 + R (dp - T^2 ba / 2),
/// with R the camera_link orientation at the interval's start in odom (z up, g = -9.81 z). The
/// velocity at the last tracked frame, ba, the accelerometer's bias (camera_link axes, turns with
/// the head) and b, gravity leaking through the tilt error of odom (odom axes), are fitted to the
/// tracked frames of the last `window_s`: p_k = c + v0 t_k + (g + b) t_k^2 / 2 + S_k - Mp_k ba,
/// with S_k the preintegrated IMU chained over the window from zero velocity and Mp_k the same
/// chain for a unit bias (linear least squares, 12 unknowns, priors on b and ba). The position
/// covariance grows with the fit's uncertainty, the accelerometer's noise, the tilt the gyro's
/// noise and bias error add while coasting (gravity leaking through it), and the VO's correlated
/// velocity error that the white-noise fit cannot see (a fraction of the speed): an honest, growing
/// covariance while coasting.
class InertialCoaster
{
public:
  struct Options
  {
    double window_s = 1.5;             ///< tracked frames the velocity is fitted over, s
    double min_window_s = 0.3;         ///< a shorter window: no fit (cannot coast)
    double gravity = 9.81;             ///< m/s^2, along -z of odom
    double position_sigma_m = 0.003;   ///< floor on the VO's position noise in the fit
    double accel_error_sigma = 0.15;   ///< prior on b and on ba (tilt x g; accelerometer bias), m/s^2
    double accel_noise_density = 2e-3; ///< m/s^2/sqrt(Hz), for the covariance growth
    double max_frame_gap_s = 0.2;      ///< a longer interval between frames restarts the window
    double max_bridge_s = 0.25;        ///< a coast this short keeps the window (see addTracked)
    double gyro_noise_density = 2e-4;  ///< rad/s/sqrt(Hz): tilt random walk while coasting
    double gyro_bias_sigma = 0.0;      ///< rad/s: error of the gyro bias estimate (tilt grows linearly)
    /// The VO's velocity error correlated over the fit window (its drift: the white-noise fit
    /// sees only the scatter), as a fraction of the speed, plus a floor in m/s.
    /// Measured on the generated set's 2 s blackouts (imperfect cameras: the tracked path is a
    /// few percent too long or short), where 0.02 and no acceleration term gave errors up to 7.8 sigma.
    double velocity_error_frac = 0.08;
    double velocity_error_floor = 0.005;
    /// Acceleration the fit cannot follow (a walk that stops or starts, a turn on the spot), m/s^2.
    double accel_model_sigma = 0.1;
    /// A long coast's velocity starts the next window (addTracked).
    bool carry_velocity = true;
  };
  InertialCoaster() = default;
  explicit InertialCoaster(const Options& o) : o_(o) {}
  void setOptions(const Options& o) { o_ = o; }
  /// Forgets the window and stops coasting.
  void clear();
  /// A tracked frame: camera_link in odom, and the IMU over the interval since the previous frame
  /// (null: none, the window restarts here). Ends a coast: after a short one (<= max_bridge_s:
  /// a single failed frame, a re-initialisation) the window goes on, the coasted frames carrying
  /// the IMU chain but no position measurement; after a longer one it restarts here, with the
  /// coast's velocity (carried over the interval, its variance) as a prior on the new window's
  /// first velocity: a few tracked frames between losses (a plain wall coming into view) can
  /// coast again instead of waiting for min_window_s.
  void addTracked(double stamp, const Eigen::Isometry3d& T_odom_link, const ImuDelta* d);
  /// The window is long enough to coast, or it starts where a coast ended (the velocity prior) and
  /// holds at least one tracked frame, or a coast is running.
  bool available() const;
  /// Starts a coast at the last tracked frame (fits velocity and b); false when not available().
  bool start();
  bool coasting() const { return coasting_; }
  /// One frame of the coast: the odom displacement of camera_link over the interval, given its
  /// orientation in odom at the interval's start; updates the velocity and the covariance.
  Eigen::Vector3d step(const Eigen::Matrix3d& R_odom_link, const ImuDelta& d);
  /// Velocity now (odom axes, m/s), the constant acceleration error fitted (odom axes) and the
  /// accelerometer bias fitted (camera_link axes).
  const Eigen::Vector3d& velocity() const { return v_; }
  const Eigen::Vector3d& accelError() const { return b_; }
  const Eigen::Vector3d& accelBias() const { return ba_; }
  /// Variance (m^2, per axis) of the coasted position against the last tracked frame's, after
  /// `tau` s of coasting.
  double positionVariance(double tau) const;
  /// Variance (m^2/s^2, per axis) of the coasted velocity after `tau` s of coasting.
  double velocityVariance(double tau) const;
  /// Coasting time so far.
  double coastTime() const { return tau_; }
  /// positionVariance(tau) split by direction (RangeAid): `iso` per axis from the fit, the
  /// accelerometer's noise and the tilt; `along` the whole variance of the VO's correlated velocity
  /// error (its scale: the tracked path too long or too short) and of the acceleration the fit
  /// cannot follow (a stop or a start), both along the walk: positionVariance = iso + along / 3.
  void positionVarianceSplit(double tau, double& iso, double& along) const;
  /// The horizontal direction of the walk when the coast started (odom, unit; zero when slower than
  /// 0.2 m/s): the axis of `along`.
  const Eigen::Vector3d& walkDirection() const { return walk_dir_; }
  /// Moves the coasted velocity by `dv` (odom, m/s): a measurement of it (RangeAid).
  void correctVelocity(const Eigen::Vector3d& dv) { v_ += dv; }

private:
  struct Frame
  {
    double t;
    Eigen::Vector3d p;
    Eigen::Matrix3d R;
    ImuDelta d;  ///< IMU from the previous frame to this one (unused for the first)
    bool measured = true;  ///< a tracked frame (false: coasted, IMU chain only)
  };
  bool fit();
  /// The velocity prior (addTracked after a long coast) holds while the window still starts at
  /// the frame it was set for.
  bool hasPrior() const { return prior_ && !f_.empty() && f_.front().t == prior_t_; }
  Options o_;
  bool prior_ = false;
  double prior_t_ = 0.0, prior_var_ = 0.0;  ///< the window's first frame; per-axis variance, m^2/s^2
  Eigen::Vector3d prior_v_ = Eigen::Vector3d::Zero();
  std::deque<Frame> f_;
  bool coasting_ = false;
  Eigen::Vector3d v_ = Eigen::Vector3d::Zero(), b_ = Eigen::Vector3d::Zero(), ba_ = Eigen::Vector3d::Zero();
  using Mat12 = Eigen::Matrix<double, 12, 12>;
  Mat12 cov_ = Mat12::Zero();                          ///< of (c, v0, b, ba)
  Eigen::Matrix<double, 3, 12> J_vend_ = Eigen::Matrix<double, 3, 12>::Zero();  ///< d v_end / d (c, v0, b, ba)
  Eigen::Matrix3d R_end_ = Eigen::Matrix3d::Identity();  ///< orientation at the last tracked frame
  double v_model_var_ = 0.0;  ///< velocity variance of the VO's correlated error (per axis), at the fit
  Eigen::Vector3d walk_dir_ = Eigen::Vector3d::Zero();  ///< see walkDirection()
  double tau_ = 0.0;
};
}  // namespace assistive_vo
