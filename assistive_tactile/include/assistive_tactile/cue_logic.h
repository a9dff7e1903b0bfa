#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <string>

#include <assistive_common/codes.h>
#include "assistive_tactile/params.h"
#include "assistive_tactile/sweep.h"
#include "assistive_tactile/vest_protocol.h"

namespace assistive_tactile
{
/// Navigation status and cue modes: one definition for every stage (assistive_common/codes.h;
/// the values of assistive_msgs/NavigationState and TactileCue).
using assistive_common::CrossingAdvice;
using assistive_common::CueMode;
using assistive_common::NavStatus;

enum Motor : int
{
  LEFT_SHOULDER = 0,
  RIGHT_SHOULDER = 1,
  LEFT_WAIST = 2,
  RIGHT_WAIST = 3,
  NUM_MOTORS = 4
};

/// What the cue logic needs from the planner state (SI units, radians).
struct NavInput
{
  NavStatus status = NavStatus::NO_POSE;
  std::string message;
  double heading = 0.0;          ///< motion vector yaw
  double path_heading = 0.0;     ///< yaw of the path segment ahead
  /// Yaw from the wearer to the steering point (the look-ahead point on the path, pure pursuit).
  double steer_heading = 0.0;
  /// Yaw the body walks along (the planner's walked chord over the last fraction of a second;
  /// the head's yaw while standing).
  double walk_heading = 0.0;
  double walking_speed = 0.0;    ///< m/s
  double head_yaw = 0.0;         ///< the head's yaw now (its rate tells a turn being carried out)
  /// The torso's yaw rate (rad/s, about the vertical) from the vest's own gyro; NaN: the vest has
  /// none (the body's facing is then estimated from the head, whose scan it must filter out).
  double body_yaw_rate = std::numeric_limits<double>::quiet_NaN();
  /// Free distance along `steer_heading` (NaN or +inf: unknown / not limited).
  double free_steer = std::numeric_limits<double>::infinity();
  double waypoint_distance = 0.0;
  /// A doorway or gap narrower than the planner's passage_width_m on the path ahead: metres along
  /// the path to its middle (< 0 or NaN: none), the yaw from the wearer to its middle, its width.
  double passage_distance = -1.0;
  double passage_heading = 0.0;
  double passage_width = 0.0;
  /// That middle (in the frame of `grid`, as x, y) and the passage's axis (rad): across its
  /// jamb-to-jamb line, the way the path goes through it (NaN: unknown; the doorway is then faced
  /// from wherever the wearer stands).
  double passage_x = std::numeric_limits<double>::quiet_NaN();
  double passage_y = std::numeric_limits<double>::quiet_NaN();
  double passage_axis = std::numeric_limits<double>::quiet_NaN();
  double free_ahead = 0.0;
  double free_left = 0.0;
  double free_right = 0.0;
  /// Someone whose predicted path crosses the wearer's (the planner's most urgent advice).
  CrossingAdvice crossing = CrossingAdvice::NONE;
  int crossing_id = 0;             ///< mover behind it
  double crossing_time = 0.0;      ///< s until the closest approach
  double crossing_distance = 0.0;  ///< m, predicted closest distance
  /// The wearer's position on the ground (the state's `wearer`) in the frame of `grid`.
  double x = 0.0, y = 0.0;
  /// The grid the planner planned on (its `planner/grid`), for the body's predicted sweep; null:
  /// none (the cue logic then judges the way ahead on the planner's rays alone, as before).
  std::shared_ptr<const ObstacleGrid> grid;
  /// The path the wearer is steered along, from about where it stands on (the state's
  /// `path_ahead`, in the frame of `grid`; empty: not known, no corner is taken walking).
  std::vector<GroundPoint> path;
  /// Time of the camera image behind the state (source_stamp), on the clock of `now`;
  /// NaN = unknown (zero stamp): such a state is never guided on.
  double source_time = std::numeric_limits<double>::quiet_NaN();
};

/// What a cue asks of the wearer (the protocol page in README.md).
enum class Instruction : uint8_t
{
  NONE = 0,      ///< nothing felt (UNSURE after its opening pattern, link lost)
  WALK_ON = 1,   ///< clear: a tick on both shoulders every `tick_period_s`
  VEER = 2,      ///< keep walking, veer by level x `veer_step_deg` (one shoulder, two short pulses)
  TURN = 3,      ///< stop and turn on the spot by level x `turn_step_deg` (one shoulder, one long buzz)
  SIDESTEP = 4,  ///< step sideways while the waist motor buzzes
  STOP = 5,      ///< all four: stop (obstacle, person crossing, nothing free)
  UNSURE = 6     ///< three quick pulses on both waist motors, then silence: stop, use the cane
};
const char* instructionName(Instruction i);

struct Cue
{
  CueMode mode = CueMode::UNSURE;
  /// The drive of each motor while the pattern is on (0..1).
  std::array<float, NUM_MOTORS> intensity{ { 0.f, 0.f, 0.f, 0.f } };
  /// How the motors pulse (the vest renders it; a new id restarts it). Default: steady.
  vest_pattern_t pattern{ 0, 0, 0, 0 };
  Instruction instruction = Instruction::NONE;
  int level = 0;          ///< 1..3 for VEER / TURN
  std::string reason;
};

/// The drive of every motor `t_s` after the cue's pattern started (what the vest does).
std::array<float, NUM_MOTORS> renderCue(const Cue& c, double t_s);

const char* modeName(CueMode m);
using assistive_common::crossingName;

/// Wraps an angle to (-pi, pi].
double wrapAngle(double a);

/**
 * The walking protocol (issue 33; the page in README.md): steering cues a person can follow while
 * walking (a veer burst asks for an amount, a stop-and-turn buzz lasts the angle at the wearer's
 * turning rate), the walk-on tick that makes silence mean "stop", the UNSURE pattern, and the
 * seed's obstacle cues (5.2-5.3) with people crossing (issue 22) over them. Each cue is a pattern
 * the vest plays (`Cue::pattern`; a new id starts it, the same id continues it).
 *
 * The order, first wins:
 *   1. input not usable (NaN, camera image too old or unstamped), or status not OK: UNSURE (three
 *      pulses on both waists, then silence), or the obstacle stop of NO_PATH / NO_WAYPOINT; a
 *      NO_POSE lasting lost_turn_after_s on fresh images: a turn on the spot to look elsewhere;
 *   2. the obstacle stop: free ahead inside the stop distance (alert_m plus the walk during the
 *      wearer's reaction, learnt from its starts, and its stop), unless the steering point lies
 *      clear to a side and the obstacle lies beyond what no reaction can prevent;
 *   3. crossing STOP: all four; 4. crossing LEFT / RIGHT: that waist motor;
 *   5. the obstacle side-step (unless steering away, or a turn on the spot is under way);
 *   6. steering: a veer while walking, a stop-and-turn above turn_on_deg (standing: stand_turn_deg);
 *   7. the walk-on tick.
 * A crossing cue lasts at least crossing_hold_s, then ends once the advice has been NONE for
 * crossing_release_s. Stateful; not thread-safe. Times are seconds on any monotonic clock.
 */
class CueLogic
{
public:
  explicit CueLogic(const CueParams& p = CueParams()) : params_(p) {}

