#include "assistive_tactile/cue_logic.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace assistive_tactile
{
namespace
{
constexpr double kRadToDeg = 180.0 / M_PI;

double clamp01(double v)
{
  return std::min(1.0, std::max(0.0, v));
}

std::string fmt(const char* f, double a)
{
  char buf[96];
  std::snprintf(buf, sizeof(buf), f, a);
  return buf;
}

}  // namespace

const char* modeName(CueMode m)
{
  switch (m)
  {
    case CueMode::IDLE:
      return "IDLE";
    case CueMode::GUIDANCE:
      return "GUIDANCE";
    case CueMode::PROXIMITY:
      return "PROXIMITY";
    case CueMode::ALERT:
      return "ALERT";
    case CueMode::UNSURE:
      return "UNSURE";
  }
  return "?";
}

double wrapAngle(double a)
{
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a <= 0.0)
    a += 2.0 * M_PI;
  return a - M_PI;
}

void CueLogic::reset()
{
  last_mode_ = CueMode::UNSURE;
  turn_side_ = 0;
  waist_side_ = 0;
  clearCrossing();
}

void CueLogic::clearCrossing()
{
  cross_ = CrossingAdvice::NONE;
  cross_since_ = cross_seen_ = cross_time_ = 0.0;
}

namespace
{
/// Empty when the camera image behind a state is fresh enough at `now`, else why not.
std::string inputAgeProblem(double source_time, double now, double max_age)
{
  if (std::isnan(source_time))
    return "no camera stamp behind the planner state";
  const double age = now - source_time;
  if (age < -max_age)
    return fmt("camera stamp %.2f s in the future (clock?)", -age);
  if (!(age <= max_age))
    return fmt("input too old (camera image %.2f s old)", age);
  return std::string();
}
}  // namespace

bool CueLogic::stale(double now) const
{
  return !have_state_ || (now - last_state_time_) > params_.state_timeout_s ||
         !inputAgeProblem(last_source_time_, now, params_.max_input_age_s).empty();
}

Cue CueLogic::staleCue(double now)
{
  reset();
  Cue c;
  c.mode = CueMode::UNSURE;
  if (!have_state_)
    c.reason = "no planner state yet";
  else if ((now - last_state_time_) > params_.state_timeout_s)
    c.reason = fmt("planner state stale (%.1f s old)", now - last_state_time_);
  else
    c.reason = inputAgeProblem(last_source_time_, now, params_.max_input_age_s);
  last_mode_ = c.mode;
  return c;
}

