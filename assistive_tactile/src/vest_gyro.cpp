#include "assistive_tactile/vest_gyro.h"

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
    turn_ += rate.dot(up_) * dt;  // the rate held over the interval since the last sample
  }
  if (!(dt <= max_gap_s_))
    gap_ = true;
  last_sample_ = t;
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
