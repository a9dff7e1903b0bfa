// assistive_obstacles/obstacles: glue between ROS and the core's frame step (ObstacleFrameProcessor).
#include <atomic>
#include <deque>
#include <memory>
#include <mutex>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <message_filters/subscriber.h>
#include <message_filters/time_synchronizer.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Range.h>
#include <sensor_msgs/image_encodings.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_listener.h>

#include <assistive_common/callback_guard.h>
#include <assistive_common/ros_params.h>
#include <assistive_common/wearer.h>

#include <assistive_obstacles/conversions.h>
#include <assistive_obstacles/frame_processor.h>
#include <nav_msgs/Odometry.h>

namespace assistive_obstacles
{
using sensor_msgs::CameraInfo;
using sensor_msgs::Image;

class ObstaclesNodelet : public nodelet::Nodelet
{
  using ExactPolicy = message_filters::sync_policies::ExactTime<Image, Image, CameraInfo, CameraInfo>;
  using ApproxPolicy = message_filters::sync_policies::ApproximateTime<Image, Image, CameraInfo, CameraInfo>;

public:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    readParams(pnh);
    proc_ = std::make_unique<ObstacleFrameProcessor>(params_, node_.octomap_insert_every);
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>(ros::Duration(10.0));
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);

    pub_disp_ = nh.advertise<stereo_msgs::DisparityImage>("disparity", 1);
    pub_points_ = nh.advertise<sensor_msgs::PointCloud2>("points", 1);
    pub_grid_ = nh.advertise<nav_msgs::OccupancyGrid>("traversability", 1);
    pub_markers_ = nh.advertise<visualization_msgs::MarkerArray>("octomap_markers", 1);
    pub_dropout_ = nh.advertise<nav_msgs::OccupancyGrid>("dropout", 1);
    if (params_.movers)
    {
      pub_movers_ = nh.advertise<assistive_msgs::MoverArray>("movers", 1);
      pub_mover_markers_ = nh.advertise<visualization_msgs::MarkerArray>("movers_markers", 1);
    }
    srv_save_ = nh.advertiseService("save_octomap", &ObstaclesNodelet::saveOctomap, this);
    if (node_.use_odom)
      sub_odom_ = nh.subscribe("odom", 5, &ObstaclesNodelet::odomCb, this);
    if (params_.sonar_enabled)
      sub_sonar_ = nh.subscribe("sonar/front", 20, &ObstaclesNodelet::sonarCb, this);

    diag_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    diag_->setHardwareID("stereo camera");
    diag_->add("obstacle map", this, &ObstaclesNodelet::diagnose);
    diag_timer_ = nh.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) {
      assistive_common::guarded(getName(), "diagnostics", [&] { diag_->update(); });
    });

    if (params_.projected && params_.movers)
    {
      // the emitter-off pairs, for the movers' scene flow only (latest pair kept)
      sub_track_l_.subscribe(nh, "track/left/image_rect", 1);
      sub_track_r_.subscribe(nh, "track/right/image_rect", 1);
      track_sync_ = std::make_shared<message_filters::TimeSynchronizer<Image, Image>>(sub_track_l_, sub_track_r_,
                                                                                       node_.queue_size);
      track_sync_->registerCallback(&ObstaclesNodelet::trackCb, this);
    }
    sub_l_.subscribe(nh, "left/image_rect", 1);
    sub_r_.subscribe(nh, "right/image_rect", 1);
    sub_li_.subscribe(nh, "left/camera_info", 1);
    sub_ri_.subscribe(nh, "right/camera_info", 1);
    sub_l_.registerCallback(&ObstaclesNodelet::inputCb, this);
    // The left image waits for its pose in the tf filter (no blocking lookup in a callback); the
    // synchroniser pairs it with the rest of the frame afterwards.
    tf_filter_ = std::make_unique<tf2_ros::MessageFilter<Image>>(sub_l_, *tf_buffer_, node_.world_frame,
                                                                 node_.queue_size, nh);
    tf_filter_->registerFailureCallback(
        [this](const sensor_msgs::ImageConstPtr& l, tf2_ros::filter_failure_reasons::FilterFailureReason) {
          std::lock_guard<std::mutex> lock(stats_mutex_);
          ++tf_failures_;
          NODELET_WARN_THROTTLE(5.0, "obstacles: no pose %s -> %s at %.3f: frame dropped", node_.world_frame.c_str(),
                                l->header.frame_id.c_str(), l->header.stamp.toSec());
        });
    if (node_.approximate_sync)
    {
      approx_ = std::make_shared<message_filters::Synchronizer<ApproxPolicy>>(ApproxPolicy(node_.queue_size),
                                                                               *tf_filter_, sub_r_, sub_li_, sub_ri_);
      approx_->registerCallback(&ObstaclesNodelet::frameCb, this);
    }
    else
    {
      exact_ = std::make_shared<message_filters::Synchronizer<ExactPolicy>>(ExactPolicy(node_.queue_size), *tf_filter_,
                                                                             sub_r_, sub_li_, sub_ri_);
      exact_->registerCallback(&ObstaclesNodelet::frameCb, this);
    }
  }

