// Vest bridge nodelet: tactile/cue -> serial packets to the vest (+ /diagnostics). Glue only:
// the port, packets, re-send, stale guard and reconnection live in VestBridge.
#include <assistive_msgs/TactileCue.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include <chrono>
#include <mutex>

#include "assistive_tactile/conversions.h"
#include "assistive_tactile/sim_vest.h"
#include "assistive_tactile/vest_bridge.h"

namespace assistive_tactile
{
namespace
{
double steadyNow()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

class VestBridgeNodelet : public nodelet::Nodelet
{
public:
  ~VestBridgeNodelet() override
  {
    timer_.stop();
    std::lock_guard<std::mutex> lock(mutex_);
    if (bridge_)
      bridge_->shutdown();  // all motors off before the port closes
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    BridgeParams p;
    pnh.param("port", p.port, p.port);
    pnh.param("baud", p.baud, p.baud);
    pnh.param("resend_hz", p.resend_hz, p.resend_hz);
    pnh.param("stale_s", p.stale_s, p.stale_s);
    pnh.param("reopen_s", p.reopen_s, p.reopen_s);
    pnh.param("link_timeout_s", p.link_timeout_s, p.link_timeout_s);
    unsigned int speed = 0;
    if (!baudToSpeed(p.baud, &speed))
    {
      NODELET_WARN("vest_bridge: unsupported baud %d, using 57600", p.baud);
      p.baud = 57600;
    }
    if (clampParam(p.resend_hz, 1.0, 200.0))
      NODELET_WARN("vest_bridge: resend_hz clamped to %g", p.resend_hz);
    if (clampParam(p.stale_s, 0.05, 5.0))
      NODELET_WARN("vest_bridge: stale_s clamped to %g", p.stale_s);
    if (clampParam(p.reopen_s, 0.05, 60.0))
      NODELET_WARN("vest_bridge: reopen_s clamped to %g", p.reopen_s);
    if (clampParam(p.link_timeout_s, 0.1, 60.0))
      NODELET_WARN("vest_bridge: link_timeout_s clamped to %g", p.link_timeout_s);
    NODELET_INFO("vest_bridge: port %s @ %d baud, resend %.1f Hz, stale %.3f s, reopen %.2f s", p.port.c_str(),
                 p.baud, p.resend_hz, p.stale_s, p.reopen_s);
    bridge_.reset(new VestBridge(p));
    bridge_->spinOnce(steadyNow());

    cue_sub_ = nh.subscribe("tactile/cue", 1, &VestBridgeNodelet::cueCb, this, ros::TransportHints().tcpNoDelay());
    updater_.reset(new diagnostic_updater::Updater(nh, pnh, getName()));
    updater_->setHardwareID(p.port);
    updater_->add("vest link", this, &VestBridgeNodelet::diagnose);
    // 100 Hz housekeeping: stale detection within 10 ms, re-send at resend_hz, replies read.
    timer_ = nh.createWallTimer(ros::WallDuration(0.01), &VestBridgeNodelet::timerCb, this);
  }

  void cueCb(const assistive_msgs::TactileCue::ConstPtr& msg)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const Cue cue = fromMsg(*msg);
    bridge_->setCue(cue.intensity, steadyNow());
  }

  void timerCb(const ros::WallTimerEvent&)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const double now = steadyNow();
    const bool was_open = bridge_->stats().open;
    const bool was_stale = bridge_->stats().cue_stale;
    bridge_->spinOnce(now);
    const LinkStats& s = bridge_->stats();
    if (!was_stale && s.cue_stale)
      NODELET_WARN("vest_bridge: no tactile/cue for %.3f s: all motors off", bridge_->params().stale_s);
    if (was_open && !s.open)
      NODELET_ERROR("vest_bridge: lost %s (%s), reopening every %.1f s", bridge_->params().port.c_str(),
                    s.last_error.c_str(), bridge_->params().reopen_s);
    if (!was_open && s.open)
      NODELET_INFO("vest_bridge: opened %s", bridge_->params().port.c_str());
    if (!s.open)
      NODELET_WARN_THROTTLE(10.0, "vest_bridge: port %s closed: %s", bridge_->params().port.c_str(),
                            s.last_error.c_str());
    updater_->update();
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat)
  {
    const double now = steadyNow();
    const LinkStats& s = bridge_->stats();
    if (!s.open)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "port closed: " + s.last_error);
    else if (!bridge_->linkUp(now))
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "port open, no reply from the vest");
    else if (s.cue_stale)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "link up, no cues: motors off");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "link up");
    stat.add("port", bridge_->params().port);
    stat.add("baud", bridge_->params().baud);
    stat.add("link up", bridge_->linkUp(now));
    stat.add("cue stale", s.cue_stale);
    stat.add("opens", s.opens);
    stat.add("losses", s.losses);
    stat.add("packets sent", s.packets_sent);
    stat.add("bytes written", s.bytes_written);
    stat.add("packets skipped (buffer full)", s.packets_skipped);
    stat.add("status packets", s.status_packets);
    stat.add("garbage bytes", s.garbage_bytes);
    stat.add("rejected packets", s.rejected_packets);
    stat.add("commanded", SimVest::describe(bridge_->sentDuty().data()));
    stat.add("vest reports", s.status_packets ? SimVest::describe(s.last_status.intensity) : std::string("-"));
  }

  std::mutex mutex_;
  std::unique_ptr<VestBridge> bridge_;
  ros::Subscriber cue_sub_;
  ros::WallTimer timer_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
};

}  // namespace assistive_tactile

PLUGINLIB_EXPORT_CLASS(assistive_tactile::VestBridgeNodelet, nodelet::Nodelet)
