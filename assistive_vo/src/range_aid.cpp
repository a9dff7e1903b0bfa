#include "assistive_vo/range_aid.h"
#include <algorithm>
#include <cmath>
#include <vector>
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
  track_.clear();
  anchored_ = false;
  dv_total_.setZero();
  dp_total_.setZero();
}

bool RangeAid::rangeAt(double stamp, double& r, double& r_var, double& rate, double& rate_var) const
{
  std::vector<std::pair<double, double>> w;  // the readings in the window
  for (const auto& x : ranges_)
    if (x.first <= stamp + 1e-6 && x.first >= stamp - o_.rate_window_s)
      w.push_back(x);
  const int n = static_cast<int>(w.size());
  if (n < std::max(2, o_.rate_min_ranges) || stamp - w.back().first > o_.max_range_age_s)
    return false;
  double mt = 0, mr = 0;
  for (const auto& [t, x] : w)
  {
    mt += t / n;
    mr += x / n;
  }
  double stt = 0, str = 0;
  for (const auto& [t, x] : w)
  {
    stt += (t - mt) * (t - mt);
    str += (t - mt) * (x - mr);
  }
  if (stt < 1e-6)
    return false;
  rate = str / stt;
  double ss = 0;
  for (const auto& [t, x] : w)
    ss += std::pow(x - mr - rate * (t - mt), 2);
  const double rms = std::sqrt(ss / std::max(1, n - 2));
  if (rms > o_.max_fit_rms_m)
    return false;  // more than one surface in the window (an edge, a person passing)
  const double s2 = std::max(rms * rms, o_.sigma_m * o_.sigma_m);
  // the slope is the window's mean rate (at its mean time: a walk slowing to a stop is 0.3 m/s
  // slower by the frame); the range at the frame is the newest reading carried over the few ms since
  const double age = stamp - w.back().first;
  rate_var = s2 / stt;
  r = w.back().second + rate * age;
  r_var = o_.sigma_m * o_.sigma_m + rate_var * age * age;
  return true;
}

Eigen::Matrix2d RangeAid::covariance(const InertialCoaster& c, double tau, double* iso_out) const
{
  double iso = 0, along = 0;
  c.positionVarianceSplit(tau, iso, along);
  if (iso_out)
    *iso_out = iso;
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
  if (ax.norm() < 0.7)
  {
    anchored_ = false;  // looking down or up steeply: the next range anchors anew
    return out;
  }
  const Eigen::Vector2d u = ax.normalized();
  // the axis and the coasted velocity over the rate window (the head's turn adds to the range's
  // rate; the rate is the window's mean)
  if (!track_.empty() && (stamp - track_.back().t > 0.2 || stamp <= track_.back().t))
    track_.clear();
  track_.push_back(Sample{stamp, u, coast.velocity().head<2>()});
  while (track_.size() > 2 && track_[1].t <= stamp - o_.rate_window_s)
    track_.pop_front();
  double r = 0, r_var = 0, rate = 0, rate_var = 0;
  if (!rangeAt(stamp, r, r_var, rate, rate_var))
  {
    anchored_ = false;  // no surface: the next range anchors anew
    return out;
  }
  // the range along a pitched axis (the head looks down at the floor ahead): to an upright surface
  // it is the horizontal distance over the axis's horizontal share (20 deg of pitch: 6 % longer, and
  // so is its rate)
  const double level = ax.norm();
  r *= level;
  rate *= level;
  r_var *= level * level;
  rate_var *= level * level;
  const double span = stamp - track_.front().t;
  const double turn_rate = span > 1e-3 ? std::acos(std::clamp(u.dot(track_.front().axis), -1.0, 1.0)) / span : 0.0;
  const double tan_inc = std::tan(o_.max_incidence_deg * M_PI / 180.0);
  if (!anchored_ || u.dot(u_a_) < std::cos(o_.max_axis_change_deg * M_PI / 180.0))
  {
    anchored_ = true;
    r_a_ = r;
    r_a_var_ = r_var;
    u_a_ = u;
    tau_a_ = tau;
    d_ = 0.0;
    dp_total_.setZero();
    return out;
  }
  d_ += u_a_.dot(dpos.head<2>());  // the coast's own walk along the axis since the anchor
  // the range's rate is the speed along the axis: an echo that does not close as the IMU says the
  // wearer walks (a person walking ahead, something stepping into the beam) measures no walk
  Eigen::Vector2d v_mean = Eigen::Vector2d::Zero();
  for (const Sample& k : track_)
    v_mean += k.v / static_cast<double>(track_.size());
  // against the coast's own velocity, without what the ranger already corrected: each frame's
  // rate is one measurement of the same offset, not another one to add up
  const double v_u = u_a_.dot(v_mean - dv_total_);
  const double Vv = coast.velocityVariance(tau);
  const double Rv = rate_var + std::pow(o_.model_rel * rate, 2) + std::pow(r * tan_inc * turn_rate, 2);
  const double nu_v = -rate - v_u;
  if (nu_v * nu_v > o_.gate_sigmas * o_.gate_sigmas * (Vv + Rv))
  {
    anchored_ = false;
    return out;
  }
  // the range's change measures the walk along the axis since the anchor
  const double d_m = r_a_ - r;
  const double turned = std::acos(std::clamp(u.dot(u_a_), -1.0, 1.0));
  const double R = r_a_var_ + r_var + std::pow(o_.model_rel * d_m, 2) + std::pow(r * tan_inc * turned, 2);
  double iso = 0;
  const Eigen::Matrix2d P = covariance(coast, tau, &iso);
  const Eigen::Matrix2d dP = P - covariance(coast, tau_a_);
  const Eigen::Vector2d Pu = dP * u_a_;
  const double S = u_a_.dot(Pu) + R;
  const double nu = d_m - d_;
  if (!(S > 0) || nu * nu > o_.gate_sigmas * o_.gate_sigmas * S)
  {
    anchored_ = false;  // another surface, or the model does not hold: no correction
    return out;
  }
  // the correction since the anchor as one update of the coast's own walk with this range: each
  // frame's range measures the same walk again with much the same error (the surface's angle, the
  // head's turn), so the corrections do not add up
  const Eigen::Vector2d dp_total = Pu * (nu / S);
  out.dpos.head<2>() = dp_total - dp_total_;
  dp_total_ = dp_total;
  const Eigen::Matrix2d post = P - Pu * Pu.transpose() / S;
  // the worst axis after the update, never above the unaided rule's (the aid only adds information;
  // a walk across the axis keeps its error on the axis the ranger does not see)
  out.gate_var = std::min(out.gate_var,
                          std::max(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(post).eigenvalues().maxCoeff(), iso));
  // the rate against the coast's mean velocity over the same window: their difference is the
  // coast's velocity error (a constant offset over the window), taken out of the velocity now
  const Eigen::Vector2d dv_total = u_a_ * (Vv / (Vv + Rv) * nu_v);
  out.dv.head<2>() = dv_total - dv_total_;
  dv_total_ = dv_total;
  out.aided = true;
  return out;
}
}  // namespace assistive_vo
