// Vest bridge nodelet: tactile/cue -> serial packets to the vest (+ /diagnostics). Glue only:
// the port, packets, stamp checks, expiry, re-send and reconnection live in VestBridge, the
// housekeeping thread in VestBridgeRunner.
#include <assistive_msgs/TactileCue.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/Joy.h>
#include <sensor_msgs/Range.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

#include <assistive_common/callback_guard.h>
#include <assistive_common/ros_params.h>

#include "assistive_tactile/conversions.h"
#include "assistive_tactile/vest_bridge.h"

namespace assistive_tactile
{
class VestBridgeNodelet : public nodelet::Nodelet
{
public:
  ~VestBridgeNodelet() override
  {
    // Unload or shutdown: no more cues, then all motors off before the port closes.
    cue_sub_.shutdown();
    if (runner_)
      runner_->stop();
    if (handlers_installed_)
      removeAllOffSignalHandlers();
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    BridgeParams p;
    std::vector<std::string> clamped = assistive_common::readParams(pnh, p);
    for (const std::string& w : clampParams(p))
      clamped.push_back(w);  // the rules a range cannot say
    for (const std::string& w : clamped) NODELET_WARN("vest_bridge: %s", w.c_str());
    NODELET_INFO("vest_bridge: port %s @ %d baud, protocol v%u, resend %.1f Hz, stale %.3f s, max source age "
                 "%.3f s, reopen %.2f s",
                 p.port.c_str(), p.baud, VEST_PROTOCOL_VERSION, p.resend_hz, p.stale_s, p.max_source_age_s,
                 p.reopen_s);
    params_ = p;
    sonar_frame_ = pnh.param<std::string>("sonar_frame", "sonar_front");
    // Since protocol version 3: the forward ranger and the wearer's buttons.
    pub_range_ = nh.advertise<sensor_msgs::Range>("sonar/front", 10);
    pub_buttons_ = nh.advertise<sensor_msgs::Joy>("buttons", 10);
    // Since protocol version 5: the vest's IMU, the torso's turns for the cue logic.
    imu_frame_ = pnh.param<std::string>("imu_frame", "vest_imu");
    pub_imu_ = nh.advertise<sensor_msgs::Imu>("imu", 100);

    // SIGINT/SIGTERM to this process (manager or standalone): all-off written by the handler.
    installAllOffSignalHandlers();
    handlers_installed_ = true;

    updater_.reset(new diagnostic_updater::Updater(nh, pnh, getName()));
    updater_->setHardwareID(p.port);
    updater_->add("vest link", this, &VestBridgeNodelet::diagnose);
    // Housekeeping in its own thread (100 Hz and at each cue's expiry): the all-off does not wait
    // for the manager's callback queue.
    runner_.reset(new VestBridgeRunner(p, 0.01, [this](VestBridge& b, double now) {
      assistive_common::guarded(getName(), "vest housekeeping", [&] { afterSpin(b, now); });
    }));
    const std::string sched = runner_->schedulingError();
    if (!sched.empty())
      NODELET_WARN("vest_bridge: housekeeping thread on normal scheduling (%s): under CPU overload the all-off "
                   "may be late; the vest's TTL still ends each cue (grant rtprio, e.g. limits.conf)",
                   sched.c_str());

    cue_sub_ = nh.subscribe("cue", 1, &VestBridgeNodelet::cueCb, this, ros::TransportHints().tcpNoDelay());
  }

  void cueCb(const assistive_msgs::TactileCue::ConstPtr& msg)
  {
    assistive_common::guarded(getName(), "cue", [&] { handleCue(msg); });
  }

  void handleCue(const assistive_msgs::TactileCue::ConstPtr& msg)
  {
    // Ages in ROS time (simulated in bag replay), like the stamps; an unstamped cue cannot be
    // judged (infinitely old), a zero source_stamp is unknown.
    const ros::Time now = ros::Time::now();
    CueAge age;
    age.stamp_age_s = msg->header.stamp.isZero() ? std::numeric_limits<double>::infinity() :
                                                   (now - msg->header.stamp).toSec();
    age.source_age_s = msg->source_stamp.isZero() ? std::numeric_limits<double>::quiet_NaN() :
                                                    (now - msg->source_stamp).toSec();
    const Cue cue = fromMsg(*msg);
    VestCue vc;
    vc.intensity = cue.intensity;
    vc.pattern = cue.pattern;  // the vest times the pulses (protocol version 4)
    vc.unsure = cue.mode == CueMode::UNSURE;
    const CueCheck verdict = runner_->setCue(vc, age);
    if (verdict != CueCheck::FRESH)
      NODELET_WARN_THROTTLE(2.0, "vest_bridge: ignoring a %s cue (%s): stamp age %.3f s, source age %.3f s",
                            modeName(cue.mode), cueCheckName(verdict), age.stamp_age_s, age.source_age_s);
  }

