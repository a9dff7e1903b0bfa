// assistive_obstacles/obstacles: glue between ROS and the core (disparity, ObstacleMap).
#include <chrono>
#include <deque>
#include <memory>
#include <mutex>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <message_filters/subscriber.h>
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
#include <assistive_obstacles/disparity.h>
#include <assistive_obstacles/frame_gate.h>
#include <assistive_obstacles/mover_pipeline.h>
#include <assistive_obstacles/obstacle_map.h>
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
    disparity_ = std::make_unique<DisparityEstimator>(params_);
    map_ = std::make_unique<ObstacleMap>(params_);
    gate_ = FrameGate({ params_.max_frame_gap_s, params_.rebuild_frames, params_.min_fresh_points });
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

  /// Every left image, before it waits for its pose: the diagnostics tell "input stopped" from
  /// "no pose".
  void inputCb(const sensor_msgs::ImageConstPtr&)
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    last_input_ = ros::WallTime::now();
  }

  /// The forward ranger: queued, applied before the next frame's update once its pose is on tf.
  void sonarCb(const sensor_msgs::Range::ConstPtr& r)
  {
    std::lock_guard<std::mutex> lock(sonar_mutex_);
    sonar_queue_.push_back(r);
    while (sonar_queue_.size() > 100) sonar_queue_.pop_front();  // no frames: keep the latest 5 s
  }

  /// Readings stamped up to `stamp` into the map (tf world_frame <- the reading's frame).
  void applySonar(const ros::Time& stamp)
  {
    std::deque<sensor_msgs::Range::ConstPtr> ready;
    {
      std::lock_guard<std::mutex> lock(sonar_mutex_);
      while (!sonar_queue_.empty() && sonar_queue_.front()->header.stamp <= stamp)
      {
        ready.push_back(sonar_queue_.front());
        sonar_queue_.pop_front();
      }
    }
    for (const auto& m : ready)
    {
      bool in_epoch;
      {
        std::lock_guard<std::mutex> lock(gate_mutex_);
        in_epoch = gate_.inEpoch(m->header.stamp.toSec());
      }
      if (!in_epoch)
      {
        // Queued through a black-out or a gap: tf would interpolate its pose across the spell
        // the VO could not trust, and its echo would hold cells of the new map for good.
        NODELET_WARN_THROTTLE(5.0, "obstacles: ranger reading stamped %.3f is from before the map's last clear: "
                              "not used", m->header.stamp.toSec());
        std::lock_guard<std::mutex> lock(stats_mutex_);
        ++sonar_stale_;
        continue;
      }
      RangeReading r;
      r.range = m->range;
      r.min_range = m->min_range;
      r.max_range = m->max_range;
      r.field_of_view = m->field_of_view;
      try
      {
        r.T_world_sensor = tf2::transformToEigen(tf_buffer_->lookupTransform(node_.world_frame, m->header.frame_id,
                                                                             m->header.stamp)).cast<float>();
      }
      catch (const tf2::TransformException& e)
      {
        NODELET_WARN_THROTTLE(5.0, "obstacles: ranger reading without a pose (%s): not used", e.what());
        std::lock_guard<std::mutex> lock(stats_mutex_);
        ++sonar_tf_failures_;
        continue;
      }
      const RangeCheck rc = map_->addRange(r);
      std::lock_guard<std::mutex> lock(stats_mutex_);
      if (rc == RangeCheck::ECHO || rc == RangeCheck::NO_ECHO)
      {
        ++sonar_used_;
        last_sonar_ = ros::WallTime::now();
      }
      else
      {
        ++sonar_rejected_;
        sonar_rejection_ = rangeCheckName(rc);
        NODELET_WARN_THROTTLE(5.0, "obstacles: ranger reading rejected (%s, range %.3f in [%.2f, %.2f]): not used",
                              rangeCheckName(rc), m->range, m->min_range, m->max_range);
      }
    }
  }

  /// vo/odom marks a pose it cannot trust with variances of 9999: the map built on the old pose
  /// chain is dropped once the VO trusts its pose again.
  void odomCb(const nav_msgs::Odometry::ConstPtr& o)
  {
    constexpr double kUntrustedVariance = 9999.0;
    if (!(o->pose.covariance[0] < 0.5 * kUntrustedVariance))
    {
      std::lock_guard<std::mutex> lock(gate_mutex_);
      gate_.poseUntrusted();
    }
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
    const auto t0 = std::chrono::steady_clock::now();
    StereoModel model;
    if (!fromMsg(*li, *ri, model) || model.width != static_cast<int>(l->width) ||
        model.height != static_cast<int>(l->height) || l->width != r->width || l->height != r->height)
    {
      NODELET_ERROR_THROTTLE(5.0, "obstacles: unusable stereo input (camera_info without fx/baseline or size mismatch)");
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
      ++bad_input_;
      return;
    }
    // A gap or a time jump (bag loop) makes the old map a guess about a place the wearer has left.
    bool clear = false;
    {
      std::lock_guard<std::mutex> lock(gate_mutex_);
      clear = gate_.clearBefore(l->header.stamp.toSec());
      if (clear && !gate_.reason().empty())
        NODELET_WARN_THROTTLE(2.0, "obstacles: %s", gate_.reason().c_str());
    }
    if (clear)
    {
      map_->reset();
      if (movers_) movers_->reset();
    }
    cv::Mat disp;
    if (!disparity_->compute(cl->image, cr->image, disp))
    {
      NODELET_ERROR_THROTTLE(5.0, "obstacles: disparity failed (image %ux%u too small for %d disparities?)", l->width,
                             l->height, disparity_->numDisparities());
      ++bad_input_;
      return;
    }
    const bool want_normals = map_->usesNormals();
    disparity_->toPoints(disp, model, points_, want_normals ? &normals_ : nullptr);
    const auto t1 = std::chrono::steady_clock::now();
    if (pub_disp_.getNumSubscribers() > 0)
      pub_disp_.publish(boost::make_shared<stereo_msgs::DisparityImage>(
          toDisparityMsg(disp, model, disparity_->numDisparities(), l->header)));
    if (pub_points_.getNumSubscribers() > 0)
      pub_points_.publish(boost::make_shared<sensor_msgs::PointCloud2>(toCloudMsg(points_, l->header)));

    Eigen::Isometry3f T_world_cam;
    try
    {
      // Available: the tf filter let the left image through (no timeout, no wait).
      const auto tf = tf_buffer_->lookupTransform(node_.world_frame, l->header.frame_id, l->header.stamp);
      T_world_cam = tf2::transformToEigen(tf).cast<float>();
    }
    catch (const tf2::TransformException& e)
    {
      NODELET_WARN_THROTTLE(5.0, "obstacles: no pose %s -> %s at %.3f: %s", node_.world_frame.c_str(),
                            l->header.frame_id.c_str(), l->header.stamp.toSec(), e.what());
      std::lock_guard<std::mutex> lock(stats_mutex_);
      ++tf_failures_;
      return;
    }
    // A frame without depth must not make the old map look fresh: no update, no grid (the planner
    // then sees the grid's stamp fall behind the pose's and stops guiding).
    FrameGate::Verdict verdict;
    {
      std::lock_guard<std::mutex> lock(gate_mutex_);
      verdict = gate_.verdict(points_.size());
    }
    {
      std::lock_guard<std::mutex> lock(stats_mutex_);
      last_verdict_ = verdict;
      gate_reason_ = gate_.reason();
      gate_clears_ = gate_.clears();
      gate_no_depth_ = gate_.noDepthFrames();
    }
    if (verdict == FrameGate::Verdict::NO_DEPTH)
    {
      NODELET_WARN_THROTTLE(2.0, "obstacles: %s", gate_.reason().c_str());
      return;
    }
    if (params_.sonar_enabled)
    {
      applySonar(l->header.stamp);
      std::lock_guard<std::mutex> lock(stats_mutex_);
      if (sonar_used_ > 0 && (ros::WallTime::now() - last_sonar_).toSec() > 1.0)
        NODELET_WARN_THROTTLE(5.0, "obstacles: no ranger reading for %.1f s: glass is not covered",
                              (ros::WallTime::now() - last_sonar_).toSec());
    }
    // Movers (issue 22): scene flow against the ego-motion between this pose and the last one;
    // their cells take no vote in this update.
    if (params_.movers)
    {
      if (!movers_) movers_ = std::make_unique<MoverPipeline>(moverPipelineParams(params_, model));
      map_->setMovers(movers_->process(l->header.stamp.toSec(), cl->image, disp, model, T_world_cam.cast<double>(), &cr->image));
    }
    const auto t_movers = std::chrono::steady_clock::now();
    map_->update(points_, T_world_cam, &model, &disp, want_normals ? &normals_ : nullptr);
    const auto t2 = std::chrono::steady_clock::now();
    if (movers_)
    {
      // Every frame with depth, also with no one (an empty array: "no one", not "no news").
      const std::vector<ReportedMover> reported = movers_->confirmed();
      const double feet = T_world_cam.translation().z() - params_.camera_height;
      pub_movers_.publish(boost::make_shared<assistive_msgs::MoverArray>(
          toMoverArray(reported, feet, node_.world_frame, l->header.stamp)));
      if (pub_mover_markers_.getNumSubscribers() > 0)
        pub_mover_markers_.publish(boost::make_shared<visualization_msgs::MarkerArray>(
            toMoverMarkers(reported, feet, CrossingHorizonS, node_.world_frame, l->header.stamp)));
      std::lock_guard<std::mutex> lock(stats_mutex_);
      mover_count_ = static_cast<int>(reported.size());
      mover_cells_ = map_->stats().mover_cells;
      ms_movers_ = std::chrono::duration<double, std::milli>(t_movers - t1).count();
      ms_tracking_ = movers_->msTracking();
      flow_points_ = static_cast<int>(movers_->flow().size());
    }
    GridData grid;
    if (verdict == FrameGate::Verdict::FRESH)
    {
      map_->grid(grid);
      pub_grid_.publish(boost::make_shared<nav_msgs::OccupancyGrid>(toMsg(grid, node_.world_frame, l->header.stamp)));
    }
    if (pub_dropout_.getNumSubscribers() > 0)
      pub_dropout_.publish(boost::make_shared<nav_msgs::OccupancyGrid>(toMsg(map_->dropout(), node_.world_frame, l->header.stamp)));
    ++frames_;
    if (params_.octomap_enabled && frames_ % node_.octomap_insert_every == 0)
    {
      map_->insertOctomap();
      if (pub_markers_.getNumSubscribers() > 0)
      {
        std::vector<Eigen::Vector3f> c;
        std::vector<float> s;
        map_->octree().occupiedCenters(c, s);
        pub_markers_.publish(boost::make_shared<visualization_msgs::MarkerArray>(toMarkers(c, s, node_.world_frame, l->header.stamp)));
      }
    }
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ms_disparity_ = std::chrono::duration<double, std::milli>(t1 - t0).count();
    ms_map_ = std::chrono::duration<double, std::milli>(t2 - t_movers).count();
    last_stats_ = map_->stats();
    last_sonar_held_ = map_->sonar().stats().held;
  }

  bool saveOctomap(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    if (!params_.octomap_enabled)
    {
      res.success = false;
      res.message = "octomap_enabled is false";
      return true;
    }
    res.success = map_->octree().save(params_.octomap_save_path);
    res.message = res.success ? params_.octomap_save_path : "cannot write " + params_.octomap_save_path;
    NODELET_INFO("obstacles: save_octomap -> %s (%s)", params_.octomap_save_path.c_str(), res.success ? "ok" : "FAILED");
    return true;
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st)
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    const double idle = (ros::WallTime::now() - last_input_).toSec();
    if (frames_ == 0)
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
    st.add("frames", frames_);
    st.add("ms disparity", ms_disparity_);
    st.add("ms map", ms_map_);
    st.add("points", last_stats_.points_in);
    st.add("cells observed", last_stats_.cells_observed);
    st.add("dropout cells", last_stats_.dropout_cells);
    st.add("tf failures", tf_failures_);
    st.add("bad inputs", bad_input_);
    st.add("map clears (gap / time jump)", gate_clears_);
    st.add("frames without depth", gate_no_depth_);
    st.add("ranger readings used", sonar_used_);
    st.add("ranger readings rejected", sonar_rejected_);
    if (!sonar_rejection_.empty())
      st.add("last ranger rejection", sonar_rejection_);
    st.add("ranger readings without pose", sonar_tf_failures_);
    st.add("ranger readings from before a map clear", sonar_stale_);
    st.add("ranger", !params_.sonar_enabled ? std::string("disabled")
                     : sonar_used_ == 0 ? std::string("no reading yet (glass is not covered)")
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
  std::unique_ptr<DisparityEstimator> disparity_;
  std::unique_ptr<ObstacleMap> map_;
  std::unique_ptr<MoverPipeline> movers_;  // with `movers`; created at the first frame (its rig)
  static constexpr double CrossingHorizonS = 3.0;  // s, predicted path drawn in the markers (CrossingParams::horizon)
  int mover_count_ = 0, mover_cells_ = 0, flow_points_ = 0;  // under stats_mutex_
  double ms_movers_ = 0, ms_tracking_ = 0;
  FrameGate gate_;
  std::mutex gate_mutex_;  // odomCb and frameCb run on different threads
  ros::Subscriber sub_odom_, sub_sonar_;
  std::mutex sonar_mutex_;
  std::deque<sensor_msgs::Range::ConstPtr> sonar_queue_;  // under sonar_mutex_
  long sonar_used_ = 0, sonar_rejected_ = 0, sonar_tf_failures_ = 0, sonar_stale_ = 0;  // under stats_mutex_
  std::string sonar_rejection_;
  ros::WallTime last_sonar_;
  size_t last_sonar_held_ = 0;
  FrameGate::Verdict last_verdict_ = FrameGate::Verdict::REBUILDING;  // these four under stats_mutex_
  std::string gate_reason_;
  long gate_clears_ = 0, gate_no_depth_ = 0;
  std::vector<Eigen::Vector3f> points_, normals_;  // left optical frame
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  message_filters::Subscriber<Image> sub_l_, sub_r_;
  std::unique_ptr<tf2_ros::MessageFilter<Image>> tf_filter_;
  message_filters::Subscriber<CameraInfo> sub_li_, sub_ri_;
  std::shared_ptr<message_filters::Synchronizer<ExactPolicy>> exact_;
  std::shared_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_;
  ros::Publisher pub_disp_, pub_points_, pub_grid_, pub_markers_, pub_dropout_, pub_movers_, pub_mover_markers_;
  ros::ServiceServer srv_save_;
  std::unique_ptr<diagnostic_updater::Updater> diag_;
  ros::Timer diag_timer_;
  std::mutex stats_mutex_;
  ros::WallTime last_input_;
  FrameStats last_stats_;
  double ms_disparity_ = 0, ms_map_ = 0;
  long frames_ = 0, tf_failures_ = 0, bad_input_ = 0;
};

}  // namespace assistive_obstacles

PLUGINLIB_EXPORT_CLASS(assistive_obstacles::ObstaclesNodelet, nodelet::Nodelet)