  const CueParams& params() const { return params_; }

  /// One planner state -> one cue. `now` is when the state arrived (ROS time, maybe simulated).
  /// A state whose camera image (source_time) is older than max_input_age_s, or unknown, gives
  /// UNSURE (motors off) whatever it says. A status other than OK gives UNSURE, except ALERT
  /// for NO_PATH / NO_WAYPOINT ("nothing free") from fresh input when the way ahead is blocked
  /// under alert_m, or under proximity_m with no room to either side.
  Cue update(const NavInput& in, double now);

  /// True when no state arrived for state_timeout_s (or none ever), or the last state's camera
  /// image is now older than max_input_age_s (or unknown): the last cue must not be repeated.
  bool stale(double now) const;

  /// The cue to send while stale (motors off, mode UNSURE, reason says why).
  Cue staleCue(double now);

  /// Forget the hysteresis state (e.g. after a stale period).
  void reset();

private:
  Cue decideProximity(const NavInput& in, bool have_path);
  Cue decideGuidance(const NavInput& in, double now);
  /// decideGuidance, then the predictive stop over it (sweepStop).
  Cue guideWithSweep(const NavInput& in, double now);
  /// The head's turn rate, the metres walked, how long the head has been steady, the drift, the
  /// body's yaw.
  void observeHead(const NavInput& in, double now);
  /// The body's facing: the walk chord while walking; standing, the head's yaw without its scan
  /// (a head-mounted camera's only heading scans +-8 deg over a body that stands still: aligned on
  /// the head, a turn on the spot chased the scan). With the vest's gyro (as observeHead last saw
  /// it): the gyro's facing, walking or standing.
  double facing(const NavInput& in) const;
  /// The body's turn rate (rad/s, smoothed over 0.25 s): the vest gyro's, else the head's (with
  /// its scan).
  double turnRate() const;
  /// How far the body has turned since the veer being carried out began (rad, + = left): the
  /// vest gyro's facing; else the walk chord's, or with `head` the head's.
  double veerTurned(const NavInput& in, bool head) const;
  /// Walking forwards: at walking speed with the walk chord along the head (within 50 deg), not a
  /// side-step or a step back, whose chord is no facing.
  bool walksForward(const NavInput& in) const;
  /// A stop-and-turn being carried out: true (and the held cue) while it lasts; its end learns
  /// the turning rate.
  bool holdTurn(const NavInput& in, double now, Cue& out);
  /// A veer being carried out: true (and the held cue) until it was seen and steadied, overshot,
  /// or timed out; `superseding` when a corner asks for more at once.
  bool holdVeer(const NavInput& in, double now, double err, bool walking, Cue& out, bool& superseding);
  /// A walker nearing a corner of the path (`NavInput::path`) of `corner_veer_deg` to 90 deg, its
  /// leg out 1.2 m or more, no passage before it: the veer round it asked when the arc at its speed
  /// (`veer_rate_deg`) must begin a reaction and a pulse later, if that walk (the arc ending on the
  /// leg out) sweeps the body clear; over 45 deg the rest follows as a second pair as soon as it
  /// can be felt apart. Up to 3 m of walk before that, the walk on to it (no slight veer, no
  /// short walk's stop). True and the cue.
  bool cornerVeer(const NavInput& in, double now, bool walking, Cue& out);
  /// A doorway or gap ahead (the planner's passage_*): walk straight through when the walk passes
  /// its middle within the room, else stop and face the middle (closed loop on the head's yaw).
  /// False: no passage near, ordinary steering.
  bool passageCue(const NavInput& in, double now, bool walking, Cue& out);
  /// A standing wearer before a passage but off its axis (more than passage_square_deg, seen from
  /// the middle): turned towards the point passage_stage_m before the middle on the axis, then
  /// sent there with a timed stop (true and the cue).
  bool stageForPassage(const NavInput& in, double now, Cue& out);
  /// The wearer in the last passage reported (within passage_inside_m before its middle to
  /// passage_clear_m past it): a walker along its axis walks on (a turn beyond waits; the stop
  /// before it is timed so that the body stands clear of the jambs), a standing wearer faces the
  /// axis and steps out first. False: not in a passage.
  bool throughPassage(const NavInput& in, double now, bool walking, Cue& out);
  /// A walker on the slant towards a passage whose walk crosses the passage's axis 0.35-1.5 m before
  /// its middle: walk on, then a stop timed (its reach `stop_m`) to stand on the axis.
  bool stopOnAxis(const NavInput& in, double now, double stop_m, Cue& out);
  /// Standing in a passage `lateral` m left of its axis (`axis`, rad), more than its room (half
  /// `width` less passage_body_m) plus 5 cm: a short side-step towards the middle (true and the
  /// cue, or the wait while one is carried out).
  bool centreInPassage(const NavInput& in, double now, double axis, double lateral, double width, Cue& out);
  /// Keeps the passage the planner reports (door_, prev_door_).
  void noteDoor(const NavInput& in);
  /// A go to a standing wearer with a stop timed so that it walks `room` m (it starts and stops a
  /// reaction late: the walk does not depend on the reaction), for the walks to and out of a passage.
  Cue timedGo(double now, double room, std::string reason);
  /// When to ask the stop after a go for a walk of `room` m (s after the go).
  double stopAfterGo(double room) const;
  /// How long a stop-and-turn buzz for `angle` (rad) lasts: the turn at the learnt rate after the
  /// moment it takes to tell it from a veer's pulse, at least a little longer than that, at most 2.5 s.
  double turnBuzzS(double angle) const;
  /// A stop-and-turn buzz for `angle` (rad, + = left) from the wearer's facing now; `level`
  /// (its strength, 1..3) from the angle when 0.
  Cue startTurn(const NavInput& in, double now, double angle, const char* why, int level = 0);
  /// One shoulder motor at the level's intensity, and the state that watches the veer or turn asked.
  std::array<float, NUM_MOTORS> beginShoulderCue(const NavInput& in, double now, int side, int level, double angle,
                                                 bool turn);
  /// A "go" to a standing wearer with little floor ahead: the stop timed from the go (true and
  /// the stop cue while it is due).
  bool shortWalk(const NavInput& in, double now, Cue& out);
  /// A new steering decision: walk on, a veer (walking) or a stop-and-turn.
  /// A standing wearer's walk along its facing would sweep the body into an edge within
  /// `go_clear_m`, and facing the steering point sweeps clear for longer.
  bool goMeetsEdge(const NavInput& in) const;
  /// A standing wearer's walk once told to go, for the sweep (its start, its pace).
  WalkModel goWalk(double horizon_s) const;
  /// A short side-step begun at `since` is still being carried out (its buzz and a reaction).
  bool sideStepUnderWay(double since, double now) const;
  /// A short side-step (kCentreBuzzS on one waist motor; + = left).
  Cue shortSideStep(int side, double now, std::string reason);
  /// A standing wearer a hand's breadth beside an edge side-steps away before the go (`go_side_m`).
  bool stepClearOfEdge(const NavInput& in, double now, Cue& out);
  Cue askSteer(const NavInput& in, double now, double err, double ask, bool walking);
  /// A veer burst: two short pulses on one shoulder (`side` +1 left) at `level`, asking level x
  /// `veer_step_deg`; the veer is watched from now on (a chain's when `chain_next_`).
  Cue veerPair(const NavInput& in, double now, int side, int level, std::string reason);
  /// A new pattern on the given motors (a new pattern id).
  Cue startPattern(CueMode mode, Instruction ins, int level, std::array<float, NUM_MOTORS> drive, uint8_t on_10ms,
                   uint8_t off_10ms, uint8_t count, double now, std::string reason);
  /// The pattern being played again (same id: the vest continues it).
  Cue holdPattern(std::string reason) const;
  /// A `NO_POSE` that has lasted `lost_turn_after_s` on fresh input: a turn on the spot (open loop:
  /// a lost pose carries no heading) so that the camera looks away from the blank view it lost
  /// itself on (true and the cue, also while its buzz plays).
  bool lookElsewhere(double now, const std::string& why, Cue& out);
  /// UNSURE with its opening pattern when it starts, silence after.
  Cue unsureCue(std::string reason, double now);
  /// A steady cue (side-step, stop): the running pattern when it drives the same motors, else new.
  Cue steady(CueMode mode, Instruction ins, const std::array<float, NUM_MOTORS>& drive, double now, std::string reason);
  bool steadyHeld(CueMode mode, Instruction ins, const std::array<float, NUM_MOTORS>& drive) const;
  /// A planned stop on all four (the predictive, timed and doorway stops): steady ALERT, and
  /// nothing being watched any more.
  Cue stopAll(double now, std::string reason);
  /// An ALERT / PROXIMITY decision (mode, intensities, reason) as its steady pattern.
  Cue shapeSteady(const Cue& c, double now);
  /// The wearer's reaction time now: learnt, clamped to [0.3, 1.5] s, or `alert_reaction_s`.
  double reactionEstimate() const;
  /// How quickly this wearer speeds up from standing and stops from walking (m/s^2): learnt from
  /// its starts and its stops on all four (clamped to [0.3, 3] and [0.5, 5]), or `start_accel` /
  /// `stop_decel` until the first.
  double startAccelEstimate() const;
  double stopDecelEstimate() const;
  /// Learns the reaction and the start's acceleration from a standing wearer's start after a go.
  void observeStart(const NavInput& in, double now);
  /// Learns the stop's deceleration from a walking wearer's stop on all four.
  void observeStop(const NavInput& in, double now);
  /// Learns the wearer's pace: its walking speed once steady for a second.
  void observePace(const NavInput& in, double now);
  /// How far a wearer walking at `v` goes before it stands when told to stop now: its reaction
  /// `tau` (still speeding up, at its learnt start, towards its pace, while the last pattern asked
  /// it to walk), then its stop.
  double stopReach(double v, double tau) const;
  /// Learns the walk's drift (rad/m) from the walk heading while no cued turn is under way.
  void observeDrift(const NavInput& in, double now, bool walking);
  /// The steering error expected when a veer asked now is carried out: the walk drifts on during
  /// the wearer's reaction (and the walk chord's lag), and `drift_aim_s` beyond it.
  double predictedError(double err, double v) const;
  /// The walk the wearer is committed to now (issue 33): its speed (speeding up towards its pace
  /// while told to walk), the veer it is carrying out (what is left of it, from when it will
  /// start), its stop beginning `stop_in_s` from now; from its learnt reaction, start, stop, pace
  /// and veer gain.
  WalkModel committedWalk(const NavInput& in, double now, double stop_in_s) const;
  /// The reaction the sweep assumes: the learnt one, else the population's slow end (1.2 s).
  double sweepReaction() const;
  /// Status OK: the obstacle cues (stop, side-step), or the guidance where steering away wins over
  /// them or a standing wearer is boxed in; the crossing cue over either.
  Cue decideOk(const NavInput& in, double now);
  /// A predictive stop asked before is held while the wearer still walks (true and the cue).
  bool holdSweepStop(const NavInput& in, Cue& out);
  /// The planner's grid came with the state and the sweep is on.
  bool sweepReady(const NavInput& in) const;
  /// The walk committed to a veer of `turn` (rad, + = left; 0 = walking on) asked now, until it is
  /// carried out, then stopped by a stop asked then.
  WalkModel veerWalk(const NavInput& in, double now, double turn) const;
  /// The walk (m) that sweeps the body clear after a turn of `angle` (rad) asked now, with the turn
  /// off by `turn_go_spread` either side (+inf: clear; 0: no grid). At least `turn_go_clear_m`: the
  /// walk-on follows the turn at once.
  double turnGoRoom(const NavInput& in, double angle) const;
  /// When the stop after the last go is due (s), given the free distance ahead (the ray) and the
  /// room its walk sweeps clear (m): a short walk gets a stop timed from the go; -1: none.
  double shortWalkStopAt(double free_ahead, double room) const;
  /// The body stands between two jambs (obstacle cells close on both sides across the walk) or
  /// within `passage_inside_m` of a passage's middle.
  bool inDoorway(const NavInput& in) const;
  /// The body's disc swept along `m` from where the wearer stands, heading its body's facing.
  SweepResult sweep(const NavInput& in, const WalkModel& m) const;
  /// The predictive stop: a walker whose committed walk, stopped by a stop asked one cycle from now,
  /// sweeps the body into an obstacle of the planner's grid is stopped now (true and the cue).
  bool sweepStop(const NavInput& in, double now, Cue& out);
  /// "Clear, walk on": a tick when one is due, else the running pattern (it has ended).
  Cue walkOn(std::string reason, double now, bool standing);
  /// The crossing cue over `base` (the obstacle / guidance cue of a fresh OK state).
  Cue overlayCrossing(const NavInput& in, const Cue& base, double now);
  void clearCrossing();