  // Runs in the runner's thread with the bridge locked.
  void afterSpin(VestBridge& b, double now)
  {
    const LinkStats& s = b.stats();
    publishSensors(b, now);
    if (!was_stale_ && s.cue_stale)
      NODELET_WARN("vest_bridge: no valid tactile/cue (last one expired %.3f s after its stamp): all motors off",
                   params_.stale_s);
    if (was_open_ && !s.open)
      NODELET_ERROR("vest_bridge: lost %s (%s), reopening every %.1f s", params_.port.c_str(), s.last_error.c_str(),
                    params_.reopen_s);
    if (!was_open_ && s.open)
      NODELET_INFO("vest_bridge: opened %s", params_.port.c_str());
    if (!s.open)
      NODELET_WARN_THROTTLE(10.0, "vest_bridge: port %s closed: %s", params_.port.c_str(), s.last_error.c_str());
    if (s.version_mismatches != mismatches_)
      NODELET_ERROR_THROTTLE(10.0, "vest_bridge: the vest speaks protocol version %u, this bridge %u: reflash "
                                   "firmware/vest/vest.ino",
                             s.vest_version, VEST_PROTOCOL_VERSION);
    was_stale_ = s.cue_stale;
    was_open_ = s.open;
    mismatches_ = s.version_mismatches;
    snap_ = s;
    snap_link_up_ = b.linkUp(now);
    snap_sent_ = b.sentDuty();
    snap_pattern_ = b.sentPattern();
    const std::array<uint8_t, VEST_NUM_MOTORS> peak = b.takeStatusPeak();
    for (size_t i = 0; i < peak_.size(); ++i)
      peak_[i] = std::max(peak_[i], peak[i]);
    updater_->update();  // calls diagnose() at its own rate
  }

