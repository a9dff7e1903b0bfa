// Glue: params, camera_info_manager, the capture thread calling StereoCamera::grab(),
// publishing and diagnostics. No pixel work here.
#include <assistive_common/callback_guard.h>
#include <assistive_common/ros_params.h>
#include <assistive_description/conversions.h>
#include <assistive_description/stereo_camera.h>

#include <camera_info_manager/camera_info_manager.h>
#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/image_encodings.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <thread>

namespace assistive_description
{
class StereoCameraNodelet : public nodelet::Nodelet
{
public:
  ~StereoCameraNodelet() override
  {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    StereoCameraParams& p = params_;
    std::vector<std::string> clamped = assistive_common::readParams(pnh, p);
    for (const std::string& msg : p.clamp())
      clamped.push_back(msg);  // the rules a range cannot say
    for (const std::string& msg : clamped) NODELET_WARN("%s", msg.c_str());
    NODELET_INFO("stereo_camera: device %s %dx%d @ %.1f Hz %s, swap_halves %d, time_offset %.4f s, "
                 "retry_period %.1f s, frames %s / %s, calibration '%s' / '%s'",
                 p.device.c_str(), p.width, p.height, p.fps, p.fourcc.c_str(), p.swap_halves,
                 p.time_offset, p.retry_period, p.left_frame_id.c_str(), p.right_frame_id.c_str(),
                 p.left_camera_info_url.c_str(), p.right_camera_info_url.c_str());

    // camera_info_manager: set_camera_info services in left/ and right/ (camera_calibration).
    left_info_ = std::make_unique<camera_info_manager::CameraInfoManager>(
        ros::NodeHandle(nh, "left"), p.left_camera_name, p.left_camera_info_url);
    right_info_ = std::make_unique<camera_info_manager::CameraInfoManager>(
        ros::NodeHandle(nh, "right"), p.right_camera_name, p.right_camera_info_url);

    std::unique_ptr<FrameSource> source = makeFrameSource(p);
    std::unique_ptr<EmitterControl> emitter = makeEmitterControl(p, *source);
    camera_ = std::make_unique<StereoCamera>(std::move(source), p, std::move(emitter));

    image_transport::ImageTransport it(nh);
    left_rect_pub_ = it.advertiseCamera("left/image_rect", 1);
    right_rect_pub_ = it.advertiseCamera("right/image_rect", 1);
    left_raw_pub_ = it.advertise("left/image_raw", 1);
    right_raw_pub_ = it.advertise("right/image_raw", 1);
    if (p.emitter == "alternate")
    {
      // an active camera: its emitter-on pairs (the projector's dots: for disparity, never tracking)
      left_projected_pub_ = it.advertiseCamera("projected/left/image_rect", 1);
      right_projected_pub_ = it.advertiseCamera("projected/right/image_rect", 1);
    }

    updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    updater_->setHardwareID(p.device);
    updater_->add("Camera", this, &StereoCameraNodelet::diagnoseCamera);
    min_rate_ = max_rate_ = p.fps;
    source_name_ = camera_->source().describe();
    rate_diag_ = std::make_unique<diagnostic_updater::TopicDiagnostic>(
        "left/image_rect", *updater_,
        diagnostic_updater::FrequencyStatusParam(&min_rate_, &max_rate_, 0.2, 10),
        diagnostic_updater::TimeStampStatusParam(-1.0, 1.0));
    diag_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
      assistive_common::guarded(getName(), "diagnostics", [&] { updater_->update(); });
    });

