// Cue logic nodelet: planner/state (+ planner/grid) -> tactile/cue (+ tactile/markers, /diagnostics). Glue only.
#include <assistive_msgs/NavigationState.h>
#include <nav_msgs/OccupancyGrid.h>
#include <assistive_msgs/TactileCue.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>

#include <assistive_common/callback_guard.h>
#include <assistive_common/code_grid_msg.h>
#include <assistive_common/ros_params.h>

#include "assistive_tactile/conversions.h"
#include "assistive_tactile/cue_logic.h"
#include "assistive_tactile/vest_gyro.h"

namespace assistive_tactile
{
class CueLogicNodelet : public nodelet::Nodelet
{
public:
  ~CueLogicNodelet() override
  {
    timer_.stop();
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    CueParams p;
    for (const std::string& w : assistive_common::readParams(pnh, p)) NODELET_WARN("cue_logic: %s", w.c_str());
    NODELET_INFO("cue_logic: %s", assistive_common::describe(p).c_str());
    logic_ = CueLogic(p);

    cue_pub_ = nh.advertise<assistive_msgs::TactileCue>("cue", 1);
    marker_pub_ = nh.advertise<visualization_msgs::MarkerArray>("markers", 1);
    state_sub_ = nh.subscribe("state", 1, &CueLogicNodelet::stateCb, this);
    // the grid each state was planned on: the body's predicted sweep (none: the rays alone)
    grid_sub_ = nh.subscribe("grid", 1, &CueLogicNodelet::gridCb, this);
    // the vest's own IMU, when it has one: the torso's turns without the head's scan (none: the
    // body's facing is estimated from the head, as before)
    imu_sub_ = nh.subscribe("vest_imu", 50, &CueLogicNodelet::imuCb, this);
    // its offset as the last run left it, until the vest is still for a second ("": not kept;
    // device.launch keeps it in ~/.ros, the trials and tests never: each run its own)
    offset_file_ = pnh.param<std::string>("vest_gyro_offset_file", "");
    double kept = 0.0;
    std::string why;
    if (!offset_file_.empty() && loadOffset(offset_file_, &kept, &why))
    {
      vest_gyro_.setOffset(kept);
      offset_kept_ = true;
      NODELET_INFO("cue_logic: vest gyro offset %.3f deg/s kept from %s", kept * 180.0 / M_PI, offset_file_.c_str());
    }
    else if (!offset_file_.empty())
      NODELET_INFO("cue_logic: no vest gyro offset kept (%s): captured when the vest is still", why.c_str());
    updater_.reset(new diagnostic_updater::Updater(nh, pnh, getName()));
    updater_->setHardwareID("cue_logic");
    updater_->add("cue logic", this, &CueLogicNodelet::diagnose);
    // Checked every 20 ms (not only at the heartbeat) so input that stops arriving turns into
    // UNSURE within max_input_age_s of its camera stamp, not up to a heartbeat period later.
    timer_ = nh.createTimer(ros::Duration(std::min(0.02, 1.0 / p.heartbeat_hz)), &CueLogicNodelet::timerCb, this);
  }

  void stateCb(const assistive_msgs::NavigationState::ConstPtr& msg)
  {
    assistive_common::guarded(getName(), "planner state", [&] { handleState(msg); });
  }

  void gridCb(const nav_msgs::OccupancyGrid::ConstPtr& msg)
  {
    assistive_common::guarded(getName(), "planner grid", [&] {
      auto g = std::make_shared<ObstacleGrid>();
      if (!assistive_common::fromMsg(*msg, *g))
      {
        NODELET_WARN_THROTTLE(5.0, "cue_logic: malformed or rotated planner grid ignored");
        return;
      }
      std::lock_guard<std::mutex> lock(mutex_);
      grid_ = std::move(g);
      grid_stamp_ = msg->header.stamp;
      grid_frame_ = msg->header.frame_id;
    });
  }

