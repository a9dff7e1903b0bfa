// assistive_slam/slam: glue between ROS and the SlamSystem core. Rectified stereo + camera_info +
// vo/odom (same stamp) in; tf map -> odom, the corrected trajectory, the submap graph, rviz
// markers, loop-closure events and diagnostics out. Keyframe work runs on the core's worker thread,
// loop closing on its loop closer thread (loop_closing_thread).
#include <memory>
#include <mutex>
#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>
#include <ros/file_log.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>
#include <assistive_common/callback_guard.h>
#include <assistive_common/ros_params.h>
#include <assistive_msgs/GuideToPlace.h>
#include <assistive_msgs/SubmapGraph.h>
#include <assistive_msgs/TagPlace.h>
#include <geometry_msgs/PoseStamped.h>

#include "assistive_slam/map_file.h"
#include "assistive_slam/slam_system.h"
#include "assistive_slam/vo_adapter.h"

namespace assistive_slam
{
class SlamNodelet : public nodelet::Nodelet
{
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;
  using Odom = nav_msgs::Odometry;
  using Policy = message_filters::sync_policies::ExactTime<Image, Info, Image, Info, Odom>;

  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    for (const std::string& m : assistive_common::readParams(pnh, p_))
      NODELET_WARN("slam: %s", m.c_str());
    for (const std::string& m : assistive_common::readParams(pnh, node_))
      NODELET_WARN("slam: %s", m.c_str());
    if (p_.metric_backend != "keyframe_ba" && p_.metric_backend != "fastslam")
    {
      NODELET_WARN("slam: metric_backend '%s' is neither keyframe_ba nor fastslam: keyframe_ba", p_.metric_backend.c_str());
      p_.metric_backend = "keyframe_ba";
    }
    NODELET_INFO("slam: %s", assistive_common::describe(p_).c_str());
    NODELET_INFO("slam: %s", assistive_common::describe(node_).c_str());
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_);

    path_pub_ = nh.advertise<nav_msgs::Path>("slam/path", 1, true);
    graph_pub_ = nh.advertise<assistive_msgs::SubmapGraph>("slam/submap_graph", 1, true);
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("slam/markers", 1, true);
    loop_pub_ = nh.advertise<std_msgs::String>("slam/loop_closures", 10);
    // Latched: a planner started later still receives the way back.
    goal_pub_ = nh.advertise<geometry_msgs::PoseStamped>("planner/goal", 1, true);

    left_sub_.subscribe(nh, "left/image_rect", 2);
    left_info_sub_.subscribe(nh, "left/camera_info", 2);
    right_sub_.subscribe(nh, "right/image_rect", 2);
    right_info_sub_.subscribe(nh, "right/camera_info", 2);
    odom_sub_.subscribe(nh, "vo/odom", 10);
    sync_ = std::make_shared<message_filters::Synchronizer<Policy>>(Policy(static_cast<uint32_t>(node_.sync_queue_size)),
                                                                    left_sub_, left_info_sub_, right_sub_,
                                                                    right_info_sub_, odom_sub_);
    sync_->registerCallback(&SlamNodelet::frameCb, this);
    save_srv_ = nh.advertiseService("slam/save_map", &SlamNodelet::saveMap, this);
    load_srv_ = nh.advertiseService("slam/load_map", &SlamNodelet::loadMap, this);
    if (node_.load_map_at_start)
    {
      std_srvs::Trigger::Request rq;
      std_srvs::Trigger::Response rs;
      loadMap(rq, rs);
    }
    tag_srv_ = nh.advertiseService("slam/tag_place", &SlamNodelet::tagPlace, this);
    guide_srv_ = nh.advertiseService("slam/guide_to_place", &SlamNodelet::guideToPlace, this);

