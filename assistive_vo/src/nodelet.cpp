// assistive_vo/stereo_odometry: glue between ROS and the VisualOdometry core.
#include <memory>
#include <mutex>
#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/update_functions.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/Range.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <assistive_common/callback_guard.h>
#include <assistive_common/ros_params.h>
#include <assistive_common/wearer.h>

#include "assistive_vo/conversions.h"
#include "assistive_vo/vo_front_end.h"

namespace assistive_vo
{
namespace enc = sensor_msgs::image_encodings;

class StereoOdometryNodelet : public nodelet::Nodelet
{
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;
  using ExactPolicy = message_filters::sync_policies::ExactTime<Image, Info, Image, Info>;
  using ApproxPolicy = message_filters::sync_policies::ApproximateTime<Image, Info, Image, Info>;

  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    readParams(pnh);
    VoFrontEnd::Options fo;
    fo.imu_wait_s = node_.imu_wait;
    fe_ = std::make_unique<VoFrontEnd>(p_, fo);

    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 10);
    feat_pub_ = nh.advertise<sensor_msgs::Image>("features", 1);

    left_sub_.subscribe(nh, "left/image_rect", 2);
    left_info_sub_.subscribe(nh, "left/camera_info", 2);
    right_sub_.subscribe(nh, "right/image_rect", 2);
    right_info_sub_.subscribe(nh, "right/camera_info", 2);
    // Count raw arrivals so the watchdog can name the input that is missing or not in sync.
    left_sub_.registerCallback(&StereoOdometryNodelet::countLeft, this);
    left_info_sub_.registerCallback(&StereoOdometryNodelet::countLeftInfo, this);
    right_sub_.registerCallback(&StereoOdometryNodelet::countRight, this);
    right_info_sub_.registerCallback(&StereoOdometryNodelet::countRightInfo, this);
    if (node_.approximate_sync)
    {
      approx_ = std::make_shared<message_filters::Synchronizer<ApproxPolicy>>(
          ApproxPolicy(static_cast<uint32_t>(node_.queue_size)), left_sub_, left_info_sub_, right_sub_, right_info_sub_);
      approx_->registerCallback(&StereoOdometryNodelet::stereoCb, this);
    }
    else
    {
      exact_ = std::make_shared<message_filters::Synchronizer<ExactPolicy>>(
          ExactPolicy(static_cast<uint32_t>(node_.queue_size)), left_sub_, left_info_sub_, right_sub_, right_info_sub_);
      exact_->registerCallback(&StereoOdometryNodelet::stereoCb, this);
    }
    if (p_.use_imu)
      imu_sub_ = nh.subscribe("imu/data", 400, &StereoOdometryNodelet::imuCb, this);
    if (p_.use_imu && p_.range_aided_coast)
    {
      // the ranger's axis comes from tf (the URDF's sonar_front)
      tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
      tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
      range_sub_ = nh.subscribe("sonar/front", 20, &StereoOdometryNodelet::rangeCb, this);
    }

