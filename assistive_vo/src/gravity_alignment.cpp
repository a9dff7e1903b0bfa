#include "assistive_vo/gravity_alignment.h"
#include <algorithm>
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
  // A window needs window_s of time and room for both velocity ends (2 m + 1 intervals).
  const size_t m = static_cast<size_t>(std::max(1, o_.velocity_intervals));
  if (f_.size() < 2 * m + 2 || f_.back().t - f_.front().t < o_.window_s)
    return false;

  const size_t n = f_.size() - 1;  // intervals 1..n, interval i = (t_{i-1}, t_i]
  auto mid = [&](size_t i) { return 0.5 * (f_[i - 1].t + f_[i].t); };
  auto len = [&](size_t i) { return f_[i].t - f_[i - 1].t; };
  auto mean = [&](size_t i) { return Eigen::Vector3d(f_[i].dv / len(i)); };
  // Mean velocities over the first and the last m intervals (A, B): their difference is the
  // acceleration weighted by w(u) = F_A(u) - F_B(u), ramping up over A and down over B (F: the
  // fraction of the span before u). Per interval, with the acceleration linear in it (slope s):
  // integral = mean * len * w(middle) +- s len^3 / (12 span).
  const double tA0 = f_[0].t, tA1 = f_[m].t, tB0 = f_[n - m].t, tB1 = f_[n].t;
  const Eigen::Vector3d v_first = (f_[m].p - f_[0].p) / (tA1 - tA0);
  const Eigen::Vector3d v_last = (f_[n].p - f_[n - m].p) / (tB1 - tB0);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (size_t i = 1; i <= n; ++i)
  {
    const bool inA = i <= m, inB = i > n - m;
    if (!inA && !inB)
    {
      sum += f_[i].dv;
      continue;
    }
    const size_t lo = i > 1 ? i - 1 : i, hi = i < n ? i + 1 : i;
    const Eigen::Vector3d slope = (mean(hi) - mean(lo)) / (mid(hi) - mid(lo));
    const double l3 = len(i) * len(i) * len(i);
    if (inA)
      sum += f_[i].dv * (mid(i) - tA0) / (tA1 - tA0) + slope * l3 / (12.0 * (tA1 - tA0));
    else
      sum += f_[i].dv * (tB1 - mid(i)) / (tB1 - tB0) - slope * l3 / (12.0 * (tB1 - tB0));
  }
  const double T = 0.5 * (tB0 + tB1) - 0.5 * (tA0 + tA1);
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
