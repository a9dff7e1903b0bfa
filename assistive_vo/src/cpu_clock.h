#pragma once
// Private to the VO core's sources: the stage timer and small rotation helpers they share.
#include <time.h>
#include <Eigen/Geometry>

namespace assistive_vo
{
namespace internal
{
/// Stage timers: CPU time of the calling thread (what one core spends on the frame, not
/// inflated by other processes on a shared machine).
struct Clock
{
  using time_point = double;
  static double now()
  {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
  }
};
inline double msSince(double t0)
{
  return Clock::now() - t0;
}
inline double angleOf(const Eigen::Matrix3d& R)
{
  return Eigen::AngleAxisd(R).angle();
}
}  // namespace internal
}  // namespace assistive_vo
