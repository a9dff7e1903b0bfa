#pragma once
// The simulated wearer of the mobility trials (issue 19, seed 5.2 and 5.5): a body that walks in a
// world and reacts only to the vest's four motors as the study told its subjects to (its body is
// assistive_sim::BodyCollider, which counts collisions by obstacle kind), and a cane-only walker for the baseline.
// ROS-free. The wearer never reads the map: it knows only what the vest tells it.
#include <array>
#include <deque>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <assistive_sim/body_collider.h>
#include <assistive_sim/world.h>

namespace assistive_trials
{
/// One wearer: the body and how it reacts to the vest. A trial draws one from the population
/// (wearer_population.h: every value cites its source in docs/wearer_population.md); the defaults
/// are a typical adult. The protocol (what each cue asks) is assistive_tactile/README.md's page:
/// the wearer was taught it, and acts on what it feels, never on the map.
struct WearerParams
{
  double walk_speed = 1.1;        ///< m/s preferred walking speed; the sighted-guide run uses it too
  double accel = 0.85;            ///< m/s^2 to start walking (stopping: stopDecel()); the population's mean
  double reaction_s = 0.6;        ///< s from a cue's onset to the body's response (walking, torso vibration)
  double turn_gain = 1.0;         ///< this wearer's turns: actual / asked (a lasting bias)
  double turn_gain_sd = 0.15;     ///< and its spread from one turn to the next (lognormal sigma)
  double turn_rate_deg = 90.0;    ///< deg/s turning on the spot
  double veer_rate_deg = 60.0;    ///< deg/s changing direction while walking (a veer)
  double veer_sigma_deg = 1.0;    ///< veering while walking straight: heading random walk, deg per sqrt(m)
  double veer_bias_deg_per_m = 0.0;  ///< and its constant drift (signed, + = left)
  int intensity_levels = 3;       ///< vibration intensities this wearer tells apart (absolute identification)
  double min_pulse_s = 0.05;      ///< shortest pulse felt (s); shorter ones go unnoticed
  double sidestep_speed = 0.3;    ///< m/s sideways while a waist motor buzzes
  double scan_amplitude_deg = 8.0;///< head yaw scanning while walking (the worlds' default)
  double scan_period_s = 7.0;
  double body_radius = 0.25;      ///< m, the body's cylinder (shoulders)
  double eye_height = 1.6;        ///< m; the body reaches 0.12 m above it
  double bump_explore_s = 1.0;    ///< s feeling around after bumping into something
  double explore_rate_deg = 40.0; ///< deg/s turning while feeling around (and the cane-only walker)
  /// The protocol's silence rule, as taught: no cue felt for this long (two walk-on ticks missed)
  /// means stop and use the cane.
  double silence_stop_s = 4.5;
  /// m/s^2 stopping: the model stops at twice its start (`accel`).
  double stopDecel() const { return 2.0 * accel; }
};

/// Body state on the floor: position, body yaw, head yaw, walking speed.
struct BodyState
{
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  double yaw = 0.0;       ///< body (torso) yaw, rad
  double head_yaw = 0.0;  ///< rad, body yaw + scanning
  double speed = 0.0;     ///< m/s forward
};

/**
 * The vest wearer of the walking protocol (issue 33; assistive_tactile/README.md): it stands until
 * told to go, walks at its own pace while the walk-on ticks come, veers by the amount a shoulder's
 * two short pulses ask (level = felt intensity) without stopping, stops and turns on the spot by
 * the amount a shoulder's long buzz asks, side-steps while a waist motor buzzes, and stops on all
 * four, on the UNSURE pattern (both waists pulsing) and when the vest stays silent for
 * `silence_stop_s`. Everything felt acts `reaction_s` after it began; turns come out
 * `turn_gain` x asked (lognormal spread); walking straight the heading wanders (veering); pulses
 * shorter than `min_pulse_s` go unnoticed; intensities are told apart in `intensity_levels` steps.
 */
class VestWearer
{
public:
  VestWearer(const WearerParams& p, const BodyState& start, uint32_t seed);
  /// Advance by dt at time t (s) with the motors' drive now (0..1: left shoulder, right
  /// shoulder, left waist, right waist). `collider` may be null (free space).
  void step(double t, double dt, const std::array<float, 4>& motors, assistive_sim::BodyCollider* collider);
  const BodyState& state() const { return s_; }
  /// What the wearer is doing, for the per-trial summary.
  enum Action { WALK, TURN, SIDESTEP, EXPLORE, STOPPED, VEER };
  Action action() const { return action_; }
  /// What it understood last (the percept) and when, for the timeline.
  enum Percept { NOTHING, WALK_ON, VEER_LEFT, VEER_RIGHT, TURN_LEFT, TURN_RIGHT, SIDESTEP_LEFT, SIDESTEP_RIGHT, STOP, UNSURE };
  Percept lastPercept() const { return percept_; }
  int lastLevel() const { return percept_level_; }

private:
  /// What the motors did `reaction_s` ago (the response lags the cue by the reaction time).
  std::array<float, 4> felt(double t) const;
  int perceivedLevel(float intensity);
  void perceive(double t, double dt, const std::array<float, 4>& m);

