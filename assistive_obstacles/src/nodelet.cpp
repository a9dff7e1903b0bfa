// assistive_obstacles/obstacles: glue between ROS and the core (disparity, ObstacleMap).
#include <chrono>
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
#include <sensor_msgs/image_encodings.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <assistive_obstacles/conversions.h>
#include <assistive_obstacles/disparity.h>
#include <assistive_obstacles/frame_gate.h>
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
    srv_save_ = nh.advertiseService("save_octomap", &ObstaclesNodelet::saveOctomap, this);
    bool use_odom = true;
    pnh.param("use_odom", use_odom, use_odom);
    if (use_odom)
      sub_odom_ = nh.subscribe("odom", 5, &ObstaclesNodelet::odomCb, this);

    diag_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    diag_->setHardwareID("stereo camera");
    diag_->add("obstacle map", this, &ObstaclesNodelet::diagnose);
    diag_timer_ = nh.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { diag_->update(); });

    sub_l_.subscribe(nh, "left/image_rect", 1);
    sub_r_.subscribe(nh, "right/image_rect", 1);
    sub_li_.subscribe(nh, "left/camera_info", 1);
    sub_ri_.subscribe(nh, "right/camera_info", 1);
    if (approximate_sync_)
    {
      approx_ = std::make_shared<message_filters::Synchronizer<ApproxPolicy>>(ApproxPolicy(queue_size_), sub_l_, sub_r_,
                                                                               sub_li_, sub_ri_);
      approx_->registerCallback(&ObstaclesNodelet::frameCb, this);
    }
    else
    {
      exact_ = std::make_shared<message_filters::Synchronizer<ExactPolicy>>(ExactPolicy(queue_size_), sub_l_, sub_r_,
                                                                             sub_li_, sub_ri_);
      exact_->registerCallback(&ObstaclesNodelet::frameCb, this);
    }
  }

