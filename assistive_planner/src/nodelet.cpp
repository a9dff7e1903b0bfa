// Thin nodelet around assistive_planner::Planner: grid + tf in, NavigationState / path / waypoint out.
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "assistive_planner/conversions.h"
#include "assistive_planner/input_monitor.h"
#include "assistive_planner/planner.h"

namespace assistive_planner
{
class PlannerNodelet : public nodelet::Nodelet
{
private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("world_frame", world_frame_, world_frame_);
    pnh.param("camera_frame", camera_frame_, camera_frame_);
    PlannerParams& p = params_;
    pnh.param("motion_update_distance", p.motion_update_distance, p.motion_update_distance);
    pnh.param("heading_update_angle", p.heading_update_angle, p.heading_update_angle);
    pnh.param("triangle_length", p.triangle_length, p.triangle_length);
    pnh.param("triangle_half_angle", p.triangle_half_angle, p.triangle_half_angle);
    pnh.param("switch_area_ratio", p.switch_area_ratio, p.switch_area_ratio);
    pnh.param("abandon_angle", p.abandon_angle, p.abandon_angle);
    pnh.param("reached_distance", p.reached_distance, p.reached_distance);
    pnh.param("step_cost", p.step_cost, p.step_cost);
    pnh.param("clearance_weight", p.clearance_weight, p.clearance_weight);
    pnh.param("clearance_radius", p.clearance_radius, p.clearance_radius);
    pnh.param("unknown_traversable", p.unknown_traversable, p.unknown_traversable);
    pnh.param("path_lookahead", p.path_lookahead, p.path_lookahead);
    pnh.param("free_ray_max", p.free_ray_max, p.free_ray_max);
    pnh.param("unknown_ahead_m", p.unknown_ahead_m, p.unknown_ahead_m);
    pnh.param("grid_timeout", p.grid_timeout, p.grid_timeout);
    pnh.param("use_odom", p.use_odom, p.use_odom);
    pnh.param("max_input_age_s", p.max_input_age_s, p.max_input_age_s);
    pnh.param("max_frame_gap_s", p.max_frame_gap_s, p.max_frame_gap_s);
    clamp("motion_update_distance", p.motion_update_distance, 0.05, 10.0);
    clamp("heading_update_angle", p.heading_update_angle, 0.0, 180.0);
    clamp("triangle_length", p.triangle_length, 0.2, 20.0);
    clamp("triangle_half_angle", p.triangle_half_angle, 1.0, 89.0);
    clamp("switch_area_ratio", p.switch_area_ratio, 0.0, 100.0);
    clamp("abandon_angle", p.abandon_angle, 0.0, 180.0);
    clamp("reached_distance", p.reached_distance, 0.0, 5.0);
    clamp("step_cost", p.step_cost, 0.0, 1000.0);
    clamp("clearance_weight", p.clearance_weight, 0.0, 1000.0);
    clamp("clearance_radius", p.clearance_radius, 0.0, 5.0);
    clamp("path_lookahead", p.path_lookahead, 0.05, 10.0);
    clamp("free_ray_max", p.free_ray_max, 0.1, 50.0);
    clamp("unknown_ahead_m", p.unknown_ahead_m, 0.0, 5.0);
    clamp("grid_timeout", p.grid_timeout, 0.05, 60.0);
    clamp("max_input_age_s", p.max_input_age_s, 0.05, 10.0);
    clamp("max_frame_gap_s", p.max_frame_gap_s, 0.05, 60.0);
    NODELET_INFO_STREAM("planner: world_frame " << world_frame_ << ", camera_frame " << camera_frame_
                        << ", triangle " << p.triangle_length << " m / +-" << p.triangle_half_angle
                        << " deg, motion " << p.motion_update_distance << " m / " << p.heading_update_angle
                        << " deg, step_cost " << p.step_cost << ", clearance " << p.clearance_weight << " within "
                        << p.clearance_radius << " m, unknown_traversable " << p.unknown_traversable);
    planner_ = std::make_unique<Planner>(p);
    monitor_ = InputMonitor(p.max_input_age_s, p.max_frame_gap_s);

    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
    state_pub_ = nh.advertise<assistive_msgs::NavigationState>("state", 1);
    path_pub_ = nh.advertise<nav_msgs::Path>("path", 1, true);
    waypoint_pub_ = nh.advertise<geometry_msgs::PointStamped>("waypoint", 1, true);
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("markers", 1);
    grid_sub_ = nh.subscribe("traversability", 1, &PlannerNodelet::gridCb, this);
    goal_sub_ = nh.subscribe("goal", 1, &PlannerNodelet::goalCb, this);
    if (p.use_odom)
      odom_sub_ = nh.subscribe("odom", 5, &PlannerNodelet::odomCb, this);

