#pragma once

#include <string>

namespace assistive_tactile
{
/// Cue logic parameters. These initializers are the only defaults (README and config match).
struct CueParams
{
  // Guidance (shoulder motors)
  double guidance_min_waypoint_m = 1.0;  ///< guidance only when the waypoint is at least this far
  double turn_on_deg = 20.0;             ///< start a turn cue when |path - motion| exceeds this
  double turn_off_deg = 8.0;             ///< keep it until the deviation falls below this
  double turn_full_deg = 90.0;           ///< deviation at which intensity reaches 1
  double min_intensity = 0.25;           ///< weakest drive that is still felt (0..1)
  // Proximity (waist motors) and alert (all four)
  double proximity_m = 1.0;    ///< free distance ahead under which proximity mode starts
  double alert_m = 0.5;        ///< free distance ahead under which all four motors fire
  double hysteresis_m = 0.1;   ///< a mode entered at d is left only above d + hysteresis_m
  double side_free_m = 0.6;    ///< free distance to a side that counts as room to side-step
  double side_switch_m = 0.2;  ///< the other side must be this much freer to switch waist motor
  // Freshness of the planner state
  double state_timeout_s = 0.5;  ///< older planner state -> UNSURE, motors off
  double max_input_age_s = 0.4;  ///< state whose camera image (source_stamp) is older -> UNSURE (0.1 s inside the 0.5 s goal)
  double heartbeat_hz = 10.0;    ///< cue re-published at least this often (bridge stale guard)
  std::string body_frame = "torso";
};

/// Vest bridge parameters.
struct BridgeParams
{
  std::string port = "/dev/ttyUSB0";  ///< serial device (or the simulated vest's pty link)
  int baud = 57600;                   ///< 9600 .. 921600
  double resend_hz = 20.0;            ///< COMMAND re-sent at this rate
  double stale_s = 0.3;               ///< a cue drives until header.stamp + stale_s, then all off
  double max_source_age_s = 0.5;      ///< a cue drives until source_stamp + this (camera image age)
  double reopen_s = 1.0;              ///< retry period while the port is closed
  double link_timeout_s = 1.0;        ///< no STATUS from the vest for this long -> link WARN
  int realtime_priority = 10;         ///< SCHED_FIFO priority of the housekeeping thread, 0 = normal
};

/// Clamps a value into [lo, hi]; returns true when it had to.
template <typename T>
inline bool clampParam(T& v, T lo, T hi)
{
  if (!(v >= lo))  // also catches NaN
  {
    v = lo;
    return true;
  }
  if (v > hi)
  {
    v = hi;
    return true;
  }
  return false;
}

}  // namespace assistive_tactile
