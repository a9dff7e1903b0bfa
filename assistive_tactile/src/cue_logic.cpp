#include "assistive_tactile/cue_logic.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <assistive_common/codes.h>

namespace assistive_tactile
{
namespace
{
constexpr double kRadToDeg = 180.0 / M_PI;
/// A veer's pulses last 0.15 s: a one-shoulder buzz is a turn once it lasted longer (README).
constexpr double kTellApartS = 0.25;
/// A stop-and-turn buzz lasts at least this much beyond kTellApartS: one barely longer than the
/// time that tells it from a veer's pulse is read as a veer (issue 33, traced: a 1 deg turn's
/// 0.26 s buzz asked of a walker before a doorway was carried out as a 15 deg veer, into the jamb).
constexpr double kTurnMarginS = 0.05;
/// Standing before a passage, the share of its room a straight walk may pass its middle off by
/// (the rest is left for the walk's own drift); session 31: 0.5 (152 vs 155 collisions on the
/// twelve tuning rows; 1.0 gave 168).
constexpr double kAlignRoomShare = 0.5;
/// A turn teaches the wearer's turning rate only when it turned for at least this long (s).
constexpr double kRateSampleMinS = 0.3;
/// The walk-on that follows a turn at once comes this long after its buzz ended: a tick that
/// begins as the buzz ends would be felt as part of it.
constexpr double kTurnGoGapS = 0.2;
/// After such a turn is judged, the wearer is starting to walk for this long (s): no stand turn.
constexpr double kTurnGoStartS = 1.0;
/// With the vest's gyro, a turn seen under way is over once the torso's raw rate has stayed under
/// `body_turn_rate_deg` this long (s): two camera frames, and a hesitation shorter than this.
constexpr double kTurnOverQuietS = 0.15;
/// The population's fastest reaction to a torso vibration (s; assistive_trials/docs/wearer_population.md).
constexpr double kFastestReactionS = 0.3;
/// A camera frame, and a little more (s): when a motion was last seen, to that much.
constexpr double kFrameS = 0.1;
/// A stop-and-turn this shortly (s) before a loss of the pose is undone by the first look-elsewhere
/// turn: the VO's coast (at most 2.5 s) and the walk it began.
constexpr double kLostTurnBackS = 8.0;

double clamp01(double v)
{
  return std::min(1.0, std::max(0.0, v));
}

std::string fmt(const char* f, double a)
{
  char buf[160];
  std::snprintf(buf, sizeof(buf), f, a);
  return buf;
}

/// The level (1..3) whose amount (level x step, carried out at `gain`) comes closest to `want_deg`.
int veerLevel(double want_deg, double step_deg, double gain)
{
  return std::max(1, std::min(3, int(std::lround(want_deg / (step_deg * gain)))));
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

const char* instructionName(Instruction i)
{
  switch (i)
  {
    case Instruction::NONE:
      return "none";
    case Instruction::WALK_ON:
      return "walk on";
    case Instruction::VEER:
      return "veer";
    case Instruction::TURN:
      return "stop and turn";
    case Instruction::SIDESTEP:
      return "side-step";
    case Instruction::STOP:
      return "stop";
    case Instruction::UNSURE:
      return "unsure";
  }
  return "?";
}

std::array<float, NUM_MOTORS> renderCue(const Cue& c, double t_s)
{
  std::array<float, NUM_MOTORS> m{ { 0.f, 0.f, 0.f, 0.f } };
  if (!(t_s >= 0.0) || !vest_pattern_on(&c.pattern, uint32_t(std::min(t_s, 4.0e6) * 1000.0)))
    return m;
  return c.intensity;
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
  waist_side_ = 0;
  busy_ = false;
  burst_at_ = -1e300;
  chain_next_ = false;
  last_yaw_time_ = -1e300;
  yaw_rate_ = 0.0;
  body_rate_ = 0.0;
  door_ = Door();
  prev_door_ = Door();
  stage_walk_ = false;
  corner_veer_ = false;
  corner_rest_ = 0.0;
  centre_at_ = -1e300;
  edge_step_at_ = -1e300;
  edge_steps_ = 0;
  turn_go_ = false;
  turn_go_start_until_ = -1e300;
  side_steps_.clear();
  dither_steer_until_ = -1e300;
  clearCrossing();
}

Cue CueLogic::startPattern(CueMode mode, Instruction ins, int level, std::array<float, NUM_MOTORS> drive,
                           uint8_t on_10ms, uint8_t off_10ms, uint8_t count, double now, std::string reason)
{
  Cue c;
  if (ins == Instruction::SIDESTEP)
    sidestep_at_ = now;
  c.mode = mode;
  c.instruction = ins;
  c.level = level;
  c.intensity = drive;
  c.pattern.id = next_id_;
  next_id_ = uint8_t(next_id_ == 255 ? 1 : next_id_ + 1);  // 0 is never used: a vest's "no pattern yet"
  c.pattern.on_10ms = on_10ms;
  c.pattern.off_10ms = off_10ms;
  c.pattern.count = count;
  c.reason = std::move(reason);
  current_ = c;
  last_tick_ = now;
  return c;
}

double CueLogic::reactionEstimate() const
{
  return have_reaction_ ? std::clamp(reaction_est_, 0.3, 1.5) : params_.alert_reaction_s;
}

double CueLogic::startAccelEstimate() const
{
  return have_accel_ ? std::clamp(accel_est_, 0.3, 3.0) : params_.start_accel;
}

double CueLogic::stopDecelEstimate() const
{
  return have_decel_ ? std::clamp(decel_est_, 0.5, 5.0) : params_.stop_decel;
}

namespace
{
/// When a quantity sampled at (t0, v0) and (t1, v1) crossed `mark`, by linear interpolation.
double crossingTime(double t0, double v0, double t1, double v1, double mark)
{
  if (!(t1 > t0) || std::fabs(v1 - v0) < 1e-9)
    return t1;
  return t0 + (t1 - t0) * std::clamp((mark - v0) / (v1 - v0), 0.0, 1.0);
}

// The planner's walking speed is the chord of the wearer's positions over its last 0.4 s
// (`walk_window_s`): on a ramp of acceleration a it runs a (t - t0 - 0.2 s) once the window lies
// inside the ramp, so between two marks it rises at a, and extrapolated back to 0 it is half the
// window late.
constexpr double kHalfWindowS = 0.2;

/// Free width (m) across `yaw` at (x, y): both sides' free distance, each counted up to 1 m.
double freeAcross(const ObstacleGrid& g, double x, double y, double yaw)
{
  return sideFree(g, x, y, yaw, +1, 1.0) + sideFree(g, x, y, yaw, -1, 1.0);
}
}  // namespace

void CueLogic::observeStart(const NavInput& in, double now)
{
  // The wearer's reaction and its start, read off its starts: a walk-on tick to a standing
  // wearer, then the walk's speed rising through kLo and kHi (0.3-0.6 m/s: on the ramp for
  // starts up to 1.5 m/s^2 and preferred speeds from 0.9 m/s). Their slope is the start's
  // acceleration; extrapolated back to 0 (less half the chord's window) they give when the body
  // began to move; the tick is understood when it ends, 0.1 s after it began.
  constexpr double kLo = 0.3, kHi = 0.6, kTickS = 0.1;
  const double v = in.walking_speed;
  if (start_tick_ >= 0.0 && std::isfinite(v))
  {
    const bool fresh = prev_speed_t_ >= start_tick_;
    if (start_lo_t_ < 0.0 && v >= kLo)
      start_lo_t_ = fresh ? crossingTime(prev_speed_t_, prev_speed_, now, v, kLo) : now;
    if (start_lo_t_ >= 0.0 && v >= kHi)
    {
      const double t_hi = fresh ? crossingTime(prev_speed_t_, prev_speed_, now, v, kHi) : now;
      const double a = (kHi - kLo) / std::max(0.05, t_hi - start_lo_t_);
      const double tau = start_lo_t_ - kLo / a - kHalfWindowS - (start_tick_ + kTickS);
      if (tau > 0.1 && tau < 3.0)
      {
        reaction_est_ = have_reaction_ ? 0.7 * reaction_est_ + 0.3 * tau : tau;
        have_reaction_ = true;
      }
      if (a > 0.2 && a < 5.0)
      {
        accel_est_ = have_accel_ ? 0.7 * accel_est_ + 0.3 * a : a;
        have_accel_ = true;
      }
      start_tick_ = -1.0;
      start_lo_t_ = -1.0;
    }
  }
  if (current_.instruction != Instruction::WALK_ON)
  {
    start_tick_ = -1.0;  // something else came before the start: not a clean sample
    start_lo_t_ = -1.0;
  }
}

namespace
{
/// Metres walked over `tau` s from `v` m/s, speeding up at `a` m/s^2 (0: not at all) towards
/// `pace`; `v_end` the speed reached then.
double walkSpeedingUp(double v, double a, double pace, double tau, double& v_end)
{
  const double t_up = a > 0.0 && v < pace ? std::min(tau, (pace - v) / a) : 0.0;
  v_end = v + a * t_up;
  return 0.5 * (v + v_end) * t_up + v_end * (tau - t_up);
}
}  // namespace

double CueLogic::stopReach(double v, double tau) const
{
  constexpr double kPacePrior = 1.4;  // m/s: the fast end of preferred walking speeds (0.9-1.4)
  const double pace = have_pace_ ? pace_est_ : kPacePrior;
  // A go timed to stop short of the obstacle (shortWalk; judged on the next guidance cycle) is no
  // walk on while the wearer still stands: its timed stop bounds it. Counted as one, the go's own
  // reach alerted the standing wearer on the next cycle, the stop made it a standing wearer
  // again, the go came back: stop and go in turn every cycle, the wearer standing for good 1.55 m
  // before an obstacle (traced, vision trial gen_lobby_2101 trial 1 of seed 21). Once it walks,
  // its speeding up counts again (the alert's margin over the timed stop's estimates).
  const bool timed_go_standing = (go_at_ > go_handled_ || short_stop_at_ >= 0.0) && v < params_.walking_speed_mps;
  const bool told_to_walk =
      (current_.instruction == Instruction::WALK_ON || current_.instruction == Instruction::VEER) && !timed_go_standing;
  double v1 = v;
  const double walked = walkSpeedingUp(v, told_to_walk ? startAccelEstimate() : 0.0, pace, tau, v1);
  return walked + v1 * v1 / (2.0 * stopDecelEstimate());
}

void CueLogic::observePace(const NavInput& in, double now)
{
  // a walk whose speed stays within 0.03 m/s a cycle for a second
  if (std::isfinite(in.walking_speed) && in.walking_speed >= 0.6 &&
      std::fabs(in.walking_speed - prev_speed_) < 0.03 && now - prev_speed_t_ < 0.5)
  {
    if (steady_speed_since_ < -1e299)
      steady_speed_since_ = now;
    if (now - steady_speed_since_ >= 1.0)
    {
      pace_est_ = have_pace_ ? 0.9 * pace_est_ + 0.1 * in.walking_speed : in.walking_speed;
      have_pace_ = true;
    }
  }
  else
    steady_speed_since_ = -1e300;
}

void CueLogic::observeStop(const NavInput& in, double now)
{
  // The wearer's stop, read off its stops on all four from a walk (0.6 m/s or more): the walk's
  // speed falling through 0.7 and 0.3 of its speed when the stop began. A bump ends a walk at
  // once and reads as a quick stop: a stop that ends at the obstacle is not sampled, and a
  // quicker stop than the one learnt moves the estimate less than a slower one (the stop
  // distances err long).
  const double v = in.walking_speed;
  if (current_.instruction != Instruction::STOP || !std::isfinite(v))
  {
    stop_v0_ = -1.0;
    stop_hi_t_ = -1.0;
    return;
  }
  if (stop_v0_ < 0.0)
  {
    stop_v0_ = v >= 0.6 ? v : 0.0;
    return;
  }
  if (stop_v0_ <= 0.0)
    return;
  const double hi = 0.7 * stop_v0_, lo = 0.3 * stop_v0_;
  // A walk-on felt after the stop was asked (a tick sent before it, felt a reaction late) sends the
  // wearer on between the marks: such a fall is no stop (traced, gen_home_3012 trial 0 of seed 11:
  // 0.35 m/s^2 learnt for a 2.31 m/s^2 stop; the estimate then stayed at its floor, 0.5, and the
  // predictive stop halted a walker on a clear corridor every few metres). The fall is timed again
  // from the high mark once the walk has sped up again.
  if (stop_hi_t_ >= 0.0 && v > stop_low_v_ + 0.05)
    stop_hi_t_ = -1.0;
  stop_low_v_ = std::min(stop_low_v_, v);
  if (stop_hi_t_ < 0.0 && v <= hi && prev_speed_ > hi)
  {
    stop_hi_t_ = crossingTime(prev_speed_t_, prev_speed_, now, v, hi);
    stop_low_v_ = v;
  }
  if (stop_hi_t_ >= 0.0 && v <= lo)
  {
    const double d = (hi - lo) / std::max(0.05, crossingTime(prev_speed_t_, prev_speed_, now, v, lo) - stop_hi_t_);
    // (a stop that ends at the obstacle, under 0.15 m free ahead, is no sample: a bump ends a walk at once)
    if (d > 0.2 && d < 10.0 && !(in.free_ahead < 0.15))
    {
      const double k = !have_decel_ ? 1.0 : d < decel_est_ ? 0.5 : 0.2;
      decel_est_ += k * (d - decel_est_);
      have_decel_ = true;
    }
    stop_v0_ = 0.0;  // this stop is sampled
  }
}

void CueLogic::observeDrift(const NavInput& in, double now, bool walking)
{
  // A walker without sight drifts to one side (a constant bias of up to about 6 deg/m, plus a
  // random walk): learnt from the walk heading while nothing cued turns it (not during a veer or
  // turn and not for 0.6 s after one: the walk chord still holds it), as rad per metre walked.
  constexpr double kDriftTauS = 4.0;
  const bool quiet = walking && !busy_ && now - quiet_since_ >= 0.6 && std::isfinite(in.walk_heading);
  if (!quiet)
  {
    drift_time_ = -1e300;
    return;
  }
  const double dt = now - drift_time_;
  if (dt > 0.0 && dt < 0.5 && in.walking_speed > 0.2)
  {
    const double per_m = wrapAngle(in.walk_heading - drift_heading_) / (dt * in.walking_speed);
    if (std::fabs(per_m) < 0.5)  // a walk that turns by more than 30 deg/m is not drifting
      drift_per_m_ += std::min(1.0, dt * in.walking_speed / (kDriftTauS * std::max(0.5, in.walking_speed))) *
                      (per_m - drift_per_m_);
  }
  drift_heading_ = in.walk_heading;
  drift_time_ = now;
}

double CueLogic::predictedError(double err, double v) const
{
  // The walk chord lags the body by half its window (0.2 s); the veer acts when its first pulse
  // (0.15 s) is felt, one reaction time late; and `drift_aim_s` beyond that the error lands on
  // the other side of the path by as much as the drift brings it back.
  const double lead_s = reactionEstimate() + 0.15 + 0.2 + params_.drift_aim_s;
  const double drift = std::clamp(drift_per_m_, -0.12, 0.12);  // at most ~7 deg/m
  return wrapAngle(err - drift * std::max(0.0, v) * lead_s);
}

Cue CueLogic::holdPattern(std::string reason) const
{
  Cue c = current_;
  c.reason = std::move(reason);
  return c;
}

bool CueLogic::steadyHeld(CueMode mode, Instruction ins, const std::array<float, NUM_MOTORS>& drive) const
{
  // A steady cue (side-step, stop) carries on under the same id while it stays the same motors.
  if (current_.instruction != ins || current_.mode != mode || current_.pattern.on_10ms != 0)
    return false;
  for (int i = 0; i < NUM_MOTORS; ++i)
    if ((current_.intensity[size_t(i)] > 0.f) != (drive[size_t(i)] > 0.f))
      return false;
  return true;
}

Cue CueLogic::steady(CueMode mode, Instruction ins, const std::array<float, NUM_MOTORS>& drive, double now,
                     std::string reason)
{
  if (steadyHeld(mode, ins, drive))
  {
    if (ins == Instruction::SIDESTEP)
      sidestep_at_ = now;
    current_.intensity = drive;  // the level may follow the distance
    return holdPattern(std::move(reason));
  }
  return startPattern(mode, ins, 0, drive, 0, 0, 0, now, std::move(reason));
}

Cue CueLogic::stopAll(double now, std::string reason)
{
  busy_ = false;  // a stop ends any veer or turn being watched
  return steady(CueMode::ALERT, Instruction::STOP, { { 1.f, 1.f, 1.f, 1.f } }, now, std::move(reason));
}

Cue CueLogic::unsureCue(std::string reason, double now)
{
  // Three quick pulses on both waist motors when UNSURE begins, then silence: a silent vest means
  // stop and use the cane, and the wearer is told so the moment it starts, not two ticks later.
  if (current_.instruction == Instruction::UNSURE || current_.instruction == Instruction::NONE)
  {
    Cue c = holdPattern(std::move(reason));
    c.mode = CueMode::UNSURE;
    return c;
  }
  return startPattern(CueMode::UNSURE, Instruction::UNSURE, 0, { { 0.f, 0.f, 1.f, 1.f } }, 10, 10, 3, now,
                      std::move(reason));
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
  no_pose_since_ = -1.0;  // no camera, no turning: only fresh images can show the turn worked
  std::string why;
  if (!have_state_)
    why = "no planner state yet";
  else if ((now - last_state_time_) > params_.state_timeout_s)
    why = fmt("planner state stale (%.1f s old)", now - last_state_time_);
  else
    why = inputAgeProblem(last_source_time_, now, params_.max_input_age_s);
  const Cue c = unsureCue(why, now);
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
    c = unsureCue("invalid planner state (NaN)", now);
    last_mode_ = c.mode;
    return c;
  }
  // Never guide on a guess: a decision from an old camera image describes where the wearer was.
  const std::string old = inputAgeProblem(in.source_time, now, params_.max_input_age_s);
  if (!old.empty())
  {
    reset();
    no_pose_since_ = -1.0;
    return unsureCue(old, now);
  }
  // A loss lasts until the planner guides again: the map rebuilt after the pose's return (NO_MAP)
  // and unmapped floor around (IN_UNKNOWN) are part of it, not a new loss to turn afresh for.
  if (in.status == NavStatus::OK || in.status == NavStatus::NO_PATH || in.status == NavStatus::NO_WAYPOINT)
    no_pose_since_ = -1.0;

  observeStart(in, now);
  observeStop(in, now);
  observePace(in, now);
  // (the walk still speeding up: a walker keeps to the last cue it felt, so it speeds up until a
  // stop or turn asked meanwhile is felt)
  speeding_up_ = std::isfinite(in.walking_speed) && in.walking_speed > prev_speed_ + 1e-3;
  prev_speed_ = std::isfinite(in.walking_speed) ? in.walking_speed : 0.0;
  prev_speed_t_ = now;
  switch (in.status)
  {
    case NavStatus::OK:
    {
      c = decideOk(in, now);
      if (c.instruction == Instruction::TURN && c.pattern.id != sent_turn_id_)
      {
        // a stop-and-turn the wearer feels (one the predictive stop replaced never was)
        sent_turn_id_ = c.pattern.id;
        last_turn_at_ = now;
        last_turn_from_ = turn_from_;
      }
      return c;
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
      busy_ = false;
      if (c.mode == CueMode::ALERT)
      {
        c.reason = std::string(what) + ", " + c.reason;
        c = shapeSteady(c, now);
      }
      else
      {
        waist_side_ = 0;
        c = unsureCue(what + suffix, now);
      }
      break;
    }
    case NavStatus::NO_POSE:
    case NavStatus::NO_MAP:
    case NavStatus::IN_UNKNOWN:
    default:
    {
      // The vest says it cannot tell (its opening pattern), then goes quiet rather than lying.
      reset();
      const char* what = in.status == NavStatus::NO_POSE  ? "no pose" :
                         in.status == NavStatus::NO_MAP   ? "no map" :
                         in.status == NavStatus::IN_UNKNOWN ? "in unknown space" :
                                                              "unknown planner status";
      if (!(in.status == NavStatus::NO_POSE && lookElsewhere(now, what + suffix, c)))
        c = unsureCue(what + suffix, now);
      break;
    }
  }
  last_mode_ = c.mode;
  return c;
}

bool CueLogic::lookElsewhere(double now, const std::string& why, Cue& out)
{
  // A head-mounted camera lost at a plain wall stays lost while the wearer, told UNSURE, stands
  // facing it (vision corridor trial: 27 s nose to a bare wall until the timeout). Turning on the
  // spot is safe for a standing wearer and gives the VO texture again, the way back first.
  const CueParams& p = params_;
  if (!(p.lost_turn_after_s > 0.0))
    return false;
  if (no_pose_since_ < 0.0)
  {
    no_pose_since_ = now;
    lost_turns_ = 0;
    lost_turn_end_ = -1e300;
  }
  if (now < lost_turn_end_ && current_.instruction == Instruction::TURN)
  {
    out = holdPattern(why + ": turning to look elsewhere");
    return true;
  }
  const double due = lost_turns_ == 0 ? no_pose_since_ + p.lost_turn_after_s : lost_turn_end_ + p.lost_turn_wait_s;
  if (now < due || lost_turns_ >= p.lost_turns_max)
    return false;
  // First back to where the body faced before its last stop-and-turn, when that came shortly
  // before the loss: the camera tracked there, and SLAM's keyframes near the last trusted pose
  // look that way (a view it never had cannot be found again in the map). Else the way back.
  // Open loop: a lost pose has no heading, and the wearer has stood since the loss began.
  double angle = (lost_turns_ == 0 ? p.lost_turn_deg : 90.0) / kRadToDeg;
  const double back = wrapAngle(last_turn_from_ - ok_facing_);
  if (lost_turns_ == 0 && no_pose_since_ - last_turn_at_ <= kLostTurnBackS && std::fabs(back) * kRadToDeg >= 30.0)
    angle = back;
  lost_turn_side_ = lost_turns_ == 0 ? (angle > 0.0 ? 1 : -1) : lost_turn_side_;
  angle = lost_turn_side_ * std::fabs(angle);
  const double dur = turnBuzzS(angle);
  const uint8_t on_10ms = uint8_t(std::lround(dur * 100.0));
  ++lost_turns_;
  lost_turn_end_ = now + 0.01 * on_10ms;
  char buf[240];
  std::snprintf(buf, sizeof(buf), "%s for %.1f s: turn %s %.0f deg on the spot to look elsewhere (%.2f s buzz, %d of %d)",
                why.c_str(), now - no_pose_since_, angle > 0.0 ? "left" : "right", std::fabs(angle) * kRadToDeg,
                0.01 * on_10ms, lost_turns_, p.lost_turns_max);
  const float l = angle > 0.0 ? 1.f : 0.f;
  out = startPattern(CueMode::GUIDANCE, Instruction::TURN, 3, { { l, 1.f - l, 0.f, 0.f } }, on_10ms, 0, 1, now, buf);
  return true;
}

Cue CueLogic::decideOk(const NavInput& in, double now)
{
  // The head is watched on every cycle, the obstacle cues' too: watched only while guiding, a veer
  // carried out during a stop was never seen, and the body's facing stayed 20 deg off for good
  // (traced, plaza trial 13 of seed 11: facing 179 deg, the body 160, boxed in at the curb).
  observeHead(in, now);
  ok_facing_ = facing(in);
  // a path and a waypoint: the obstacle cues, or the guidance where steering wins over them
  Cue c = decideProximity(in, true);
  // Near an obstacle (not yet at alert distance) with the path turning away from it, steering
  // is the cue (a veer while walking, a turn on the spot while standing). A side-step there
  // kept the wearer facing the obstacle and stepping left and right in front of it (mobility
  // trials: stuck in front of the course's 2 m wall with the way round 50 deg to the left), and
  // stopped every wearer who approached a doorway at an angle.
  // The same inside part of the stop distance: an obstacle the wearer would reach only if it
  // walked on, unreacting, while the steering point lies clear to a side. Only the walk no
  // reaction can prevent forces a stop: the fastest reaction (0.3 s) or this wearer's learnt
  // one discounted by half above that (a veer turns the walk away while it still goes on),
  // and the stop itself.
  const double v = std::max(0.0, in.walking_speed);
  const double tau = reactionEstimate();
  const double must_stop = params_.alert_m + stopReach(v, std::max(0.3, std::min(tau, 0.3 + 0.5 * tau)));
  const bool steering_away =
      in.waypoint_distance >= params_.guidance_min_waypoint_m &&
      std::fabs(wrapAngle(in.steer_heading - in.walk_heading)) * kRadToDeg > params_.veer_on_deg &&
      !(in.free_steer < params_.proximity_m);
  // A wearer who stands with no obstacle inside its stop distance and no room to step aside
  // (the approach to a narrow doorway, a jamb 0.6-1.1 m ahead along the facing) is not held by
  // the stop either: it stood there for good (traced, gen_home_3015 trial 4: 86 s on "no room
  // left or right: stop", 0.45 m before an 0.80 m doorway's middle). The guidance turns it on
  // the spot or sends it on with its walk timed and swept (shortWalk, sweepStop).
  const bool standing = !(in.walking_speed >= params_.walking_speed_mps);
  const bool alert_outside_stop = c.mode == CueMode::ALERT && in.free_ahead >= must_stop;
  // A wearer standing boxed in (an obstacle inside the alert distance, no room to step aside)
  // with the way on well to a side is turned towards it on the spot, which sweeps a round body
  // into nothing; the stop alone held it there for good (traced, plaza trial 13 of seed 11:
  // 0.15 m before a planter, 0.05 m free to either side, 150 s on "obstacle ahead: stop").
  const bool boxed_turn = standing && c.mode == CueMode::ALERT && !alert_outside_stop &&
                          in.waypoint_distance >= params_.guidance_min_waypoint_m &&
                          std::fabs(wrapAngle(in.steer_heading - facing(in))) * kRadToDeg > params_.stand_turn_deg;
  // (a turn on the spot under way is not interrupted by a side-step: it turns the wearer away)
  // (nor one whose side-steps have gone left and right in turn, getting it no nearer: traced,
  // gen_home_3015 trial 4 of seed 11, 40 s stepping before a wall with the way on 76 deg right
  // through a doorway, where the steering ray meets the jamb and `steering_away` stays false)
  const bool dither = c.mode == CueMode::PROXIMITY && standing && sideStepsDither(in, now);
  if (((c.mode == CueMode::PROXIMITY || alert_outside_stop) && steering_away) || (standing && alert_outside_stop) ||
      boxed_turn || dither ||
      (c.mode == CueMode::PROXIMITY && busy_ && busy_turn_))
  {
    waist_side_ = 0;
    c.mode = CueMode::IDLE;
  }
  if (c.mode != CueMode::PROXIMITY && c.mode != CueMode::ALERT)
    c = guideWithSweep(in, now);
  else
  {
    busy_ = false;  // an obstacle cue ends a veer or turn being executed
    c = shapeSteady(c, now);
  }
  noteSideStep(c, in, now);
  last_mode_ = c.mode;  // the obstacle / guidance hysteresis runs under the crossing cue
  return overlayCrossing(in, c, now);
}

void CueLogic::noteSideStep(const Cue& c, const NavInput& in, double now)
{
  if (c.mode != CueMode::PROXIMITY || c.instruction != Instruction::SIDESTEP)
    return;
  const int side = c.intensity[LEFT_WAIST] > 0.f ? +1 : -1;
  if (sideStepBegins(side, now))
    side_steps_.push_back({ now, side, in.waypoint_distance });
  else
    side_steps_.back().t = now;
}

bool CueLogic::sideStepBegins(int side, double now) const
{
  // a side-step goes on while it is asked: a new one is a change of side or one begun after a pause
  return side_steps_.empty() || side_steps_.back().side != side || now - side_steps_.back().t > 1.0;
}

bool CueLogic::sideStepsDither(const NavInput& in, double now)
{
  // A fifth side-step about to begin after four within 20 s, both ways, and the waypoint no nearer
  // by 0.5 m: the obstacle cues are holding the wearer in place (each side-step opens the other
  // side's room). The guidance then turns it towards the way on for 6 s (its walk is swept and
  // timed as ever).
  constexpr double kWindowS = 20.0, kHoldS = 6.0, kProgressM = 0.5;
  constexpr size_t kSteps = 4;
  if (now < dither_steer_until_)
    return true;
  if (!sideStepBegins(waist_side_, now))
    return false;
  while (!side_steps_.empty() && now - side_steps_.front().t > kWindowS)
    side_steps_.pop_front();
  if (side_steps_.size() < kSteps)
    return false;
  bool left = false, right = false;
  double nearest = side_steps_.front().waypoint_distance;
  for (const SideStepBegun& b : side_steps_)
  {
    left |= b.side > 0;
    right |= b.side < 0;
    nearest = std::min(nearest, b.waypoint_distance);
  }
  if (!(left && right) || side_steps_.front().waypoint_distance - std::min(nearest, in.waypoint_distance) > kProgressM)
    return false;
  side_steps_.clear();
  dither_steer_until_ = now + kHoldS;
  return true;
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
    busy_ = false;
    return shapeSteady(c, now);
  }
  const bool left = cross_ == CrossingAdvice::LEFT;
  const double span = std::max(1e-6, p.crossing_far_s - p.crossing_near_s);
  const double k = clamp01((p.crossing_far_s - t) / span);
  c.mode = CueMode::PROXIMITY;
  c.intensity[left ? LEFT_WAIST : RIGHT_WAIST] = static_cast<float>(p.min_intensity + (1.0 - p.min_intensity) * k);
  c.reason = fmt(left ? "person crossing, step left %.1f s" : "person crossing, step right %.1f s", t);
  busy_ = false;
  return shapeSteady(c, now);
}

Cue CueLogic::shapeSteady(const Cue& c, double now)
{
  const Instruction ins = c.mode == CueMode::ALERT ? Instruction::STOP : Instruction::SIDESTEP;
  return steady(c.mode, ins, c.intensity, now, c.reason);
}

Cue CueLogic::decideProximity(const NavInput& in, bool /*have_path*/)
{
  const CueParams& p = params_;
  Cue c;
  c.mode = CueMode::IDLE;
  const bool was_alert = last_mode_ == CueMode::ALERT;
  const bool was_close = was_alert || last_mode_ == CueMode::PROXIMITY;
  const double d = in.free_ahead;
  // a walking wearer needs its reaction time's walk, and then its stop, before it stands
  const double v = std::max(0.0, std::isfinite(in.walking_speed) ? in.walking_speed : 0.0);
  const double tau = reactionEstimate();
  const double reach = stopReach(v, tau);
  const bool alert = d < p.alert_m + reach + (was_alert ? p.hysteresis_m : 0.0);
  // the side-step distance is the protocol's 1 m (SPEC), not grown by the walk: a walker is
  // stopped first (the stop distance grows with its speed) and stepped aside from standing; a
  // side-step asked of a walker 1.5-2 m before an obstacle sent it sideways into doorway jambs
  // just before the path turned away from the wall ahead (mobility trials, homes)
  const bool close = alert || d < p.proximity_m + (was_close ? p.hysteresis_m : 0.0);
  if (!close)
  {
    waist_side_ = 0;
    return c;
  }
  // A wearer who already stands is not told to stop again and again (it would stand there for
  // good): with room to a side it is stepped out of the tight spot instead.
  const bool standing = v < p.walking_speed_mps;
  const bool side_room = in.free_left >= p.side_free_m || in.free_right >= p.side_free_m;
  if (alert && !(standing && side_room && in.waypoint_distance > 0.0))
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
  return c;
}

WalkModel CueLogic::committedWalk(const NavInput& in, double now, double stop_in_s) const
{
  constexpr double kPacePrior = 1.4;  // m/s, as stopReach
  WalkModel m;
  m.v0 = std::isfinite(in.walking_speed) ? std::max(0.0, in.walking_speed) : 0.0;
  m.pace = std::max(m.v0, have_pace_ ? pace_est_ : kPacePrior);
  const bool told_to_walk = current_.instruction == Instruction::WALK_ON || current_.instruction == Instruction::VEER;
  m.accel = told_to_walk || speeding_up_ ? startAccelEstimate() : 0.0;
  // Until this wearer's own reaction and stop are learnt, the sweep takes the slow ends of the
  // population (a reaction of 1.2 s; a stop at twice its learnt start, people stop about twice as
  // fast as they start, else at 1 m/s^2): a stop asked early costs a moment, one asked late a bump.
  m.decel = have_decel_ ? stopDecelEstimate() : have_accel_ ? std::max(1.0, 2.0 * startAccelEstimate()) : 1.0;
  m.turn_rate = params_.veer_rate_deg / kRadToDeg;
  m.spread_per_m = params_.sweep_spread_m;
  const double tau = sweepReaction();
  m.stop_at_s = stop_in_s + tau;
  m.horizon_s = m.stop_at_s + m.v0 / std::max(0.1, m.decel) + 3.0;
  // the veer being carried out: all of it from when its first pulse has been felt, or what is
  // left of it once it was seen (the head has turned by part of it)
  if (busy_ && busy_turn_)
  {
    // a stop-and-turn buzz: told from a veer's pulse 0.25 s after it began, felt a reaction later;
    // the wearer then slows and turns on the spot at its turning rate while it buzzes
    const double felt = std::max(0.0, busy_since_ + kTellApartS + tau - now);
    m.stop_at_s = std::min(m.stop_at_s, felt);
    m.turn_start_s = felt;
    m.turn = busy_angle_;
    m.turn_rate = turn_rate_est_;
    m.turn_while_stopping = true;
    m.horizon_s = m.stop_at_s + m.v0 / std::max(0.1, m.decel) + 3.0;
  }
  if (busy_ && !busy_turn_)
  {
    const double sign = busy_angle_ > 0.0 ? 1.0 : -1.0;
    // (a corner veer's second pair, still to come, is part of the walk)
    const double asked = (std::fabs(busy_angle_) + (corner_veer_ ? std::fabs(corner_rest_) : 0.0)) * veer_gain_est_;
    if (!veer_seen_)
    {
      m.turn_start_s = std::max(0.0, busy_since_ + 0.15 + tau - now);
      m.turn = sign * asked;
    }
    else
    {
      const double turned = veerTurned(in, true) * sign;
      m.turn = sign * std::max(0.0, asked - turned);
    }
  }
  // A body turning now (faster than the head's scan) goes on turning until it feels the stop: a
  // veer carried out beyond its amount (a level misread, two chained bursts read as more) was
  // predicted straight on, and the stop came once the turn had already aimed it at a shelf
  // (issue 33, traced: gen_shop_4011 seed 11 trial 1, 93 deg turned for about 60, stopped 1.1 m
  // before it while still turning at 50 deg/s).
  const double going = turnRate() * m.stop_at_s;
  if (!(busy_ && busy_turn_) && std::fabs(turnRate()) * kRadToDeg > params_.body_turn_rate_deg &&
      (std::fabs(going) > std::fabs(m.turn) || going * m.turn < 0.0))
  {
    m.turn = going;
    m.turn_start_s = 0.0;
    m.turn_rate = std::fabs(turnRate());
  }
  return m;
}

double CueLogic::sweepReaction() const
{
  return have_reaction_ ? reactionEstimate() : 1.2;
}

bool CueLogic::sweepReady(const NavInput& in) const
{
  return in.grid && !in.grid->empty() && params_.sweep_radius_m > 0.0;
}

WalkModel CueLogic::veerWalk(const NavInput& in, double now, double turn) const
{
  // committed until the veer is carried out (its first pulse felt a reaction late, then turned
  // at veer_rate_deg), stopped by a stop asked then; walking on: as long as a slight veer takes
  const double tau = sweepReaction();
  const double rate = params_.veer_rate_deg / kRadToDeg;
  const double done = 0.15 + tau + std::max(std::fabs(turn), params_.veer_step_deg / kRadToDeg) / rate;
  WalkModel m = committedWalk(in, now, done);
  if (turn != 0.0)
  {
    m.turn_start_s = 0.15 + tau;
    m.turn = turn;
    m.turn_rate = rate;
  }
  return m;
}

bool CueLogic::aisleAhead(const NavInput& in, const Door& d, double axis) const
{
  // (a doorway's jambs are 0.1-0.3 m deep: past them the room opens)
  if (!in.grid || in.grid->empty())
    return false;
  return freeAcross(*in.grid, in.x + 0.8 * std::cos(axis), in.y + 0.8 * std::sin(axis), axis) < d.width + 0.3;
}

bool CueLogic::inDoorway(const NavInput& in) const
{
  // the body between two jambs: obstacle cells within 1 m across the walk on both sides, less
  // than a doorway's free cells apart, or within passage_inside_m of a passage's middle
  const double yaw = have_body_yaw_ ? body_yaw_ : in.walk_heading;
  const bool near_middle = std::isfinite(in.passage_distance) && in.passage_distance >= 0.0 &&
                           in.passage_distance < params_.passage_inside_m;
  return freeAcross(*in.grid, in.x, in.y, yaw) < 1.0 || near_middle;
}

SweepResult CueLogic::sweep(const NavInput& in, const WalkModel& m) const
{
  // the body's facing: the walk chord lags a veer by its half window; the body's yaw carries the
  // head's fast turns at once
  const double yaw = have_body_yaw_ ? body_yaw_ : in.walk_heading;
  return sweepWalk(*in.grid, in.x, in.y, yaw, m, params_.sweep_radius_m);
}

bool CueLogic::sweepStop(const NavInput& in, double now, Cue& out)
{
  // A stop asked now is felt a reaction time later; one asked on the next cycle a cycle later
  // still. While the walk the wearer is committed to (its pace, the veer it carries out) would
  // still stand clear with a stop asked on the next cycle, it walks on; once it would not, the stop
  // is asked now (the body's disc against the planner's grid: a jamb beside the body, which the
  // ray ahead does not see, and a veer carried out late).
  if (!in.grid || in.grid->empty() || !(params_.sweep_radius_m > 0.0))
    return false;
  if (!walksForward(in))
    return false;
  // (a stop-and-turn buzz stops a walker too, once told from a veer's pulse, and turns it while
  // it slows: committedWalk)
  const WalkModel m = committedWalk(in, now, params_.sweep_cycle_s);
  const SweepResult r = sweep(in, m);
  if (!r.hit)
    return false;
  waist_side_ = 0;
  char buf[220];
  std::snprintf(buf, sizeof(buf),
                "the walk would sweep the body into an obstacle %.2f m on (%.1f s): stop (v %.2f, reaction %.2f s, "
                "start %.2f, stop %.2f m/s^2, pace %.2f, turn %.0f deg)",
                r.hit_along, r.hit_t, m.v0, sweepReaction(), m.accel, m.decel, m.pace, m.turn * kRadToDeg);
  out = stopAll(now, buf);
  sweep_stop_ = true;
  return true;
}

Cue CueLogic::walkOn(std::string reason, double now, bool standing)
{
  // A tick is due once tick_period_s passed since the last pattern began, and at once when the
  // last pattern was a steady one (a stop or side-step ends with "go").
  // "go" comes at once after anything that left the wearer standing (a stop, side-step, turn,
  // UNSURE), then with every tick; a standing wearer gets one every second
  const bool after_stop = current_.instruction != Instruction::WALK_ON && current_.instruction != Instruction::VEER;
  const bool standing_wait = standing && now - last_tick_ >= 1.0;
  if (after_stop || standing_wait || now - last_tick_ >= params_.tick_period_s - 1e-9)
  {
    const float k = static_cast<float>(params_.min_intensity + 0.5 * (1.0 - params_.min_intensity));
    const bool first_go = standing && start_tick_ < 0.0;
    Cue c = startPattern(CueMode::IDLE, Instruction::WALK_ON, 0, { { k, k, 0.f, 0.f } }, 10, 0, 1, now,
                         std::move(reason));
    if (first_go)
      start_tick_ = now;  // the first "go" to a standing wearer: its start times its reaction
    if (standing && now - go_at_ > 2.5)
      go_at_ = now;  // how far it may walk is judged in shortWalk (not on the repeated ticks while it starts)
    return c;
  }
  Cue c = holdPattern(std::move(reason));
  c.mode = CueMode::IDLE;
  return c;
}

void CueLogic::observeHead(const NavInput& in, double now)
{
  // the head's turn rate (smoothed), to tell when a veer or turn has been carried out (the head
  // scans by a few deg/s at most while the body keeps its direction); with the vest's gyro, the
  // body's own (turnRate)
  gyro_ = std::isfinite(in.body_yaw_rate);
  if (!gyro_)
    body_rate_ = 0.0;
  if (now > last_yaw_time_ && now - last_yaw_time_ < 1.0)
  {
    const double r = wrapAngle(in.head_yaw - last_yaw_) / (now - last_yaw_time_);
    const double a = std::min(1.0, (now - last_yaw_time_) / 0.25);
    yaw_rate_ += a * (r - yaw_rate_);
  }
  if (now > last_yaw_time_ && now - last_yaw_time_ < 1.0 && std::isfinite(in.walking_speed))
    walked_m_ += std::max(0.0, in.walking_speed) * (now - last_yaw_time_);
  // The body's yaw: the head's fast motion (a turn or veer: 40-90 deg/s) is the body's; its slow
  // motion (the scan: at most a few deg/s) is not, and fades towards the walk chord while walking
  // (within about `body_walk_tau_s`) and towards the head's mean while standing (`body_stand_tau_s`).
  const bool walking = walksForward(in);
  if (!have_body_yaw_ || !(now > last_yaw_time_ && now - last_yaw_time_ < 1.0))
  {
    body_yaw_ = walking && std::isfinite(in.walk_heading) ? in.walk_heading : in.head_yaw;
    have_body_yaw_ = true;
  }
  else
  {
    const double dt = now - last_yaw_time_;
    const double dh = wrapAngle(in.head_yaw - last_yaw_);
    if (gyro_)
    {
      // the vest's gyro turns with the torso alone: every turn, none of the head's scan. Its bias
      // (a MEMS gyro's drifts by tenths of a deg/s) is learnt while the wearer stands still: not
      // walking, the head steady, no turn felt for a second and the gyro near its bias
      const double rate = in.body_yaw_rate - gyro_bias_;
      if (!walking && params_.body_gyro_bias_tau_s > 0.0 && std::fabs(yaw_rate_) * kRadToDeg < 10.0 &&
          std::fabs(rate) * kRadToDeg < 2.0 && now - body_turned_at_ > 1.0)
        gyro_bias_ += std::min(1.0, dt / params_.body_gyro_bias_tau_s) * rate;
      body_yaw_ = wrapAngle(body_yaw_ + (in.body_yaw_rate - gyro_bias_) * dt);
      body_rate_ += std::min(1.0, dt / 0.25) * (rate - body_rate_);  // smoothed as the head's
      if (std::fabs(rate) * kRadToDeg > params_.body_turn_rate_deg)
      {
        body_turned_at_ = now;
        body_turned_sign_ = rate > 0.0 ? 1.0 : -1.0;
      }
    }
    else if (std::fabs(dh) / dt * kRadToDeg > params_.body_turn_rate_deg)
    {
      body_yaw_ = wrapAngle(body_yaw_ + dh);
      body_turned_at_ = now;
    }
    // (the walk chord, 0.4 s of positions, lags a turn: it says nothing while a turn is under
    // way or just ended, nor while the walk slows to a stop)
    // (nor while a side-step cued lately may still be in it: carried out a reaction late, then the
    // chord's window; a side-step while the walk slows makes a diagonal chord within 50 deg of the head,
    // and it pulled the body's facing 42 deg off: traced, gen_shop_4001 trial 3, t 73.3, a 139 deg
    // turn asked where 99 were needed, overshot into a shelf)
    const bool chord_ok = walking && std::isfinite(in.walk_heading) && now - body_turned_at_ > 0.6 &&
                          now - sidestep_at_ >= sweepReaction() + 2.0 * kHalfWindowS;
    // (with the gyro: the walk chord takes out what is left of its bias; standing, the gyro alone)
    if (chord_ok || (!walking && !gyro_))
    {
      const double ref = walking ? in.walk_heading : in.head_yaw;
      const double tau = gyro_ ? params_.body_gyro_tau_s : walking ? params_.body_walk_tau_s : params_.body_stand_tau_s;
      const double err = wrapAngle(ref - body_yaw_);
      body_yaw_ = wrapAngle(body_yaw_ + std::min(1.0, dt / std::max(1e-3, tau)) * err);
      // what the chord keeps pulling is the gyro's bias (the facing alone would stay bias x tau
      // off: 15 deg at 3 deg/s, and an MPU-6050's offset may be 20 deg/s, far past what standing
      // learns): its integral, critically damped (gain 1 / (4 tau^2)), settles it within about 2 tau
      if (gyro_ && params_.body_gyro_bias_tau_s > 0.0)
        gyro_bias_ -= err * dt / (4.0 * tau * tau);
    }
  }
  last_yaw_ = in.head_yaw;
  last_yaw_time_ = now;
  if (std::fabs(turnRate()) * kRadToDeg >= 10.0)
    steady_since_ = now;
  else if (steady_since_ < -1e299)
    steady_since_ = now;
  observeDrift(in, now, walking);
}

bool CueLogic::walksForward(const NavInput& in) const
{
  // A side-step (0.3 m/s, 90 deg off the facing) or a step back moves the body as fast as a slow
  // walk: its chord is no facing. Traced (gen_home_3004 trial 0, t 1.0-3.1): a side-step's chord
  // became the body's facing, the turn towards a doorway was asked from it, and the wearer, 66 deg
  // off, was told "go" into the wall. A forward walk's chord stays within the scan (+-8 deg) and a
  // veer's lag (about 20 deg) of the head.
  constexpr double kForwardDeg = 50.0;
  return std::isfinite(in.walking_speed) && in.walking_speed >= params_.walking_speed_mps &&
         std::isfinite(in.walk_heading) && std::isfinite(in.head_yaw) &&
         std::fabs(wrapAngle(in.walk_heading - in.head_yaw)) * kRadToDeg <= kForwardDeg;
}

double CueLogic::turnRate() const
{
  return gyro_ ? body_rate_ : yaw_rate_;
}

double CueLogic::veerTurned(const NavInput& in, bool head) const
{
  // the vest's gyro: the body's own turn since the veer began (the walk chord lags it by its half
  // window, the head adds its scan); without one the chord's, or for an overshoot the head's
  if (gyro_)
    return wrapAngle(body_yaw_ - busy_body0_);
  return head ? wrapAngle(in.head_yaw - busy_head0_) : wrapAngle(in.walk_heading - busy_yaw0_);
}

double CueLogic::facing(const NavInput& in) const
{
  if (gyro_ && have_body_yaw_)
    return body_yaw_;  // the vest's gyro: the torso's own facing, walking or standing
  if (walksForward(in))
    return in.walk_heading;
  return have_body_yaw_ && params_.body_stand_tau_s > 0.0 ? body_yaw_ : in.head_yaw;
}

bool CueLogic::holdTurn(const NavInput& in, double now, Cue& out)
{
  const CueParams& p = params_;
  // Stop and turn: the wearer turns while the buzz lasts, starting its reaction time (and the
  // moment it takes to tell a buzz from a veer's pulse) after the buzz began and stopping its
  // reaction time after it ended: the reaction cancels, and the buzz's length sets the angle
  // at the wearer's own turning rate (learnt from its turns). Wait until the turn is over.
  const double sign = busy_angle_ > 0.0 ? 1.0 : -1.0;
  const double left = wrapAngle(in.steer_heading - in.head_yaw) * sign;  // still to turn
  turn_peak_rate_ = std::max(turn_peak_rate_, turnRate() * sign);
  // (the buzz's own length: the pattern now playing is the tick once a go followed the turn)
  const double buzz_end = busy_since_ + turn_buzz_s_;
  const bool steadied = std::fabs(turnRate()) * kRadToDeg < 10.0;
  // (the wearer stops turning its reaction time after the buzz ended: judged before that, a
  // slow reactor's turn was still to come and a second turn was asked on top of it: chains of
  // turns back and forth, the slowest decile's wearers timing out)
  // (and until the turn was seen in the head's turn rate, faster than its scan, or the slowest
  // reaction, 1.2 s, has passed: a reaction learnt short, or not yet, ended the wait before the
  // wearer began to turn, and the same turn was asked again on top of it)
  const bool seen = turn_peak_rate_ * kRadToDeg > 12.0;
  const double wait = seen ? reactionEstimate() : std::max(reactionEstimate(), 1.2);
  auto hold = [&](CueMode mode, const char* f, double a, double b) {
    char why[96];
    std::snprintf(why, sizeof(why), f, a * kRadToDeg, b * kRadToDeg);
    out = holdPattern(why);
    out.mode = mode;
    return true;
  };
  if (turn_go_ && now >= buzz_end + kTurnGoGapS && now < buzz_end + wait + 0.3)
  {
    // its new way sweeps clear: the walk-on follows the buzz (felt a reaction later, as the turn
    // ends), and the turn is judged while it walks off; the go was judged here, not by shortWalk
    if (turn_go_sent_)
      return hold(CueMode::IDLE, "turned %.0f deg: walking on (%.0f deg to go)", busy_angle_, left);
    turn_go_sent_ = true;
    out = walkOn(fmt("turned %.0f deg: walk on", busy_angle_ * kRadToDeg), now, true);
    // a short walk's stop, timed from this go as shortWalk times it, on the room the new way has
    go_handled_ = go_at_;
    short_stop_at_ = shortWalkStopAt(std::numeric_limits<double>::infinity(), turn_go_room_ - 0.1);
    return true;
  }
  // (the vest's gyro sees the torso stop at once: the smoothed rate took 0.5 s to fall from a turn's
  // 90 deg/s under 10, and the margin for a reaction learnt short another 0.3 s; with the head's
  // rate, which scans, both are kept)
  // (seen in the raw rate, its way, still turning the fastest reaction after the buzz ended, as the
  // turn this buzz asks for does: the smoothed rate still carried a turn just ended, the vest's
  // first samples read fast before its bias is learnt, and a wearer who carried out a piece of an
  // earlier buzz cut short by a stop paused 0.7 s, and was judged done before this turn began:
  // traced, gen_office_4030 trial 3 of seed 12)
  const bool over = gyro_ && body_turned_sign_ == sign && body_turned_at_ >= buzz_end + kFastestReactionS - kFrameS &&
                    now - body_turned_at_ >= kTurnOverQuietS;
  if (!over && (now < buzz_end + wait + 0.3 || (!steadied && now - busy_since_ < p.turn_timeout_s)))
    return hold(CueMode::GUIDANCE, "turning (%.0f deg to go, head %.0f deg/s)", left, turnRate());
  // its turning rate: the angle turned over the time it turned (the buzz less the moment to
  // tell it from a veer); the smoothed peak rate underestimates short turns (the next buzz
  // came out too long: turn chains that overshoot). The angle is the body's (`facing()`), not the
  // head's: the head's scan (+-8 deg over 7 s) moves by up to several degrees while a turn is
  // asked, carried out and judged, and read as part of a 20-40 deg turn it threw the learnt rate
  // about between 73 and 142 deg/s for wearers who all turn at 90 (held-out homes, traced): a
  // 168 deg turn asked at 113 deg/s came out 132 deg, and each such miss cost another turn. Only
  // turns long enough to say something (`kRateSampleMinS` of buzz) teach it.
  if (turn_go_)
    turn_go_start_until_ = now + kTurnGoStartS;  // it starts walking: steered once it walks
  const double turned = wrapAngle(facing(in) - turn_from_) * sign;
  const double turning_s = turn_buzz_s_ - kTellApartS;
  if (turn_peak_rate_ * kRadToDeg > 20.0 && turning_s >= kRateSampleMinS && turned * kRadToDeg > 10.0)
    turn_rate_est_ = std::clamp(0.7 * turn_rate_est_ + 0.3 * turned / turning_s, M_PI / 6.0, M_PI);
  busy_ = false;
  quiet_since_ = now;
  return false;
}

bool CueLogic::holdVeer(const NavInput& in, double now, double err, bool walking, Cue& out, bool& superseding)
{
  const CueParams& p = params_;
  // A veer burst asks for an amount: wait until the wearer has carried it out before judging
  // the heading again, or the next burst would ask for the same veer twice (reaction times of
  // up to 1.2 s). Carried out = seen in the head's turn rate (a veer turns the walk at tens of
  // deg/s, the walk's own drift by a few), steadied, and the walk chord has caught up. Whether
  // the walk has turned by the amount is no test: the drift during the reaction eats into it.
  const double sign = busy_angle_ > 0.0 ? 1.0 : -1.0;
  const double turned = veerTurned(in, false) * sign;
  const bool steadied = std::fabs(turnRate()) * kRadToDeg < 10.0;
  if (!veer_seen_ && turnRate() * sign * kRadToDeg > 20.0)
  {
    veer_seen_ = true;
    veer_seen_at_ = now;
    // its reaction: the veer starts when the first pulse (0.15 s) has been felt; the smoothed
    // rate crosses 20 deg/s about 0.12 s after the turn began
    const double tau = now - busy_since_ - 0.15 - 0.12;
    if (tau > 0.1 && tau < 2.5)
    {
      reaction_est_ = have_reaction_ ? 0.7 * reaction_est_ + 0.3 * tau : tau;
      have_reaction_ = true;
    }
  }
  // carried out: seen, and the head steady for 0.3 s (the walk chord, 0.4 s, has then mostly
  // left the veer behind)
  // ... or at once when the head has already turned well beyond the amount (the wearer misread
  // the level: a weak burst read as medium turned a typical wearer 34 deg for 15 towards a wall,
  // and waiting for it to steady left no time to bring it back)
  const double head_turned = veerTurned(in, true) * sign;
  const bool overshot = veer_seen_ && head_turned > 1.3 * std::fabs(busy_angle_) + 5.0 / kRadToDeg;
  const bool done = now - std::max(busy_since_, burst_at_) >= p.settle_timeout_s || overshot ||
                    (veer_seen_ && steadied && now - veer_seen_at_ >= 0.3 && now - steady_since_ >= 0.3);
  if (done && veer_seen_)
  {
    // its gain: the walk's turn, less its drift meanwhile, over the veer asked
    const double drifted = drift_per_m_ * (walked_m_ - busy_walked0_) * sign;
    const double g = (turned - drifted) / std::max(1e-6, std::fabs(busy_angle_));
    if (g > 0.4 && g < 2.0)
      veer_gain_est_ = std::clamp(0.7 * veer_gain_est_ + 0.3 * g, 0.6, 1.6);
  }
  // The way on changed while a veer is being carried out (a corner came into view): when what
  // will be left after it is large, a new cue asks for the rest at once.
  const double remaining = busy_angle_ - (busy_angle_ > 0.0 ? 1.0 : -1.0) * std::max(0.0, turned);
  const double residual = std::fabs(wrapAngle(err - remaining)) * kRadToDeg;
  // only further the same way: a path that flips to the other side of an obstacle (two ways
  // round it cost the same) must not make the wearer zig-zag; that waits until the veer is done
  const bool same_way = wrapAngle(err - remaining) * busy_angle_ > 0.0;
  // (and only once the last burst can be felt as a new pair: asked each cycle, the bursts ran
  // together into one long buzz, which the wearer took for a stop-and-turn)
  const bool superseded = walking && same_way && residual > 2.0 * p.veer_step_deg &&
                          now - burst_at_ >= kVeerChainGapS;
  if (!done && !superseded)
  {
    out = holdPattern(fmt("veering (%.0f deg to go)", std::max(0.0, std::fabs(busy_angle_) - turned) * kRadToDeg));
    out.mode = CueMode::GUIDANCE;
    return true;
  }
  superseding = !done;
  return false;
  }

WalkModel CueLogic::goWalk(double horizon_s) const
{
  // a standing wearer's walk once told to go: speeding up at its start to its pace (the fast end
  // of preferred speeds until its own is learnt)
  WalkModel m;
  m.accel = startAccelEstimate();
  m.pace = have_pace_ ? pace_est_ : 1.4;
  m.horizon_s = horizon_s;
  m.spread_per_m = params_.sweep_spread_m;
  return m;
}

double CueLogic::turnGoRoom(const NavInput& in, double angle) const
{
  // A turn comes out a part of what was asked off (the wearer's rate, learnt, and its spread from
  // turn to turn): the room is the shortest walk, along the new way and that much off either side,
  // that sweeps the body clear. Floor nobody has seen (an unknown cell on the line, most often the
  // new way the camera has not yet looked along) ends it where the body's front would reach it:
  // the go is then judged once the wearer faces that way, as always (traced, vision corridor
  // trial 0: a 73 deg turn into unseen floor, the walk on met the wall beyond it).
  const CueParams& p = params_;
  if (!in.grid || in.grid->empty() || !(p.sweep_radius_m > 0.0))
    return 0.0;
  const double off = std::max(8.0 / kRadToDeg, p.turn_go_spread * std::fabs(angle));
  const double yaw = facing(in) + angle;
  const WalkModel m = goWalk(5.0);
  double room = std::numeric_limits<double>::infinity();
  for (const double d : { 0.0, -off, off })
  {
    const SweepResult r = sweepWalk(*in.grid, in.x, in.y, yaw + d, m, p.sweep_radius_m);
    if (r.hit)
      room = std::min(room, r.hit_along);
    const double look = std::min(room, p.turn_go_clear_m) + p.sweep_radius_m;
    const double unseen = alongRayUntil(*in.grid, in.x, in.y, yaw + d, look, 0.5 * in.grid->resolution,
                                        assistive_common::isUnknownCode);
    if (unseen < look)
      room = std::min(room, std::max(0.0, unseen - p.sweep_radius_m));
  }
  return room;
}

bool CueLogic::sideStepUnderWay(double since, double now) const
{
  // a short side-step is judged once carried out: its buzz, then a reaction and 0.3 s
  return now - since < kCentreBuzzS + reactionEstimate() + 0.3;
}

Cue CueLogic::shortSideStep(int side, double now, std::string reason)
{
  std::array<float, NUM_MOTORS> drive{ { 0.f, 0.f, 0.f, 0.f } };
  drive[side > 0 ? LEFT_WAIST : RIGHT_WAIST] = 1.f;
  busy_ = false;
  return startPattern(CueMode::PROXIMITY, Instruction::SIDESTEP, 0, drive, uint8_t(std::lround(kCentreBuzzS * 100.0)),
                      0, 1, now, std::move(reason));
}

bool CueLogic::goMeetsEdge(const NavInput& in) const
{
  // A standing wearer told to go walks along its facing, a reaction late, and a stop acts another
  // reaction later: beside a shelf's corner or a jamb, a walk a few degrees off the steering point
  // sweeps the body into it within half a metre, whatever stop is timed from the go (traced,
  // gen_shop_4001 trial 0, t 57.1: 15 deg off with a shelf corner 0.15 m beside the walk's line,
  // the stop asked before it moved; it walked 0.35 m into the corner). It turns to face the
  // steering point first when that way sweeps clear for longer.
  const CueParams& p = params_;
  const double err = wrapAngle(in.steer_heading - facing(in));
  if (!(p.go_clear_m > 0.0) || !in.grid || in.grid->empty() || !(p.sweep_radius_m > 0.0) ||
      std::fabs(err) * kRadToDeg < 3.0)
    return false;
  const WalkModel m = goWalk(4.0);
  const SweepResult ahead = sweepWalk(*in.grid, in.x, in.y, facing(in), m, p.sweep_radius_m);
  if (!ahead.hit || ahead.hit_along >= p.go_clear_m)
    return false;
  const SweepResult turned = sweepWalk(*in.grid, in.x, in.y, in.steer_heading, m, p.sweep_radius_m);
  return !turned.hit || turned.hit_along > ahead.hit_along + 0.3;
}

bool CueLogic::stepClearOfEdge(const NavInput& in, double now, Cue& out)
{
  // A wearer standing a hand's breadth beside a shelf or a jamb (a side under go_side_m, the other
  // side much freer) walks off along a line that its veering and a turn landed a few degrees off
  // bend into it within a metre or two, before a correction can act. It side-steps away first:
  // short steps, each judged once carried out (a reaction after its buzz), three at most.
  const CueParams& p = params_;
  if (sideStepUnderWay(edge_step_at_, now))
  {
    out = holdPattern("standing beside an edge: a side-step away from it");
    return true;
  }
  const double near = std::min(in.free_left, in.free_right), far = std::max(in.free_left, in.free_right);
  if (!(p.go_side_m > 0.0) || !(near < p.go_side_m) || !(far >= near + 0.3) || edge_steps_ >= 3)
    return false;
  const int side = in.free_left > in.free_right ? +1 : -1;
  edge_step_at_ = now;
  ++edge_steps_;
  out = shortSideStep(side, now,
                      fmt(side > 0 ? "standing %.2f m beside an edge: step left" :
                                     "standing %.2f m beside an edge: step right",
                          near));
  return true;
}

bool CueLogic::cornerVeer(const NavInput& in, double now, bool walking, Cue& out)
{
  // The floor of any guidance (trials README) takes a home's corners walking; here the wearer
  // walked to the free floor's end, stopped, turned on the spot and started again, paying its
  // reaction twice at every corner. The veer round it is asked so that the arc begins where the
  // corner needs it (a reaction and the first pulse after the ask), when its walk sweeps clear.
  const CueParams& p = params_;
  if (!(p.corner_veer_deg > 0.0))
    return false;
  const double step = p.veer_step_deg / kRadToDeg;
  if (corner_veer_)
  {
    if (!busy_ || busy_turn_ || !walking)
    {
      corner_veer_ = false;  // carried out, or something else came first
      corner_rest_ = 0.0;
      return false;
    }
    if (corner_rest_ == 0.0 || now - burst_at_ < kVeerChainGapS)
      return false;  // holdVeer watches it
    const int side = corner_rest_ > 0.0 ? +1 : -1;
    const int level = veerLevel(std::fabs(corner_rest_) * kRadToDeg, p.veer_step_deg, 1.0);
    corner_rest_ = std::fabs(corner_rest_) > level * step + 1e-9 ? corner_rest_ - side * level * step : 0.0;
    chain_next_ = true;
    out = veerPair(in, now, side, level,
                   fmt(side > 0 ? "round the corner: veer left %.0f deg more" : "round the corner: veer right %.0f deg more",
                       level * p.veer_step_deg));
    return true;
  }
  if (!walking || busy_ || in.path.empty() || !sweepReady(in))
    return false;
  const PathCorner c = nextCorner(in.path, in.x, in.y, 0.15, 8.0);
  if (!c.found)
    return false;
  const double yaw = facing(in);
  const double turn = wrapAngle(c.heading_out - yaw);
  // (a corner whose leg out is short is one of a chicane round an obstacle: pure pursuit's
  // steering point cuts across both, where a veer round each swung the wearer out and back)
  if (std::fabs(turn) * kRadToDeg < p.corner_veer_deg || std::fabs(turn) * kRadToDeg > 90.0 || c.leg_out < 1.2)
    return false;
  // the walk's line meets the path's leg out of the corner this far ahead (the wearer walks beside
  // the path as often as on it: an arc tangent to both ends on the leg out)
  const double ahead =
      ((c.x - in.x) * std::sin(c.heading_out) - (c.y - in.y) * std::cos(c.heading_out)) / std::sin(turn);
  if (!(ahead > 0.0) || (in.passage_distance >= 0.0 && in.passage_distance < ahead + 1.0))
    return false;  // a doorway at or before the corner: the doorway routine squares up to it
  // the walk until the veer acts (speeding up towards its pace while told to walk; 1.1 m/s, the
  // population's typical pace, until its own is learnt), and the arc's tangent length: it begins
  // R tan(turn / 2) before the corner, R = speed / veer rate
  constexpr double kTypicalPace = 1.1;
  const double tau = reactionEstimate() + 0.15;
  const double v = std::max(0.0, in.walking_speed);
  const bool told_to_walk = current_.instruction == Instruction::WALK_ON || current_.instruction == Instruction::VEER;
  const double pace = std::max(v, have_pace_ ? pace_est_ : kTypicalPace);
  double v_arc = v;
  const double reach = walkSpeedingUp(v, told_to_walk ? startAccelEstimate() : 0.0, pace, tau, v_arc);
  const double rate = p.veer_rate_deg / kRadToDeg;
  const double tangent = v_arc / rate * std::tan(0.5 * std::fabs(turn));
  const double slack = ahead - tangent - reach;
  if (slack < -0.3 || slack > 3.0)
    return false;  // too late for the arc (stopped and turned as before), or not near yet
  // due on the last cycle before the arc would begin too late (a cycle is 1/15 s); else asked
  // `ask_in` s from now, after the walk on to it
  const bool due = slack <= v * 0.1;
  const double ask_in = due ? 0.0 : slack / std::max(0.3, v_arc);
  // the walk on, the arc and the leg out as far as it runs before the next corner (that one is
  // judged then), stopped by a stop asked then
  WalkModel m = committedWalk(in, now, ask_in + tau + std::fabs(turn) / rate);
  m.turn_start_s = ask_in + tau;
  m.turn = turn;
  m.turn_rate = rate;
  m.stop_at_s = std::min(m.stop_at_s, m.turn_start_s + std::fabs(turn) / rate +
                                          std::max(0.0, c.leg_out - 0.5) / std::max(0.3, v_arc));
  m.horizon_s = m.stop_at_s + v_arc / std::max(0.1, m.decel) + 0.5;
  // (the nominal walk: judged again on every cycle, and the wearer's strays are the next cycle's
  // start; the spread of a walk left to itself, sweep_spread_m, allowed no corner in a hall)
  m.spread_per_m = 0.0;
  if (sweep(in, m).hit)
    return false;  // the arc at this speed does not fit: stopped and turned as before
  if (!due)
  {
    // the walk goes on straight to it (a slight veer asked now would be carried out on top of the
    // corner's), not stopped at the free floor's end (the predictive stop still watches it)
    short_stop_at_ = -1.0;
    out = walkOn(fmt("a corner %.2f m ahead: walk on to it", ahead), now, false);
    return true;
  }
  const double asked = turn / veer_gain_est_;
  const int side = asked > 0.0 ? +1 : -1;
  const int level = veerLevel(std::fabs(asked) * kRadToDeg, p.veer_step_deg, 1.0);
  corner_rest_ = std::fabs(asked) > level * step + 0.5 * step ? asked - side * level * step : 0.0;
  corner_veer_ = true;
  chain_next_ = false;
  short_stop_at_ = -1.0;  // the walk goes on round the corner, not to the free floor's end
  char why[160];
  std::snprintf(why, sizeof(why), "a corner of %.0f deg %.2f m ahead: veer %s %.0f deg (the arc from %.2f m before it)",
                turn * kRadToDeg, ahead, side > 0 ? "left" : "right", level * p.veer_step_deg, tangent);
  out = veerPair(in, now, side, level, why);
  return true;
}

Cue CueLogic::veerPair(const NavInput& in, double now, int side, int level, std::string reason)
{
  // one shoulder, two short pulses (0.15 s on, 0.15 s off); the veer asked is watched from here
  const auto drive = beginShoulderCue(in, now, side, level, side * level * params_.veer_step_deg / kRadToDeg, false);
  return startPattern(CueMode::GUIDANCE, Instruction::VEER, level, drive, 15, 15, 2, now, std::move(reason));
}

Cue CueLogic::askSteer(const NavInput& in, double now, double err, double ask, bool walking)
{
  const CueParams& p = params_;
  const double a = std::fabs(err) * kRadToDeg;
  if (busy_)
    quiet_since_ = now;  // a veer just ended: the walk chord still holds it
  busy_ = false;
  // walking, a veer is asked for the error expected when it is carried out (the drift goes on)
  if (walking)
    ask = predictedError(ask, in.walking_speed);
  const double a_ask = std::fabs(ask) * kRadToDeg;
  // standing in a tight spot (the way ahead short, or a side close): turned until it faces the
  // way on, since it will walk along its facing and every veer acts a reaction time late
  const bool tight = in.free_ahead < p.stand_near_m || std::min(in.free_left, in.free_right) < p.side_free_m;
  // (also a wearer that has just been told to go and is starting: a wearer who walks off at an
  // angle in a tight spot meets the jamb before any veer can act; letting it start anyway was
  // measured worse in generated homes)
  const double stand_deg = tight ? std::min(p.stand_turn_near_deg, p.stand_turn_deg) : p.stand_turn_deg;
  const bool turn = walking ? a > p.turn_on_deg : a > stand_deg;
  const bool veer = walking && !turn && a_ask > p.veer_on_deg;
  if (veer && sweepReady(in) && inDoorway(in))
  {
    // In a doorway (issue 33): a veer acts a reaction time late, often just past the jambs and
    // larger than asked, and there it met the wall beyond (traced, gen_home_3005: a 15 deg veer
    // asked 0.6 m before the middle, carried out as 27 deg just past it). No veer while walking on,
    // stopped by a stop asked once a slight veer would be done, sweeps the body clear.
    if (!sweep(in, veerWalk(in, now, 0.0)).hit)
      return walkOn(fmt("%.0f deg off, in a doorway: straight on (walking on sweeps clear)", err * kRadToDeg), now,
                    false);
  }
  if (!walking && now < turn_go_start_until_ && a <= p.turn_on_deg)
  {
    // told to walk on after its turn and starting: what the turn left over is veered once it
    // walks (a stop-and-turn asked as it starts stops it again, a reaction late)
    return walkOn(fmt("turned, starting to walk (%.0f deg off)", err * kRadToDeg), now, false);
  }
  if (!walking && !turn && goMeetsEdge(in))
    return startTurn(in, now, wrapAngle(in.steer_heading - facing(in)), "its walk on would meet an edge: ");
  Cue edge_step;
  if (!walking && !turn && stepClearOfEdge(in, now, edge_step))
    return edge_step;
  if (!turn && !veer)
  {
    edge_steps_ = 0;
    return walkOn(fmt("on course (%.0f deg off)", err * kRadToDeg), now, !walking);
  }
  const double step = turn ? p.turn_step_deg : p.veer_step_deg;
  // what is asked beyond a veer still being carried out (the wearer completes it, then turns)
  // the level whose veer comes closest at this wearer's learnt gain (a turn's buzz sets its
  // angle by its length; its level only tells how far)
  const double gain = turn ? 1.0 : veer_gain_est_;
  const int level = veerLevel(a_ask, step, gain);
  if (turn)
  {
    const double angle = wrapAngle(in.steer_heading - facing(in));
    const double room = walking ? 0.0 : turnGoRoom(in, angle);
    const bool go_after = params_.turn_go_clear_m > 0.0 && room >= params_.turn_go_clear_m;
    Cue c = startTurn(in, now, angle, go_after ? "then walk on: " : "", level);
    turn_go_ = go_after;
    turn_go_room_ = room;
    return c;
  }
  const int side = ask > 0.0 ? +1 : -1;
  const char* dir = side > 0 ? "left" : "right";
  char buf[160];
  std::snprintf(buf, sizeof(buf),
                "veer %s %.0f deg (level %d, %.0f deg off, %.0f expected; "
                "drift %.1f deg/m, gain %.2f, reaction %.2f s)",
                dir, level * step, level, a, a_ask, drift_per_m_ * kRadToDeg, veer_gain_est_, reactionEstimate());
  return veerPair(in, now, side, level, buf);
}

std::array<float, NUM_MOTORS> CueLogic::beginShoulderCue(const NavInput& in, double now, int side, int level,
                                                        double angle, bool turn)
{
  // one shoulder at the level's intensity; the veer or turn is then watched from here
  const CueParams& p = params_;
  std::array<float, NUM_MOTORS> drive{ { 0.f, 0.f, 0.f, 0.f } };
  drive[side > 0 ? LEFT_SHOULDER : RIGHT_SHOULDER] =
      static_cast<float>(p.min_intensity + (1.0 - p.min_intensity) * 0.5 * (level - 1));
  busy_ = true;
  burst_at_ = now;
  const bool chain = chain_next_ && !turn && !busy_turn_;
  chain_next_ = false;
  turn_go_ = false;
  turn_go_sent_ = false;
  if (chain)
  {
    busy_angle_ += angle;  // the chain's origin stays: the walk is judged on all it asked
    return drive;
  }
  veer_seen_ = false;
  busy_walked0_ = walked_m_;
  busy_since_ = now;
  busy_yaw0_ = in.walk_heading;
  busy_head0_ = in.head_yaw;
  busy_body0_ = body_yaw_;
  busy_angle_ = angle;
  busy_turn_ = turn;
  return drive;
}

double CueLogic::turnBuzzS(double angle) const
{
  return std::min(2.5, std::max(kTellApartS + kTurnMarginS, std::fabs(angle) / turn_rate_est_ + kTellApartS));
}

Cue CueLogic::startTurn(const NavInput& in, double now, double angle, const char* why, int level)
{
  // stop and turn: a buzz that lasts while the wearer should turn (the level tells how far:
  // 45 / 90 / 135 deg and more), stopped early by the wearer's reaction
  const CueParams& p = params_;
  const int side = angle > 0.0 ? +1 : -1;
  const double a = std::fabs(angle) * kRadToDeg;
  if (level < 1)
    level = veerLevel(a, p.turn_step_deg, 1.0);
  const auto drive = beginShoulderCue(in, now, side, level, angle, true);
  turn_peak_rate_ = 0.0;
  turn_from_ = facing(in);
  const double dur = turnBuzzS(angle);
  char buf[200];
  std::snprintf(buf, sizeof(buf), "%sstop, turn %s %.0f deg (%.2f s buzz)", why, side > 0 ? "left" : "right", a, dur);
  const uint8_t on_10ms = uint8_t(std::lround(dur * 100.0));
  turn_buzz_s_ = 0.01 * on_10ms;
  return startPattern(CueMode::GUIDANCE, Instruction::TURN, level, drive, on_10ms, 0, 1, now, buf);
}

bool CueLogic::passageCue(const NavInput& in, double now, bool walking, Cue& out)
{
  // What a mobility instructor teaches at a doorway: stop short of it, square up to its middle,
  // walk straight through. A veer (15 deg at least, carried out a reaction time late) cannot
  // place a walker within the 0.1-0.2 m a 0.80-0.90 m doorway leaves beside the body; a turn on
  // the spot, judged on the head after it ended and repeated in small steps, can.
  const CueParams& p = params_;
  const double d = in.passage_distance;
  if (!(p.passage_align_m > 0.0) || !std::isfinite(d) || d < 0.0 || !std::isfinite(in.passage_heading) ||
      !(in.passage_width > 0.0))
    return false;
  const double v = std::max(0.0, in.walking_speed);
  char why[160];
  if (d < p.passage_inside_m)
    return false;  // in it: ordinary steering (a turn just beyond it must come at once)
  const double room = std::max(0.02, 0.5 * in.passage_width - p.passage_body_m);
  if (!walking)
  {
    if (d > p.passage_stand_m)
      return false;
    const double err = wrapAngle(in.passage_heading - facing(in));
    // told to go: it starts its reaction time later (the head's scanning meanwhile is no new error)
    if (now - passage_go_ < reactionEstimate() + 1.0)
    {
      out = walkOn(fmt("facing a passage's middle (%.0f deg off): going", err * kRadToDeg), now, true);
      return true;
    }
    if (stageForPassage(in, now, out))
      return true;
    // faced within passage_align_deg, or within what passes the middle inside half the room (a wide
    // passage is not squared up to the degree: the walk straight on passes it, with room to drift)
    const double align = std::max(p.passage_align_deg, std::atan2(kAlignRoomShare * room, d) * kRadToDeg);
    if (std::fabs(err) * kRadToDeg > align)
    {
      std::snprintf(why, sizeof(why), "passage %.2f m wide %.2f m ahead, middle %.0f deg off: ", in.passage_width, d,
                    err * kRadToDeg);
      out = startTurn(in, now, err, why);
      return true;
    }
    std::snprintf(why, sizeof(why), "facing a passage's middle (%.0f deg off, facing %.0f deg): go", err * kRadToDeg,
                  facing(in) * kRadToDeg);
    out = walkOn(why, now, true);
    passage_go_ = now;
    return true;
  }
  // walking: the wearer stops its reaction time and its stop later
  const double stop_m = stopReach(v, reactionEstimate());
  if (stopOnAxis(in, now, stop_m, out))
    return true;
  if (d > p.passage_align_m + stop_m + 0.3)
    return false;  // not yet: ordinary steering brings it towards the passage
  const double err = wrapAngle(in.passage_heading - in.walk_heading);
  // where the straight walk passes the middle (the learnt drift bends it on the way)
  const double miss = d * std::sin(err) - 0.5 * drift_per_m_ * d * d;
  const double slant = door_.valid ? std::fabs(wrapAngle(in.walk_heading - door_.axis)) * kRadToDeg : 0.0;
  const bool square = !(p.passage_square_deg > 0.0) || slant <= p.passage_square_deg;
  if (std::fabs(miss) <= room && square)
  {
    std::snprintf(why, sizeof(why), "passage %.2f m wide %.2f m ahead: straight on (passes %.2f m off its middle)",
                  in.passage_width, d, miss);
    out = walkOn(why, now, false);
    return true;
  }
  // stop and face the middle as seen from here (where it will stand depends on a reaction and a
  // stop it may not have learnt yet: seen from there the middle lies further off, and the next
  // turn, standing, asks for the rest); on the slant, standing, it squares up on the axis first
  std::snprintf(why, sizeof(why), "passage %.2f m wide %.2f m ahead, would pass %.2f m off its middle, %.0f deg off its axis: ",
                in.passage_width, d, miss, slant);
  out = startTurn(in, now, err, why);
  return true;
}

bool CueLogic::stopOnAxis(const NavInput& in, double now, double stop_m, Cue& out)
{
  // A walk along a hall towards a doorway in its side crosses the doorway's axis before it: the
  // stop timed to land there leaves the wearer standing square to it, a turn on the spot from
  // walking through (where a stop short of it on the slant needs a walk to the axis first).
  const CueParams& p = params_;
  if (!(p.passage_square_deg > 0.0) || !door_.valid)
    return false;
  const double ca = std::cos(door_.axis), sa = std::sin(door_.axis);
  const double ch = std::cos(in.walk_heading), sh = std::sin(in.walk_heading);
  const double det = std::sin(in.walk_heading - door_.axis);  // the walk against the axis
  if (std::fabs(det) < std::sin(p.passage_square_deg / kRadToDeg))
    return false;  // along the axis (or nearly): straight through, the ordinary routine
  // the walk P + t h meets the axis M + u n
  const double dx = door_.x - in.x, dy = door_.y - in.y;
  const double t = (-dx * sa + ca * dy) / det, u = (ch * dy - sh * dx) / det;
  const double before = -u;
  if (t < 0.0 || before < 0.35 || before > 1.5)
    return false;
  const double xx = in.x + t * ch, xy = in.y + t * sh;
  if (in.grid && !in.grid->empty() && obstacleClearance(*in.grid, xx, xy, 1.0) < p.sweep_radius_m + 0.05)
    return false;  // no room to stand there
  if (t > stop_m + 0.05)
  {
    out = walkOn(fmt("the doorway's axis %.2f m ahead: walk on to it", t), now, false);
    return true;
  }
  if (t < stop_m - 0.3)
    return false;  // too late to stand on it: stop and turn as before
  out = stopAll(now, fmt("stop on the doorway's axis (%.2f m on)", t));
  return true;
}

double CueLogic::stopAfterGo(double room) const
{
  // walked after accelerating for s: a s^2 / 2, then the stop (a s)^2 / (2 stop_decel)
  const double a = startAccelEstimate();
  const double k = 0.5 * a + a * a / (2.0 * stopDecelEstimate());
  return 0.1 + std::sqrt(std::max(0.0, room) / k);  // (the tick is felt when it ends, 0.1 s)
}

Cue CueLogic::timedGo(double now, double room, std::string reason)
{
  Cue c = walkOn(std::move(reason), now, true);
  go_at_ = now;
  go_handled_ = now;  // judged here, not on the free floor ahead
  short_stop_at_ = now + stopAfterGo(room);
  passage_go_ = now;
  stage_walk_ = true;
  return c;
}

void CueLogic::noteDoor(const NavInput& in)
{
  if (!(in.passage_distance >= 0.0) || !(in.passage_width > 0.0) || !std::isfinite(in.passage_x) ||
      !std::isfinite(in.passage_y) || !std::isfinite(in.passage_axis))
    return;
  if (door_.valid && std::hypot(in.passage_x - door_.x, in.passage_y - door_.y) > 0.3)
    prev_door_ = door_;
  door_ = { true, in.passage_x, in.passage_y, in.passage_axis, in.passage_width };
}

bool CueLogic::stageForPassage(const NavInput& in, double now, Cue& out)
{
  // Through a doorway on the slant the jambs come closer to the body's line by the cosine and the
  // wall's depth: square up first, as an instructor would, on the doorway's own axis.
  const CueParams& p = params_;
  if (!(p.passage_square_deg > 0.0) || !door_.valid)
    return false;
  const double ca = std::cos(door_.axis), sa = std::sin(door_.axis);
  const double rx = in.x - door_.x, ry = in.y - door_.y;
  const double before = -(rx * ca + ry * sa), lateral = -rx * sa + ry * ca;
  if (before < 0.15 || std::atan2(std::fabs(lateral), before) * kRadToDeg <= p.passage_square_deg)
    return false;  // in it, or near enough its axis: face the middle from here
  // the point on the axis, nearer the middle when it lies against an obstacle
  double s = p.passage_stage_m, sx = door_.x - s * ca, sy = door_.y - s * sa;
  while (s > 0.25 && in.grid && !in.grid->empty() &&
         obstacleClearance(*in.grid, sx, sy, 1.0) < p.sweep_radius_m + 0.05)
  {
    s -= 0.1;
    sx = door_.x - s * ca;
    sy = door_.y - s * sa;
  }
  const double dist = std::hypot(sx - in.x, sy - in.y);
  if (dist < 0.1)
    return false;
  const double err = wrapAngle(std::atan2(sy - in.y, sx - in.x) - facing(in));
  char why[200];
  if (std::fabs(err) * kRadToDeg > std::max(p.passage_align_deg, 8.0))
  {
    std::snprintf(why, sizeof(why), "passage %.2f m wide, %.0f deg off its axis: to its axis first (%.2f m), ",
                  door_.width, std::atan2(std::fabs(lateral), before) * kRadToDeg, dist);
    out = startTurn(in, now, err, why);
    return true;
  }
  std::snprintf(why, sizeof(why), "passage %.2f m wide: walk %.2f m to its axis (%.2f m before its middle)", door_.width,
                dist, s);
  out = timedGo(now, dist, why);
  return true;
}

bool CueLogic::throughPassage(const NavInput& in, double now, bool walking, Cue& out)
{
  // A turn just beyond a doorway, cued while the body is still between the jambs, swings it out on
  // the slant into one (most homes' collisions were there, the body 45-90 deg off the doorway's
  // axis): the body leaves on the axis first.
  const CueParams& p = params_;
  if (!(p.passage_clear_m > 0.0))
    return false;
  for (const Door* dp : { &door_, &prev_door_ })
  {
    const Door& d = *dp;
    if (!d.valid)
      continue;
    // the axis the way the wearer goes on (the way may lead back out through it)
    const double axis = std::cos(in.steer_heading - d.axis) >= 0.0 ? d.axis : wrapAngle(d.axis + M_PI);
    const double ca = std::cos(axis), sa = std::sin(axis);
    const double rx = in.x - d.x, ry = in.y - d.y;
    const double past = rx * ca + ry * sa, lateral = -rx * sa + ry * ca;
    if (past < -p.passage_inside_m || past > p.passage_clear_m || std::fabs(lateral) > 0.5 * d.width)
      continue;
    // (judged on the axis, not on the facing: a standing wearer squared up to it is not turned away
    // by a steering error its own scan makes)
    const bool turn_after = std::fabs(wrapAngle(in.steer_heading - axis)) * kRadToDeg > p.stand_turn_deg;
    const double to_clear = p.passage_clear_m - past;
    if (walking)
    {
      // An aisle whose way runs straight on: ordinary steering keeps the walk on it. Told
      // "straight on" regardless, a veering wearer in an aisle (which the planner reports as a
      // passage that moves along with the wearer) drifted into the shelf: traced, gen_shop_4001
      // trial 2, t 27.4, 21 deg of veer over 3 m and no cue until the ray ahead met the shelf 1.4 m
      // on at 1 m/s (31 of 100 collisions of shops 4001-4020 x5 came after this "straight on").
      // In a doorway the walk goes on straight as before: steered there too, homes 3011-3020 x5
      // seed 12 collided more at the jambs (0.58 -> 0.90 a trial).
      if (!turn_after && aisleAhead(in, d, axis))
        return false;
      if (std::fabs(wrapAngle(in.walk_heading - axis)) * kRadToDeg > 2.0 * p.passage_square_deg)
        return false;  // walking across it, not through it (the sweep judges)
      const double v = std::max(0.0, in.walking_speed);
      if (turn_after && stopReach(v, reactionEstimate()) >= to_clear)
      {
        out = stopAll(now, fmt("in a passage: stop clear of its jambs (%.2f m on), then turn", to_clear));
        return true;
      }
      out = walkOn(fmt("in a passage: straight on through it (%.2f m to clear its jambs)", to_clear), now, false);
      return true;
    }
    if (std::fabs(past) <= 0.35 && centreInPassage(in, now, axis, lateral, d.width, out))
      return true;
    if (!turn_after || std::fabs(past) > 0.25)
      return false;  // the way goes on straight, or the body is not between the jambs (before
                     // them the doorway routine squares it up)
    const double ferr = wrapAngle(axis - facing(in));
    if (std::fabs(ferr) * kRadToDeg > std::max(p.passage_align_deg, 8.0))
    {
      out = startTurn(in, now, ferr, "in a passage: face its axis, ");
      return true;
    }
    out = timedGo(now, to_clear + 0.05, fmt("in a passage: step %.2f m out of it", to_clear + 0.05));
    return true;
  }
  return false;
}

bool CueLogic::centreInPassage(const NavInput& in, double now, double axis, double lateral, double width, Cue& out)
{
  // A body standing against a jamb cannot walk on along the axis: each step scrapes the jamb
  // (the grid's cells put the jamb's face anywhere within 0.2 m: judged on the middle's offset).
  // Short side-steps towards the middle, each judged once it was carried out (a reaction after
  // the buzz ended).
  const CueParams& p = params_;
  if (sideStepUnderWay(centre_at_, now))
  {
    out = holdPattern("in a passage: a side-step towards its middle");
    return true;
  }
  const double room = std::max(0.02, 0.5 * width - p.passage_body_m);
  if (std::fabs(lateral) <= room + 0.05)
    return false;
  // towards the middle (-lateral across the axis), as seen from the body's facing
  const double mx = lateral * std::sin(axis), my = -lateral * std::cos(axis);
  const double yaw = facing(in);
  const int side = std::cos(yaw) * my - std::sin(yaw) * mx > 0.0 ? +1 : -1;
  centre_at_ = now;
  out = shortSideStep(side, now,
                      fmt(side > 0 ? "in a passage %.2f m off its middle: step left" :
                                     "in a passage %.2f m off its middle: step right",
                          std::fabs(lateral)));
  return true;
}

bool CueLogic::shortWalk(const NavInput& in, double now, Cue& out)
{
  // A standing wearer told to go with little free floor ahead (a wall a metre or two on, a
  // doorway into a hall): it starts a reaction time (0.3-1.2 s) after the tick and speeds up; a
  // stop asked once it is seen walking lands another reaction time later, 1.5 m on for the
  // slowest. A stop asked S after the go lands after S of walking whatever the reaction (the
  // wearer starts and stops a reaction late): S is chosen so that the walk and the stop end
  // short of the obstacle.
  const CueParams& p = params_;
  if (!(p.short_walk_m > 0.0))
    return false;
  const bool walking = in.walking_speed >= p.walking_speed_mps;
  if (go_at_ > go_handled_)
  {
    go_handled_ = go_at_;  // (the go of the last cycle: judged on this cycle's free floor)
    short_stop_at_ = -1.0;
    double room = in.free_ahead - p.alert_m;
    // the body's disc swept along its facing (a jamb beside the body, which the ray does not see):
    // it stops 0.1 m short of where the disc would first meet an obstacle cell
    if (in.grid && !in.grid->empty() && p.sweep_radius_m > 0.0)
    {
      const SweepResult r = sweep(in, goWalk(6.0));
      if (r.hit)
        room = std::min(room, r.hit_along - 0.1);
    }
    short_stop_at_ = shortWalkStopAt(in.free_ahead, room);
  }
  if (short_stop_at_ < 0.0)
    return false;
  if (now < short_stop_at_)
    return false;
  if (!walking && now - short_stop_at_ > 0.5)
  {
    short_stop_at_ = -1.0;  // it stands: the next cue turns it or sends it on
    return false;
  }
  out = stopAll(now, fmt("a short walk: stop (%.2f m free when it went)", in.free_ahead));
  return true;
}

double CueLogic::shortWalkStopAt(double free_ahead, double room) const
{
  // a walk shorter than short_walk_m, or than this wearer needs to stop from its pace when that
  // is known, gets a stop timed from the go (short_walk_m 0: no timed stop at all)
  const CueParams& p = params_;
  if (!(p.short_walk_m > 0.0))
    return -1.0;
  const double reach_at_pace = have_pace_ ? p.alert_m + stopReach(pace_est_, reactionEstimate()) : 0.0;
  const double need = std::max(p.short_walk_m, reach_at_pace);
  if ((std::isfinite(free_ahead) && free_ahead < need) || room + p.alert_m < need)
    return go_at_ + stopAfterGo(room);
  return -1.0;
}

bool CueLogic::holdSweepStop(const NavInput& in, Cue& out)
{
  // Once asked, the predictive stop is held until the wearer stands: its slowing walk would sweep
  // clear again and a tick would send it on. Judged before the guidance, which replaces the
  // pattern being played: judged after it, the stop lasted one cycle whenever the guidance
  // wanted to walk on (77 of 313 predictive stops on homes 3011-3020 x5, traced: a 67 ms stop,
  // then the tick, and the walk went on into the wall it was stopped for).
  const bool moving = std::isfinite(in.walking_speed) && in.walking_speed >= params_.walking_speed_mps;
  if (sweep_stop_ && moving && current_.instruction == Instruction::STOP)
  {
    busy_ = false;
    out = holdPattern("stopping: the walk would sweep the body into an obstacle");
    out.mode = CueMode::ALERT;
    return true;
  }
  sweep_stop_ = false;
  return false;
}

Cue CueLogic::guideWithSweep(const NavInput& in, double now)
{
  // the guidance cue, unless the walk it leaves the wearer committed to sweeps the body into an
  // obstacle (the predictive stop)
  Cue stop;
  if (holdSweepStop(in, stop))
  {
    noteDoor(in);  // (what the guidance watches goes on while the stop is held)
    return stop;
  }
  const Cue c = decideGuidance(in, now);
  if ((c.instruction == Instruction::WALK_ON || c.instruction == Instruction::VEER ||
       c.instruction == Instruction::TURN) &&
      sweepStop(in, now, stop))
    return stop;
  return c;
}

Cue CueLogic::decideGuidance(const NavInput& in, double now)
{
  const CueParams& p = params_;
  noteDoor(in);
  {
    Cue stop;
    if (shortWalk(in, now, stop))
      return stop;
  }
  const bool guiding = last_mode_ == CueMode::GUIDANCE;
  const double min_wp = p.guidance_min_waypoint_m - (guiding ? p.hysteresis_m : 0.0);
  if (in.waypoint_distance < min_wp)
  {
    busy_ = false;
    return walkOn(fmt("waypoint %.2f m away: walk on", in.waypoint_distance), now,
                  in.walking_speed < p.walking_speed_mps);
  }
  const bool walking = walksForward(in);
  // + = the steering point lies left of the walk (standing: of the body, not the scanning head)
  const double err = wrapAngle(in.steer_heading - (walking ? in.walk_heading : facing(in)));
  bool superseding = false;  // a veer under way is overtaken: ask beyond it
  chain_next_ = false;
  Cue held;
  if (busy_ && busy_turn_ && holdTurn(in, now, held))
    return held;
  if (cornerVeer(in, now, walking, held))
    return held;
  if (busy_ && holdVeer(in, now, err, walking, held, superseding))
    return held;
  if (stage_walk_)
  {
    // walking to a passage's axis or out of it: its timed stop ends the walk (shortWalk)
    if (short_stop_at_ >= 0.0 || now - passage_go_ < reactionEstimate() + 1.0)
      return walkOn("walking to a passage's axis or out of it", now, !walking);
    stage_walk_ = false;
  }
  // after a superseded veer the new one asks for what is left beyond the one being carried out
  double ask = err;
  if (superseding)
  {
    const double sign = busy_angle_ > 0.0 ? 1.0 : -1.0;
    ask = wrapAngle(err - (busy_angle_ - sign * std::max(0.0, veerTurned(in, false) * sign)));
    chain_next_ = true;
  }
  if (!superseding)
  {
    // a doorway or gap ahead: stop short, face its middle, walk straight through
    if (busy_)
      quiet_since_ = now;
    busy_ = false;
    if (throughPassage(in, now, walking, held))
      return held;
    if (passageCue(in, now, walking, held))
      return held;
  }
  return askSteer(in, now, err, ask, walking);
}

}  // namespace assistive_tactile