    diag_.setHardwareID("stereo_visual_odometry");
    diag_.add("status", this, &StereoOdometryNodelet::diagStatus);
    freq_ = std::make_unique<diagnostic_updater::FrequencyStatus>(
        diagnostic_updater::FrequencyStatusParam(&min_freq_, &max_freq_, 0.2, 10));
    diag_.add(*freq_);
    watchdog_ = nh.createWallTimer(ros::WallDuration(1.0), &StereoOdometryNodelet::watchdog, this);
  }

  void readParams(ros::NodeHandle& pnh)
  {
    for (const std::string& m : assistive_common::readParams(pnh, p_))
      NODELET_WARN("stereo_odometry: %s", m.c_str());
    for (const std::string& m : assistive_common::readParams(pnh, node_))
      NODELET_WARN("stereo_odometry: %s", m.c_str());
    // The wearer's eye height is the URDF's (robot_description); camera_height only without one.
    bool overridden = false;
    const std::string h = assistive_common::wearerCameraHeight(pnh, node_.base_frame, node_.footprint_frame,
                                                               "camera_height", p_.camera_height_m, &overridden);
    if (overridden)
      NODELET_WARN("stereo_odometry: %s", h.c_str());
    else
      NODELET_INFO("stereo_odometry: %s", h.c_str());
    for (const std::string& m : assistive_common::clampToTable(p_))
      NODELET_WARN("stereo_odometry: %s", m.c_str());
    if (p_.motion_solver != "points" && p_.motion_solver != "pointline" && p_.motion_solver != "points_lines")
      NODELET_WARN("stereo_odometry: motion_solver '%s' is neither 'points' nor 'pointline': using 'points'",
                   p_.motion_solver.c_str());
    min_freq_ = 0.5 * node_.expected_rate;
    max_freq_ = 2.0 * node_.expected_rate;
    NODELET_INFO("stereo_odometry: %s", assistive_common::describe(p_).c_str());
    NODELET_INFO("stereo_odometry: %s", assistive_common::describe(node_).c_str());
  }

  void countLeft(const sensor_msgs::ImageConstPtr&) { ++n_left_; }
  void countRight(const sensor_msgs::ImageConstPtr&) { ++n_right_; }
  void countLeftInfo(const sensor_msgs::CameraInfoConstPtr&) { ++n_left_info_; }
  void countRightInfo(const sensor_msgs::CameraInfoConstPtr&) { ++n_right_info_; }

  void imuCb(const sensor_msgs::ImuConstPtr& m)
  {
    assistive_common::guarded(getName(), "IMU sample", [&] { imu(m); });
  }

  void imu(const sensor_msgs::ImuConstPtr& m)
  {
    const Eigen::Vector3d w(m->angular_velocity.x, m->angular_velocity.y, m->angular_velocity.z);
    const Eigen::Vector3d a(m->linear_acceleration.x, m->linear_acceleration.y, m->linear_acceleration.z);
    if (!w.allFinite() || !a.allFinite())
    {
      NODELET_WARN_THROTTLE(5.0, "IMU sample with NaN/inf ignored");
      return;
    }
    if (!m->header.frame_id.empty() && m->header.frame_id != node_.base_frame)
      NODELET_WARN_THROTTLE(30.0, "IMU frame '%s' is not '%s': the gyro is assumed to be in %s axes",
                            m->header.frame_id.c_str(), node_.base_frame.c_str(), node_.base_frame.c_str());
    fe_->addImu(m->header.stamp.toSec(), w, a);
    ++n_imu_;
    if (pend_l_ && fe_->imu().latest() >= pend_l_->header.stamp.toSec() - 1e-4)
      flushPending();  // the frame waiting for its IMU interval has it now
  }

  void rangeCb(const sensor_msgs::RangeConstPtr& m)
  {
    assistive_common::guarded(getName(), "ranger reading", [&] { range(m); });
  }

  /// A forward ranger's reading (range_aided_coast), its axis from tf.
  void range(const sensor_msgs::RangeConstPtr& m)
  {
    if (range_frame_ != m->header.frame_id)
    {
      try
      {
        const Eigen::Isometry3d T = tf2::transformToEigen(
            tf_buffer_->lookupTransform(node_.base_frame, m->header.frame_id, ros::Time(0)));
        range_axis_ = T.linear() * Eigen::Vector3d::UnitX();
        range_frame_ = m->header.frame_id;
      }
      catch (const tf2::TransformException& e)
      {
        NODELET_WARN_THROTTLE(10.0, "ranger frame '%s' not on tf (%s): its readings do not aid the IMU coast",
                              m->header.frame_id.c_str(), e.what());
        return;
      }
    }
    fe_->addRange(m->header.stamp.toSec(), m->range, m->min_range, m->max_range, range_axis_);
  }

  /// With the IMU flowing but not yet up to this frame's stamp (the samples behind the images:
  /// they come from another process, the images from a nodelet in this manager), the frame would
  /// go without its gyro and accelerometer interval: tracked, it loses the gyro prior and restarts
  /// the coast's window; lost, it cannot coast and is untrusted at once (the closed-loop trial's
  /// stand at a plain wall, issue 34). Such a frame waits (imu_sync_wait, wall clock) for it.
  bool imuBehind(double t) const
  {
    if (!p_.use_imu || node_.imu_sync_wait <= 0.0 || !fe_->vo().started())
      return false;
    const double last = fe_->imu().latest();
    return last > 0.0 && last < t - 1e-4 && last > t - 0.5;
  }

  void flushPending()
  {
    if (!pend_l_)
      return;
    pend_timer_.stop();
    const sensor_msgs::ImageConstPtr l = pend_l_, r = pend_r_;
    const sensor_msgs::CameraInfoConstPtr li = pend_li_, ri = pend_ri_;
    pend_l_.reset();
    pend_r_.reset();
    pend_li_.reset();
    pend_ri_.reset();
    processFrame(l, li, r, ri);
  }

  void pendingTimeout(const ros::WallTimerEvent&)
  {
    assistive_common::guarded(getName(), "frame waiting for the IMU", [&] {
      if (pend_l_)
      {
        ++imu_wait_timeouts_;
        NODELET_WARN_THROTTLE(5.0, "stereo_odometry: the IMU did not reach the frame's stamp within imu_sync_wait (%.2f s)",
                              node_.imu_sync_wait);
      }
      flushPending();
    });
  }

  void watchdog(const ros::WallTimerEvent&)
  {
    assistive_common::guarded(getName(), "watchdog", [&] { checkInputs(); });
  }

  void checkInputs()
  {
    // Names the missing / unsynchronised input when images arrive but nothing gets processed.
    const bool stalled = n_processed_ == last_processed_;
    if (stalled && (n_left_ != last_left_ || n_right_ != last_right_))
    {
      if (n_left_info_ == 0 || n_right_info_ == 0)
        input_problem_ = "images arrive but no camera_info on " +
                         std::string(n_left_info_ == 0 ? "left/camera_info " : "") +
                         std::string(n_right_info_ == 0 ? "right/camera_info" : "");
      else if (n_left_ == last_left_ || n_right_ == last_right_)
        input_problem_ = std::string("only the ") + (n_left_ == last_left_ ? "right" : "left") + " image arrives";
      else
        input_problem_ = node_.approximate_sync ? "stereo inputs arrive but never pair up (approximate sync)"
                                           : "stereo inputs are not synchronised (stamps differ; "
                                             "exact sync, see approximate_sync)";
      NODELET_ERROR_THROTTLE(5.0, "stereo_odometry: %s", input_problem_.c_str());
    }
    else if (stalled && n_processed_ > 0)
    {
      input_problem_ = "no stereo input";
      NODELET_WARN_THROTTLE(10.0, "stereo_odometry: no stereo input for a while");
    }
    else if (!stalled)
      input_problem_.clear();
    last_left_ = n_left_;
    last_right_ = n_right_;
    last_processed_ = n_processed_;
    if (input_problem_ != last_problem_)
      diag_.force_update();
    else
      diag_.update();
    last_problem_ = input_problem_;
  }

  bool toMono(const sensor_msgs::ImageConstPtr& m, cv_bridge::CvImageConstPtr& out, const char* side)
  {
    try
    {
      if (m->encoding == enc::MONO8)
        out = cv_bridge::toCvShare(m, enc::MONO8);
      else if (m->encoding == enc::BGR8 || m->encoding == enc::RGB8 || m->encoding == enc::BGRA8 ||
               m->encoding == enc::RGBA8)
        out = cv_bridge::toCvShare(m, enc::MONO8);  // converted copy
      else
      {
        NODELET_ERROR_THROTTLE(5.0, "%s image has encoding '%s'; expected mono8 (or 8-bit colour)", side,
                               m->encoding.c_str());
        return false;
      }
    }
    catch (const cv_bridge::Exception& e)
    {
      NODELET_ERROR_THROTTLE(5.0, "%s image conversion failed: %s", side, e.what());
      return false;
    }
    return true;
  }

  void stereoCb(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
                const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri)
  {
    assistive_common::guarded(getName(), "stereo frame", [&] { stereo(l, li, r, ri); });
  }

  void stereo(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
              const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri)
  {
    flushPending();  // an older frame still waiting: now, with the IMU there is
    if (imuBehind(l->header.stamp.toSec()))
    {
      pend_l_ = l;
      pend_r_ = r;
      pend_li_ = li;
      pend_ri_ = ri;
      ++imu_waits_;
      pend_timer_ = getNodeHandle().createWallTimer(ros::WallDuration(node_.imu_sync_wait),
                                                    &StereoOdometryNodelet::pendingTimeout, this, true);
      return;
    }
    processFrame(l, li, r, ri);
  }

  void processFrame(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
                    const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri)
  {
    ++n_processed_;
    StereoCamera cam;
    std::string err;
    if (!fromMsg(*li, *ri, cam, &err))
    {
      NODELET_ERROR_THROTTLE(5.0, "stereo_odometry: %s; frame skipped", err.c_str());
      input_problem_ = err;
      publishUntrusted(l->header.stamp, err);
      return;
    }
    if (l->width != r->width || l->height != r->height || static_cast<int>(l->width) != cam.width ||
        static_cast<int>(l->height) != cam.height)
    {
      NODELET_ERROR_THROTTLE(5.0, "stereo_odometry: image sizes differ (left %ux%u, right %ux%u, camera_info %dx%d); "
                                  "frame skipped",
                             l->width, l->height, r->width, r->height, cam.width, cam.height);
      input_problem_ = "image sizes differ";
      publishUntrusted(l->header.stamp, input_problem_);
      return;
    }
    if (l->encoding != r->encoding)
      NODELET_WARN_THROTTLE(10.0, "left/right encodings differ ('%s' vs '%s')", l->encoding.c_str(),
                            r->encoding.c_str());
    cv_bridge::CvImageConstPtr lc, rc;
    if (!toMono(l, lc, "left") || !toMono(r, rc, "right"))
    {
      input_problem_ = "unsupported image encoding";
      publishUntrusted(l->header.stamp, input_problem_);
      return;
    }
    const double t = l->header.stamp.toSec();
    // The core's driving loop (vo_front_end.h): the start-up rule, the IMU integrals, the gravity
    // hint, then VisualOdometry; the benchmarks run the same.
    const FrontEndStep step = fe_->process(cam, lc->image, rc->image, t);
    if (step.camera_changed)
      NODELET_WARN("stereo_odometry: calibration changed, re-initialising tracking");
    if (step.time_went_back)
      NODELET_WARN_THROTTLE(5.0, "stereo_odometry: time went backwards (%.3f s, bag loop?): re-initialising", t);
    if (step.startup_decided)
    {
      if (step.startup == StartupRule::Decision::WAIT_FOR_IMU)
      {
        NODELET_INFO_THROTTLE(1.0, "stereo_odometry: waiting for the IMU (gravity) before starting (%.1f of %.1f s)",
                              fe_->startup().waited(t), node_.imu_wait);
        input_problem_ = "waiting for the IMU";
        return;
      }
      if (step.startup == StartupRule::Decision::START_WITHOUT_IMU && p_.use_imu)
        NODELET_WARN_ONCE("stereo_odometry: no IMU sample within %.1f s; gravity from initial_roll/initial_pitch "
                          "(%.1f / %.1f deg), no gyro prior until it comes",
                          node_.imu_wait, p_.initial_roll_deg, p_.initial_pitch_deg);
      if (p_.use_imu)
        input_problem_.clear();
    }
    const VoOutput& o = step.out;
    last_ = o;
    freq_->tick();
    if (!o.message.empty())
      NODELET_WARN_THROTTLE(2.0, "stereo_odometry: %s (%s)", o.message.c_str(), toString(o.state));
    if (!o.pose_valid || !o.T_odom_link.matrix().allFinite())
      return;
    if (o.pose_trusted != last_trusted_)
    {
      if (o.pose_trusted)
        NODELET_INFO("stereo_odometry: pose trusted");
      else
        NODELET_ERROR("stereo_odometry: pose not trusted: %s", o.untrusted_reason.c_str());
      last_trusted_ = o.pose_trusted;
      diag_.force_update();
    }
    // Every processed frame: an untrusted one carries the last trusted pose with
    // kUntrustedVariance and no tf, so nothing downstream guides on a guess.
    auto odom = boost::make_shared<nav_msgs::Odometry>(toOdometryMsg(o, l->header.stamp, node_.odom_frame, node_.base_frame));
    odom_pub_.publish(odom);
    if (node_.publish_tf && o.pose_trusted)
      tf_.sendTransform(toTransformMsg(o.T_odom_link, l->header.stamp, node_.odom_frame, node_.base_frame));
    if (feat_pub_.getNumSubscribers() > 0)
    {
      cv_bridge::CvImage ov(l->header, enc::BGR8, fe_->vo().drawOverlay(lc->image));
      feat_pub_.publish(ov.toImageMsg());
    }
  }

  /// A frame the core never saw (unusable calibration, size or encoding): downstream hears at once
  /// that the pose cannot be trusted (the last trusted pose, variances 9999, no tf) instead of
  /// hearing nothing until its inputs go stale.
  void publishUntrusted(const ros::Time& stamp, const std::string& why)
  {
    if (!last_.pose_valid)
      return;  // nothing published yet: downstream has no pose to distrust
    VoOutput u = last_;
    u.pose_trusted = false;
    u.untrusted_reason = why;
    u.linear_velocity.setZero();
    u.angular_velocity.setZero();
    if (last_trusted_)
      NODELET_ERROR("stereo_odometry: pose not trusted: %s", why.c_str());
    last_trusted_ = false;
    odom_pub_.publish(boost::make_shared<nav_msgs::Odometry>(toOdometryMsg(u, stamp, node_.odom_frame, node_.base_frame)));
  }

  void diagStatus(diagnostic_updater::DiagnosticStatusWrapper& s)
  {
    using diagnostic_msgs::DiagnosticStatus;
    if (!input_problem_.empty())
      s.summary(DiagnosticStatus::ERROR, input_problem_);
    else if (n_processed_ == 0)
      s.summary(DiagnosticStatus::WARN, "waiting for stereo input");
    else if (last_.pose_valid && !last_.pose_trusted)
      s.summary(DiagnosticStatus::ERROR, "pose not trusted: " + last_.untrusted_reason);
    else if (last_.state == TrackingState::TRACKING)
      s.summary(DiagnosticStatus::OK, "tracking");
    else if (last_.state == TrackingState::LOST)
      s.summary(DiagnosticStatus::ERROR, "lost: " + last_.message);
    else
      s.summary(DiagnosticStatus::WARN, std::string(toString(last_.state)) +
                                            (last_.message.empty() ? "" : ": " + last_.message));
    s.add("state", toString(last_.state));
    s.add("features", last_.stats.tracks);
    s.add("inliers", last_.stats.inliers);
    s.add("aligned_to_keyframe", last_.stats.aligned);
    s.add("ransac_trials", last_.stats.ransac_trials);
    s.add("ms_per_frame", last_.stats.ms_total);
    s.add("fast_threshold", last_.stats.fast_threshold);
    s.add("resets", fe_ ? fe_->vo().resets() : 0);
    s.add("imu_waits", imu_waits_);
    s.add("imu_wait_timeouts", imu_wait_timeouts_);
    s.add("pose_trusted", last_.pose_trusted);
    if (fe_)
    {
      const FailSafeCounters& f = fe_->vo().failSafe();
      s.add("untrusted_frames", f.untrusted_frames);
      s.add("frozen_camera", f.frozen);
      s.add("gyro_disagreement", f.gyro_disagreement);
      s.add("frame_gaps", f.gaps);
      s.add("frame_gaps_bridged", fe_->vo().gapsBridged());
      s.add("time_jumps", f.time_jumps);
      s.add("gravity_relevels", f.gravity_relevels);
      s.add("stereo_inconsistent", f.stereo_inconsistent);
    }
    s.add("frames", n_processed_);
    s.add("imu_samples", n_imu_);
    if (fe_)
    {
      s.add("gravity_tilt_deg", fe_->vo().gravity().lastTiltDeg());
      s.add("gravity_windows_accepted", fe_->vo().gravity().accepted());
      s.add("gravity_windows_rejected", fe_->vo().gravity().rejected());
      s.add("holding_still", fe_->vo().holdingStill());
      s.add("standing_holds", fe_->vo().standingHolds());
      s.add("standing_accel_sigma", fe_->vo().standingDetector().statistic());
    }
  }

  VoParams p_;
  std::unique_ptr<VoFrontEnd> fe_;
  VoNodeParams node_;
  double min_freq_ = 7.5, max_freq_ = 30.0;

  message_filters::Subscriber<Image> left_sub_, right_sub_;
  message_filters::Subscriber<Info> left_info_sub_, right_info_sub_;
  std::shared_ptr<message_filters::Synchronizer<ExactPolicy>> exact_;
  std::shared_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_;
  ros::Subscriber imu_sub_, range_sub_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::string range_frame_;  ///< the ranger's frame whose axis range_axis_ holds (camera_link axes)
  Eigen::Vector3d range_axis_ = Eigen::Vector3d::UnitX();
  ros::Publisher odom_pub_, feat_pub_;
  tf2_ros::TransformBroadcaster tf_;
  diagnostic_updater::Updater diag_;
  std::unique_ptr<diagnostic_updater::FrequencyStatus> freq_;
  ros::WallTimer watchdog_;
  // a frame waiting for its IMU interval (imuBehind)
  sensor_msgs::ImageConstPtr pend_l_, pend_r_;
  sensor_msgs::CameraInfoConstPtr pend_li_, pend_ri_;
  ros::WallTimer pend_timer_;
  int imu_waits_ = 0, imu_wait_timeouts_ = 0;

  VoOutput last_;
  bool last_trusted_ = false;
  std::string input_problem_, last_problem_;
  uint64_t n_left_ = 0, n_right_ = 0, n_left_info_ = 0, n_right_info_ = 0, n_imu_ = 0, n_processed_ = 0;
  uint64_t last_left_ = 0, last_right_ = 0, last_processed_ = 0;
};
}  // namespace assistive_vo

PLUGINLIB_EXPORT_CLASS(assistive_vo::StereoOdometryNodelet, nodelet::Nodelet)