  WearerParams p_;
  BodyState s_;
  std::mt19937 rng_;
  double scan_phase_ = 0.0;
  std::deque<std::pair<double, std::array<float, 4>>> history_;
  Action action_ = STOPPED;
  Percept percept_ = NOTHING;
  int percept_level_ = 0;
  bool go_ = false;             ///< told to walk (a walk-on, veer or turn since the last stop)
  double last_felt_ = 0.0;      ///< when something was last felt
  // the pulse being felt on a shoulder: its side, start, strongest drive
  int shoulder_side_ = 0;
  double shoulder_since_ = -1.0;
  float shoulder_peak_ = 0.f;
  bool shoulder_used_ = false;  ///< this buzz already understood as a turn
  int last_veer_side_ = 0;      ///< the last one-shoulder pulse: side and end (a veer is two pulses)
  double last_veer_end_ = -1e9;
  // a turn being carried out: rad still to turn (signed), on the spot or while walking
  double turn_left_ = 0.0;
  int spot_side_ = 0;           ///< turning on the spot towards this side while the buzz is felt
  int explore_side_ = 0;
  double explore_until_ = -1.0;
  double walked_since_noise_ = 0.0;
};

/// The cane-only baseline. The cane senses contact within its reach and sweep ahead, low down
/// (nothing at head height); the walker heads for the next place of the route it was told,
/// turns away from a contact on one side of the sweep, keeps to that side (following what it touches),
/// and picks a side at random when blocked across the middle (seed
/// 5.4.2.2: cane users "were forced to choose randomly to go left or right").
struct CaneParams
{
  double reach = 1.0;         ///< m ahead of the body's centre that the tip reaches
  double sweep_deg = 20.0;    ///< half-angle of the arc the tip sweeps (+-0.34 m at 1 m: shoulder width and a bit)
  double tip_height = 0.3;    ///< m: the cane feels what lies between the floor and this height
  double heading_rate_deg = 30.0;  ///< deg/s turning back towards the route while the cane is clear
  double avoid_step_deg = 30.0;    ///< deg turned away at each contact
  double heading_noise_deg = 10.0; ///< sigma of the walker's sense of the route's direction
  double follow_m = 1.0;      ///< m walked along what was touched before heading back to the route
  /// s a walker whose cane touches only a person (nothing static) stands and lets them pass
  /// before treating them as an obstacle (a standing group); walking people step aside for it
  /// (assistive_sim/people_give_way.h), standing ones stay
  double person_wait_s = 3.0;
};

class CaneWalker
{
public:
  CaneWalker(const WearerParams& wp, const CaneParams& cp, const BodyState& start, uint32_t seed);
  /// Advance by dt; `target` is the next place of the route (m).
  void step(double t, double dt, const Eigen::Vector2d& target, assistive_sim::BodyCollider& collider);
  const BodyState& state() const { return s_; }
  /// Does the cane touch anything now (tip arc within reach, low down)?
  bool caneContact(const assistive_sim::BodyCollider& collider, double yaw) const;
  /// The same, with the sweep angles (deg, + = left) of the leftmost and rightmost contact;
  /// `with_people` false: the static world only.
  bool caneContact(const assistive_sim::BodyCollider& collider, double yaw, double& lo_deg, double& hi_deg,
                   bool with_people = true) const;
  int contacts() const { return contacts_; }

private:
  WearerParams wp_;
  CaneParams cp_;
  BodyState s_;
  std::mt19937 rng_;
  int side_ = 0;              ///< side chosen when blocked: +1 left, -1 right, 0 none
  double turned_ = 0.0;       ///< rad turned away on this side without progress
  double follow_left_ = 0.0;  ///< m still to walk along the obstacle
  double bias_ = 0.0;         ///< the walker's error on the route's direction (rad)
  double pause_until_ = -1.0;
  double wait_since_ = -1.0;  ///< waiting for a person to pass since (s), < 0: not waiting
  int contacts_ = 0;
};

/// A sighted guide's walk from `start` to `goal` on the shortest collision-free path at the
/// wearer's cruise speed (seed 5.5.2.2, PWS): returns the time (s), or a negative value when there
/// is no path. `path` (if given) receives the walked points.
double sightedGuideTime(const assistive_sim::World& world, const WearerParams& p, const Eigen::Vector2d& start,
                        const std::vector<Eigen::Vector2d>& route, std::vector<Eigen::Vector2d>* path = nullptr);

/// What the fastest walk this wearer's body allows costs beyond the sighted guide's (issue 33).
struct WalkFloor
{
  double time_s = -1.0;       ///< the floor's time (s); negative: no path
  double guide_time_s = -1.0; ///< the guide's (sightedGuideTime)
  double start_s = 0.0;       ///< the first go's reaction, the tick and a turn on the spot to the first leg
  double turns_s = 0.0;       ///< the corners' braking (for a veer that fits, or a turn on the spot)
  int corners = 0;            ///< corners of the guide's path turned by more than 15 deg
  int in_stride = 0;          ///< of them, veered in stride
};

/// The floor of any cue policy (an oracle that knows this wearer and times every cue perfectly):
/// the guide's path walked by the wearer's body as `VestWearer` moves it. The first go costs a
/// reaction and a tick (and a turn on the spot, 0.25 s to tell the buzz plus the angle at
/// `turn_rate_deg`, when the first leg lies over 20 deg off the start's facing); a corner over
/// 15 deg is veered at `veer_rate_deg`, in stride when that arc at cruise speed, pushed out to pass
/// through the corner, keeps the body clear, else after braking (a stop, then the tick) to the
/// fastest speed whose arc fits; or turned on the spot while braking (stopDecel), the tick and the
/// start again (`accel`), whichever loses less. Optimistic: no veering noise, no turn error, the
/// arc's entry and exit and the braking turn's overshoot not checked against the walls; bends under
/// 15 deg cost nothing.
WalkFloor wearerFloor(const assistive_sim::World& world, const WearerParams& p, const BodyState& start,
                      const std::vector<Eigen::Vector2d>& route);

}  // namespace assistive_trials