    diag_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh);
    diag_->setHardwareID("none");
    diag_->add("planner", this, &PlannerNodelet::diagnose);
    timer_ = nh.createTimer(ros::Duration(0.5), &PlannerNodelet::timerCb, this);
  }

  void clamp(const char* name, double& v, double lo, double hi)
  {
    if (!(v >= lo && v <= hi))
    {
      const double c = std::isfinite(v) ? std::min(std::max(v, lo), hi) : lo;
      NODELET_WARN("planner: parameter %s = %g outside [%g, %g], using %g", name, v, lo, hi, c);
      v = c;
    }
  }

  bool wearerPose(const ros::Time& stamp, Point2& pos, double& yaw)
  {
    geometry_msgs::TransformStamped t;
    try
    {
      t = tf_buffer_->lookupTransform(world_frame_, camera_frame_, stamp, ros::Duration(0.05));
    }
    catch (const tf2::TransformException&)
    {
      try
      {
        t = tf_buffer_->lookupTransform(world_frame_, camera_frame_, ros::Time(0));
        if (std::abs((t.header.stamp - stamp).toSec()) > 0.5)
          throw tf2::TransformException("latest pose too old");
      }
      catch (const tf2::TransformException& e)
      {
        NODELET_WARN_THROTTLE(5.0, "planner: no wearer pose %s -> %s: %s", world_frame_.c_str(),
                              camera_frame_.c_str(), e.what());
        return false;
      }
    }
    pos.x = t.transform.translation.x;
    pos.y = t.transform.translation.y;
    const auto& q = t.transform.rotation;
    // camera x axis projected onto the ground plane
    const double fx = 1.0 - 2.0 * (q.y * q.y + q.z * q.z);
    const double fy = 2.0 * (q.x * q.y + q.w * q.z);
    yaw = std::atan2(fy, fx);
    return std::isfinite(pos.x) && std::isfinite(pos.y) && std::isfinite(yaw);
  }

  /// The VO's verdict on its own pose comes with every frame: an untrusted pose or a map that no
  /// longer follows the camera stops the guidance at once, without waiting for a grid.
  void odomCb(const nav_msgs::Odometry::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool trusted = poseTrusted(*msg);
    const char* why = msg->header.stamp.toSec() < last_pose_stamp_ ? "time went back" :
                      trusted && !last_pose_trusted_            ? "the pose is trusted again" :
                                                                  "gap";
    last_pose_trusted_ = trusted;
    if (monitor_.onPose(msg->header.stamp.toSec(), trusted))
    {
      NODELET_WARN_THROTTLE(2.0, "planner: %s: motion vector, waypoint and map forgotten", why);
      const bool had_goal = planner_->hasGoal();
      planner_ = std::make_unique<Planner>(params_);
      if (had_goal)
        NODELET_WARN("planner: explicit goal dropped after the gap (its position is no longer known)");
    }
    last_pose_stamp_ = msg->header.stamp.toSec();
    const InputVerdict v = monitor_.check(true);
    if (!v.ok())
    {
      std_msgs::Header h;
      h.frame_id = world_frame_;
      h.stamp = msg->header.stamp;
      NODELET_WARN_THROTTLE(2.0, "planner: %s", v.reason.c_str());
      publish(status(v.status, v.reason), h, msg->header.stamp);
    }
  }

  /// vo/odom marks an untrusted pose with variances of 9999 (rtabmap's convention for a lost odometry).
  static bool poseTrusted(const nav_msgs::Odometry& o)
  {
    constexpr double kUntrustedVariance = 9999.0;
    for (int i : { 0, 7, 35 })
      if (!std::isfinite(o.pose.covariance[i]) || o.pose.covariance[i] >= 0.5 * kUntrustedVariance)
        return false;
    const auto& p = o.pose.pose.position;
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  }

  void gridCb(const nav_msgs::OccupancyGrid::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_grid_time_ = ros::WallTime::now();
    have_grid_ = true;
    std_msgs::Header header;
    header.frame_id = world_frame_;
    header.stamp = msg->header.stamp;
    if (!monitor_.onGrid(msg->header.stamp.toSec()))
    {
      NODELET_WARN_THROTTLE(2.0, "planner: grid from %.2f s ignored: built before a gap or a time jump",
                            msg->header.stamp.toSec());
      return;
    }
    const InputVerdict v = monitor_.check(params_.use_odom);
    if (!v.ok())
    {
      publish(status(v.status, v.reason), header, msg->header.stamp);
      return;
    }
    Grid grid;
    if (!msg->header.frame_id.empty() && msg->header.frame_id != world_frame_)
    {
      NODELET_ERROR_THROTTLE(5.0, "planner: grid frame '%s' is not the world frame '%s'",
                             msg->header.frame_id.c_str(), world_frame_.c_str());
      publish(status(PlanStatus::NO_MAP, "grid frame differs from world_frame"), header, msg->header.stamp);
      return;
    }
    if (!fromMsg(*msg, grid))
    {
      NODELET_ERROR_THROTTLE(5.0, "planner: malformed or rotated traversability grid ignored");
      publish(status(PlanStatus::NO_MAP, "malformed traversability grid"), header, msg->header.stamp);
      return;
    }
    Point2 pos;
    double yaw = 0.0;
    if (!wearerPose(msg->header.stamp, pos, yaw))
    {
      publish(status(PlanStatus::NO_POSE, "no wearer pose on tf"), header, msg->header.stamp);
      return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const PlanOutput out = planner_->update(grid, pos, yaw);
    plan_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    publish(out, header, msg->header.stamp);
  }

  void goalCb(const geometry_msgs::PoseStamped::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (msg->header.frame_id.empty())
    {
      planner_->clearGoal();
      NODELET_INFO("planner: explicit goal cleared, back to the automatic waypoint");
      return;
    }
    try
    {
      geometry_msgs::PoseStamped g;
      tf_buffer_->transform(*msg, g, world_frame_, ros::Duration(0.1));
      if (!std::isfinite(g.pose.position.x) || !std::isfinite(g.pose.position.y))
        throw tf2::TransformException("non-finite goal");
      planner_->setGoal({ g.pose.position.x, g.pose.position.y });
      NODELET_INFO("planner: explicit goal (%.2f, %.2f) in %s", g.pose.position.x, g.pose.position.y,
                   world_frame_.c_str());
    }
    catch (const tf2::TransformException& e)
    {
      NODELET_WARN_THROTTLE(5.0, "planner: goal ignored: %s", e.what());
    }
  }

  void timerCb(const ros::TimerEvent&)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool stale = !have_grid_ || (ros::WallTime::now() - last_grid_time_).toSec() > params_.grid_timeout;
    if (stale)
    {
      NODELET_WARN_THROTTLE(10.0, "planner: no traversability grid for %.1f s", params_.grid_timeout);
      std_msgs::Header h;
      h.frame_id = world_frame_;
      h.stamp = ros::Time::now();
      publish(status(PlanStatus::NO_MAP, have_grid_ ? "traversability grid is stale" : "no traversability grid yet"),
              h, ros::Time(0));
    }
    diag_->update();
  }

  PlanOutput status(PlanStatus s, const std::string& msg) const
  {
    PlanOutput o;
    o.status = s;
    o.message = msg;
    return o;
  }

  void publish(const PlanOutput& out, const std_msgs::Header& header, const ros::Time& source_stamp)
  {
    last_ = out;
    state_pub_.publish(boost::make_shared<assistive_msgs::NavigationState>(toMsg(out, header, source_stamp)));
    if (out.status == PlanStatus::OK)
    {
      path_pub_.publish(boost::make_shared<nav_msgs::Path>(toPathMsg(out, header)));
      waypoint_pub_.publish(boost::make_shared<geometry_msgs::PointStamped>(toWaypointMsg(out, header)));
    }
    else if (out.status != PlanStatus::NO_MAP || have_grid_)
    {
      path_pub_.publish(boost::make_shared<nav_msgs::Path>(toPathMsg(out, header)));  // empty path: none valid
    }
    if (markers_pub_.getNumSubscribers() > 0 && out.status != PlanStatus::NO_MAP && out.status != PlanStatus::NO_POSE)
      markers_pub_.publish(boost::make_shared<visualization_msgs::MarkerArray>(toMarkers(out, header)));
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st)
  {
    using diagnostic_msgs::DiagnosticStatus;
    const PlanOutput& o = last_;
    const uint8_t level = o.status == PlanStatus::OK ? DiagnosticStatus::OK
                          : (o.status == PlanStatus::NO_MAP || o.status == PlanStatus::NO_POSE) ? DiagnosticStatus::ERROR
                                                                                                : DiagnosticStatus::WARN;
    st.summary(level, o.message.empty() ? "starting" : o.message);
    st.add("status", int(o.status));
    st.add("plan_ms", plan_ms_);
    st.add("expansions", o.expansions);
    st.add("changed_cells", o.changed_cells);
    st.add("waypoint_distance_m", o.waypoint_distance);
    st.add("path_length_m", o.path_length);
    st.add("explicit_goal", o.explicit_goal);
    st.add("grid_age_s", have_grid_ ? (ros::WallTime::now() - last_grid_time_).toSec() : -1.0);
    st.add("grid_lag_behind_newest_frame_s", monitor_.newest() - monitor_.gridStamp());
    st.add("resets_after_gap", monitor_.resets());
  }

  std::string world_frame_ = "odom";
  std::string camera_frame_ = "camera_link";
  PlannerParams params_;
  std::unique_ptr<Planner> planner_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Publisher state_pub_, path_pub_, waypoint_pub_, markers_pub_;
  ros::Subscriber grid_sub_, goal_sub_, odom_sub_;
  InputMonitor monitor_;
  double last_pose_stamp_ = 0.0;
  bool last_pose_trusted_ = true;
  ros::Timer timer_;
  std::unique_ptr<diagnostic_updater::Updater> diag_;
  std::mutex mutex_;
  bool have_grid_ = false;
  ros::WallTime last_grid_time_;
  PlanOutput last_;
  double plan_ms_ = 0.0;
};
}  // namespace assistive_planner

PLUGINLIB_EXPORT_CLASS(assistive_planner::PlannerNodelet, nodelet::Nodelet)