  void imuCb(const sensor_msgs::Imu::ConstPtr& msg)
  {
    assistive_common::guarded(getName(), "vest imu", [&] {
      const auto& w = msg->angular_velocity;
      const auto& a = msg->linear_acceleration;
      std::lock_guard<std::mutex> lock(mutex_);
      vest_gyro_.add(msg->header.stamp.toSec(), Eigen::Vector3d(w.x, w.y, w.z), Eigen::Vector3d(a.x, a.y, a.z));
      ++imu_samples_;
      keepOffset();
    });
  }

  /// The captured offset into `offset_file_`, at most once a minute (the caller holds mutex_).
  void keepOffset()
  {
    if (offset_file_.empty() || vest_gyro_.offsetCaptures() == saved_captures_)
      return;
    const ros::WallTime now = ros::WallTime::now();
    if ((now - offset_saved_).toSec() < 60.0)
      return;
    std::string why;
    if (!saveOffset(offset_file_, vest_gyro_.offset(), &why))
      NODELET_WARN_THROTTLE(600.0, "cue_logic: vest gyro offset not kept: %s", why.c_str());
    saved_captures_ = vest_gyro_.offsetCaptures();
    offset_saved_ = now;
  }

  void handleState(const assistive_msgs::NavigationState::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::Time now = ros::Time::now();
    NavInput in = fromMsg(*msg);
    in.body_yaw_rate = vest_gyro_.take(now.toSec());
    vest_gyro_used_ = std::isfinite(in.body_yaw_rate);
    // the grid of the same planning cycle (its stamp is the state's source_stamp; one a cycle older
    // still serves), in the state's frame
    if (grid_ && grid_frame_ == msg->header.frame_id && !msg->source_stamp.isZero() &&
        std::fabs((grid_stamp_ - msg->source_stamp).toSec()) <= 0.2)
      in.grid = grid_;
    const Cue cue = logic_.update(in, now.toSec());
    if (cue.reason.find("NaN") != std::string::npos)
      NODELET_WARN_THROTTLE(5.0, "cue_logic: planner state with NaN fields, vest quiet");
    publish(cue, now, msg->source_stamp);
    ++states_;
  }

  void timerCb(const ros::TimerEvent& e)
  {
    assistive_common::guarded(getName(), "timer", [&] { handleTimer(e); });
  }

  void handleTimer(const ros::TimerEvent&)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::Time now = ros::Time::now();
    if (logic_.stale(now.toSec()))
    {
      // No state for state_timeout_s, or the last one's camera image is older than
      // max_input_age_s: never repeat an old GUIDANCE/ALERT, say UNSURE instead.
      const Cue quiet = logic_.staleCue(now.toSec());
      NODELET_WARN_THROTTLE(5.0, "cue_logic: %s: vest quiet", quiet.reason.c_str());
      if (last_cue_.mode != CueMode::UNSURE || (now - last_pub_).toSec() >= 0.9 / logic_.params().heartbeat_hz)
        publish(quiet, now, last_source_stamp_);
    }
    else if ((now - last_pub_).toSec() >= 0.9 / logic_.params().heartbeat_hz)
    {
      publish(last_cue_, now, last_source_stamp_);  // heartbeat: the bridge's stale guard stays calm
    }
    updater_->update();
  }

  void publish(const Cue& cue, const ros::Time& now, const ros::Time& source_stamp)
  {
    last_cue_ = cue;
    last_pub_ = now;
    last_source_stamp_ = source_stamp;
    cue_pub_.publish(boost::make_shared<assistive_msgs::TactileCue>(
        toMsg(cue, now, source_stamp, logic_.params().body_frame)));
    ++cues_;
    if (marker_pub_.getNumSubscribers() > 0)
      publishMarkers(cue, now);
  }

