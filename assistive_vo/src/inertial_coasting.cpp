#include "assistive_vo/inertial_coasting.h"
#include <algorithm>
#include <cmath>

namespace assistive_vo
{
void InertialCoaster::clear()
{
  f_.clear();
  coasting_ = false;
  tau_ = 0.0;
  prior_ = false;
}

void InertialCoaster::addTracked(double stamp, const Eigen::Isometry3d& T_odom_link, const ImuDelta* d)
{
  const bool bridged = coasting_ && tau_ <= o_.max_bridge_s + 1e-9;
  const bool joined = d && !f_.empty() && stamp > f_.back().t && stamp - f_.back().t <= o_.max_frame_gap_s;
  if ((coasting_ && !bridged) || !joined)
  {
    // A long coast ends: its velocity, carried over this interval, starts the new window.
    const bool carry = o_.carry_velocity && coasting_ && joined;
    Eigen::Vector3d v_here = Eigen::Vector3d::Zero();
    double var_here = 0.0;
    if (carry)
    {
      const double h = d->dt;
      v_here = v_ + (Eigen::Vector3d(0, 0, -o_.gravity) + b_) * h + f_.back().R * (d->dv - h * ba_);
      var_here = velocityVariance(tau_ + h);
    }
    clear();
    if (carry && v_here.allFinite() && std::isfinite(var_here) && var_here > 0.0)
    {
      prior_ = true;
      prior_t_ = stamp;
      prior_v_ = v_here;
      prior_var_ = var_here;
    }
  }
  coasting_ = false;
  tau_ = 0.0;
  f_.push_back(Frame{stamp, T_odom_link.translation(), T_odom_link.linear(), d ? *d : ImuDelta(), true});
  // keep window_s, plus the frame just before it; the window starts at a tracked frame
  while (f_.size() > 2 && (f_.back().t - f_[1].t >= o_.window_s || !f_.front().measured))
    f_.pop_front();
}

bool InertialCoaster::available() const
{
  if (coasting_)
    return true;
  if (f_.empty() || !f_.back().measured)
    return false;
  if (hasPrior())
    return true;
  int measured = 0;
  for (const Frame& f : f_)
    measured += f.measured;
  return measured >= 3 && f_.back().t - f_.front().t >= o_.min_window_s;
}

bool InertialCoaster::fit()
{
  // Chain the preintegrated IMU over the window from zero velocity (S: position, U: velocity),
  // and the same for a unit accelerometer bias (Mp, Mv), with the VO's orientation at each
  // interval's start.
  const size_t n = f_.size();
  std::vector<double> t(n);
  std::vector<Eigen::Vector3d> S(n, Eigen::Vector3d::Zero());
  std::vector<Eigen::Matrix3d> Mp(n, Eigen::Matrix3d::Zero());
  Eigen::Vector3d U = Eigen::Vector3d::Zero();
  Eigen::Matrix3d Mv = Eigen::Matrix3d::Zero();
  const Eigen::Vector3d g(0, 0, -o_.gravity);
  for (size_t k = 0; k < n; ++k)
  {
    t[k] = f_[k].t - f_[0].t;
    if (k == 0)
      continue;
    const Frame& a = f_[k - 1];
    const double h = f_[k].t - a.t;
    S[k] = S[k - 1] + U * h + a.R * f_[k].d.dp;
    U += a.R * f_[k].d.dv;
    Mp[k] = Mp[k - 1] + Mv * h + a.R * (0.5 * h * h);
    Mv += a.R * h;
  }
  const double T = t[n - 1];
  // y_k = p_k - p_0 - g t^2 / 2 - S_k = c + v0 t + b t^2 / 2 - Mp_k ba: rows of A (3 x 12) per frame
  double sigma = o_.position_sigma_m;
  Eigen::Matrix<double, 12, 1> x = Eigen::Matrix<double, 12, 1>::Zero();
  for (int pass = 0; pass < 2; ++pass)
  {
    Mat12 N = Mat12::Zero();
    Eigen::Matrix<double, 12, 1> r = Eigen::Matrix<double, 12, 1>::Zero();
    std::vector<Eigen::Matrix<double, 3, 12>> A(n);
    for (size_t k = 0; k < n; ++k)
    {
      A[k].setZero();
      A[k].block<3, 3>(0, 0).setIdentity();
      A[k].block<3, 3>(0, 3) = Eigen::Matrix3d::Identity() * t[k];
      A[k].block<3, 3>(0, 6) = Eigen::Matrix3d::Identity() * 0.5 * t[k] * t[k];
      A[k].block<3, 3>(0, 9) = -Mp[k];
      const Eigen::Vector3d y = f_[k].p - f_[0].p - 0.5 * g * t[k] * t[k] - S[k];
      if (!f_[k].measured)
        continue;
      N += A[k].transpose() * A[k] / (sigma * sigma);
      r += A[k].transpose() * y / (sigma * sigma);
    }
    for (int i = 6; i < 12; ++i)  // priors b, ba ~ N(0, sigma_b^2)
      N(i, i) += 1.0 / (o_.accel_error_sigma * o_.accel_error_sigma);
    if (hasPrior())  // v0 ~ N(the ended coast's velocity, its variance)
    {
      N.block<3, 3>(3, 3) += Eigen::Matrix3d::Identity() / prior_var_;
      r.segment<3>(3) += prior_v_ / prior_var_;
    }
    cov_ = N.inverse();
    if (!cov_.allFinite())
      return false;
    x = cov_ * r;
    // the residuals set the position noise (never below the floor)
    double ss = 0;
    int rows = 0;
    for (size_t k = 0; k < n; ++k)
    {
      if (!f_[k].measured)
        continue;
      rows += 3;
      const Eigen::Vector3d y = f_[k].p - f_[0].p - 0.5 * g * t[k] * t[k] - S[k];
      ss += (y - A[k] * x).squaredNorm();
    }
    const double rms = std::sqrt(ss / std::max(1.0, rows - 12.0));
    if (rms <= sigma)
      break;
    sigma = rms;
  }
  b_ = x.segment<3>(6);
  ba_ = x.segment<3>(9);
  v_ = x.segment<3>(3) + (g + b_) * T + U - Mv * ba_;
  J_vend_.setZero();
  J_vend_.block<3, 3>(0, 3).setIdentity();
  J_vend_.block<3, 3>(0, 6) = Eigen::Matrix3d::Identity() * T;
  J_vend_.block<3, 3>(0, 9) = -Mv;
  R_end_ = f_.back().R;
  const double sv = o_.velocity_error_floor + o_.velocity_error_frac * v_.norm();
  v_model_var_ = sv * sv;
  if (hasPrior())
  {
    // The VO's correlated velocity error enters as far as its frames, not the carried prior (whose
    // variance has it already), set the velocity: the share of the information they add.
    const double post = cov_.block<3, 3>(3, 3).trace() / 3.0;
    v_model_var_ *= std::clamp(1.0 - post / prior_var_, 0.0, 1.0);
  }
  return v_.allFinite() && b_.allFinite() && ba_.allFinite();
}

bool InertialCoaster::start()
{
  if (coasting_)
    return true;
  if (!available() || !fit())
    return false;
  coasting_ = true;
  tau_ = 0.0;
  const Eigen::Vector3d vh(v_.x(), v_.y(), 0.0);
  walk_dir_ = vh.norm() > 0.2 ? Eigen::Vector3d(vh.normalized()) : Eigen::Vector3d::Zero();
  return true;
}

Eigen::Vector3d InertialCoaster::step(const Eigen::Matrix3d& R_odom_link, const ImuDelta& d)
{
  const Eigen::Vector3d a = Eigen::Vector3d(0, 0, -o_.gravity) + b_;
  const double h = d.dt;
  const Eigen::Vector3d dpos = v_ * h + 0.5 * a * h * h + R_odom_link * (d.dp - 0.5 * h * h * ba_);
  v_ += a * h + R_odom_link * (d.dv - h * ba_);
  tau_ += h;
  if (!f_.empty() && !f_.back().measured)
    f_.back().R = R_odom_link;  // the previous coasted frame's own orientation, now known
  if (!f_.empty())  // the IMU chain goes on through the coasted frame (bridges a short coast)
    f_.push_back(Frame{f_.back().t + h, f_.back().p + dpos, R_odom_link, d, false});
  return dpos;
}

double InertialCoaster::positionVariance(double tau) const
{
  // From the fit: v_end tau + (b - R ba) tau^2 / 2 (the head's orientation at the last tracked
  // frame); from the accelerometer's white noise: q tau^3 / 3; from the VO's correlated velocity
  // error: (sv tau)^2; from acceleration the fit cannot follow: (sa tau^2 / 2)^2; from the tilt the gyro adds while coasting (angle random walk qg, bias
  // error sb), gravity through it integrated twice: g^2 (qg tau^5 / 20 + sb^2 tau^6 / 36), on the
  // two horizontal axes of three. Mean over the axes.
  Eigen::Matrix<double, 3, 12> J = J_vend_ * tau;
  J.block<3, 3>(0, 6) += Eigen::Matrix3d::Identity() * 0.5 * tau * tau;
  J.block<3, 3>(0, 9) -= R_end_ * 0.5 * tau * tau;
  const double q = o_.accel_noise_density * o_.accel_noise_density;
  const double qg = o_.gyro_noise_density * o_.gyro_noise_density, sb2 = o_.gyro_bias_sigma * o_.gyro_bias_sigma;
  const double g2 = o_.gravity * o_.gravity, t2 = tau * tau, t5 = t2 * t2 * tau;
  const double tilt = g2 * (qg * t5 / 20.0 + sb2 * t5 * tau / 36.0) * 2.0 / 3.0;
  const double am = 0.5 * o_.accel_model_sigma * t2;
  return (J * cov_ * J.transpose()).trace() / 3.0 + q * t2 * tau / 3.0 + v_model_var_ * t2 + tilt + am * am;
}

void InertialCoaster::positionVarianceSplit(double tau, double& iso, double& along) const
{
  const double am = 0.5 * o_.accel_model_sigma * tau * tau;
  const double per_axis = v_model_var_ * tau * tau + am * am;
  iso = positionVariance(tau) - per_axis;
  along = 3.0 * per_axis;
}

double InertialCoaster::velocityVariance(double tau) const
{
  Eigen::Matrix<double, 3, 12> J = J_vend_;
  J.block<3, 3>(0, 6) += Eigen::Matrix3d::Identity() * tau;
  J.block<3, 3>(0, 9) -= R_end_ * tau;
  const double q = o_.accel_noise_density * o_.accel_noise_density;
  const double qg = o_.gyro_noise_density * o_.gyro_noise_density, sb2 = o_.gyro_bias_sigma * o_.gyro_bias_sigma;
  const double g2 = o_.gravity * o_.gravity, t2 = tau * tau;
  const double tilt = g2 * (qg * t2 * tau / 3.0 + sb2 * t2 * t2 / 4.0) * 2.0 / 3.0;
  const double am = o_.accel_model_sigma * tau;
  return (J * cov_ * J.transpose()).trace() / 3.0 + q * tau + v_model_var_ + tilt + am * am;
}
}  // namespace assistive_vo