  /// RANGE -> sonar/front (+Inf = no echo, REP 117), BUTTONS -> buttons (sensor_msgs/Joy:
  /// buttons = [A short, A long, B short, B long, A held, B held], presses counted in the message
  /// that reports them). Bad readings are never published; they are counted and warned about.
  void publishSensors(VestBridge& b, double now)
  {
    const LinkStats& s = b.stats();
    const ros::Time ros_now = ros::Time::now();
    b.takeRanges(ranges_);
    for (const RangeEvent& e : ranges_)
    {
      auto m = boost::make_shared<sensor_msgs::Range>();
      m->header.stamp = ros_now - ros::Duration(std::max(0.0, now - e.time));
      m->header.frame_id = sonar_frame_;
      m->radiation_type = sensor_msgs::Range::ULTRASOUND;
      m->field_of_view = static_cast<float>(params_.sonar_fov_deg * M_PI / 180.0);
      m->min_range = static_cast<float>(params_.sonar_min_range);
      m->max_range = static_cast<float>(params_.sonar_max_range);
      m->range = static_cast<float>(e.range_m);
      pub_range_.publish(m);
    }
    b.takeImu(imu_);
    for (const ImuEvent& e : imu_)
    {
      if (!e.ok)
        continue;  // a missing sensor measured nothing: the gap tells the cue logic to use the head
      auto m = boost::make_shared<sensor_msgs::Imu>();
      m->header.stamp = ros_now - ros::Duration(std::max(0.0, now - e.time));
      m->header.frame_id = imu_frame_;
      m->orientation_covariance[0] = -1.0;  // no orientation (REP-145); rate and accel: unknown covariance
      m->angular_velocity.x = e.rate[0];
      m->angular_velocity.y = e.rate[1];
      m->angular_velocity.z = e.rate[2];
      m->linear_acceleration.x = e.accel[0];
      m->linear_acceleration.y = e.accel[1];
      m->linear_acceleration.z = e.accel[2];
      pub_imu_.publish(m);
    }
    if (s.imu_sensor_missing != imu_missing_)
      NODELET_WARN_THROTTLE(10.0, "vest_bridge: the vest reports its IMU missing (not answering on I2C): the cue "
                                  "logic takes the body's turns from the head");
    snap_imu_silent_ = b.imuSilent(now);
    if (snap_imu_silent_)
      NODELET_WARN_THROTTLE(10.0, "vest_bridge: no IMU packet for over %.2f s: the cue logic takes the body's "
                                  "turns from the head", params_.imu_timeout_s);
    if (b.linkUp(now) && s.command_version < VEST_IMU_VERSION && !s.vest_refused)
      NODELET_WARN_THROTTLE(30.0, "vest_bridge: the vest's firmware speaks protocol version %u: driven in it, "
                                  "but it has no IMU (the cue logic takes the body's turns from the head). "
                                  "Reflash firmware/vest/vest.ino for the body's heading",
                            s.command_version);
    imu_missing_ = s.imu_sensor_missing;
    b.takeButtons(buttons_);
    for (const ButtonEvent& e : buttons_)
    {
      auto m = boost::make_shared<sensor_msgs::Joy>();
      m->header.stamp = ros_now - ros::Duration(std::max(0.0, now - e.time));
      m->header.frame_id = "vest";
      m->buttons = { e.short_a, e.long_a, e.short_b, e.long_b, e.held & 1 ? 1 : 0, e.held & 2 ? 1 : 0 };
      pub_buttons_.publish(m);
    }
    if (s.ranges_out_of_limits != out_of_limits_)
      NODELET_WARN_THROTTLE(5.0, "vest_bridge: %lu ranger readings outside [%.2f, %.2f] m dropped",
                            static_cast<unsigned long>(s.ranges_out_of_limits), params_.sonar_min_range,
                            params_.sonar_max_range);
    if (s.ranges_sensor_missing != sensor_missing_)
      NODELET_ERROR_THROTTLE(5.0, "vest_bridge: the vest reports its ranger missing (echo line never rises): "
                                  "nothing published on sonar/front, glass is not covered");
    if (b.rangerSilent(now))
      NODELET_ERROR_THROTTLE(5.0, "vest_bridge: no ranger reading for over %.2f s: glass is not covered",
                             params_.sonar_timeout_s);
    if (s.vest_refused)
      NODELET_ERROR_THROTTLE(10.0, "vest_bridge: the vest's firmware speaks protocol version %u, this bridge %u "
                                   "(pulse patterns): vest refused, all motors OFF (the wearer feels silence = stop, "
                                   "use the cane). Reflash firmware/vest/vest.ino",
                             s.vest_version, VEST_PROTOCOL_VERSION);
    out_of_limits_ = s.ranges_out_of_limits;
    sensor_missing_ = s.ranges_sensor_missing;
    snap_ranger_silent_ = b.rangerSilent(now);
    snap_range_age_ = now - s.last_range_ok_time;
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat)
  {
    const LinkStats& s = snap_;
    if (!s.open)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "port closed: " + s.last_error);
    else if (s.version_mismatches > 0 && !snap_link_up_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "vest speaks protocol version " + std::to_string(s.vest_version) + ", bridge " +
                       std::to_string(VEST_PROTOCOL_VERSION) + ": reflash the vest");
    else if (!snap_link_up_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "port open, no reply from the vest");
    else if (s.vest_refused)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "old vest firmware (protocol version " + std::to_string(s.vest_version) + ", bridge " +
                       std::to_string(VEST_PROTOCOL_VERSION) +
                       "): refused, motors OFF (silence = stop), no ranger, no buttons: reflash the vest");
    else if (s.last_range_status == VEST_RANGE_SENSOR_MISSING && s.ranges > 0)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "ranger missing: glass is not covered");
    else if (snap_ranger_silent_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "ranger silent: glass is not covered");
    else if (s.command_version < VEST_IMU_VERSION)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "vest firmware protocol version " + std::to_string(s.command_version) +
                       ": driven, no IMU (body turns from the head): reflash the vest");
    else if (s.last_imu_status == VEST_IMU_SENSOR_MISSING && s.imu_packets > 0)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "vest IMU missing: body turns from the head");
    else if (snap_imu_silent_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "vest IMU silent: body turns from the head");
    else if (s.cue_stale)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "link up, no valid cues: motors off");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "link up");
    stat.add("port", params_.port);
    stat.add("baud", params_.baud);
    stat.add("protocol version", static_cast<int>(VEST_PROTOCOL_VERSION));
    stat.add("vest protocol version", static_cast<int>(s.vest_version));
    stat.add("commands sent in version", static_cast<int>(s.command_version));
    stat.add("version probes sent", s.probes_sent);
    stat.add("vest refused (old firmware)", s.vest_refused);
    stat.add("cues not driven (old firmware)", s.cues_refused);
    stat.add("link up", snap_link_up_);
    stat.add("cue stale", s.cue_stale);
    stat.add("cues accepted", s.cues_accepted);
    stat.add("cues ignored (old stamps)", s.cues_rejected);
    stat.add("last ignored because", s.last_rejection.empty() ? std::string("-") : s.last_rejection);
    stat.add("opens", s.opens);
    stat.add("losses", s.losses);
    stat.add("packets sent", s.packets_sent);
    stat.add("bytes written", s.bytes_written);
    stat.add("packets skipped (buffer full)", s.packets_skipped);
    stat.add("status packets", s.status_packets);
    stat.add("garbage bytes", s.garbage_bytes);
    stat.add("rejected packets", s.rejected_packets);
    stat.add("version mismatches", s.version_mismatches);
    stat.add("ranger packets", s.ranges);
    stat.add("ranger readings published", s.ranges_published);
    stat.add("ranger readings out of limits", s.ranges_out_of_limits);
    stat.add("ranger missing reports", s.ranges_sensor_missing);
    stat.add("ranger packets lost", s.ranges_lost);
    stat.add("ranger last reading age s", snap_range_age_ < 1e9 ? snap_range_age_ : -1.0);
    stat.add("imu packets", s.imu_packets);
    stat.add("imu packets lost", s.imu_lost);
    stat.add("imu missing reports", s.imu_sensor_missing);
    stat.add("imu clock resets", s.imu_clock_resets);
    stat.add("button packets", s.buttons_packets);
    stat.add("button presses", s.button_presses);
    stat.add("button counter resyncs", s.button_resyncs);
    stat.add("patterns ended by the bridge", s.patterns_ended);
    stat.add("commanded", describeDuty(snap_sent_.data()));
    stat.add("commanded pattern", describePattern(snap_pattern_));
    stat.add("vest reports", s.status_packets ? describeDuty(s.last_status.intensity) : std::string("-"));
    stat.add("vest pattern", s.status_packets ? describePattern(s.last_status.pattern) : std::string("-"));
    // The highest duty the vest reported since the last diagnostics: pulses are felt between
    // two reports, and "vest reports" may fall into a gap.
    stat.add("vest drove since last report", describeDuty(peak_.data()));
    peak_.fill(0);
  }

  BridgeParams params_;
  std::unique_ptr<VestBridgeRunner> runner_;
  bool handlers_installed_ = false;
  // Touched only in the runner's thread (afterSpin / diagnose).
  bool was_stale_ = true, was_open_ = false;
  uint64_t mismatches_ = 0;
  LinkStats snap_;
  bool snap_link_up_ = false;
  std::array<uint8_t, VEST_NUM_MOTORS> snap_sent_{ { 0, 0, 0, 0 } };
  vest_pattern_t snap_pattern_{ 0, 0, 0, 0 };
  std::array<uint8_t, VEST_NUM_MOTORS> peak_{ { 0, 0, 0, 0 } };  ///< highest duties reported since diagnose()
  ros::Subscriber cue_sub_;
  ros::Publisher pub_range_, pub_buttons_, pub_imu_;
  std::string sonar_frame_, imu_frame_;
  std::vector<ImuEvent> imu_;
  uint64_t imu_missing_ = 0;
  bool snap_imu_silent_ = false;
  std::vector<RangeEvent> ranges_;
  std::vector<ButtonEvent> buttons_;
  uint64_t out_of_limits_ = 0, sensor_missing_ = 0;
  bool snap_ranger_silent_ = false;
  double snap_range_age_ = 1e300;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
};

}  // namespace assistive_tactile

PLUGINLIB_EXPORT_CLASS(assistive_tactile::VestBridgeNodelet, nodelet::Nodelet)