private:
  template <typename T>
  void param(ros::NodeHandle& pnh, const std::string& name, T& v)
  {
    pnh.param(name, v, v);
  }

  void readParams(ros::NodeHandle& pnh)
  {
    ObstaclesParams& p = params_;
    param(pnh, "disparity_method", p.disparity_method);
    param(pnh, "disparity_scale", p.disparity_scale);
    param(pnh, "max_disparity", p.max_disparity);
    param(pnh, "block_size", p.block_size);
    param(pnh, "uniqueness_ratio", p.uniqueness_ratio);
    param(pnh, "speckle_window_size", p.speckle_window_size);
    param(pnh, "speckle_range", p.speckle_range);
    param(pnh, "disp12_max_diff", p.disp12_max_diff);
    param(pnh, "sgbm_p1", p.sgbm_p1);
    param(pnh, "sgbm_p2", p.sgbm_p2);
    param(pnh, "min_depth", p.min_depth);
    param(pnh, "max_depth", p.max_depth);
    param(pnh, "point_stride", p.point_stride);
    param(pnh, "edge_filter", p.edge_filter);
    param(pnh, "texture_max_depth_sigma", p.texture_max_depth_sigma);
    param(pnh, "image_noise_sigma", p.image_noise_sigma);
    param(pnh, "cell_size", p.cell_size);
    param(pnh, "window_radius", p.window_radius);
    param(pnh, "min_points_per_cell", p.min_points_per_cell);
    param(pnh, "gap_height", p.gap_height);
    param(pnh, "step_height", p.step_height);
    param(pnh, "min_step", p.min_step);
    param(pnh, "head_clearance", p.head_clearance);
    param(pnh, "camera_height", p.camera_height);
    param(pnh, "max_surface_rise", p.max_surface_rise);
    param(pnh, "max_surface_drop", p.max_surface_drop);
    param(pnh, "cluster_gap", p.cluster_gap);
    param(pnh, "min_cluster_points", p.min_cluster_points);
    param(pnh, "thickness_trim", p.thickness_trim);
    param(pnh, "min_traversable_edges", p.min_traversable_edges);
    param(pnh, "closing_radius", p.closing_radius);
    param(pnh, "fine_factor", p.fine_factor);
    param(pnh, "peak_fraction", p.peak_fraction);
    param(pnh, "ground_quantile", p.ground_quantile);
    param(pnh, "surface_push", p.surface_push);
    param(pnh, "surface_push_normal", p.surface_push_normal);
    param(pnh, "closing_weight", p.closing_weight);
    param(pnh, "disparity_sigma", p.disparity_sigma);
    param(pnh, "obstacle_max_sigma", p.obstacle_max_sigma);
    param(pnh, "min_observations", p.min_observations);
    param(pnh, "obstacle_ratio", p.obstacle_ratio);
    param(pnh, "permanent_flips", p.permanent_flips);
    param(pnh, "max_count", p.max_count);
    param(pnh, "full_weight_range", p.full_weight_range);
    param(pnh, "dropout_max_range", p.dropout_max_range);
    param(pnh, "dropout_free_weight", p.dropout_free_weight);
    param(pnh, "vote_max_range", p.vote_max_range);
    param(pnh, "octomap_enabled", p.octomap_enabled);
    param(pnh, "octomap_resolution", p.octomap_resolution);
    param(pnh, "octomap_max_range", p.octomap_max_range);
    param(pnh, "octomap_point_stride", p.octomap_point_stride);
    param(pnh, "octomap_save_path", p.octomap_save_path);
    param(pnh, "max_frame_gap_s", p.max_frame_gap_s);
    param(pnh, "rebuild_frames", p.rebuild_frames);
    param(pnh, "min_fresh_points", p.min_fresh_points);
    for (const std::string& w : clampParams(p)) NODELET_WARN("%s", w.c_str());
    pnh.param("world_frame", world_frame_, world_frame_);
    pnh.param("queue_size", queue_size_, queue_size_);
    pnh.param("approximate_sync", approximate_sync_, approximate_sync_);
    pnh.param("tf_timeout", tf_timeout_, tf_timeout_);
    pnh.param("octomap_insert_every", octomap_every_, octomap_every_);
    if (queue_size_ < 1)
    {
      NODELET_WARN("queue_size %d < 1, using 1", queue_size_);
      queue_size_ = 1;
    }
    if (octomap_every_ < 1)
    {
      NODELET_WARN("octomap_insert_every %d < 1, using 1", octomap_every_);
      octomap_every_ = 1;
    }
    NODELET_INFO("obstacles: %s disparity at scale %.2f (%d px full res), cells %.2f m, window %.1f m, G %.2f m, "
                 "T %.2f m, world frame '%s'",
                 p.disparity_method.c_str(), p.disparity_scale, p.max_disparity, p.cell_size, p.window_radius,
                 p.gap_height, p.step_height, world_frame_.c_str());
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
    const auto t0 = std::chrono::steady_clock::now();
    last_input_ = ros::WallTime::now();
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
      map_->reset();
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
      const auto tf = tf_buffer_->lookupTransform(world_frame_, l->header.frame_id, l->header.stamp,
                                                  ros::Duration(tf_timeout_));
      T_world_cam = tf2::transformToEigen(tf).cast<float>();
    }
    catch (const tf2::TransformException& e)
    {
      NODELET_WARN_THROTTLE(5.0, "obstacles: no pose %s -> %s at %.3f: %s", world_frame_.c_str(),
                            l->header.frame_id.c_str(), l->header.stamp.toSec(), e.what());
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
    map_->update(points_, T_world_cam, &model, &disp, want_normals ? &normals_ : nullptr);
    const auto t2 = std::chrono::steady_clock::now();
    GridData grid;
    if (verdict == FrameGate::Verdict::FRESH)
    {
      map_->grid(grid);
      pub_grid_.publish(boost::make_shared<nav_msgs::OccupancyGrid>(toMsg(grid, world_frame_, l->header.stamp)));
    }
    if (pub_dropout_.getNumSubscribers() > 0)
      pub_dropout_.publish(boost::make_shared<nav_msgs::OccupancyGrid>(toMsg(map_->dropout(), world_frame_, l->header.stamp)));
    ++frames_;
    if (params_.octomap_enabled && frames_ % octomap_every_ == 0)
    {
      map_->insertOctomap();
      if (pub_markers_.getNumSubscribers() > 0)
      {
        std::vector<Eigen::Vector3f> c;
        std::vector<float> s;
        map_->octree().occupiedCenters(c, s);
        pub_markers_.publish(boost::make_shared<visualization_msgs::MarkerArray>(toMarkers(c, s, world_frame_, l->header.stamp)));
      }
    }
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ms_disparity_ = std::chrono::duration<double, std::milli>(t1 - t0).count();
    ms_map_ = std::chrono::duration<double, std::milli>(t2 - t1).count();
    last_stats_ = map_->stats();
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
  }

  ObstaclesParams params_;
  std::string world_frame_ = "odom";
  int queue_size_ = 5;
  bool approximate_sync_ = false;
  double tf_timeout_ = 0.1;
  int octomap_every_ = 5;
  std::unique_ptr<DisparityEstimator> disparity_;
  std::unique_ptr<ObstacleMap> map_;
  FrameGate gate_;
  std::mutex gate_mutex_;  // odomCb and frameCb run on different threads
  ros::Subscriber sub_odom_;
  FrameGate::Verdict last_verdict_ = FrameGate::Verdict::REBUILDING;  // these four under stats_mutex_
  std::string gate_reason_;
  long gate_clears_ = 0, gate_no_depth_ = 0;
  std::vector<Eigen::Vector3f> points_, normals_;  // left optical frame
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  message_filters::Subscriber<Image> sub_l_, sub_r_;
  message_filters::Subscriber<CameraInfo> sub_li_, sub_ri_;
  std::shared_ptr<message_filters::Synchronizer<ExactPolicy>> exact_;
  std::shared_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_;
  ros::Publisher pub_disp_, pub_points_, pub_grid_, pub_markers_, pub_dropout_;
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
