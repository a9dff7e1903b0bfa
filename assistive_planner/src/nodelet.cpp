// Thin nodelet around assistive_planner::Planner: grid + tf in, NavigationState / path / waypoint out.
#include <chrono>
#include <limits>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Range.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <assistive_common/callback_guard.h>
#include <assistive_common/ros_params.h>

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
    for (const std::string& w : assistive_common::readParams(pnh, params_)) NODELET_WARN("planner: %s", w.c_str());
    for (const std::string& w : assistive_common::readParams(pnh, node_)) NODELET_WARN("planner: %s", w.c_str());
    const PlannerParams& p = params_;
    NODELET_INFO("planner: %s", assistive_common::describe(p).c_str());
    NODELET_INFO("planner: %s", assistive_common::describe(node_).c_str());
    planner_ = std::make_unique<Planner>(p);
    monitor_ = InputMonitor(p.max_input_age_s, p.max_frame_gap_s);

    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
    state_pub_ = nh.advertise<assistive_msgs::NavigationState>("state", 1);
    path_pub_ = nh.advertise<nav_msgs::Path>("path", 1, true);
    waypoint_pub_ = nh.advertise<geometry_msgs::PointStamped>("waypoint", 1, true);
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("markers", 1);
    // the grid each state was planned on (the cue logic sweeps the body's predicted walk over it)
    planned_grid_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("grid", 1);
    grid_sub_ = nh.subscribe("traversability", 1, &PlannerNodelet::gridCb, this);
    goal_sub_ = nh.subscribe("goal", 1, &PlannerNodelet::goalCb, this);
    movers_sub_ = nh.subscribe("movers", 1, &PlannerNodelet::moversCb, this);
    if (node_.use_odom)
      odom_sub_ = nh.subscribe("odom", 5, &PlannerNodelet::odomCb, this);
    // the forward ranger vouches for the blind zone just ahead (README, the blind zone)
    ranger_sub_ = nh.subscribe("sonar/front", 5, &PlannerNodelet::rangerCb, this);

    diag_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh);
    diag_->setHardwareID("none");
    diag_->add("planner", this, &PlannerNodelet::diagnose);
    timer_ = nh.createTimer(ros::Duration(0.5), &PlannerNodelet::timerCb, this);
  }

  bool wearerPose(const ros::Time& stamp, Point2& pos, double& yaw)
  {
    geometry_msgs::TransformStamped t;
    try
    {
      // No timeout: a callback never waits for tf (the grid's pose came before the grid).
      t = tf_buffer_->lookupTransform(node_.world_frame, node_.camera_frame, stamp);
    }
    catch (const tf2::TransformException&)
    {
      try
      {
        t = tf_buffer_->lookupTransform(node_.world_frame, node_.camera_frame, ros::Time(0));
        if (std::abs((t.header.stamp - stamp).toSec()) > 0.5)
          throw tf2::TransformException("latest pose too old");
      }
      catch (const tf2::TransformException& e)
      {
        NODELET_WARN_THROTTLE(5.0, "planner: no wearer pose %s -> %s: %s", node_.world_frame.c_str(),
                              node_.camera_frame.c_str(), e.what());
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
    assistive_common::guarded(getName(), "pose", [&] { odom(msg); });
  }

  void odom(const nav_msgs::Odometry::ConstPtr& msg)
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
      planner_ = std::make_unique<Planner>(params_);
      // A goal given in world_frame (the VO's odom) is lost with the pose; one given in another
      // frame (SLAM's map) is found again through tf at the next grid, once the map has the wearer.
      if (goal_ && goal_->header.frame_id == node_.world_frame)
      {
        goal_.reset();
        NODELET_WARN("planner: explicit goal in %s dropped after the gap (its position is no longer known); "
                     "a goal in the map frame survives", node_.world_frame.c_str());
      }
    }
    last_pose_stamp_ = msg->header.stamp.toSec();
    const InputVerdict v = monitor_.check(true);
    if (!v.ok())
    {
      std_msgs::Header h;
      h.frame_id = node_.world_frame;
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

  /// The forward ranger: its newest valid reading is kept for the next grid (RangerReading).
  void rangerCb(const sensor_msgs::Range::ConstPtr& msg)
  {
    assistive_common::guarded(getName(), "ranger", [&] { ranger(msg); });
  }

  void ranger(const sensor_msgs::Range::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const double r = msg->range;
    const bool ok = !msg->header.frame_id.empty() && !msg->header.stamp.isZero() && std::isfinite(msg->max_range) &&
                    msg->max_range > 0.0 &&
                    (r == std::numeric_limits<float>::infinity() || (std::isfinite(r) && r >= msg->min_range && r <= msg->max_range));
    if (!ok)
    {
      NODELET_WARN_THROTTLE(5.0, "planner: ranger reading ignored (frame '%s', stamp %.3f, range %.3f in [%.2f, %.2f]): "
                            "the blind zone is not vouched for", msg->header.frame_id.c_str(),
                            msg->header.stamp.toSec(), r, msg->min_range, msg->max_range);
      return;
    }
    ranger_msg_ = msg;
  }

  /// The kept ranger reading with its axis in world_frame at `stamp` (the grid's); none without tf.
  RangerReading rangerAt(const ros::Time& stamp)
  {
    RangerReading out;
    if (!ranger_msg_)
      return out;
    geometry_msgs::TransformStamped t;
    try
    {
      t = tf_buffer_->lookupTransform(node_.world_frame, ranger_msg_->header.frame_id, stamp);
    }
    catch (const tf2::TransformException&)
    {
      try
      {
        t = tf_buffer_->lookupTransform(node_.world_frame, ranger_msg_->header.frame_id, ros::Time(0));
      }
      catch (const tf2::TransformException& e)
      {
        NODELET_WARN_THROTTLE(5.0, "planner: no pose of the ranger %s in %s: %s", ranger_msg_->header.frame_id.c_str(),
                              node_.world_frame.c_str(), e.what());
        return out;
      }
    }
    const auto& q = t.transform.rotation;
    out.stamp = ranger_msg_->header.stamp.toSec();
    out.range = std::isfinite(ranger_msg_->range) ? double(ranger_msg_->range) : std::numeric_limits<double>::infinity();
    out.max_range = ranger_msg_->max_range;
    out.field_of_view = ranger_msg_->field_of_view;
    out.yaw = std::atan2(2.0 * (q.x * q.y + q.w * q.z), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
    return out;
  }

  void gridCb(const nav_msgs::OccupancyGrid::ConstPtr& msg)
  {
    assistive_common::guarded(getName(), "grid", [&] { grid(msg); });
  }

  void grid(const nav_msgs::OccupancyGrid::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_grid_time_ = ros::WallTime::now();
    have_grid_ = true;
    std_msgs::Header header;
    header.frame_id = node_.world_frame;
    header.stamp = msg->header.stamp;
    if (!monitor_.onGrid(msg->header.stamp.toSec()))
    {
      NODELET_WARN_THROTTLE(2.0, "planner: grid from %.2f s ignored: built before a gap or a time jump",
                            msg->header.stamp.toSec());
      return;
    }
    const InputVerdict v = monitor_.check(node_.use_odom);
    if (!v.ok())
    {
      publish(status(v.status, v.reason), header, msg->header.stamp);
      return;
    }
    Grid grid;
    if (!msg->header.frame_id.empty() && msg->header.frame_id != node_.world_frame)
    {
      NODELET_ERROR_THROTTLE(5.0, "planner: grid frame '%s' is not the world frame '%s'",
                             msg->header.frame_id.c_str(), node_.world_frame.c_str());
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
    planner_->setRanger(rangerAt(msg->header.stamp));
    // the planner is rebuilt after a gap: the movers and the goal are handed over every cycle
    if (have_movers_)
      planner_->setMovers(movers_stamp_, movers_);
    else
      planner_->clearMovers();
    if (goal_ && !goalInWorld(msg->header.stamp))
    {
      publish(status(PlanStatus::NO_POSE, "explicit goal: " + goal_frame_error_), header, msg->header.stamp);
      return;
    }
    const PlanOutput out = planner_->update(grid, pos, yaw, msg->header.stamp.toSec());
    if (goal_ && !planner_->hasGoal())
    {
      NODELET_INFO("planner: explicit goal reached, back to the automatic waypoint");
      goal_.reset();
    }
    plan_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    publish(out, header, msg->header.stamp);
  }

  /// The obstacle stage's tracked movers (every frame, empty when none): kept for the next cycle;
  /// the core judges their age against the grid's stamp.
  void moversCb(const assistive_msgs::MoverArray::ConstPtr& msg)
  {
    assistive_common::guarded(getName(), "movers", [&] { movers(msg); });
  }

  void movers(const assistive_msgs::MoverArray::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!msg->header.frame_id.empty() && msg->header.frame_id != node_.world_frame)
    {
      NODELET_ERROR_THROTTLE(5.0, "planner: movers in frame '%s', not the world frame '%s': ignored (no crossing advice)",
                             msg->header.frame_id.c_str(), node_.world_frame.c_str());
      have_movers_ = false;
      return;
    }
    have_movers_ = true;
    movers_stamp_ = msg->header.stamp.toSec();
    movers_ = fromMsg(*msg);
  }

  void goalCb(const geometry_msgs::PoseStamped::ConstPtr& msg)
  {
    assistive_common::guarded(getName(), "goal", [&] { goal(msg); });
  }

  void goal(const geometry_msgs::PoseStamped::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (msg->header.frame_id.empty())
    {
      goal_.reset();
      planner_->clearGoal();
      NODELET_INFO("planner: explicit goal cleared, back to the automatic waypoint");
      return;
    }
    if (!std::isfinite(msg->pose.position.x) || !std::isfinite(msg->pose.position.y))
    {
      NODELET_WARN_THROTTLE(5.0, "planner: goal ignored: non-finite position");
      return;
    }
    // Kept in the frame it was given in and expressed in world_frame at every grid: a goal in `map`
    // follows SLAM's corrections and survives the VO's re-initialisation.
    goal_ = *msg;
    goal_frame_error_.clear();
    if (goalInWorld())
      NODELET_INFO("planner: explicit goal (%.2f, %.2f) in %s", msg->pose.position.x, msg->pose.position.y,
                   msg->header.frame_id.c_str());
    else
      NODELET_WARN_THROTTLE(5.0, "planner: explicit goal in %s not yet in %s (%s): kept, guidance waits for it",
                            msg->header.frame_id.c_str(), node_.world_frame.c_str(), goal_frame_error_.c_str());
  }

  /// The kept goal through the newest tf into world_frame and on to the core; false (with
  /// goal_frame_error_) while the transform is not known, e.g. before SLAM has placed the wearer,
  /// or, against the grid's stamp `at`, older than `goal_tf_max_age` (SLAM no longer places the
  /// wearer after a VO loss: tf2 would hand out its last map -> odom however old). Static frames
  /// (stamp 0) never age; `at` zero skips the check.
  bool goalInWorld(const ros::Time& at = ros::Time(0))
  {
    try
    {
      // the newest correction: the goal is a fixed place in its frame (no timeout: no wait in a callback)
      const geometry_msgs::TransformStamped tf =
          tf_buffer_->lookupTransform(node_.world_frame, goal_->header.frame_id, ros::Time(0));
      if (!at.isZero() && !tf.header.stamp.isZero() && (at - tf.header.stamp).toSec() > node_.goal_tf_max_age)
        throw tf2::TransformException("the newest " + goal_->header.frame_id + " -> " + node_.world_frame + " is " +
                                      std::to_string((at - tf.header.stamp).toSec()) +
                                      " s old (the wearer is no longer placed in it)");
      geometry_msgs::PoseStamped g;
      tf2::doTransform(*goal_, g, tf);
      if (!std::isfinite(g.pose.position.x) || !std::isfinite(g.pose.position.y))
        throw tf2::TransformException("non-finite goal after the transform");
      planner_->setGoal({ g.pose.position.x, g.pose.position.y });
      goal_frame_error_.clear();
      return true;
    }
    catch (const tf2::TransformException& e)
    {
      goal_frame_error_ = e.what();
      return false;
    }
  }

  void timerCb(const ros::TimerEvent& e)
  {
    assistive_common::guarded(getName(), "timer", [&] { timer(e); });
  }

  void timer(const ros::TimerEvent&)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool stale = !have_grid_ || (ros::WallTime::now() - last_grid_time_).toSec() > node_.grid_timeout;
    if (stale)
    {
      NODELET_WARN_THROTTLE(10.0, "planner: no traversability grid for %.1f s", node_.grid_timeout);
      std_msgs::Header h;
      h.frame_id = node_.world_frame;
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
    // the grid first: a cue logic in the same manager has it when the state arrives
    if (out.grid && planned_grid_pub_.getNumSubscribers() > 0)
    {
      std_msgs::Header gh = header;
      gh.stamp = source_stamp;
      planned_grid_pub_.publish(boost::make_shared<nav_msgs::OccupancyGrid>(toMsg(*out.grid, gh)));
    }
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
    st.add("explicit_goal_frame", goal_ ? goal_->header.frame_id : std::string());
    st.add("grid_age_s", have_grid_ ? (ros::WallTime::now() - last_grid_time_).toSec() : -1.0);
    st.add("grid_lag_behind_newest_frame_s", monitor_.newest() - monitor_.gridStamp());
    st.add("resets_after_gap", monitor_.resets());
    st.add("blind_zone_vouched_cells", o.vouched_cells);
    st.add("blind_zone_note", o.vouch_note);
    st.add("unseen_floor_cells_held", o.unseen_held_cells);
    st.add("step_cells_crossed", o.crossed_step_cells);
    st.add("movers", o.crossing.movers);
    st.add("movers_fresh", o.crossing.movers_fresh);
    st.add("movers_age_s", have_movers_ ? monitor_.gridStamp() - movers_stamp_ : -1.0);
    st.add("crossing", crossingName(o.crossing.advice));
    st.add("wearer_speed_mps", o.crossing.wearer_speed);
  }

  PlannerParams params_;
  PlannerNodeParams node_;
  std::unique_ptr<Planner> planner_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Publisher state_pub_, path_pub_, waypoint_pub_, markers_pub_;
  ros::Publisher planned_grid_pub_;
  ros::Subscriber grid_sub_, goal_sub_, odom_sub_, movers_sub_, ranger_sub_;
  sensor_msgs::Range::ConstPtr ranger_msg_;  ///< the newest valid ranger reading
  std::optional<geometry_msgs::PoseStamped> goal_;  ///< as given (its own frame); empty: automatic waypoint
  std::string goal_frame_error_;
  bool have_movers_ = false;
  double movers_stamp_ = 0.0;
  std::vector<MoverState> movers_;
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
