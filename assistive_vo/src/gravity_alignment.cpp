#include "assistive_vo/gravity_alignment.h"
#include <cmath>

namespace assistive_vo
{
bool GravityAligner::add(double stamp, const Eigen::Isometry3d& T_odom_link, const Eigen::Vector3d& dv_prev,
                         Eigen::Matrix3d& correction)
{
  correction.setIdentity();
  if (o_.time_constant_s <= 0.0 || !T_odom_link.matrix().allFinite() || !dv_prev.allFinite())
  {
    f_.clear();
    return false;
  }
  Frame fr;
  fr.t = stamp;
  fr.p = T_odom_link.translation();
  fr.R = T_odom_link.linear();
  fr.dv.setZero();
  if (!f_.empty())
  {
    const double dt = stamp - f_.back().t;
    if (!(dt > 0.0) || dt > o_.max_frame_gap_s)
      f_.clear();
    else
      fr.dv = f_.back().R * dv_prev;
  }
  f_.push_back(fr);
  // A window needs at least three intervals (first and last half-weighted) and window_s of time.
  if (f_.size() < 4 || f_.back().t - f_.front().t < o_.window_s)
    return false;

  const size_t n = f_.size() - 1;  // intervals 1..n
  auto dt = [&](size_t k) { return f_[k].t - f_[k - 1].t; };
  const Eigen::Vector3d v_first = (f_[1].p - f_[0].p) / dt(1);
  const Eigen::Vector3d v_last = (f_[n].p - f_[n - 1].p) / dt(n);
  Eigen::Vector3d sum = 0.5 * f_[1].dv + 0.5 * f_[n].dv;
  for (size_t k = 2; k < n; ++k)
    sum += f_[k].dv;
  // The end intervals' weights ramp (up in the first, down in the last): with the acceleration's
  // slope s over an interval, the ramp adds +-s dt^2 / 12 to the half-weighted increment. Left out,
  // a walking bob's slope costs up to 0.01 deg of tilt per window (test_gravity_alignment).
  const Eigen::Vector3d s_first = (f_[2].dv / dt(2) - f_[1].dv / dt(1)) / (0.5 * (dt(1) + dt(2)));
  const Eigen::Vector3d s_last = (f_[n].dv / dt(n) - f_[n - 1].dv / dt(n - 1)) / (0.5 * (dt(n) + dt(n - 1)));
  sum += (dt(1) * dt(1) * s_first - dt(n) * dt(n) * s_last) / 12.0;
  const double T = 0.5 * (f_[n].t + f_[n - 1].t) - 0.5 * (f_[1].t + f_[0].t);
  const Eigen::Vector3d g = (sum - (v_last - v_first)) / T;

  // The next window starts at this frame (its position does not move with a correction about it).
  Frame last = f_.back();
  f_.clear();
  if (!g.allFinite() || std::abs(g.norm() - o_.gravity) > o_.max_residual)
  {
    ++rejected_;
    f_.push_back(last);
    return true;
  }
  ++accepted_;
  const Eigen::Vector3d up = g.normalized();
  const Eigen::Vector3d axis = up.cross(Eigen::Vector3d::UnitZ());
  const double tilt = std::atan2(axis.norm(), up.z());
  last_tilt_deg_ = tilt * 180.0 / M_PI;
  if (axis.norm() > 1e-12)
    correction = Eigen::AngleAxisd(tilt * std::min(1.0, T / o_.time_constant_s), axis.normalized()).toRotationMatrix();
  last.R = correction * last.R;
  f_.push_back(last);
  return true;
}
}  // namespace assistive_vo
