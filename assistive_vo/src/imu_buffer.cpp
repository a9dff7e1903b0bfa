#include "assistive_vo/imu_buffer.h"
#include <algorithm>

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
  R.setIdentity();
  if (s_.size() < 2 || t1 <= t0 || s_.front().t > t0 + slack || s_.back().t < t1 - slack)
    return false;
  // Piecewise-linear gyro between samples (clamped at the ends), integrated over [t0, t1].
  auto rateAt = [&](double t) {
    if (t <= s_.front().t)
      return s_.front().w;
    if (t >= s_.back().t)
      return s_.back().w;
    auto it = std::lower_bound(s_.begin(), s_.end(), t, [](const Sample& s, double x) { return s.t < x; });
    const Sample& b = *it;
    const Sample& a = *(it - 1);
    const double f = (t - a.t) / std::max(1e-9, b.t - a.t);
    return Eigen::Vector3d((1 - f) * a.w + f * b.w);
  };
  double t = t0;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (const Sample& s : s_)
  {
    if (s.t <= t)
      continue;
    const double te = std::min(s.t, t1);
    q = q * expq(0.5 * (rateAt(t) + rateAt(te)) * (te - t));
    t = te;
    if (t >= t1)
      break;
  }
  if (t < t1)
    q = q * expq(rateAt(t) * (t1 - t));
  R = q.normalized();
  return true;
}

bool ImuBuffer::meanAccel(double t, double window, Eigen::Vector3d& a) const
{
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (const Sample& s : s_)
    if (s.t <= t + 1e-6 && s.t >= t - window)
    {
      sum += s.a;
      ++n;
    }
  if (n == 0)
    return false;
  a = sum / n;
  return true;
}
}  // namespace assistive_vo
