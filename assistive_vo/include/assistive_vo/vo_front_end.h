#pragma once
// The VO's driving loop, one for the device and every benchmark (issue 32): the IMU buffer, the
// start-up rule of the odom frame, the gyro and accelerometer integration between frames, the
// gravity hint and the call into VisualOdometry. The nodelet converts messages and calls it;
// vo_benchmark and slam_benchmark call it on a bag's frames, so what they measure is what runs
// on the device.
#include <cmath>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include "assistive_vo/imu_buffer.h"
#include "assistive_vo/params.h"
#include "assistive_vo/startup_rule.h"
#include "assistive_vo/stereo_camera.h"
#include "assistive_vo/visual_odometry.h"

namespace assistive_vo
{
/// What the front end did with one stereo frame.
struct FrontEndStep
{
  /// False: the frame waited for the IMU (start-up rule) and VisualOdometry never saw it; `out`
  /// is then empty.
  bool processed = false;
  /// The start-up rule's decision on a frame before the VO started (`started_now` or a wait).
  bool startup_decided = false;
  StartupRule::Decision startup = StartupRule::Decision::START_WITHOUT_IMU;
  bool camera_changed = false;  ///< the calibration differed from the previous one: tracking re-initialised
  bool time_went_back = false;  ///< older than the previous processed frame (bag loop)
  /// Gyro and accelerometer integrated over the frame interval (ImuBuffer::integrate), handed to
  /// VisualOdometry::process; identity / zero without.
  bool have_gyro = false;
  Eigen::Quaterniond gyro = Eigen::Quaterniond::Identity();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero(), dp = Eigen::Vector3d::Zero();
  /// The accelerometer's up handed to VisualOdometry::setGravityHint for this frame.
  bool gravity_hint = false;
  Eigen::Vector3d up_hint = Eigen::Vector3d::Zero();
  VoOutput out;
};

/// How VoFrontEnd is fed (VoFrontEnd::Options).
struct VoFrontEndOptions
{
  /// The input carries an IMU (a bag without /imu/data: false). With VoParams::use_imu off the
  /// IMU is never used whatever this says.
  bool input_has_imu = true;
  double imu_wait_s = VoNodeParams().imu_wait;  ///< the start-up rule's wait for the IMU (image time)
  /// IMU samples kept (ImuBuffer): a stamp gap up to this long still gets its gyro and accelerometer
  /// integrals (VoParams::imu_bridge_gaps bridges it within imu_coast_max_s, 2.5 s).
  double imu_keep_s = 3.0;
};

class VoFrontEnd
{
public:
  using Options = VoFrontEndOptions;
  /// The gravity hint: the accelerometer's mean over kHintWindowS before the frame when its samples
  /// span at least kHintMinSpanS (a step's accelerations average out) and its norm is gravity's
  /// (kHintMinAccel, kHintMaxAccel) m/s^2.
  static constexpr double kHintWindowS = 0.5, kHintMinSpanS = 0.3, kHintMinAccel = 5.0, kHintMaxAccel = 15.0;
  /// The gyro's rate for a rolling shutter: its mean over the readout, at least this window.
  static constexpr double kMinRateWindowS = 0.01;

  explicit VoFrontEnd(const VoParams& p = VoParams(), const Options& o = Options());
  /// One IMU sample (camera_link axes, stamp order; an older one starts a new timeline). Samples up
  /// to a frame's stamp must be added before the frame.
  void addImu(double stamp, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel);
  /// One reading of the forward ranger (VisualOdometry::addRange), added before the frames after it,
  /// with the ranger's limits (sensor_msgs/Range): no echo (+inf, or outside them) measures nothing.
  void addRange(double stamp, double range, double min_range, double max_range, const Eigen::Vector3d& axis_link)
  {
    if (std::isfinite(range) && range >= min_range && range <= max_range)
      vo_.addRange(stamp, range, axis_link);
  }
  /// One stereo pair (mono8, rectified) with its calibration; a changed calibration re-initialises
  /// tracking (the pose chain is kept).
  FrontEndStep process(const StereoCamera& cam, const cv::Mat& left, const cv::Mat& right, double stamp);

  const VisualOdometry& vo() const { return vo_; }
  /// VisualOdometry::setKnownGyroBias.
  void setKnownGyroBias(const Eigen::Vector3d& bias_link, double sigma) { vo_.setKnownGyroBias(bias_link, sigma); }
  const ImuBuffer& imu() const { return imu_; }
  const StartupRule& startup() const { return startup_; }
  const Options& options() const { return o_; }
  bool useImu() const { return vo_.params().use_imu; }

private:
  Options o_;
  VisualOdometry vo_;
  ImuBuffer imu_;
  StartupRule startup_;
  double last_stamp_ = -1.0;  ///< the previous processed frame's stamp
};
}  // namespace assistive_vo