Cue CueLogic::update(const NavInput& in, double now)
{
  have_state_ = true;
  last_state_time_ = now;
  last_source_time_ = in.source_time;

  Cue c;
  const bool finite = std::isfinite(in.heading) && std::isfinite(in.path_heading) &&
                      std::isfinite(in.waypoint_distance) && !std::isnan(in.free_ahead) &&
                      !std::isnan(in.free_left) && !std::isnan(in.free_right) &&
                      (in.crossing == CrossingAdvice::NONE ||
                       (std::isfinite(in.crossing_time) && std::isfinite(in.crossing_distance)));
  const std::string suffix = in.message.empty() ? std::string() : ": " + in.message;
  if (!finite)
  {
    reset();
    c.mode = CueMode::UNSURE;
    c.reason = "invalid planner state (NaN)";
    last_mode_ = c.mode;
    return c;
  }
  // Never guide on a guess: a decision from an old camera image describes where the wearer was.
  const std::string old = inputAgeProblem(in.source_time, now, params_.max_input_age_s);
  if (!old.empty())
  {
    reset();
    c.mode = CueMode::UNSURE;
    c.reason = old;
    return c;
  }

  switch (in.status)
  {
    case NavStatus::OK:
    {
      const int turning = turn_side_;
      c = decideProximity(in, true);
      // Near an obstacle (not yet at alert distance) with the path turning away from it, the turn
      // is the cue: the wearer stops and turns on the spot, which is safe. A side-step there kept
      // the wearer facing the obstacle and stepping left and right in front of it (mobility trials:
      // stuck in front of the course's 2 m wall with the way round 50 deg to the left).
      if (c.mode == CueMode::PROXIMITY && in.waypoint_distance >= params_.guidance_min_waypoint_m)
      {
        const double dev = std::fabs(wrapAngle(in.path_heading - in.heading)) * kRadToDeg;
        if (dev > params_.turn_on_deg || (turning != 0 && dev > params_.turn_off_deg))
        {
          waist_side_ = 0;
          turn_side_ = turning;  // keep the turn's hysteresis
          c = decideGuidance(in);
        }
      }
      if (c.mode != CueMode::PROXIMITY && c.mode != CueMode::ALERT)
        c = decideGuidance(in);
      last_mode_ = c.mode;  // the obstacle / guidance hysteresis runs under the crossing cue
      return overlayCrossing(in, c, now);
    }
    case NavStatus::NO_PATH:
    case NavStatus::NO_WAYPOINT:
    {
      // "Nothing free": map and pose are valid (and the input is fresh, checked above), so the
      // free distance ahead is real: a STOP (ALERT) still fires when the way is blocked. No
      // side-step (PROXIMITY) or turn: without a path, a direction would be a guess.
      const char* what = in.status == NavStatus::NO_PATH ? "no path" : "no waypoint";
      c = decideProximity(in, false);
      clearCrossing();  // no crossing cue without a path: the side would be a guess
      if (c.mode == CueMode::ALERT)
      {
        c.reason = std::string(what) + ", " + c.reason;
      }
      else
      {
        turn_side_ = 0;
        waist_side_ = 0;
        c.mode = CueMode::UNSURE;
        c.intensity.fill(0.f);
        c.reason = what + suffix;
      }
      break;
    }
    case NavStatus::NO_POSE:
    case NavStatus::NO_MAP:
    case NavStatus::IN_UNKNOWN:
    default:
    {
      // The vest goes quiet rather than lying.
      reset();
      c.mode = CueMode::UNSURE;
      const char* what = in.status == NavStatus::NO_POSE  ? "no pose" :
                         in.status == NavStatus::NO_MAP   ? "no map" :
                         in.status == NavStatus::IN_UNKNOWN ? "in unknown space" :
                                                              "unknown planner status";
      c.reason = what + suffix;
      break;
    }
  }
  last_mode_ = c.mode;
  return c;
}

Cue CueLogic::overlayCrossing(const NavInput& in, const Cue& base, double now)
{
  const CueParams& p = params_;
  auto severity = [](CrossingAdvice a) { return a == CrossingAdvice::STOP ? 2 : a == CrossingAdvice::NONE ? 0 : 1; };
  const CrossingAdvice a = in.crossing;
  if (a != CrossingAdvice::NONE)
  {
    // Raise, escalate to STOP, or (after the hold) change side or calm down to a side-step.
    const bool held_long = now - cross_since_ >= p.crossing_hold_s;
    if (cross_ == CrossingAdvice::NONE || severity(a) > severity(cross_) || (a != cross_ && held_long))
    {
      cross_ = a;
      cross_since_ = now;
    }
    if (a == cross_)
    {
      cross_seen_ = now;
      cross_time_ = std::max(0.0, in.crossing_time);
    }
  }
  else if (cross_ != CrossingAdvice::NONE && now - cross_since_ >= p.crossing_hold_s &&
           now - cross_seen_ >= p.crossing_release_s)
  {
    clearCrossing();  // the advice has ended
  }
  if (cross_ == CrossingAdvice::NONE || base.mode == CueMode::ALERT)
    return base;  // nothing held, or an obstacle under alert_m (or boxed in) comes first

  // The time to the closest approach, counted down while the held cue outlives the advice.
  const double t = std::max(0.0, cross_time_ - (now - cross_seen_));
  Cue c;
  if (cross_ == CrossingAdvice::STOP)
  {
    c.mode = CueMode::ALERT;
    c.intensity.fill(1.f);
    c.reason = fmt("person crossing, stop %.1f s", t);
    return c;
  }
  const bool left = cross_ == CrossingAdvice::LEFT;
  const double span = std::max(1e-6, p.crossing_far_s - p.crossing_near_s);
  const double k = clamp01((p.crossing_far_s - t) / span);
  c.mode = CueMode::PROXIMITY;
  c.intensity[left ? LEFT_WAIST : RIGHT_WAIST] = static_cast<float>(p.min_intensity + (1.0 - p.min_intensity) * k);
  c.reason = fmt(left ? "person crossing, step left %.1f s" : "person crossing, step right %.1f s", t);
  return c;
}

