#include "assistive_vo/standing_detector.h"
#include <cmath>

namespace assistive_vo
{
void StandingDetector::add(double stamp, double dt, const Eigen::Vector3d& f_odom)
{
  if (!(dt > 0.0) || !f_odom.allFinite())
    return;
  if (!s_.empty() && stamp <= s_.back().t)
    s_.clear();
  // a hole in the samples (a frame without IMU) restarts the window: the gait may hide in it
  if (!s_.empty() && stamp - dt > s_.back().t + 1e-3)
    s_.clear();
  s_.push_back(Sample{stamp, dt, f_odom});
  while (s_.size() > 1 && s_.back().t - (s_[1].t - s_[1].dt) >= o_.window_s)
    s_.pop_front();
}

double StandingDetector::statistic() const
{
  if (s_.empty() || s_.back().t - (s_.front().t - s_.front().dt) < o_.window_s - 1e-6)
    return -1.0;
  return partialStatistic();
}

double StandingDetector::partialStatistic() const
{
  return statisticSince(-1e300);
}

double StandingDetector::statisticSince(double t0) const
{
  // time-weighted mean and rms deviation (the moving-variance statistic's square root)
  double T = 0.0;
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (const Sample& s : s_)
    if (s.t - s.dt >= t0 - 1e-6)
    {
      m += s.f * s.dt;
      T += s.dt;
    }
  if (!(T > 0.0))
    return -1.0;
  m /= T;
  double v = 0.0;
  for (const Sample& s : s_)
    if (s.t - s.dt >= t0 - 1e-6)
      v += (s.f - m).squaredNorm() * s.dt;
  return std::sqrt(v / T);
}
}  // namespace assistive_vo
