#include "assistive_vo/vo_front_end.h"

namespace assistive_vo
{
VoFrontEnd::VoFrontEnd(const VoParams& p, const Options& o) : o_(o), vo_(p), imu_(o.imu_keep_s)
{
  StartupRule::Options so;
  so.expect_imu = p.use_imu && o.input_has_imu;
  so.wait_s = o.imu_wait_s;
  startup_.setOptions(so);
}

void VoFrontEnd::addImu(double stamp, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel)
{
  imu_.add(stamp, gyro, accel);
}

FrontEndStep VoFrontEnd::process(const StereoCamera& cam, const cv::Mat& left, const cv::Mat& right, double stamp)
{
  FrontEndStep s;
  const StereoCamera& cur = vo_.camera();
  if (cur.fx != cam.fx || cur.fy != cam.fy || cur.cx != cam.cx || cur.cy != cam.cy || cur.baseline != cam.baseline ||
      cur.width != cam.width || cur.height != cam.height)
  {
    s.camera_changed = cur.valid();  // the first calibration is no change
    vo_.setCamera(cam);
  }
  // The core keeps the pose and marks the frame untrusted; the IMU buffer dropped the old
  // timeline when the first older sample came.
  s.time_went_back = last_stamp_ > 0 && stamp < last_stamp_;
  if (!vo_.started())
  {
    Eigen::Vector3d up;
    s.startup_decided = true;
    s.startup = startup_.decide(stamp, imu_, up);
    if (s.startup == StartupRule::Decision::WAIT_FOR_IMU)
      return s;
    if (s.startup == StartupRule::Decision::START_WITH_GRAVITY)
      vo_.setInitialUp(up);
  }
  const bool use_imu = useImu();
  if (use_imu && last_stamp_ > 0 && stamp > last_stamp_)
    s.have_gyro = imu_.integrate(last_stamp_, stamp, s.gyro, s.dv, s.dp);
  last_stamp_ = stamp;
  // The core levels the pose by the hint after a gap the gyro does not cover.
  double span = 0.0;
  Eigen::Vector3d up;
  if (use_imu && imu_.meanAccel(stamp, kHintWindowS, up, &span) && span >= kHintMinSpanS &&
      up.norm() > kHintMinAccel && up.norm() < kHintMaxAccel)
  {
    vo_.setGravityHint(up);
    s.gravity_hint = true;
    s.up_hint = up;
  }
  // The rolling shutter's rows span stamp +- readout / 2: the gyro's mean rate over that window
  // (as far as the buffer reaches; its last sample held beyond).
  Eigen::Vector3d rate;
  const double readout = vo_.params().rolling_shutter_readout_s;
  if (use_imu && readout > 0 && imu_.meanRate(stamp, std::max(readout, kMinRateWindowS), rate))
    vo_.setGyroRateAtStamp(rate);
  s.out = vo_.process(left, right, stamp, s.have_gyro ? &s.gyro : nullptr, s.have_gyro ? &s.dv : nullptr,
                      s.have_gyro ? &s.dp : nullptr);
  s.processed = true;
  return s;
}
}  // namespace assistive_vo
