#include "assistive_tactile/vest_gyro.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace assistive_tactile
{
void VestGyro::add(double t, const Eigen::Vector3d& rate, const Eigen::Vector3d& accel)
{
  if (!rate.allFinite() || !accel.allFinite() || accel.norm() < 1.0)
    return;  // (a free fall or a broken sample says nothing about up)
  const double dt = t - last_sample_;
  if (!(dt > 0.0))
    return;  // out of order, repeated or no time: ignored
  if (!have_up_)
  {
    up_ = accel.normalized();
    have_up_ = true;
  }
  else if (dt <= max_gap_s_)
  {
    up_ = (up_ + std::min(1.0, dt / up_tau_s_) * (accel.normalized() - up_)).normalized();
    const double r = rate.dot(up_);
    turn_ += (r - offset_) * dt;  // the rate held over the interval since the last sample
    watchStill(r, accel.norm(), dt);
  }
  if (!(dt <= max_gap_s_))
  {
    gap_ = true;
    win_t_ = win_r_ = win_rr_ = win_a_ = win_aa_ = 0.0;
  }
  last_sample_ = t;
}

void VestGyro::watchStill(double rate_up, double accel_norm, double dt)
{
  win_t_ += dt;
  win_r_ += rate_up * dt;
  win_rr_ += rate_up * rate_up * dt;
  win_a_ += accel_norm * dt;
  win_aa_ += accel_norm * accel_norm * dt;
  if (win_t_ < still_window_s_)
    return;
  const double r = win_r_ / win_t_, a = win_a_ / win_t_;
  const double r_sd = std::sqrt(std::max(0.0, win_rr_ / win_t_ - r * r));
  const double a_sd = std::sqrt(std::max(0.0, win_aa_ / win_t_ - a * a));
  if (a_sd < kStillAccelSd && r_sd < kStillRateSd && std::fabs(r) < kMaxOffset)
  {
    offset_ = r;
    ++captures_;
  }
  win_t_ = win_r_ = win_rr_ = win_a_ = win_aa_ = 0.0;
}

double VestGyro::take(double now)
{
  const bool fresh = have_up_ && now - last_sample_ <= max_gap_s_ && now > last_take_ &&
                     now - last_take_ <= max_gap_s_ + 1.0 && !gap_;
  const double r = fresh ? turn_ / (now - last_take_) : std::numeric_limits<double>::quiet_NaN();
  turn_ = 0.0;
  gap_ = false;
  last_take_ = now;
  return r;
}

}  // namespace assistive_tactile