  CueParams params_;
  CueMode last_mode_ = CueMode::UNSURE;
  int waist_side_ = 0;  ///< +1 left waist, -1 right, 0 none
  /// The side-steps begun lately (time, side, the waypoint's distance then), and until when a
  /// standing wearer stepping left and right in turn is steered instead (sideStepsDither).
  struct SideStepBegun
  {
    double t;
    int side;
    double waypoint_distance;
  };
  std::deque<SideStepBegun> side_steps_;
  double dither_steer_until_ = -1e300;
  /// A standing wearer's side-steps have gone left and right in turn without bringing it nearer its
  /// waypoint: true while it is steered (turned towards the way on) instead.
  bool sideStepsDither(const NavInput& in, double now);
  /// A side-step to `side` (+1 left, -1 right) asked now is a new one, not the last one going on.
  bool sideStepBegins(int side, double now) const;
  /// Notes a side-step cue `c` given now (its side, when it began).
  void noteSideStep(const Cue& c, const NavInput& in, double now);
  // the crossing cue being held
  CrossingAdvice cross_ = CrossingAdvice::NONE;
  double cross_since_ = 0.0;      ///< when the held advice (this side / stop) was raised
  double cross_seen_ = 0.0;       ///< when the planner last advised it
  double cross_time_ = 0.0;       ///< its time to the closest approach then
  // guidance while walking: the burst being executed and the walk's yaw when it started
  Cue current_;                 ///< the pattern last started
  uint8_t next_id_ = 1;
  double last_tick_ = -1e300;   ///< when the last pattern (a tick or any other) started
  bool busy_ = false;           ///< a veer / turn burst is being executed
  double busy_since_ = 0.0;
  double busy_yaw0_ = 0.0;      ///< walk heading when it started (a veer is judged on the walk)
  double busy_head0_ = 0.0;     ///< head yaw when it started (a turn on the spot is judged on the head)
  double turn_from_ = 0.0;      ///< the body's facing when a stop-and-turn buzz began (its turning rate is learnt)
  double busy_angle_ = 0.0;     ///< signed angle asked for (rad, + = left)
  bool busy_turn_ = false;      ///< a stop-and-turn (else a veer)
  double turn_buzz_s_ = 0.0;    ///< its buzz's length (s)
  /// The stop-and-turn is followed by the walk-on at once (its new way sweeps clear, `turnGoRoom`),
  /// and whether that tick has been given.
  bool turn_go_ = false;
  bool turn_go_sent_ = false;
  double turn_go_room_ = 0.0;  ///< m, turnGoRoom when it was asked
  double turn_go_start_until_ = -1e300;  ///< the wearer walking on after such a turn is starting until then
  double turn_peak_rate_ = 0.0;  ///< rad/s, the fastest head turn seen in this turn
  /// The veer being carried out was seen in the head's turn rate (the wearer's response), and when.
  bool veer_seen_ = false;
  double veer_seen_at_ = 0.0;
  double steady_since_ = -1e300;  ///< the head's turn rate has been under 10 deg/s since
  double walked_m_ = 0.0;        ///< metres walked (the planner's speed integrated), for the drift
  double busy_walked0_ = 0.0;    ///< walked_m_ when the veer began
  /// A veer chain (issue 33): a burst asked beyond a veer still being carried out adds to it (the
  /// protocol's "a second pair before you are done adds to the first"). The chain keeps its
  /// origin (busy_yaw0_, busy_head0_, busy_since_) and sums the bursts in busy_angle_; the last
  /// burst began at burst_at_, and the next may only begin once the wearer can feel it as a new
  /// pair (kVeerChainGapS after it).
  double burst_at_ = -1e300;
  bool chain_next_ = false;     ///< the next veer burst of this cycle adds to the chain
  /// A veer's two pulses last 0.45 s; a pulse beginning within 0.4 s of the last one's end on the
  /// same shoulder is felt as part of the same pair, so the next burst begins 0.85 s after the
  /// last began at the earliest (0.95: two 20 Hz cycles' margin).
  static constexpr double kVeerChainGapS = 0.95;
  /// A corner veer (cornerVeer) is being carried out, and what it still has to ask (rad, asked,
  /// + = left) in its next pair.
  bool corner_veer_ = false;
  double corner_rest_ = 0.0;
  /// The wearer's veers: turned / asked (learnt from the veers it carried out, the drift taken
  /// out; kept across resets: it is the wearer's). Each ask picks the level whose veer, at this
  /// gain, comes closest to the error.
  double veer_gain_est_ = 1.0;
  /// The walk's own drift (rad per metre walked, + = left): veering of a walker without sight,
  /// learnt from the walk between cues (kept across resets: it is the wearer's).
  double drift_per_m_ = 0.0;
  double drift_heading_ = 0.0, drift_time_ = -1e300;  ///< the walk heading last sampled for it
  double quiet_since_ = -1e300;  ///< the walk has been free of cued turns since (s)
  /// The wearer's reaction time (s), learnt from its starts after a walk-on tick (kept across
  /// resets: it is the wearer's, not the situation's); `alert_reaction_s` until the first.
  double reaction_est_ = 0.0;
  bool have_reaction_ = false;
  double start_tick_ = -1.0;   ///< the "go" tick to a standing wearer being timed (< 0: none)
  double start_lo_t_ = -1.0;   ///< when its walk's speed rose through the start's low mark (< 0: not yet)
  bool speeding_up_ = false;  ///< the walk's speed rose since the last cycle
  double prev_speed_ = 0.0, prev_speed_t_ = -1e300;  ///< the last cycle's walking speed, for crossings
  /// The wearer's start and stop (m/s^2), learnt (kept across resets: they are the wearer's).
  double accel_est_ = 0.0, decel_est_ = 0.0;
  bool have_accel_ = false, have_decel_ = false;
  double stop_v0_ = -1.0;      ///< the stop on all four being timed: the speed it began at (0: no sample; < 0: none)
  double stop_hi_t_ = -1.0;    ///< when its speed fell through the stop's high mark (< 0: not yet)
  double stop_low_v_ = 0.0;    ///< the lowest speed since then (a rise beyond it: the fall was broken)
  /// The wearer's pace (m/s): its walking speed once steady for a second (kept across resets);
  /// 1.4 m/s, the fast end of preferred speeds, until then.
  double pace_est_ = 0.0;
  bool have_pace_ = false;
  double steady_speed_since_ = -1e300;  ///< the walking speed has changed by under 0.03 m/s a cycle since
  /// The wearer's turning rate on the spot (rad/s), learnt from its turns (kept across resets:
  /// it is the wearer's, not the situation's); 90 deg/s until the first turn.
  double turn_rate_est_ = M_PI / 2.0;
  double last_yaw_ = 0.0, last_yaw_time_ = -1e300;  ///< for the turn rate
  double yaw_rate_ = 0.0;       ///< rad/s, smoothed
  double sidestep_at_ = -1e300;  ///< a side-step was last cued (started or held) then
  double passage_go_ = -1e300;   ///< when a standing wearer facing a passage was told to go
  /// The last passage the planner reported: its middle, axis and width (in the grid's frame).
  struct Door
  {
    bool valid = false;
    double x = 0.0, y = 0.0, axis = 0.0, width = 0.0;
  };
  Door door_, prev_door_;  ///< the last one and the one before it (a second doorway just beyond)
  /// The passage `d` is an aisle, not a doorway: 0.8 m on along `axis` from the wearer it is
  /// still about as narrow (under its width plus 0.3 m, each side counted up to 1 m).
  bool aisleAhead(const NavInput& in, const Door& d, double axis) const;
  /// A go towards a passage's axis or out of it is being walked (its stop timed from the go).
  bool stage_walk_ = false;
  /// The last side-step away from a jamb began then; each buzzes this long (about 0.1 m).
  double centre_at_ = -1e300;
  double edge_step_at_ = -1e300;  ///< a side-step away from an edge before a go began then
  int edge_steps_ = 0;            ///< such side-steps since the last go
  static constexpr double kCentreBuzzS = 0.35;
  /// The body's yaw (rad), estimated from the head (bodyYaw): the head's fast turns (a turn on the
  /// spot, a veer) carried at once, its slow motion (the scan, +-8 deg over seconds) filtered out
  /// towards the walk chord while walking and towards the head's mean while standing.
  double body_yaw_ = 0.0;
  bool have_body_yaw_ = false;
  double gyro_bias_ = 0.0;        ///< the vest gyro's bias (rad/s), learnt while standing still
  bool gyro_ = false;             ///< the last state came with the vest gyro's rate
  double body_rate_ = 0.0;        ///< the vest gyro's rate less its bias, smoothed (rad/s)
  double busy_body0_ = 0.0;       ///< the body's facing when the current veer or turn began
  bool sweep_stop_ = false;         ///< a predictive stop is held until the wearer stands
  double go_at_ = -1e300;          ///< when a standing wearer was last told to go
  double go_handled_ = -1e300;     ///< the go whose short walk was judged
  double short_stop_at_ = -1.0;    ///< a timed stop after that go is due then (< 0: none)
  double body_turned_at_ = -1e300;  ///< the head last turned fast (a turn or veer of the body)
  double body_turned_sign_ = 0.0;   ///< its way then (+1 left), the vest's gyro only
  /// The current loss began then (the first fresh `NO_POSE`; it lasts until the planner guides
  /// again; < 0: none), the look-elsewhere turns asked in it, and when the last one's buzz ends.
  double no_pose_since_ = -1.0;
  int lost_turns_ = 0;
  double lost_turn_end_ = -1e300;
  int lost_turn_side_ = 1;         ///< + left: the way the look-elsewhere turns go
  double ok_facing_ = 0.0;          ///< the body's facing at the last OK state
  /// The last stop-and-turn the wearer was sent began then, from this facing (the pattern's id).
  double last_turn_at_ = -1e300, last_turn_from_ = 0.0;
  uint8_t sent_turn_id_ = 0;
  double last_state_time_ = -1e300;
  double last_source_time_ = std::numeric_limits<double>::quiet_NaN();
  bool have_state_ = false;
};

}  // namespace assistive_tactile
