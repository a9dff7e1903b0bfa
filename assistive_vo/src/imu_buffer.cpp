#include "assistive_vo/imu_buffer.h"
#include <algorithm>
#include <cmath>

namespace assistive_vo
{
void ImuBuffer::add(double stamp, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel)
{
  if (!gyro.allFinite() || !accel.allFinite())
    return;
  if (!s_.empty() && stamp < s_.back().t)
    s_.clear();
  s_.push_back(Sample{stamp, gyro, accel});
  while (!s_.empty() && s_.front().t < stamp - keep_s_)
    s_.pop_front();
}

namespace
{
Eigen::Quaterniond expq(const Eigen::Vector3d& v)
{
  const double a = v.norm();
  if (a < 1e-12)
    return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, v / a));
}
}  // namespace

bool ImuBuffer::integrate(double t0, double t1, Eigen::Quaterniond& R, double slack) const
{
  Eigen::Vector3d dv;
  return integrate(t0, t1, R, dv, slack);
}

bool ImuBuffer::integrate(double t0, double t1, Eigen::Quaterniond& R, Eigen::Vector3d& dv, double slack) const
{
  Eigen::Vector3d dp;
  return integrate(t0, t1, R, dv, dp, slack);
}

bool ImuBuffer::integrate(double t0, double t1, Eigen::Quaterniond& R, Eigen::Vector3d& dv, Eigen::Vector3d& dp,
                          double slack) const
{
  R.setIdentity();
  dv.setZero();
  dp.setZero();
  if (s_.size() < 2 || t1 <= t0 || s_.front().t > t0 + slack || s_.back().t < t1 - slack)
    return false;
  // Piecewise-linear gyro and accelerometer between samples (clamped at the ends), integrated
  // over [t0, t1].
  auto at = [&](double t, bool gyro) {
    if (t <= s_.front().t)
      return gyro ? s_.front().w : s_.front().a;
    if (t >= s_.back().t)
      return gyro ? s_.back().w : s_.back().a;
    auto it = std::lower_bound(s_.begin(), s_.end(), t, [](const Sample& s, double x) { return s.t < x; });
    const Sample& b = *it;
    const Sample& a = *(it - 1);
    const double f = (t - a.t) / std::max(1e-9, b.t - a.t);
    return Eigen::Vector3d(gyro ? (1 - f) * a.w + f * b.w : (1 - f) * a.a + f * b.a);
  };
  double t = t0;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  auto step = [&](double te) {
    const Eigen::Vector3d w = 0.5 * (at(t, true) + at(te, true)) * (te - t);
    // accelerometer rotated at the step's middle orientation
    const Eigen::Vector3d a = (q * expq(0.5 * w)) * (0.5 * (at(t, false) + at(te, false)));
    const double h = te - t;
    dp += dv * h + 0.5 * a * h * h;
    dv += a * h;
    q = q * expq(w);
    t = te;
  };
  for (const Sample& s : s_)
  {
    if (s.t <= t)
      continue;
    step(std::min(s.t, t1));
    if (t >= t1)
      break;
  }
  if (t < t1)
    step(t1);
  R = q.normalized();
  return true;
}

bool ImuBuffer::meanRate(double t, double window, Eigen::Vector3d& w) const
{
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (const Sample& s : s_)
    if (std::abs(s.t - t) <= 0.5 * window + 1e-9)
    {
      sum += s.w;
      ++n;
    }
  if (n == 0)
    return false;
  w = sum / n;
  return true;
}

bool ImuBuffer::meanAccel(double t, double window, Eigen::Vector3d& a, double* span) const
{
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  double first = 0.0, last = 0.0;
  for (const Sample& s : s_)
    if (s.t <= t + 1e-6 && s.t >= t - window)
    {
      if (n == 0)
        first = s.t;
      last = s.t;
      sum += s.a;
      ++n;
    }
  if (n == 0)
    return false;
  a = sum / n;
  if (span)
    *span = last - first;
  return true;
}
}  // namespace assistive_vo