private:
  void readParams(ros::NodeHandle& pnh)
  {
    ObstaclesParams& p = params_;
    for (const std::string& w : assistive_common::readParams(pnh, p)) NODELET_WARN("obstacles: %s", w.c_str());
    for (const std::string& w : assistive_common::readParams(pnh, node_)) NODELET_WARN("obstacles: %s", w.c_str());
    // The wearer's eye height is the URDF's (robot_description); camera_height only without one.
    bool overridden = false;
    const std::string h = assistive_common::wearerCameraHeight(pnh, node_.camera_frame, node_.footprint_frame,
                                                               "camera_height", p.camera_height, &overridden);
    if (overridden)
      NODELET_WARN("obstacles: %s", h.c_str());
    else
      NODELET_INFO("obstacles: %s", h.c_str());
    for (const std::string& w : clampParams(p)) NODELET_WARN("obstacles: %s", w.c_str());
    NODELET_INFO("obstacles: %s", assistive_common::describe(p).c_str());
    NODELET_INFO("obstacles: %s", assistive_common::describe(node_).c_str());
  }

  /// An active camera's emitter-off pair (`projected`): kept for the next emitter-on frame's movers.
  void trackCb(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::ImageConstPtr& r)
  {
    std::lock_guard<std::mutex> lock(track_mutex_);
    track_l_ = l;
    track_r_ = r;
  }

  /// Every left image, before it waits for its pose: the diagnostics tell "input stopped" from
  /// "no pose".
  void inputCb(const sensor_msgs::ImageConstPtr&)
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    last_input_ = ros::WallTime::now();
  }

  /// The forward ranger: queued, handed to the processor at the next frame (which applies the
  /// readings stamped up to that frame before its update, once their pose is on tf).
  void sonarCb(const sensor_msgs::Range::ConstPtr& m)
  {
    RangeSample r;
    r.stamp = m->header.stamp.toSec();
    r.range = m->range;
    r.min_range = m->min_range;
    r.max_range = m->max_range;
    r.field_of_view = m->field_of_view;
    r.frame = m->header.frame_id;
    std::lock_guard<std::mutex> lock(sonar_mutex_);
    sonar_pending_.push_back(r);
    while (sonar_pending_.size() > ObstacleFrameProcessor::MaxQueuedRanges) sonar_pending_.pop_front();
  }

  /// vo/odom marks a pose it cannot trust with variances of 9999: the map built on the old pose
  /// chain is dropped once the VO trusts its pose again.
  void odomCb(const nav_msgs::Odometry::ConstPtr& o)
  {
    constexpr double kUntrustedVariance = 9999.0;
    if (!(o->pose.covariance[0] < 0.5 * kUntrustedVariance)) pose_untrusted_ = true;
  }

  void frameCb(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::ImageConstPtr& r,
               const sensor_msgs::CameraInfoConstPtr& li, const sensor_msgs::CameraInfoConstPtr& ri)
  {
    if (!assistive_common::guarded(getName(), "stereo frame", [&] { frame(l, r, li, ri); }))
    {
      std::lock_guard<std::mutex> lock(stats_mutex_);
      ++bad_input_;
    }
  }

  void frame(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::ImageConstPtr& r,
             const sensor_msgs::CameraInfoConstPtr& li, const sensor_msgs::CameraInfoConstPtr& ri)
  {
    ObstacleFrame f;
    if (!fromMsg(*li, *ri, f.model) || f.model.width != static_cast<int>(l->width) ||
        f.model.height != static_cast<int>(l->height) || l->width != r->width || l->height != r->height)
    {
      NODELET_ERROR_THROTTLE(5.0, "obstacles: unusable stereo input (camera_info without fx/baseline or size mismatch)");
      std::lock_guard<std::mutex> lock(stats_mutex_);
      ++bad_input_;
      return;
    }
    cv_bridge::CvImageConstPtr cl, cr;
    try
    {
      cl = cv_bridge::toCvShare(l, sensor_msgs::image_encodings::MONO8);
      cr = cv_bridge::toCvShare(r, sensor_msgs::image_encodings::MONO8);
    }
    catch (const cv_bridge::Exception& e)
    {
      NODELET_ERROR_THROTTLE(5.0, "obstacles: cannot convert images to mono8: %s", e.what());
      std::lock_guard<std::mutex> lock(stats_mutex_);
      ++bad_input_;
      return;
    }
    f.stamp = l->header.stamp.toSec();
    f.left = cl->image;
    f.right = cr->image;
    f.pose_trusted = !pose_untrusted_.exchange(false);
    cv_bridge::CvImageConstPtr tl, tr;
    if (params_.projected && params_.movers)
    {
      // the movers track the emitter-off pair just before (its pose on tf: the VO tracked it)
      sensor_msgs::ImageConstPtr ml, mr;
      {
        std::lock_guard<std::mutex> lock(track_mutex_);
        ml = track_l_;
        mr = track_r_;
      }
      const double age = ml ? f.stamp - ml->header.stamp.toSec() : 1e9;
      try
      {
        if (ml && mr && age >= 0.0 && age < 0.1)
        {
          tl = cv_bridge::toCvShare(ml, sensor_msgs::image_encodings::MONO8);
          tr = cv_bridge::toCvShare(mr, sensor_msgs::image_encodings::MONO8);
          f.track_pose = tf2::transformToEigen(
              tf_buffer_->lookupTransform(node_.world_frame, ml->header.frame_id, ml->header.stamp));
          f.track_left = &tl->image;
          f.track_right = &tr->image;
          f.track_stamp = ml->header.stamp.toSec();
        }
      }
      catch (const std::exception& e)
      {
        f.track_left = f.track_right = nullptr;
        NODELET_WARN_THROTTLE(5.0, "obstacles: the emitter-off pair for the movers: %s", e.what());
      }
    }
    try
    {
      // Available: the tf filter let the left image through (no timeout, no wait).
      f.T_world_cam = tf2::transformToEigen(tf_buffer_->lookupTransform(node_.world_frame, l->header.frame_id,
                                                                        l->header.stamp));
    }
    catch (const tf2::TransformException& e)
    {
      f.has_pose = false;
      NODELET_WARN_THROTTLE(5.0, "obstacles: no pose %s -> %s at %.3f: %s", node_.world_frame.c_str(),
                            l->header.frame_id.c_str(), l->header.stamp.toSec(), e.what());
    }
    std::lock_guard<std::mutex> proc_lock(proc_mutex_);
    {
      std::lock_guard<std::mutex> lock(sonar_mutex_);
      for (const RangeSample& s : sonar_pending_) proc_->queueRange(s);
      sonar_pending_.clear();
    }
    const ObstacleFrameCounters before = proc_->counters();
    const ObstacleFrameResult& res = proc_->process(f, [this](const RangeSample& s, Eigen::Isometry3f& T) {
      try
      {
        T = tf2::transformToEigen(tf_buffer_->lookupTransform(node_.world_frame, s.frame, ros::Time(s.stamp))).cast<float>();
        return true;
      }
      catch (const tf2::TransformException& e)
      {
        NODELET_WARN_THROTTLE(5.0, "obstacles: ranger reading without a pose (%s): not used", e.what());
        return false;
      }
    });
    if (!res.disparity_ok)
    {
      NODELET_ERROR_THROTTLE(5.0, "obstacles: disparity failed (image %ux%u too small for %d disparities?)", l->width,
                             l->height, proc_->disparityEstimator().numDisparities());
      return;
    }
    if (res.cleared && !res.gate_reason.empty())
      NODELET_WARN_THROTTLE(2.0, "obstacles: %s", res.gate_reason.c_str());
    publish(res, f.model, l->header);
    updateStats(res, before);
  }

  /// What the processor gave, as messages (debug outputs only with subscribers).
  void publish(const ObstacleFrameResult& res, const StereoModel& model, const std_msgs::Header& header)
  {
    if (pub_disp_.getNumSubscribers() > 0)
      pub_disp_.publish(boost::make_shared<stereo_msgs::DisparityImage>(
          toDisparityMsg(proc_->disparity(), model, proc_->disparityEstimator().numDisparities(), header)));
    if (pub_points_.getNumSubscribers() > 0)
      pub_points_.publish(boost::make_shared<sensor_msgs::PointCloud2>(toCloudMsg(proc_->points(), header)));
    if (!res.map_updated) return;
    if (res.movers_enabled)
    {
      pub_movers_.publish(boost::make_shared<assistive_msgs::MoverArray>(
          toMoverArray(res.movers, res.feet_z, node_.world_frame, header.stamp)));
      if (pub_mover_markers_.getNumSubscribers() > 0)
        pub_mover_markers_.publish(boost::make_shared<visualization_msgs::MarkerArray>(
            toMoverMarkers(res.movers, res.feet_z, CrossingHorizonS, node_.world_frame, header.stamp)));
    }
    if (res.has_grid)
      pub_grid_.publish(boost::make_shared<nav_msgs::OccupancyGrid>(toMsg(res.grid, node_.world_frame, header.stamp)));
    if (pub_dropout_.getNumSubscribers() > 0)
      pub_dropout_.publish(boost::make_shared<nav_msgs::OccupancyGrid>(
          toMsg(proc_->map().dropout(), node_.world_frame, header.stamp)));
    if (res.octomap_inserted && pub_markers_.getNumSubscribers() > 0)
    {
      std::vector<Eigen::Vector3f> c;
      std::vector<float> s;
      proc_->map().octree().occupiedCenters(c, s);
      pub_markers_.publish(boost::make_shared<visualization_msgs::MarkerArray>(toMarkers(c, s, node_.world_frame, header.stamp)));
    }
  }
  /// The diagnostics' snapshot of this frame, and the warnings on its ranger readings.
  void updateStats(const ObstacleFrameResult& res, const ObstacleFrameCounters& before)
  {
    const ObstacleFrameCounters& now = proc_->counters();
    if (now.ranges_stale > before.ranges_stale)
      NODELET_WARN_THROTTLE(5.0, "obstacles: %ld ranger reading(s) from before the map's last clear: not used",
                            now.ranges_stale - before.ranges_stale);
    bool ranger_used = false;
    for (const AppliedRange& a : res.ranges)
    {
      if (a.check == RangeCheck::ECHO || a.check == RangeCheck::NO_ECHO)
        ranger_used = true;
      else
        NODELET_WARN_THROTTLE(5.0, "obstacles: ranger reading rejected (%s, range %.3f in [%.2f, %.2f]): not used",
                              rangeCheckName(a.check), a.sample.range, a.sample.min_range, a.sample.max_range);
    }
    std::lock_guard<std::mutex> lock(stats_mutex_);
    if (!res.has_pose)
    {
      ++tf_failures_;
      return;
    }
    counters_ = now;
    last_verdict_ = res.verdict;
    gate_reason_ = res.gate_reason;
    gate_clears_ = proc_->gate().clears();
    gate_no_depth_ = proc_->gate().noDepthFrames();
    if (res.verdict == FrameGate::Verdict::NO_DEPTH)
    {
      NODELET_WARN_THROTTLE(2.0, "obstacles: %s", res.gate_reason.c_str());
      return;
    }
    if (ranger_used) last_sonar_ = ros::WallTime::now();
    if (params_.sonar_enabled && counters_.ranges_echo + counters_.ranges_no_echo > 0 &&
        (ros::WallTime::now() - last_sonar_).toSec() > 1.0)
      NODELET_WARN_THROTTLE(5.0, "obstacles: no ranger reading for %.1f s: glass is not covered",
                            (ros::WallTime::now() - last_sonar_).toSec());
    if (const MoverPipeline* m = proc_->movers())
    {
      mover_count_ = static_cast<int>(res.movers.size());
      mover_cells_ = proc_->map().stats().mover_cells;
      ms_movers_ = res.ms_movers;
      ms_tracking_ = m->msTracking();
      flow_points_ = static_cast<int>(m->flow().size());
    }
    ms_disparity_ = res.ms_disparity;
    ms_map_ = res.ms_map;
    last_stats_ = proc_->map().stats();
    last_sonar_held_ = proc_->map().sonar().stats().held;
  }

  bool saveOctomap(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    if (!params_.octomap_enabled)
    {
      res.success = false;
      res.message = "octomap_enabled is false";
      return true;
    }
    {
      std::lock_guard<std::mutex> lock(proc_mutex_);
      res.success = proc_->map().octree().save(params_.octomap_save_path);
    }
    res.message = res.success ? params_.octomap_save_path : "cannot write " + params_.octomap_save_path;
    NODELET_INFO("obstacles: save_octomap -> %s (%s)", params_.octomap_save_path.c_str(), res.success ? "ok" : "FAILED");
    return true;
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st)
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    const double idle = (ros::WallTime::now() - last_input_).toSec();
    const long frames = counters_.frames;
    if (frames == 0)
      st.summary(diagnostic_msgs::DiagnosticStatus::WARN, tf_failures_ ? "no pose from tf" : "waiting for stereo input");
    else if (idle > 2.0)
      st.summary(diagnostic_msgs::DiagnosticStatus::WARN, "stereo input stopped: map stale");
    else if (last_verdict_ != FrameGate::Verdict::FRESH)
      st.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "no grid: " + gate_reason_);
    else if (last_stats_.dropout_cells > 0)
      st.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%d mapped obstacle cells lost their depth (glass / dropout)",
                  last_stats_.dropout_cells);
    else
      st.summary(diagnostic_msgs::DiagnosticStatus::OK, "mapping");
    st.add("frames", frames);
    st.add("ms disparity", ms_disparity_);
    st.add("ms map", ms_map_);
    st.add("points", last_stats_.points_in);
    st.add("cells observed", last_stats_.cells_observed);
    st.add("dropout cells", last_stats_.dropout_cells);
    st.add("tf failures", tf_failures_);
    st.add("bad inputs", bad_input_ + counters_.bad_input);
    st.add("map clears (gap / time jump)", gate_clears_);
    st.add("frames without depth", gate_no_depth_);
    const long sonar_used = counters_.ranges_echo + counters_.ranges_no_echo;
    st.add("ranger readings used", sonar_used);
    st.add("ranger readings rejected", counters_.ranges_rejected);
    if (!counters_.last_rejection.empty())
      st.add("last ranger rejection", counters_.last_rejection);
    st.add("ranger readings without pose", counters_.ranges_no_pose);
    st.add("ranger readings from before a map clear", counters_.ranges_stale);
    st.add("ranger", !params_.sonar_enabled ? std::string("disabled")
                     : sonar_used == 0 ? std::string("no reading yet (glass is not covered)")
                     : (ros::WallTime::now() - last_sonar_).toSec() > 1.0 ? std::string("silent for over 1 s (glass is not covered)")
                     : std::string("ok"));
    st.add("ranger-held cells", static_cast<int>(last_sonar_held_));
    st.add("movers", !params_.movers ? std::string("disabled") : std::to_string(mover_count_));
    if (params_.movers)
    {
      st.add("ms movers (flow + segmentation + tracking)", ms_movers_);
      st.add("ms mover tracking", ms_tracking_);
      st.add("mover flow points", flow_points_);
      st.add("cells kept out of the votes (movers)", mover_cells_);
    }
  }

  ObstaclesParams params_;
  ObstaclesNodeParams node_;
  std::unique_ptr<ObstacleFrameProcessor> proc_;  // the whole frame step (frame_processor.h)
  std::mutex proc_mutex_;  // frameCb and the save service run on different threads
  std::atomic<bool> pose_untrusted_{ false };  // set by odomCb, taken by the next frame
  static constexpr double CrossingHorizonS = 3.0;  // s, predicted path drawn in the markers (CrossingParams::horizon)
  ros::Subscriber sub_odom_, sub_sonar_;
  std::mutex sonar_mutex_;
  std::deque<RangeSample> sonar_pending_;  // under sonar_mutex_: arrived since the last frame
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  message_filters::Subscriber<Image> sub_l_, sub_r_;
  message_filters::Subscriber<Image> sub_track_l_, sub_track_r_;
  std::shared_ptr<message_filters::TimeSynchronizer<Image, Image>> track_sync_;
  std::mutex track_mutex_;
  sensor_msgs::ImageConstPtr track_l_, track_r_;
  std::unique_ptr<tf2_ros::MessageFilter<Image>> tf_filter_;
  message_filters::Subscriber<CameraInfo> sub_li_, sub_ri_;
  std::shared_ptr<message_filters::Synchronizer<ExactPolicy>> exact_;
  std::shared_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_;
  ros::Publisher pub_disp_, pub_points_, pub_grid_, pub_markers_, pub_dropout_, pub_movers_, pub_mover_markers_;
  ros::ServiceServer srv_save_;
  std::unique_ptr<diagnostic_updater::Updater> diag_;
  ros::Timer diag_timer_;
  // The diagnostics' snapshot, under stats_mutex_.
  std::mutex stats_mutex_;
  ros::WallTime last_input_, last_sonar_;
  ObstacleFrameCounters counters_;
  FrameGate::Verdict last_verdict_ = FrameGate::Verdict::REBUILDING;
  std::string gate_reason_;
  long gate_clears_ = 0, gate_no_depth_ = 0;
  FrameStats last_stats_;
  size_t last_sonar_held_ = 0;
  int mover_count_ = 0, mover_cells_ = 0, flow_points_ = 0;
  double ms_disparity_ = 0, ms_map_ = 0, ms_movers_ = 0, ms_tracking_ = 0;
  long tf_failures_ = 0, bad_input_ = 0;  // the nodelet's own: no pose on tf, messages it cannot convert
};

}  // namespace assistive_obstacles

PLUGINLIB_EXPORT_CLASS(assistive_obstacles::ObstaclesNodelet, nodelet::Nodelet)