    running_ = true;
    thread_ = std::thread(&StereoCameraNodelet::captureLoop, this);
  }

  /// Rebuild the rectification maps when camera_info_manager's calibration changed (loaded at
  /// start or set through set_camera_info by camera_calibration).
  void updateCalibration()
  {
    const CameraCalibration l = fromMsg(left_info_->getCameraInfo());
    const CameraCalibration r = fromMsg(right_info_->getCameraInfo());
    if (have_calib_ && l == left_calib_ && r == right_calib_) return;
    const bool first = !have_calib_;
    have_calib_ = true;
    left_calib_ = l;
    right_calib_ = r;
    std::string err;
    std::vector<std::string> warnings;
    if (camera_->setCalibration(l, r, &err, &warnings))
    {
      NODELET_INFO("stereo_camera: calibration %dx%d per eye, baseline %.4f m; rectification "
                   "maps built", l.width, l.height, r.baseline());
      for (const std::string& w : warnings) NODELET_WARN("stereo_camera: %s", w.c_str());
      // The kept correction belongs to the calibration loaded at start; a new one (set_camera_info)
      // starts from nothing, and what was kept is cleared.
      if (first)
        restoreSelfCalibration();
      else if (camera_->selfCalibration())
        keepSelfCalibration();
      std::lock_guard<std::mutex> lock(mutex_);
      calib_status_ = "calibrated";
    }
    else
    {
      NODELET_ERROR("stereo_camera: cannot use the calibration (%s); publishing raw images only. "
                    "Calibrate (README) or set left/right_camera_info_url.", err.c_str());
      std::lock_guard<std::mutex> lock(mutex_);
      calib_status_ = "not usable: " + err;
    }
  }

  /// The self-calibration's file: the parameter, else $ROS_HOME (~/.ros) per right camera name.
  std::string selfCalibrationPath() const
  {
    if (params_.self_calibration_file == "none") return std::string();
    if (!params_.self_calibration_file.empty()) return params_.self_calibration_file;
    const char* ros_home = std::getenv("ROS_HOME");
    const char* home = std::getenv("HOME");
    const std::string dir = ros_home ? ros_home : std::string(home ? home : ".") + "/.ros";
    return dir + "/self_calibration_" + params_.right_camera_name + ".yaml";
  }

  /// A correction kept from an earlier run of this rig starts the maps (the estimate goes on).
  void restoreSelfCalibration()
  {
    const std::string path = selfCalibrationPath();
    if (!params_.self_calibration || path.empty()) return;
    cv::Vec3d w;
    std::string err;
    if (!loadSelfCalibration(path, params_.right_camera_name, w, &err))
    {
      NODELET_INFO("stereo_camera: self-calibration starts from the calibration as given (%s)", err.c_str());
      return;
    }
    camera_->restoreSelfCalibration(w);
    const cv::Vec3d d = w * (180.0 / M_PI);
    NODELET_INFO("stereo_camera: self-calibration: right camera turned %.4f / %.4f / %.4f deg (pitch / yaw / roll) "
                 "kept from an earlier run (%s)", d[0], d[1], d[2], path.c_str());
  }

  /// After a new correction went into the maps: say so and keep it.
  void keepSelfCalibration()
  {
    const StereoSelfCalibration* cal = camera_->selfCalibration();
    const cv::Vec3d d = cal->applied() * (180.0 / M_PI), sd = cal->rotationSigma() * (180.0 / M_PI);
    NODELET_INFO("stereo_camera: self-calibration: right camera turned %.4f / %.4f / %.4f deg (pitch / yaw / roll, "
                 "sigma %.4f / %.4f / %.4f) over %d frames: undone in the right rectification",
                 d[0], d[1], d[2], sd[0], sd[1], sd[2], cal->frameSolutions());
    const std::string path = selfCalibrationPath();
    std::string err;
    if (!path.empty() && !saveSelfCalibration(path, params_.right_camera_name, *cal, &err))
      NODELET_WARN("stereo_camera: self-calibration not kept: %s", err.c_str());
  }

  void captureLoop()
  {
    StereoOutput out;
    while (running_ && ros::ok())
    {
      // An exception escaping this thread would end the whole manager process: log it, go on.
      if (!assistive_common::guarded(getName(), "capture", [&] { captureOnce(out); }))
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }

  void captureOnce(StereoOutput& out)
  {
    updateCalibration();
    const GrabStatus status = camera_->grab(monotonicNow(), out);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (const StereoSelfCalibration* cal = camera_->selfCalibration())
        self_cal_ = *cal;
      status_ = status;
      open_ = camera_->isOpen();
      frames_ = camera_->frames();
      rate_ = camera_->frameRate();
      if (status != GrabStatus::OK && status != GrabStatus::WAITING_TO_RETRY)
        last_error_ = camera_->lastError();
    }
    switch (status)
    {
      case GrabStatus::OK:
        publish(out);
        camera_->selfCalibrate(out);  // after publishing: not in the images' latency
        if (camera_->takeSelfCalibrationChange()) keepSelfCalibration();
        break;
      case GrabStatus::WAITING_TO_RETRY:
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        break;
      case GrabStatus::OPEN_FAILED:
      case GrabStatus::READ_FAILED:
        NODELET_ERROR_THROTTLE(10.0, "stereo_camera: %s (%s); retrying every %.1f s",
                                camera_->lastError().c_str(), toString(status),
                                params_.retry_period);
        break;
      case GrabStatus::BAD_FRAME:
      case GrabStatus::STALE_STAMP:
        NODELET_ERROR_THROTTLE(10.0, "stereo_camera: %s", camera_->lastError().c_str());
        break;
    }
  }

  void publish(const StereoOutput& out)
  {
    std_msgs::Header lh, rh;
    lh.stamp = rh.stamp = ros::Time(out.stamp);
    lh.frame_id = params_.left_frame_id;
    rh.frame_id = params_.right_frame_id;
    namespace enc = sensor_msgs::image_encodings;
    if (left_raw_pub_.getNumSubscribers() > 0)
      left_raw_pub_.publish(cv_bridge::CvImage(lh, rawEncoding(out.left_raw), out.left_raw).toImageMsg());
    if (right_raw_pub_.getNumSubscribers() > 0)
      right_raw_pub_.publish(
          cv_bridge::CvImage(rh, rawEncoding(out.right_raw), out.right_raw).toImageMsg());
    if (!out.rectified)
    {
      NODELET_WARN_THROTTLE(10.0, "stereo_camera: %s", camera_->lastWarning().c_str());
      return;
    }
    auto linfo = boost::make_shared<sensor_msgs::CameraInfo>(
        toMsg(camera_->leftRectifier().rectifiedCalibration()));
    auto rinfo = boost::make_shared<sensor_msgs::CameraInfo>(
        toMsg(camera_->rightRectifier().rectifiedCalibration()));
    linfo->header = lh;
    rinfo->header = rh;
    if (!camera_->emitterError().empty())
      NODELET_WARN_THROTTLE(10.0, "stereo_camera: %s", camera_->emitterError().c_str());
    if (out.emitter_on)
    {
      left_projected_pub_.publish(cv_bridge::CvImage(lh, enc::MONO8, out.left_rect).toImageMsg(), linfo);
      right_projected_pub_.publish(cv_bridge::CvImage(rh, enc::MONO8, out.right_rect).toImageMsg(), rinfo);
      return;
    }
    left_rect_pub_.publish(cv_bridge::CvImage(lh, enc::MONO8, out.left_rect).toImageMsg(), linfo);
    right_rect_pub_.publish(cv_bridge::CvImage(rh, enc::MONO8, out.right_rect).toImageMsg(), rinfo);
    rate_diag_->tick(lh.stamp);
  }

  static std::string rawEncoding(const cv::Mat& m)
  {
    namespace enc = sensor_msgs::image_encodings;
    return m.channels() == 1 ? enc::MONO8 : m.channels() == 4 ? enc::BGRA8 : enc::BGR8;
  }

  void diagnoseCamera(diagnostic_updater::DiagnosticStatusWrapper& stat)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool open = open_;
    if (status_ == GrabStatus::OK && calib_status_ == "calibrated")
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "streaming");
    else if (status_ == GrabStatus::OK)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "streaming raw only: " + calib_status_);
    else if (!open)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "device not open: " + last_error_);
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, last_error_);
    stat.add("device", source_name_);
    stat.add("state", open ? "open" : "closed (retrying)");
    stat.add("last status", toString(status_));
    stat.add("last error", last_error_);
    stat.add("calibration", calib_status_);
    stat.add("frames", frames_);
    stat.add("measured rate (Hz)", rate_);
    stat.add("requested rate (Hz)", params_.fps);
    if (params_.self_calibration)
    {
      const cv::Vec3d w = self_cal_.rotation() * (180.0 / M_PI), sw = self_cal_.rotationSigma() * (180.0 / M_PI);
      const cv::Vec3d a = self_cal_.applied() * (180.0 / M_PI);
      char buf[200];
      std::snprintf(buf, sizeof buf, "%.4f / %.4f / %.4f (sigma %.4f / %.4f / %.4f)", w[0], w[1], w[2], sw[0], sw[1],
                    sw[2]);
      stat.add("self-calibration estimate, right camera pitch / yaw / roll (deg)",
               self_cal_.valid() ? std::string(buf) : "gathering (" + std::to_string(self_cal_.frameSolutions()) + " frames)");
      std::snprintf(buf, sizeof buf, "%.4f / %.4f / %.4f", a[0], a[1], a[2]);
      stat.add("self-calibration applied (deg)", buf);
      stat.add("self-calibration status", self_cal_.status().empty() ? "applied" : self_cal_.status());
      // An estimate too large to be a worn rig's drift: the rig was knocked or the calibration is wrong.
      if (self_cal_.status().find("beyond") != std::string::npos)
        stat.mergeSummary(diagnostic_msgs::DiagnosticStatus::WARN,
                          "self-calibration: " + self_cal_.status() + " (recalibrate the rig)");
    }
    if (params_.emitter == "alternate")
    {
      stat.add("emitter", camera_->emitterError().empty() ? "alternating" : camera_->emitterError());
      stat.add("emitter phase locked", camera_->emitterPhase().locked());
      stat.add("emitter resyncs", camera_->emitterPhase().resyncs());
    }
  }

  StereoCameraParams params_;
  std::unique_ptr<camera_info_manager::CameraInfoManager> left_info_, right_info_;
  std::unique_ptr<StereoCamera> camera_;
  CameraCalibration left_calib_, right_calib_;
  bool have_calib_ = false;
  image_transport::CameraPublisher left_rect_pub_, right_rect_pub_;
  image_transport::CameraPublisher left_projected_pub_, right_projected_pub_;
  image_transport::Publisher left_raw_pub_, right_raw_pub_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  std::unique_ptr<diagnostic_updater::TopicDiagnostic> rate_diag_;
  double min_rate_ = 0.0, max_rate_ = 0.0;
  ros::WallTimer diag_timer_;
  std::mutex mutex_;
  // Written by the capture thread, read by diagnostics (under mutex_).
  GrabStatus status_ = GrabStatus::WAITING_TO_RETRY;
  bool open_ = false;
  unsigned long long frames_ = 0;
  double rate_ = 0.0;
  std::string source_name_;
  std::string last_error_, calib_status_ = "not loaded yet";
  StereoSelfCalibration self_cal_;  // a copy of the camera's, for diagnostics
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace assistive_description

PLUGINLIB_EXPORT_CLASS(assistive_description::StereoCameraNodelet, nodelet::Nodelet)
