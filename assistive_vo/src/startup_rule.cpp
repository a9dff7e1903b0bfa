#include "assistive_vo/startup_rule.h"

namespace assistive_vo
{
StartupRule::Decision StartupRule::decide(double stamp, const ImuBuffer& imu, Eigen::Vector3d& up)
{
  if (!o_.expect_imu)
    return Decision::START_WITHOUT_IMU;
  Eigen::Vector3d a;
  if (imu.meanAccel(stamp, o_.window_s, a) && a.norm() > o_.min_accel && a.norm() < o_.max_accel)
  {
    up = a;
    return Decision::START_WITH_GRAVITY;
  }
  if (wait_start_ < 0 || stamp < wait_start_)  // first wait, or time went back (bag loop)
    wait_start_ = stamp;
  return stamp - wait_start_ < o_.wait_s ? Decision::WAIT_FOR_IMU : Decision::START_WITHOUT_IMU;
}
}  // namespace assistive_vo
