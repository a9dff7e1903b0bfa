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
#include <sensor_msgs/image_encodings.h>
#include <tf2_ros/transform_broadcaster.h>
#include "assistive_vo/conversions.h"
#include "assistive_vo/imu_buffer.h"
#include "assistive_vo/startup_rule.h"
#include "assistive_vo/visual_odometry.h"

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
    vo_ = std::make_unique<VisualOdometry>(p_);
    StartupRule::Options so;
    so.expect_imu = p_.use_imu;
    so.wait_s = imu_wait_;
    startup_.setOptions(so);

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
    if (approximate_sync_)
    {
      approx_ = std::make_shared<message_filters::Synchronizer<ApproxPolicy>>(
          ApproxPolicy(static_cast<uint32_t>(queue_size_)), left_sub_, left_info_sub_, right_sub_, right_info_sub_);
      approx_->registerCallback(&StereoOdometryNodelet::stereoCb, this);
    }
    else
    {
      exact_ = std::make_shared<message_filters::Synchronizer<ExactPolicy>>(
          ExactPolicy(static_cast<uint32_t>(queue_size_)), left_sub_, left_info_sub_, right_sub_, right_info_sub_);
      exact_->registerCallback(&StereoOdometryNodelet::stereoCb, this);
    }
    if (p_.use_imu)
      imu_sub_ = nh.subscribe("imu/data", 400, &StereoOdometryNodelet::imuCb, this);

    diag_.setHardwareID("stereo_visual_odometry");
    diag_.add("status", this, &StereoOdometryNodelet::diagStatus);
    freq_ = std::make_unique<diagnostic_updater::FrequencyStatus>(
        diagnostic_updater::FrequencyStatusParam(&min_freq_, &max_freq_, 0.2, 10));
    diag_.add(*freq_);
    watchdog_ = nh.createWallTimer(ros::WallDuration(1.0), &StereoOdometryNodelet::watchdog, this);
  }

  void readParams(ros::NodeHandle& pnh)
  {
    VoParams& p = p_;
    pnh.param("fast_threshold", p.fast_threshold, p.fast_threshold);
    pnh.param("target_features", p.target_features, p.target_features);
    pnh.param("replenish_ratio", p.replenish_ratio, p.replenish_ratio);
    pnh.param("min_tracks", p.min_tracks, p.min_tracks);
    pnh.param("replenish_coverage_ratio", p.replenish_coverage_ratio, p.replenish_coverage_ratio);
    pnh.param("max_disparity", p.max_disparity_px, p.max_disparity_px);
    pnh.param("stereo_half_window", p.stereo_half_window, p.stereo_half_window);
    pnh.param("klt_window", p.klt_window, p.klt_window);
    pnh.param("klt_levels", p.klt_levels, p.klt_levels);
    pnh.param("keyframe_alignment", p.keyframe_alignment, p.keyframe_alignment);
    pnh.param("alignment_half_window", p.alignment_half_window, p.alignment_half_window);
    pnh.param("alignment_iterations", p.alignment_iterations, p.alignment_iterations);
    pnh.param("alignment_max_shift", p.alignment_max_shift_px, p.alignment_max_shift_px);
    pnh.param("alignment_min_ncc", p.alignment_min_ncc, p.alignment_min_ncc);
    pnh.param("alignment_min_eigen_ratio", p.alignment_min_eigen_ratio, p.alignment_min_eigen_ratio);
    pnh.param("epipolar_filter", p.epipolar_filter, p.epipolar_filter);
    pnh.param("epipolar_threshold", p.epipolar_threshold_px, p.epipolar_threshold_px);
    pnh.param("ransac_probability", p.ransac_probability, p.ransac_probability);
    pnh.param("ransac_max_trials", p.ransac_max_trials, p.ransac_max_trials);
    pnh.param("inlier_threshold", p.inlier_threshold_px, p.inlier_threshold_px);
    pnh.param("min_inliers", p.min_inliers, p.min_inliers);
    pnh.param("ba_iterations", p.ba_iterations, p.ba_iterations);
    pnh.param("max_speed", p.max_speed_mps, p.max_speed_mps);
    pnh.param("max_angular_speed", p.max_angular_speed_dps, p.max_angular_speed_dps);
    pnh.param("max_frame_gap", p.max_frame_gap_s, p.max_frame_gap_s);
    pnh.param("coast_max", p.coast_max_s, p.coast_max_s);
    pnh.param("frozen_max_change", p.frozen_max_change, p.frozen_max_change);
    pnh.param("frozen_min_gyro_rate", p.frozen_min_gyro_dps, p.frozen_min_gyro_dps);
    pnh.param("frozen_frames", p.frozen_frames, p.frozen_frames);
    pnh.param("gyro_disagreement", p.gyro_disagreement_deg, p.gyro_disagreement_deg);
    pnh.param("gyro_disagreement_frames", p.gyro_disagreement_frames, p.gyro_disagreement_frames);
    pnh.param("stereo_max_error", p.stereo_max_error_px, p.stereo_max_error_px);
    pnh.param("stereo_min_matched_ratio", p.stereo_min_matched_ratio, p.stereo_min_matched_ratio);
    pnh.param("stereo_inconsistent_frames", p.stereo_inconsistent_frames, p.stereo_inconsistent_frames);
    pnh.param("use_imu", p.use_imu, p.use_imu);
    pnh.param("gyro_rotation_prior", p.gyro_rotation_prior, p.gyro_rotation_prior);
    pnh.param("gyro_noise_density", p.gyro_noise_density, p.gyro_noise_density);
    pnh.param("gyro_bias_sigma", p.gyro_bias_sigma, p.gyro_bias_sigma);
    pnh.param("gravity_time_constant", p.gravity_time_constant_s, p.gravity_time_constant_s);
    pnh.param("gravity_window", p.gravity_window_s, p.gravity_window_s);
    pnh.param("camera_height", p.camera_height_m, p.camera_height_m);
    pnh.param("initial_roll", p.initial_roll_deg, p.initial_roll_deg);
    pnh.param("initial_pitch", p.initial_pitch_deg, p.initial_pitch_deg);
    pnh.param("queue_size", queue_size_, queue_size_);
    pnh.param("approximate_sync", approximate_sync_, approximate_sync_);
    pnh.param("odom_frame", odom_frame_, odom_frame_);
    pnh.param("base_frame", base_frame_, base_frame_);
    pnh.param("publish_tf", publish_tf_, publish_tf_);
    pnh.param("expected_rate", expected_rate_, expected_rate_);
    pnh.param("imu_wait", imu_wait_, imu_wait_);

    auto clampI = [this](const char* n, int& v, int lo, int hi) {
      if (v < lo || v > hi)
      {
        NODELET_WARN("%s = %d out of [%d, %d], clamped", n, v, lo, hi);
        v = std::clamp(v, lo, hi);
      }
    };
    auto clampD = [this](const char* n, double& v, double lo, double hi) {
      if (!(v >= lo && v <= hi))
      {
        NODELET_WARN("%s = %g out of [%g, %g], clamped", n, v, lo, hi);
        v = std::isfinite(v) ? std::clamp(v, lo, hi) : lo;
      }
    };
    clampI("fast_threshold", p.fast_threshold, p.fast_threshold_min, p.fast_threshold_max);
    clampI("target_features", p.target_features, 20, 2000);
    clampD("replenish_ratio", p.replenish_ratio, 0.05, 0.95);
    clampI("min_tracks", p.min_tracks, 8, 1000);
    clampD("replenish_coverage_ratio", p.replenish_coverage_ratio, 0.0, 0.95);
    clampI("max_disparity", p.max_disparity_px, 8, 512);
    clampI("stereo_half_window", p.stereo_half_window, 1, 15);
    clampI("klt_window", p.klt_window, 5, 61);
    clampI("klt_levels", p.klt_levels, 0, 6);
    clampI("alignment_half_window", p.alignment_half_window, 2, 15);
    clampI("alignment_iterations", p.alignment_iterations, 1, 50);
    clampD("alignment_max_shift", p.alignment_max_shift_px, 0.1, 10.0);
    clampD("alignment_min_ncc", p.alignment_min_ncc, -1.0, 1.0);
    clampD("alignment_min_eigen_ratio", p.alignment_min_eigen_ratio, 0.0, 1.0);
    clampD("epipolar_threshold", p.epipolar_threshold_px, 0.1, 10.0);
    clampD("ransac_probability", p.ransac_probability, 0.5, 0.9999);
    clampI("ransac_max_trials", p.ransac_max_trials, 10, 10000);
    clampD("inlier_threshold", p.inlier_threshold_px, 0.3, 20.0);
    clampI("min_inliers", p.min_inliers, 6, 1000);
    clampI("ba_iterations", p.ba_iterations, 0, 100);
    clampD("max_speed", p.max_speed_mps, 0.1, 50.0);
    clampD("max_angular_speed", p.max_angular_speed_dps, 10.0, 5000.0);
    clampD("camera_height", p.camera_height_m, 0.0, 5.0);
    clampD("max_frame_gap", p.max_frame_gap_s, 0.05, 10.0);
    clampD("coast_max", p.coast_max_s, 0.0, 2.0);
    clampD("frozen_max_change", p.frozen_max_change, 0.0, 20.0);
    clampD("frozen_min_gyro_rate", p.frozen_min_gyro_dps, 0.1, 100.0);
    clampI("frozen_frames", p.frozen_frames, 1, 100);
    clampD("gyro_disagreement", p.gyro_disagreement_deg, 0.05, 90.0);
    clampI("gyro_disagreement_frames", p.gyro_disagreement_frames, 1, 100);
    clampD("stereo_max_error", p.stereo_max_error_px, 0.05, 50.0);
    clampD("stereo_min_matched_ratio", p.stereo_min_matched_ratio, 0.0, 1.0);
    clampI("stereo_inconsistent_frames", p.stereo_inconsistent_frames, 1, 100);
    clampD("gyro_noise_density", p.gyro_noise_density, 1e-6, 1e-1);
    clampD("gyro_bias_sigma", p.gyro_bias_sigma, 1e-6, 1.0);
    clampD("gravity_time_constant", p.gravity_time_constant_s, 0.0, 3600.0);
    clampD("gravity_window", p.gravity_window_s, 0.5, 60.0);
    clampI("queue_size", queue_size_, 1, 100);
    clampD("expected_rate", expected_rate_, 0.1, 200.0);
    clampD("imu_wait", imu_wait_, 0.0, 30.0);
    min_freq_ = 0.5 * expected_rate_;
    max_freq_ = 2.0 * expected_rate_;
    NODELET_INFO("stereo_odometry: fast_threshold %d, target_features %d, replenish %.2f, max_disparity %d, "
                 "ransac p %.3f (max %d), inlier thr %.2f px, min_inliers %d, ba_iterations %d, use_imu %d, "
                 "camera_height %.2f m, %s sync (queue %d), frames %s -> %s",
                 p.fast_threshold, p.target_features, p.replenish_ratio, p.max_disparity_px, p.ransac_probability,
                 p.ransac_max_trials, p.inlier_threshold_px, p.min_inliers, p.ba_iterations, p.use_imu,
                 p.camera_height_m, approximate_sync_ ? "approximate" : "exact", queue_size_, odom_frame_.c_str(),
                 base_frame_.c_str());
  }

  void countLeft(const sensor_msgs::ImageConstPtr&) { ++n_left_; }
  void countRight(const sensor_msgs::ImageConstPtr&) { ++n_right_; }
  void countLeftInfo(const sensor_msgs::CameraInfoConstPtr&) { ++n_left_info_; }
  void countRightInfo(const sensor_msgs::CameraInfoConstPtr&) { ++n_right_info_; }

  void imuCb(const sensor_msgs::ImuConstPtr& m)
  {
    const Eigen::Vector3d w(m->angular_velocity.x, m->angular_velocity.y, m->angular_velocity.z);
    const Eigen::Vector3d a(m->linear_acceleration.x, m->linear_acceleration.y, m->linear_acceleration.z);
    if (!w.allFinite() || !a.allFinite())
    {
      NODELET_WARN_THROTTLE(5.0, "IMU sample with NaN/inf ignored");
      return;
    }
    if (!m->header.frame_id.empty() && m->header.frame_id != base_frame_)
      NODELET_WARN_THROTTLE(30.0, "IMU frame '%s' is not '%s': the gyro is assumed to be in %s axes",
                            m->header.frame_id.c_str(), base_frame_.c_str(), base_frame_.c_str());
    imu_.add(m->header.stamp.toSec(), w, a);
    ++n_imu_;
  }

  void watchdog(const ros::WallTimerEvent&)
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
        input_problem_ = approximate_sync_ ? "stereo inputs arrive but never pair up (approximate sync)"
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
    const StereoCamera& cur = vo_->camera();
    if (cur.fx != cam.fx || cur.fy != cam.fy || cur.cx != cam.cx || cur.cy != cam.cy || cur.baseline != cam.baseline ||
        cur.width != cam.width || cur.height != cam.height)
    {
      if (cur.valid())
        NODELET_WARN("stereo_odometry: calibration changed, re-initialising tracking");
      vo_->setCamera(cam);
    }

    const double t = l->header.stamp.toSec();
    if (last_stamp_ > 0 && t < last_stamp_)
    {
      // The core keeps the pose and marks the frame untrusted (the same rule as vo_benchmark);
      // the IMU buffer dropped the old timeline when the first older sample came.
      NODELET_WARN_THROTTLE(5.0, "stereo_odometry: time went backwards (%.3f -> %.3f, bag loop?): re-initialising",
                            last_stamp_, t);
    }
    if (!vo_->started())
    {
      // The start-up rule of the core (startup_rule.h), the same as vo_benchmark's.
      Eigen::Vector3d up;
      const StartupRule::Decision d = startup_.decide(t, imu_, up);
      if (d == StartupRule::Decision::START_WITH_GRAVITY)
        vo_->setInitialUp(up);
      else if (d == StartupRule::Decision::WAIT_FOR_IMU)
      {
        NODELET_INFO_THROTTLE(1.0, "stereo_odometry: waiting for the IMU (gravity) before starting (%.1f of %.1f s)",
                              startup_.waited(t), imu_wait_);
        input_problem_ = "waiting for the IMU";
        return;
      }
      else if (p_.use_imu)
        NODELET_WARN_ONCE("stereo_odometry: no IMU sample within %.1f s; gravity from initial_roll/initial_pitch "
                          "(%.1f / %.1f deg), no gyro prior until it comes",
                          imu_wait_, p_.initial_roll_deg, p_.initial_pitch_deg);
      if (p_.use_imu)
        input_problem_.clear();
    }
    Eigen::Quaterniond gyro;
    Eigen::Vector3d dv;
    bool have_gyro = false;
    if (p_.use_imu && !imu_.empty() && last_stamp_ > 0 && t > last_stamp_)
      have_gyro = imu_.integrate(last_stamp_, t, gyro, dv);
    last_stamp_ = t;
    // Gravity over the last 0.5 s (at least 0.3 s of samples: a step's accelerations average
    // out); the core levels the pose by it after a gap the gyro does not cover.
    Eigen::Vector3d up;
    double span = 0.0;
    if (p_.use_imu && imu_.meanAccel(t, 0.5, up, &span) && span >= 0.3 && up.norm() > 5.0 && up.norm() < 15.0)
      vo_->setGravityHint(up);

    const VoOutput o =
        vo_->process(lc->image, rc->image, t, have_gyro ? &gyro : nullptr, have_gyro ? &dv : nullptr);
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
    auto odom = boost::make_shared<nav_msgs::Odometry>(toOdometryMsg(o, l->header.stamp, odom_frame_, base_frame_));
    odom_pub_.publish(odom);
    if (publish_tf_ && o.pose_trusted)
      tf_.sendTransform(toTransformMsg(o.T_odom_link, l->header.stamp, odom_frame_, base_frame_));
    if (feat_pub_.getNumSubscribers() > 0)
    {
      cv_bridge::CvImage ov(l->header, enc::BGR8, vo_->drawOverlay(lc->image));
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
    odom_pub_.publish(boost::make_shared<nav_msgs::Odometry>(toOdometryMsg(u, stamp, odom_frame_, base_frame_)));
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
    s.add("resets", vo_ ? vo_->resets() : 0);
    s.add("pose_trusted", last_.pose_trusted);
    if (vo_)
    {
      const FailSafeCounters& f = vo_->failSafe();
      s.add("untrusted_frames", f.untrusted_frames);
      s.add("frozen_camera", f.frozen);
      s.add("gyro_disagreement", f.gyro_disagreement);
      s.add("frame_gaps", f.gaps);
      s.add("time_jumps", f.time_jumps);
      s.add("gravity_relevels", f.gravity_relevels);
      s.add("stereo_inconsistent", f.stereo_inconsistent);
    }
    s.add("frames", n_processed_);
    s.add("imu_samples", n_imu_);
    if (vo_)
    {
      s.add("gravity_tilt_deg", vo_->gravity().lastTiltDeg());
      s.add("gravity_windows_accepted", vo_->gravity().accepted());
      s.add("gravity_windows_rejected", vo_->gravity().rejected());
    }
  }

  VoParams p_;
  std::unique_ptr<VisualOdometry> vo_;
  ImuBuffer imu_;
  int queue_size_ = 5;
  bool approximate_sync_ = false;
  std::string odom_frame_ = "odom", base_frame_ = "camera_link";
  bool publish_tf_ = true;
  double expected_rate_ = 15.0, min_freq_ = 7.5, max_freq_ = 30.0;

  message_filters::Subscriber<Image> left_sub_, right_sub_;
  message_filters::Subscriber<Info> left_info_sub_, right_info_sub_;
  std::shared_ptr<message_filters::Synchronizer<ExactPolicy>> exact_;
  std::shared_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_;
  ros::Subscriber imu_sub_;
  ros::Publisher odom_pub_, feat_pub_;
  tf2_ros::TransformBroadcaster tf_;
  diagnostic_updater::Updater diag_;
  std::unique_ptr<diagnostic_updater::FrequencyStatus> freq_;
  ros::WallTimer watchdog_;

  VoOutput last_;
  bool last_trusted_ = false;
  double last_stamp_ = -1.0;
  StartupRule startup_;
  double imu_wait_ = 1.0;         // s of image time
  std::string input_problem_, last_problem_;
  uint64_t n_left_ = 0, n_right_ = 0, n_left_info_ = 0, n_right_info_ = 0, n_imu_ = 0, n_processed_ = 0;
  uint64_t last_left_ = 0, last_right_ = 0, last_processed_ = 0;
};
}  // namespace assistive_vo

PLUGINLIB_EXPORT_CLASS(assistive_vo::StereoOdometryNodelet, nodelet::Nodelet)