  void publishMarkers(const Cue& cue, const ros::Time& now)
  {
    static const char* frames[NUM_MOTORS] = { "motor_left_shoulder", "motor_right_shoulder", "motor_left_waist",
                                              "motor_right_waist" };
    auto arr = boost::make_shared<visualization_msgs::MarkerArray>();
    for (int i = 0; i < NUM_MOTORS; ++i)
    {
      visualization_msgs::Marker m;
      m.header.frame_id = frames[i];
      m.header.stamp = ros::Time(0);  // latest tf: the motors are fixed on the wearer
      m.ns = "tactile_motors";
      m.id = i;
      m.type = visualization_msgs::Marker::SPHERE;
      m.action = visualization_msgs::Marker::ADD;
      m.pose.orientation.w = 1.0;
      const double k = cue.intensity[i];
      m.scale.x = m.scale.y = m.scale.z = 0.06 + 0.08 * k;
      m.color.r = static_cast<float>(0.4 + 0.6 * k);
      m.color.g = static_cast<float>(0.4 * (1.0 - k));
      m.color.b = static_cast<float>(0.4 * (1.0 - k));
      m.color.a = k > 0.0 ? 1.0f : 0.5f;
      arr->markers.push_back(m);
    }
    visualization_msgs::Marker t;
    t.header.frame_id = logic_.params().body_frame;
    t.header.stamp = ros::Time(0);
    t.ns = "tactile_reason";
    t.id = 0;
    t.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    t.action = visualization_msgs::Marker::ADD;
    t.pose.position.z = 0.5;
    t.pose.orientation.w = 1.0;
    t.scale.z = 0.1;
    t.color.r = t.color.g = t.color.b = t.color.a = 1.0f;
    t.text = std::string(modeName(cue.mode)) + ": " + cue.reason;
    arr->markers.push_back(t);
    (void)now;
    marker_pub_.publish(arr);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat)
  {
    const double now = ros::Time::now().toSec();
    if (logic_.stale(now))
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no fresh planner state (stale or camera image too old): vest quiet");
    else if (last_cue_.mode == CueMode::UNSURE)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "unsure: " + last_cue_.reason);
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, modeName(last_cue_.mode));
    stat.add("mode", modeName(last_cue_.mode));
    stat.add("reason", last_cue_.reason);
    stat.add("intensity", std::to_string(last_cue_.intensity[0]) + " " + std::to_string(last_cue_.intensity[1]) +
                              " " + std::to_string(last_cue_.intensity[2]) + " " +
                              std::to_string(last_cue_.intensity[3]));
    stat.add("vest gyro", imu_samples_ == 0 ? "none (facing from the head)" : vest_gyro_used_ ? "in use" : "stale (facing from the head)");
    if (imu_samples_ > 0)
    {
      const std::string deg = std::to_string(vest_gyro_.offset() * 180.0 / M_PI);
      stat.add("vest gyro offset (deg/s)", vest_gyro_.offsetCaptures() > 0 ? deg + " (" + std::to_string(vest_gyro_.offsetCaptures()) + " still seconds)"
                                           : offset_kept_ ? deg + " (kept from the last run; not captured yet)"
                                                          : std::string("not captured yet (the vest still for 1 s captures it)"));
    }
    stat.add("planner states", states_);
    stat.add("cues published", cues_);
    if (!last_source_stamp_.isZero())
      stat.add("source age (s)", ros::Time::now().toSec() - last_source_stamp_.toSec());
  }

  std::mutex mutex_;
  CueLogic logic_;
  Cue last_cue_;
  ros::Time last_pub_, last_source_stamp_;
  uint64_t states_ = 0, cues_ = 0;
  ros::Publisher cue_pub_, marker_pub_;
  ros::Subscriber state_sub_;
  ros::Subscriber grid_sub_;
  ros::Subscriber imu_sub_;
  VestGyro vest_gyro_;
  std::string offset_file_;  ///< where the offset is kept across runs ("": not kept)
  bool offset_kept_ = false;
  int saved_captures_ = 0;
  ros::WallTime offset_saved_;
  uint64_t imu_samples_ = 0;
  bool vest_gyro_used_ = false;
  std::shared_ptr<const ObstacleGrid> grid_;  ///< the planner's latest grid
  ros::Time grid_stamp_;
  std::string grid_frame_;
  ros::Timer timer_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
};

}  // namespace assistive_tactile

PLUGINLIB_EXPORT_CLASS(assistive_tactile::CueLogicNodelet, nodelet::Nodelet)
