#include "assistive_vo/range_aid.h"
#include <algorithm>
#include <cmath>
#include <Eigen/Eigenvalues>

namespace assistive_vo
{
void RangeAid::addRange(double stamp, double range)
{
  if (!ranges_.empty() && stamp < ranges_.back().first)
    ranges_.clear();  // time went back (a bag loop)
  ranges_.emplace_back(stamp, range);
  while (!ranges_.empty() && ranges_.front().first < stamp - 2.0 * o_.rate_window_s)
    ranges_.pop_front();
}

void RangeAid::clear()
{
  ranges_.clear();
  anchored_ = false;
}

bool RangeAid::rangeAt(double stamp, double& r, double& r_var, double& rate, double& rate_var) const
{
  double st = 0, sr = 0;
  int n = 0;
  for (const auto& [t, x] : ranges_)
    if (t <= stamp + 1e-6 && t >= stamp - o_.rate_window_s)
    {
      st += t;
      sr += x;
      ++n;
    }
  if (n < o_.rate_min_ranges)
    return false;
  const double mt = st / n, mr = sr / n;
  double stt = 0, str = 0;
  for (const auto& [t, x] : ranges_)
    if (t <= stamp + 1e-6 && t >= stamp - o_.rate_window_s)
    {
      stt += (t - mt) * (t - mt);
      str += (t - mt) * (x - mr);
    }
  if (stt < 1e-6)
    return false;
  rate = str / stt;
  double ss = 0;
  for (const auto& [t, x] : ranges_)
    if (t <= stamp + 1e-6 && t >= stamp - o_.rate_window_s)
      ss += std::pow(x - mr - rate * (t - mt), 2);
  const double rms = std::sqrt(ss / std::max(1, n - 2));
  if (rms > o_.max_fit_rms_m)
    return false;  // more than one surface in the window (an edge, a person passing)
  const double s2 = std::max(rms * rms, o_.sigma_m * o_.sigma_m);
  r = mr + rate * (stamp - mt);
  r_var = s2 / n + s2 * (stamp - mt) * (stamp - mt) / stt;
  rate_var = s2 / stt;
  return true;
}

Eigen::Matrix2d RangeAid::covariance(const InertialCoaster& c, double tau) const
{
  double iso = 0, along = 0;
  c.positionVarianceSplit(tau, iso, along);
  const Eigen::Vector2d m = c.walkDirection().head<2>();
  Eigen::Matrix2d P = Eigen::Matrix2d::Identity() * iso;
  if (m.norm() > 0.5)
    P += along * m * m.transpose();
  else
    P += Eigen::Matrix2d::Identity() * along / 3.0;  // no walk to point it along
  return P;
}

RangeAid::Step RangeAid::step(double stamp, const Eigen::Vector3d& axis_odom, const Eigen::Vector3d& dpos,
                              const InertialCoaster& coast)
{
  Step out;
  const double tau = coast.coastTime();
  out.gate_var = coast.positionVariance(tau);
  const Eigen::Vector2d ax = axis_odom.head<2>();
  double r = 0, r_var = 0, rate = 0, rate_var = 0;
  if (ax.norm() < 0.7 || !rangeAt(stamp, r, r_var, rate, rate_var))
  {
    anchored_ = false;  // looking down or up steeply, or no surface: the next range anchors anew
    return out;
  }
  const Eigen::Vector2d u = ax.normalized();
  if (!anchored_ || u.dot(u_a_) < std::cos(o_.max_axis_change_deg * M_PI / 180.0))
  {
    anchored_ = true;
    r_a_ = r;
    r_a_var_ = r_var;
    u_a_ = u;
    tau_a_ = tau;
    d_ = 0.0;
    return out;
  }
  d_ += u_a_.dot(dpos.head<2>());
  // the range's rate is the speed along the axis: an echo that does not close as the IMU says the
  // wearer walks (a person walking ahead, something stepping into the beam) measures no walk
  const double v_u = u_a_.dot(coast.velocity().head<2>());
  const double Vv = coast.velocityVariance(tau);
  const double Rv = rate_var + std::pow(o_.model_rel * rate, 2);
  const double nu_v = -rate - v_u;
  if (nu_v * nu_v > o_.gate_sigmas * o_.gate_sigmas * (Vv + Rv))
  {
    anchored_ = false;
    return out;
  }
  // the range's change measures the walk along the axis since the anchor
  const double d_m = r_a_ - r;
  const double R = r_a_var_ + r_var + std::pow(o_.model_rel * d_m, 2);
  const Eigen::Matrix2d P = covariance(coast, tau);
  const Eigen::Matrix2d dP = P - covariance(coast, tau_a_);
  const Eigen::Vector2d Pu = dP * u_a_;
  const double S = u_a_.dot(Pu) + R;
  const double nu = d_m - d_;
  if (!(S > 0) || nu * nu > o_.gate_sigmas * o_.gate_sigmas * S)
  {
    anchored_ = false;  // another surface, or the model does not hold: no correction
    return out;
  }
  const Eigen::Vector2d dp = Pu * (nu / S);
  out.dpos.head<2>() = dp;
  d_ += u_a_.dot(dp);
  const Eigen::Matrix2d post = P - Pu * Pu.transpose() / S;
  double iso = 0, along = 0;
  coast.positionVarianceSplit(tau, iso, along);
  out.gate_var = std::max(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(post).eigenvalues().maxCoeff(), iso);
  out.dv.head<2>() = u_a_ * (Vv / (Vv + Rv) * nu_v);
  out.aided = true;
  return out;
}
}  // namespace assistive_vo
