#pragma once
// The start-up rule of the odom frame, shared by the nodelet and vo_benchmark: the odom frame
// takes gravity from the accelerometer at the first frame. The IMU and the images arrive
// independently, so the first images can come before any IMU sample: wait for it (up to wait_s
// of image time) rather than assume a level camera, which would tilt the whole map (a
// pitched-down head sees the floor as a slope, i.e. obstacles). Then fall back to
// initial_roll / initial_pitch (VoParams) without gravity.
#include <Eigen/Core>
#include "assistive_vo/imu_buffer.h"

namespace assistive_vo
{
class StartupRule
{
public:
  struct Options
  {
    bool expect_imu = true;     ///< false (use_imu off, or input without an IMU): start at once
    double wait_s = 1.0;        ///< image time to wait for the IMU before falling back
    double window_s = 0.5;      ///< accelerometer averaged over this long before the frame
    double min_accel = 5.0;     ///< a mean specific force outside (min, max) m/s^2 is no gravity
    double max_accel = 15.0;
  };
  enum class Decision
  {
    START_WITH_GRAVITY,  ///< `up` holds the mean accelerometer reading: VisualOdometry::setInitialUp(up)
    WAIT_FOR_IMU,        ///< skip this frame
    START_WITHOUT_IMU    ///< start from initial_roll / initial_pitch (the fall-back, or no IMU expected)
  };

  StartupRule() = default;
  explicit StartupRule(const Options& o) : o_(o) {}
  void setOptions(const Options& o) { o_ = o; }
  const Options& options() const { return o_; }
  /// For a frame at `stamp` before the VO started, given the IMU samples so far.
  Decision decide(double stamp, const ImuBuffer& imu, Eigen::Vector3d& up);
  /// Image time waited so far (0 before the first wait).
  double waited(double stamp) const { return wait_start_ < 0 ? 0.0 : stamp - wait_start_; }
  /// A new start (the wait begins again at the next frame without IMU).
  void reset() { wait_start_ = -1.0; }

private:
  Options o_;
  double wait_start_ = -1.0;  ///< stamp of the first frame that waited
};
}  // namespace assistive_vo