    diag_.setHardwareID("slam");
    diag_.add("status", this, &SlamNodelet::diagStatus);
    tf_timer_ = nh.createWallTimer(ros::WallDuration(1.0 / node_.tf_rate), &SlamNodelet::tfTimer, this);
    graph_timer_ = nh.createWallTimer(ros::WallDuration(1.0 / node_.graph_rate), &SlamNodelet::graphTimer, this);
  }

  void frameCb(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
               const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri,
               const nav_msgs::OdometryConstPtr& odom)
  {
    assistive_common::guarded(getName(), "stereo frame", [&] { frame(l, li, r, ri, odom); });
  }

  void frame(const sensor_msgs::ImageConstPtr& l, const sensor_msgs::CameraInfoConstPtr& li,
             const sensor_msgs::ImageConstPtr& r, const sensor_msgs::CameraInfoConstPtr& ri,
             const nav_msgs::OdometryConstPtr& odom)
  {
    const ros::WallTime t0 = ros::WallTime::now();
    ++frames_;
    StereoModel cam;
    cam.fx = li->P[0];
    cam.fy = li->P[5];
    cam.cx = li->P[2];
    cam.cy = li->P[6];
    cam.baseline = cam.fx > 0 ? -ri->P[3] / cam.fx : 0.0;
    if (!cam.valid())
    {
      NODELET_ERROR_THROTTLE(5.0, "slam: camera_info without a rectified stereo projection (P): frame ignored");
      return;
    }
    // The optical frame in camera_link (URDF, static): looked up once.
    if (!have_link_optical_)
    {
      try
      {
        const auto tf = tf_buffer_.lookupTransform(odom->child_frame_id, l->header.frame_id.empty() ? node_.optical_frame : l->header.frame_id,
                                                   ros::Time(0));
        T_link_optical_ = tf2::transformToEigen(tf);
        have_link_optical_ = true;
        adapter_ = std::make_unique<VoAdapter>(node_.untrusted_variance, T_link_optical_);
      }
      catch (const tf2::TransformException& e)
      {
        NODELET_WARN_THROTTLE(5.0, "slam: waiting for %s -> %s from the URDF: %s", odom->child_frame_id.c_str(),
                              node_.optical_frame.c_str(), e.what());
        return;
      }
    }
    if (!slam_)
    {
      std::lock_guard<std::mutex> lk(m_);
      slam_ = std::make_unique<SlamSystem>(p_, cam, true);
      if (pending_map_)
      {
        std::string err;
        if (slam_->loadMap(*pending_map_, &err))
          NODELET_INFO("slam: map installed (%zu keyframes): relocalising", pending_map_->keyframes.size());
        else
          NODELET_ERROR("slam: the loaded map was refused: %s; mapping from scratch", err.c_str());
        pending_map_.reset();
      }
    }
    cv_bridge::CvImageConstPtr lc, rc;
    try
    {
      lc = cv_bridge::toCvShare(l, sensor_msgs::image_encodings::MONO8);
      rc = cv_bridge::toCvShare(r, sensor_msgs::image_encodings::MONO8);
    }
    catch (const cv_bridge::Exception& e)
    {
      NODELET_ERROR_THROTTLE(5.0, "slam: image conversion failed: %s", e.what());
      return;
    }
    // The VO's output into SLAM through the core's adapter (vo_adapter.h), as slam_benchmark does.
    VoOdometry vo;
    vo.stamp = l->header.stamp.toSec();
    tf2::fromMsg(odom->pose.pose, vo.T_odom_link);
    vo.position_variance = odom->pose.covariance[0];
    for (int i = 0; i < 36; ++i)
      vo.twist_covariance(i / 6, i % 6) = odom->twist.covariance[static_cast<size_t>(i)];
    const SlamFrame f = adapter_->frame(vo, lc->image, rc->image);
    slam_->addFrame(f);
    {
      std::lock_guard<std::mutex> lk(m_);
      odom_frame_ = odom->header.frame_id.empty() ? node_.odom_frame : odom->header.frame_id;
      last_stamp_ = l->header.stamp;
      T_odom_optical_last_ = f.T_odom_cam;
      ms_frame_ = (ros::WallTime::now() - t0).toSec() * 1e3;
      ms_max_ = std::max(ms_max_, ms_frame_);
    }
    publishLoopEvents();
  }

  std::string mapPath() const
  {
    std::string path = node_.map_file;
    if (!path.empty() && path[0] != '/')
    {
      const char* home = std::getenv("ROS_HOME");
      const char* user = std::getenv("HOME");
      path = (home ? std::string(home) : std::string(user ? user : ".") + "/.ros") + "/" + path;
    }
    return path;
  }

  /// Reads map_file into pending_map_; it is installed before the first frame (the core takes a map
  /// only then). A damaged file is refused with the reason and nothing changes.
  bool loadMap(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lk(m_);
    if (slam_)
    {
      res.success = false;
      res.message = "a map can only be loaded before the first frame (restart the stage to load one)";
      NODELET_WARN("slam: %s", res.message.c_str());
      return true;
    }
    const std::string path = mapPath();
    auto m = std::make_shared<MapData>();
    std::string err;
    res.success = loadMapFile(path, *m, &err);
    if (res.success)
    {
      pending_map_ = m;
      res.message = "map " + path + " read: " + std::to_string(m->keyframes.size()) + " keyframes, " +
                    std::to_string(m->places.size()) + " places; not localised until a stored place is in view";
      NODELET_INFO("slam: %s", res.message.c_str());
    }
    else
    {
      res.message = "map " + path + " refused: " + err;
      NODELET_ERROR("slam: %s", res.message.c_str());
    }
    return true;
  }

  bool saveMap(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    if (!slam_)
    {
      res.success = false;
      res.message = "no map yet (no frame processed)";
      return true;
    }
    const std::string path = mapPath();
    std::string err;
    res.success = saveMapFile(path, exportMap(*slam_), &err);
    res.message = res.success ? "map written to " + path : err;
    if (res.success)
      NODELET_INFO("slam: %s", res.message.c_str());
    else
      NODELET_ERROR("slam: %s", res.message.c_str());
    return true;
  }

  bool tagPlace(assistive_msgs::TagPlace::Request& req, assistive_msgs::TagPlace::Response& res)
  {
    Eigen::Isometry3d T_odom_cam;
    double stamp = 0;
    {
      std::lock_guard<std::mutex> lk(m_);
      T_odom_cam = T_odom_optical_last_;
      stamp = last_stamp_.toSec();
    }
    std::string err;
    Place p;
    res.success = slam_ && stamp > 0 && slam_->tagPlace(req.name, T_odom_cam, stamp, &p, &err);
    if (!slam_ || stamp <= 0)
      err = "no frame processed yet";
    if (res.success)
    {
      res.name = p.name;
      res.stamp = ros::Time(p.stamp);
      const Eigen::Vector3d x = (slam_->mapToOdom() * T_odom_cam * T_link_optical_.inverse()).translation();
      char buf[160];
      std::snprintf(buf, sizeof(buf), "place '%s' tagged at (%.2f, %.2f, %.2f) in %s, on keyframe %u", p.name.c_str(),
                    x.x(), x.y(), x.z(), node_.map_frame.c_str(), p.keyframe);
      res.message = buf;
      NODELET_INFO("slam: %s", buf);
    }
    else
    {
      res.message = "place not tagged: " + err;
      NODELET_WARN("slam: %s", res.message.c_str());
    }
    return true;
  }

  bool guideToPlace(assistive_msgs::GuideToPlace::Request& req, assistive_msgs::GuideToPlace::Response& res)
  {
    std::string err = "no frame processed yet";
    Eigen::Isometry3d T_map_place;
    if (slam_ && !slam_->localised())
      err = "not localised in the map yet (a loaded map, or the VO lost tracking)";
    res.success = slam_ && slam_->localised() && slam_->placePose(req.name, &T_map_place, &err);
    if (!res.success)
    {
      res.message = "no way back: " + err;
      NODELET_WARN("slam: %s", res.message.c_str());
      return true;
    }
    // The goal stays in map (the planner transforms it to its own frame with the latest
    // map -> odom). Stamp 0: "the latest transform", since map -> odom is future-dated.
    // The place is stored as the left optical frame; the goal is the head (camera_link) there.
    geometry_msgs::PoseStamped g;
    g.header.frame_id = node_.map_frame;
    g.pose = tf2::toMsg(Eigen::Isometry3d(T_map_place * T_link_optical_.inverse()));
    goal_pub_.publish(g);
    res.goal = g;
    char buf[160];
    std::snprintf(buf, sizeof(buf), "the way back to '%s': planner goal (%.2f, %.2f) in %s",
                  req.name.empty() ? "the last place" : req.name.c_str(), g.pose.position.x, g.pose.position.y,
                  node_.map_frame.c_str());
    res.message = buf;
    NODELET_INFO("slam: %s", buf);
    return true;
  }

  void publishLoopEvents()
  {
    const std::vector<LoopEvent> ev = slam_->loopEvents();
    for (; events_published_ < ev.size(); ++events_published_)
    {
      const LoopEvent& e = ev[events_published_];
      std_msgs::String s;
      char buf[256];
      std::snprintf(buf, sizeof(buf), "%s keyframe %u (submap %u) -> keyframe %u (submap %u): %d inliers, correction %.2f m %.1f deg%s%s",
                    e.relocalisation ? "relocalised" : e.accepted ? "accepted" : "rejected", e.keyframe_new, e.submap_new, e.keyframe_old, e.submap_old,
                    e.inliers, e.correction_m, e.correction_deg, e.reason.empty() ? "" : ": ", e.reason.c_str());
      s.data = buf;
      loop_pub_.publish(s);
      if (e.accepted)
        NODELET_INFO("slam: loop closure %s", buf);
      else
        NODELET_WARN("slam: loop closure %s", buf);
    }
  }

  void tfTimer(const ros::WallTimerEvent&)
  {
    assistive_common::guarded(getName(), "tf", [&] {
      if (!slam_)
        return;
      std::lock_guard<std::mutex> lk(m_);
      if (last_stamp_.isZero())
        return;
      if (!slam_->localised())
      {
        // After a load, or from a VO loss until the wearer is found again in the map: map -> odom
        // is unknown; none is invented.
        NODELET_WARN_THROTTLE(10.0, "slam: not localised (a loaded map, or the VO lost tracking): no map -> odom");
        return;
      }
      // Future-dated by one period (the tf convention for map -> odom): lookups at the latest
      // odom stamp succeed.
      // Sent once per stamp: the timer runs on the wall clock and may outpace the odometry (a bag
      // played slowly, a loaded machine), and tf2 drops a repeated stamp with a TF_REPEATED_DATA
      // warning per listener; the next odometry frame carries any newer correction. (Only a
      // repeat is skipped: time going back, a bag started again, is sent on.)
      const ros::Time stamp = last_stamp_ + ros::Duration(1.0 / node_.tf_rate);
      if (stamp == last_tf_stamp_)
        return;
      last_tf_stamp_ = stamp;
      geometry_msgs::TransformStamped t = tf2::eigenToTransform(slam_->mapToOdom());
      t.header.stamp = stamp;
      t.header.frame_id = node_.map_frame;
      t.child_frame_id = odom_frame_;
      tf_pub_.sendTransform(t);
    });
  }

  void graphTimer(const ros::WallTimerEvent&)
  {
    assistive_common::guarded(getName(), "graph", [&] {
      diag_.update();
      if (!slam_)
        return;
      ros::Time stamp;
      {
        std::lock_guard<std::mutex> lk(m_);
        stamp = last_stamp_;
      }
      const std::vector<Keyframe> kfs = slam_->keyframes();
      const std::vector<SubmapInfo> sms = slam_->submaps();
      const std::vector<SubmapLinkInfo> links = slam_->links();
      nav_msgs::Path path;
      path.header.stamp = stamp;
      path.header.frame_id = node_.map_frame;
      for (const Keyframe& k : kfs)
      {
        geometry_msgs::PoseStamped ps;
        ps.header.stamp = ros::Time(k.stamp);
        ps.header.frame_id = node_.map_frame;
        ps.pose = tf2::toMsg(k.T_map_cam);
        path.poses.push_back(ps);
      }
      path_pub_.publish(path);

      assistive_msgs::SubmapGraph g;
      g.header = path.header;
      for (const SubmapInfo& s : sms)
      {
        g.ids.push_back(s.id);
        g.origins.push_back(tf2::toMsg(s.T_map_origin));
      }
      for (const SubmapLinkInfo& li : links)
      {
        assistive_msgs::SubmapLink m;
        m.from = li.from;
        m.to = li.to;
        m.relative_pose = tf2::toMsg(li.T_from_to);
        for (int i = 0; i < 36; ++i)
          m.covariance[i] = li.covariance(i / 6, i % 6);
        m.loop_closure = li.loop_closure;
        g.links.push_back(m);
      }
      g.current = sms.empty() ? 0 : sms.back().id;
      graph_pub_.publish(g);

      // rviz: submap origins (spheres), odometry links (grey) and loop closures (green)
      visualization_msgs::MarkerArray ma;
      visualization_msgs::Marker nodes;
      nodes.header = path.header;
      nodes.ns = "submaps";
      nodes.id = 0;
      nodes.type = visualization_msgs::Marker::SPHERE_LIST;
      nodes.scale.x = nodes.scale.y = nodes.scale.z = 0.25;
      nodes.color.r = 0.1;
      nodes.color.g = 0.4;
      nodes.color.b = 1.0;
      nodes.color.a = 1.0;
      nodes.pose.orientation.w = 1.0;
      visualization_msgs::Marker odo = nodes, loops = nodes;
      odo.ns = "odometry_links";
      odo.type = visualization_msgs::Marker::LINE_LIST;
      odo.scale.x = 0.04;
      odo.color.r = odo.color.g = odo.color.b = 0.6;
      loops.ns = "loop_closures";
      loops.type = visualization_msgs::Marker::LINE_LIST;
      loops.scale.x = 0.06;
      loops.color.r = 0.0;
      loops.color.g = 0.9;
      loops.color.b = 0.2;
      for (const SubmapInfo& s : sms)
        nodes.points.push_back(tf2::toMsg(Eigen::Vector3d(s.T_map_origin.translation())));
      for (const SubmapLinkInfo& li : links)
      {
        if (li.from >= sms.size() || li.to >= sms.size())
          continue;
        auto& m = li.loop_closure ? loops : odo;
        m.points.push_back(tf2::toMsg(Eigen::Vector3d(sms[li.from].T_map_origin.translation())));
        m.points.push_back(tf2::toMsg(Eigen::Vector3d(sms[li.to].T_map_origin.translation())));
      }
      // tagged places: a yellow sphere and its name
      visualization_msgs::Marker place_pts = nodes;
      place_pts.ns = "places";
      place_pts.scale.x = place_pts.scale.y = place_pts.scale.z = 0.4;
      place_pts.color.r = 1.0;
      place_pts.color.g = 0.85;
      place_pts.color.b = 0.0;
      ma.markers = {nodes, odo, loops};
      int label_id = 0;
      for (const auto& [pl, T] : slam_->places())
      {
        const Eigen::Vector3d x = (T * T_link_optical_.inverse()).translation();
        place_pts.points.push_back(tf2::toMsg(x));
        visualization_msgs::Marker label = place_pts;
        label.ns = "place_names";
        label.id = label_id++;
        label.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
        label.points.clear();
        label.scale.x = label.scale.y = 0;
        label.scale.z = 0.4;
        label.pose.position = tf2::toMsg(Eigen::Vector3d(x + Eigen::Vector3d(0, 0, 0.5)));
        label.text = pl.name;
        ma.markers.push_back(label);
      }
      ma.markers.push_back(place_pts);
      markers_pub_.publish(ma);
    });
  }

  void diagStatus(diagnostic_updater::DiagnosticStatusWrapper& s)
  {
    if (!slam_)
    {
      s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no synchronised stereo + vo/odom frame yet");
      return;
    }
    const SlamStats st = slam_->stats();
    std::lock_guard<std::mutex> lk(m_);
    s.summary(diagnostic_msgs::DiagnosticStatus::OK, "mapping");
    if (!st.localised)
      s.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                st.vo_losses > 0 ? "not localised: the VO lost tracking; looking for the wearer near the last trusted pose"
                                 : "not localised: map loaded, waiting for a stored place in view");
    if (st.dropped > dropped_reported_)
      s.summary(diagnostic_msgs::DiagnosticStatus::WARN, "the worker fell behind: keyframes dropped");
    dropped_reported_ = st.dropped;
    s.add("frames", frames_);
    s.add("keyframes", st.keyframes);
    s.add("submaps", st.submaps);
    s.add("loop closures accepted", st.loops_accepted);
    s.add("loop closures rejected", st.loops_rejected);
    s.add("worker queue depth", st.queue_depth);
    s.add("loop closer queue depth", st.loop_queue_depth);
    s.add("keyframes dropped", st.dropped);
    s.add("localised", st.localised);
    s.add("relocalisation keyframes tried", st.relocalisation_queries);
    s.add("VO losses", st.vo_losses);
    s.add("found again after a VO loss", st.reset_relocalisations);
    s.add("relocalisations given up", st.reset_gave_up);
    s.add("VO losses bridged on the held pose", st.reset_bridged);
    s.add("worker ms (last keyframe)", st.worker_ms_last);
    s.add("loop closer ms (last keyframe)", st.loop_ms_last);
    s.add("ms per frame", ms_frame_);
    s.add("ms per frame (max)", ms_max_);
    ms_max_ = 0;
    s.add("metric backend", p_.metric_backend);
    if (const FastSlam* fs = slam_->filter())  // (callbacks are serialised: the frame thread is idle here)
    {
      const FastSlamStats& f = fs->stats();
      s.add("fastslam particles", f.particles);
      s.add("fastslam landmarks", f.landmarks);
      s.add("fastslam matches (last frame)", f.matches_last);
      s.add("fastslam resamplings", f.resamplings);
    }
  }

  SlamParams p_;
  SlamNodeParams node_;
  std::unique_ptr<SlamSystem> slam_;
  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  tf2_ros::TransformBroadcaster tf_pub_;
  std::unique_ptr<VoAdapter> adapter_;  ///< vo/odom into SlamFrames (once the optical frame is known)
  bool have_link_optical_ = false;
  Eigen::Isometry3d T_link_optical_ = Eigen::Isometry3d::Identity();
  message_filters::Subscriber<Image> left_sub_, right_sub_;
  message_filters::Subscriber<Info> left_info_sub_, right_info_sub_;
  message_filters::Subscriber<Odom> odom_sub_;
  std::shared_ptr<message_filters::Synchronizer<Policy>> sync_;
  ros::Publisher path_pub_, graph_pub_, markers_pub_, loop_pub_, goal_pub_;
  ros::WallTimer tf_timer_, graph_timer_;
  ros::ServiceServer save_srv_, load_srv_, tag_srv_, guide_srv_;
  std::shared_ptr<MapData> pending_map_;  ///< read by slam/load_map, installed before the first frame
  diagnostic_updater::Updater diag_;
  std::mutex m_;
  ros::Time last_stamp_;
  std::string odom_frame_ = "odom";
  ros::Time last_tf_stamp_;  // the newest map -> odom stamp sent
  Eigen::Isometry3d T_odom_optical_last_ = Eigen::Isometry3d::Identity();
  double ms_frame_ = 0, ms_max_ = 0;
  long frames_ = 0;
  size_t events_published_ = 0;
  int dropped_reported_ = 0;
};

}  // namespace assistive_slam

PLUGINLIB_EXPORT_CLASS(assistive_slam::SlamNodelet, nodelet::Nodelet)