Cue CueLogic::decideProximity(const NavInput& in, bool /*have_path*/)
{
  const CueParams& p = params_;
  Cue c;
  c.mode = CueMode::IDLE;
  const bool was_alert = last_mode_ == CueMode::ALERT;
  const bool was_close = was_alert || last_mode_ == CueMode::PROXIMITY;
  const double d = in.free_ahead;
  const bool alert = d < p.alert_m + (was_alert ? p.hysteresis_m : 0.0);
  const bool close = d < p.proximity_m + (was_close ? p.hysteresis_m : 0.0);
  if (!close)
  {
    waist_side_ = 0;
    return c;
  }
  if (alert)
  {
    waist_side_ = 0;
    c.mode = CueMode::ALERT;
    c.intensity.fill(1.f);
    c.reason = fmt("obstacle %.2f m ahead: stop", std::max(0.0, d));
    return c;
  }
  // Room to side-step? The side in use keeps counting as free down to side_free_m - hysteresis.
  const double left_need = p.side_free_m - (waist_side_ > 0 ? p.hysteresis_m : 0.0);
  const double right_need = p.side_free_m - (waist_side_ < 0 ? p.hysteresis_m : 0.0);
  const bool left_ok = in.free_left >= left_need;
  const bool right_ok = in.free_right >= right_need;
  int side = 0;
  if (waist_side_ > 0 && left_ok)
    side = (right_ok && in.free_right > in.free_left + p.side_switch_m) ? -1 : +1;
  else if (waist_side_ < 0 && right_ok)
    side = (left_ok && in.free_left > in.free_right + p.side_switch_m) ? +1 : -1;
  else if (left_ok || right_ok)
    side = (left_ok && (!right_ok || in.free_left >= in.free_right)) ? +1 : -1;
  if (side == 0)
  {
    waist_side_ = 0;
    c.mode = CueMode::ALERT;
    c.intensity.fill(1.f);
    c.reason = fmt("obstacle %.2f m ahead, no room left or right: stop", d);
    return c;
  }
  waist_side_ = side;
  const double span = std::max(1e-6, p.proximity_m - p.alert_m);
  const double k = clamp01((p.proximity_m - d) / span);
  const float level = static_cast<float>(p.min_intensity + (1.0 - p.min_intensity) * k);
  c.mode = CueMode::PROXIMITY;
  c.intensity[side > 0 ? LEFT_WAIST : RIGHT_WAIST] = level;
  c.reason = fmt(side > 0 ? "obstacle %.2f m ahead: step left" : "obstacle %.2f m ahead: step right", d);
  turn_side_ = 0;
  return c;
}

Cue CueLogic::decideGuidance(const NavInput& in)
{
  const CueParams& p = params_;
  Cue c;
  c.mode = CueMode::IDLE;
  const bool guiding = last_mode_ == CueMode::GUIDANCE;
  const double min_wp = p.guidance_min_waypoint_m - (guiding ? p.hysteresis_m : 0.0);
  if (in.waypoint_distance < min_wp)
  {
    turn_side_ = 0;
    c.reason = fmt("waypoint %.2f m away: walk on", in.waypoint_distance);
    return c;
  }
  const double dev = wrapAngle(in.path_heading - in.heading) * kRadToDeg;  // + = turn left
  const double a = std::fabs(dev);
  const int sign = dev > 0.0 ? +1 : -1;
  int side = 0;
  if (turn_side_ != 0 && sign == turn_side_)
    side = a > p.turn_off_deg ? turn_side_ : 0;  // keep turning until lined up
  else
    side = a > p.turn_on_deg ? sign : 0;  // new turn (or overshoot past turn_on to the other side)
  turn_side_ = side;
  if (side == 0)
  {
    c.reason = fmt("on course (%.0f deg off)", dev);
    return c;
  }
  const double span = std::max(1e-6, p.turn_full_deg - p.turn_off_deg);
  const double k = clamp01((a - p.turn_off_deg) / span);
  const float level = static_cast<float>(p.min_intensity + (1.0 - p.min_intensity) * k);
  c.mode = CueMode::GUIDANCE;
  c.intensity[side > 0 ? LEFT_SHOULDER : RIGHT_SHOULDER] = level;
  c.reason = fmt(side > 0 ? "turn left %.0f deg" : "turn right %.0f deg", a);
  return c;
}

}  // namespace assistive_tactile
