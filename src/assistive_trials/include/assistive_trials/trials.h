#pragma once
// Closed-loop mobility trials (issue 19; seed 5.4-5.5): a simulated wearer walks a world's course
// on the vest's cues (or with a cane) from a randomised start; collisions by obstacle kind,
// completion, time, percentage of preferred walking speed (PPWS, seed 5.5.2.2) against a
// sighted-guide walk from the same start, clearance, and the path for the heat maps.
// `truth` mode feeds the world's occupancy to the real planner and cue logic cores (no ROS).
// ROS-free.
#include <array>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <assistive_planner/params.h>
#include <assistive_sim/motion.h>
#include <assistive_sim/people_give_way.h>
#include <assistive_trials/wearer.h>
#include <assistive_tactile/params.h>

namespace assistive_trials
{
enum class TrialMode
{
  TRUTH,  ///< ground-truth occupancy -> planner core -> cue logic core -> vest wearer
  CANE,   ///< cane-only walker
  VISION, ///< renderer -> the whole pipeline (ROS, one nodelet manager) -> vest wearer (a CueChain)
  FLOOR   ///< no cues: the fastest the drawn wearer's body walks the guide's path (wearerFloor)
};

/// What the chain told the vest for one camera frame.
struct ChainCue
{
  std::array<float, 4> motors{ { 0.f, 0.f, 0.f, 0.f } };  ///< drive while the pattern is on
  /// How the vest pulses them (vest_protocol.h); a new id restarts the pattern. Default: steady.
  uint8_t pattern_id = 0;
  int pulse_on_ms = 0, pulse_off_ms = 0, pulse_count = 0;
  int instruction = 0;      ///< assistive_tactile::Instruction
  int level = 0;
  int mode = 4;             ///< assistive_common::CueMode (4 = UNSURE)
  /// The planner's status behind it (assistive_common::NavStatus; -1: the chain has none yet), so
  /// an unsure cue is told from a lost pose or an unmapped map.
  int planner_status = -1;
  bool received = true;     ///< false: no cue came for this frame (the vest keeps what it had)
  double latency_ms = -1.0; ///< camera image stamp -> cue (or serial write), wall ms; < 0 = not measured
  /// The planner's steering heading behind it (rad; NaN when the chain does not know it), for the
  /// timeline's heading error.
  double steer_heading = std::numeric_limits<double>::quiet_NaN();
  /// The cue came from the doorway routine (stop short, face the middle, go) (truth chain only).
  bool passage_routine = false;
};

/// One planner/cue cycle of a trial, for the timeline plot.
struct TimelineSample
{
  double t = 0.0;
  int mode = 4;            ///< CueMode
  int instruction = 0;     ///< assistive_tactile::Instruction
  int level = 0;
  float drive = 0.f;       ///< the strongest motor's drive now (what the vest does: 0 between pulses)
  double speed = 0.0;      ///< the wearer's walking speed (m/s)
  double heading_error_deg = 0.0;  ///< body yaw - steering heading (NaN: unknown)
  bool passage_routine = false;    ///< the cue came from the doorway routine
};

/// Why a collision happened, judged from what the wearer was doing and where (`--causes`):
/// `door_walk` walking or veering within `kDoorNearM` of a doorway's or gap's middle the planner
/// found (a jamb while passing), `door_turn` turning, standing or feeling around there,
/// `turn_spot` turning on the spot or standing elsewhere, `walk_wall` walking or veering into a
/// wall or glass elsewhere (a veer not corrected in time), `walk_object` walking or veering into
/// furniture or an object elsewhere, `sidestep`, `explore` feeling around after a bump, `people`,
/// `stop_late` stopping or turning anywhere while still moving at `kBrakingMps` or more: the stop
/// came too late for this wearer (counted as turning or standing before, which hid that most
/// collisions "while stopped" happen at 0.4-0.9 m/s).
enum class CollisionCause
{
  DOOR_WALK,
  DOOR_TURN,
  TURN_SPOT,
  WALK_WALL,
  WALK_OBJECT,
  SIDESTEP,
  EXPLORE,
  PEOPLE,
  STOP_LATE,
  NUM_CAUSES
};
const char* collisionCauseName(CollisionCause c);
/// A collision this close (m) to a passage middle counts as at the doorway.
constexpr double kDoorNearM = 1.0;
/// Stopping or turning at this speed (m/s) or more, the wearer is still braking (`stop_late`).
constexpr double kBrakingMps = 0.2;
/// `action`: VestWearer::Action before the step that collided; `kind`: ObstacleKind;
/// `door_m`: distance to the nearest passage middle seen (+inf: none); `speed`: the wearer's
/// walking speed before the step (m/s).
CollisionCause classifyCollision(int action, int kind, double door_m, double speed);

/// One collision of a trial, for `--causes`.
struct CollisionEvent
{
  double t = 0.0;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  int kind = 0;         ///< assistive_sim::ObstacleKind
  int action = 0;       ///< VestWearer::Action before the step
  int instruction = 0;  ///< the cue playing (assistive_tactile::Instruction)
  double door_m = std::numeric_limits<double>::infinity();
  double speed = 0.0;   ///< the wearer's speed before the step (m/s)
  CollisionCause cause = CollisionCause::WALK_WALL;
};

/// The perception -> planner -> cue chain a trial drives one camera frame at a time. Truth mode
/// uses the planner and cue logic cores in process; the ROS chains (`mobility_chain` rostest,
/// `--mode vision`) run the nodelets and are lock-stepped: `frame` returns once the cue for that
/// frame came back.
class CueChain
{
public:
  virtual ~CueChain() = default;
  /// A new trial starts with the wearer at `start` (the chain forgets the last trial).
  virtual void reset(const BodyState& start) { (void)start; }
  /// The experimenter's next place (the system's explicit goal), world frame.
  virtual void setGoal(const Eigen::Vector2d& goal) = 0;
  /// The place after it on the route (none: the goal is the last). The ROS chains ignore it.
  virtual void setNextGoal(const Eigen::Vector2d* next) { (void)next; }
  /// The trial's people: `world`'s (the trial's own copy when people give way: their tracks grow as
  /// the trial runs), valid until the trial ends. The ROS chains publish them (the truth grid's
  /// movers, the renderer's give-way topic).
  virtual void setPeople(const assistive_sim::World& world) { (void)world; }
  /// The camera frame at trial time `t` (s) with the wearer in state `s`.
  virtual ChainCue frame(double t, const BodyState& s) = 0;
  /// The wearer's state after every body step (t = the step's end): the vision chain's IMU.
  virtual void observe(double t, const BodyState& s)
  {
    (void)t;
    (void)s;
  }
  /// True once the chain has stopped answering (a vision pipeline whose nodelet manager died): the
  /// trial cannot go on, and runTrial throws rather than walk on without cues for hours.
  virtual bool stopped() const { return false; }
  /// Distance from `xy` to the nearest doorway or gap middle the planner has found so far in this
  /// trial (+inf: none, or the chain does not know).
  virtual double passageDistance(const Eigen::Vector2d& xy) const
  {
    (void)xy;
    return std::numeric_limits<double>::infinity();
  }
};

struct TrialOptions
{
  TrialMode mode = TrialMode::TRUTH;
  WearerParams wearer;
  CaneParams cane;
  assistive_planner::PlannerParams planner;
  assistive_tactile::CueParams cues;
  double rate_hz = 15.0;        ///< planner + cue rate (the camera's frame rate)
  double dt = 1.0 / 60.0;       ///< s, body simulation step
  double start_jitter_m = 0.3;  ///< start position: uniform in this radius around the course's start
  double start_yaw_deg = 20.0;  ///< start heading: +- this around the way to the first place
  /// finite: no random start; the course's start exactly, this many deg (+ = left) off the way to
  /// the first place (the rostest's fixed start)
  double fixed_start_yaw_deg = std::numeric_limits<double>::quiet_NaN();
  double goal_radius_m = 1.0;   ///< a place of the route counts as reached this close
  double timeout_factor = 4.0;  ///< a trial ends unfinished after this x the sighted guide's time (+ 20 s)
  /// false: the cue stage is removed from the chain: the vest only ticks "walk on" every
  /// tick period by itself (the negative control; a silent vest would only stop the wearer)
  bool cues_enabled = true;
  /// Each trial's wearer drawn from the wearer population (wearer_population.h) with the trial's
  /// seed; false: `wearer` as given for every trial.
  bool population = true;
  /// Draw this trial's wearer from the slowest-reacting 10 % of the population (the targets'
  /// "worst 10 % of wearers").
  bool slowest_decile = false;
  /// Analysis only (which trait costs what): drawn traits replaced by these when finite / > 0.
  double fix_reaction_s = std::numeric_limits<double>::quiet_NaN();
  double fix_turn_gain = std::numeric_limits<double>::quiet_NaN();
  double fix_veer_sigma = std::numeric_limits<double>::quiet_NaN();
  double fix_veer_bias = std::numeric_limits<double>::quiet_NaN();
  int fix_levels = 0;
  /// Analysis only: the planner's `steer_lead_s` set per trial from the drawn wearer's TRUE
  /// reaction plus a veer's first pulse (`kVeerPulseS`), not from anything the system measured.
  bool lead_from_true_reaction = false;
  /// The vest carries a gyro (truth and vision mode): the cue logic is given the torso's yaw rate
  /// (the body's turn over each cycle), so its facing needs no filtering of the head's scan. Its
  /// errors are the head IMU's (the gyro's of assistive_sim::ImuParams: white noise, a bias drawn
  /// per trial that walks); all zero: a perfect gyro (analysis).
  bool vest_gyro = false;
  assistive_sim::ImuParams vest_gyro_errors;
  /// Truth mode: the cell of the perfect map handed to the planner (m). 0.2 = the obstacle stage's
  /// `cell_size`; finer cells place a doorway's jambs finer (analysis of what a finer map is worth).
  double truth_grid_resolution = 0.2;
  /// A scripted UNSURE episode (the chain reports no pose) from this trial time on (NaN: none),
  /// for `unsure_for_s` seconds: truth mode only.
  double unsure_at_s = std::numeric_limits<double>::quiet_NaN();
  double unsure_for_s = 3.0;
  /// People step aside for the wearer as walkers do (assistive_sim/people_give_way.h, issue 37), in
  /// every mode (vision: the renderer is sent their tracks); false: they walk their scripts through
  /// the wearer (before).
  bool people_give_way = true;
  assistive_sim::GiveWayParams give_way;
};

/// The vest's own IMU as the trials simulate it (`TrialOptions::vest_gyro`), upright on the torso.
/// Its yaw rate: the mean over the interval since the last call (the body's turn over its time,
/// the gyro integrated between the calls), plus a bias drawn per trial that walks, plus white
/// noise. Its specific force: gravity, and while the wearer steps (walking, or turning on the spot,
/// which takes steps) the gait's vertical swing at the step rate (`kStepHz`, `kGaitAccelRms`), plus
/// standing sway and the sensor's noise (`kStillAccelSd`): what tells the vest standing from stepping.
class VestGyroSim
{
public:
  /// the gait's vertical trunk acceleration, RMS (m/s^2): trunk accelerometry at the preferred pace
  /// reads metres per s^2 (Sekine et al. 2013, J NeuroEng Rehabil 10:118, lower back); the low end
  static constexpr double kGaitAccelRms = 1.5;
  static constexpr double kStepHz = 1.8;        ///< steps/s (about 110 a minute, an adult's cadence)
  static constexpr double kStillAccelSd = 0.03; ///< m/s^2 per axis: quiet standing's sway and the sensor
  static constexpr double kStepTurnRate = 0.1;  ///< rad/s: turning faster than this on the spot is stepping

  struct Sample
  {
    double rate_z = 0.0;               ///< rad/s about the vest's z (the vertical)
    Eigen::Vector3d accel{ 0.0, 0.0, 9.81 };  ///< m/s^2, the vest's frame
  };
  /// `trial_seed`: the trial's (its own stream is drawn from it)
  VestGyroSim(const assistive_sim::ImuParams& errors, uint32_t trial_seed);
  /// The sample at time t with the body in `s`; the rate is 0 at the first call (no interval yet)
  Sample sample(double t, const BodyState& s);

private:
  double noise_density_, bias_walk_;
  std::mt19937 rng_;
  double bias_ = 0.0;
  double last_yaw_ = std::numeric_limits<double>::quiet_NaN(), last_t_ = -1e300;
};

struct TrialResult
{
  int index = 0;
  uint32_t seed = 0;
  BodyState start;
  bool completed = false;
  double time_s = 0.0;        ///< to completion (or the timeout)
  double guide_time_s = 0.0;  ///< sighted guide from the same start
  WalkFloor floor;            ///< mode FLOOR: what the time is made of
  bool people_give_way = false;  ///< the world's people stepped aside for the wearer
  int give_way_episodes = 0;  ///< times a person began to step aside for the wearer
  /// The trial's people as they walked (their give-way tracks; empty when they kept their scripts).
  std::vector<assistive_sim::Person> people;
  double ppws_pct = 0.0;      ///< guide time / time x 100 (0 when not completed)
  std::array<int, size_t(assistive_sim::ObstacleKind::NUM_KINDS)> collisions{};
  int totalCollisions() const;
  double mean_clearance_m = 0.0;  ///< body surface to the nearest obstacle, mean over the walk
  double min_clearance_m = 0.0;
  double min_person_clearance_m = 0.0;  ///< body surface to the nearest person's, over the walk (+inf: no people)
  std::array<int, 5> cue_modes{};  ///< planner/cue cycles per CueMode (IDLE .. UNSURE)
  /// The UNSURE ones per planner status (NavStatus OK .. NO_WAYPOINT, then none known).
  std::array<int, 7> unsure_by_status{};
  /// Where the wearer's time went (truth and vision modes): seconds per VestWearer::Action
  /// (walk, turn on the spot, side-step, feel around, stand, veer), summing to `time_s`.
  std::array<double, 6> action_s{};
  /// The standing part of it (action_s[STOPPED]) by what the wearer stands for: a turn on the spot
  /// asked and not yet begun (the buzz felt a reaction late, the walk stopped first), the go after
  /// a turn on the spot, any other stand (a stop, the start, a side-step's end).
  enum Standing { BEFORE_TURN, AFTER_TURN, OTHER_STAND };
  std::array<double, 3> standing_s{};
  /// Cue patterns the vest began, per assistive_tactile::Instruction (NONE .. UNSURE), and the
  /// stop-and-turn buzzes of them that the doorway routine asked.
  std::array<int, 7> cues_begun{};
  int doorway_turns = 0;
  std::vector<double> latency_ms;  ///< per frame, when the chain measures it
  int missed_cues = 0;             ///< frames whose cue never came (ROS chains)
  std::vector<Eigen::Vector2d> path;      ///< body positions, one per body step
  std::vector<Eigen::Vector2d> collision_places;
  WearerParams wearer;                     ///< who walked (drawn from the population, or as given)
  std::vector<TimelineSample> timeline;    ///< one per planner/cue cycle
  /// With a scripted UNSURE episode: metres walked from its start until the body stood still
  /// (or the episode ended); NaN without one.
  double unsure_walked_m = std::numeric_limits<double>::quiet_NaN();
  std::vector<CollisionEvent> collision_events;  ///< each collision, with its cause
  /// A trial not completed: why (`stuck_door`, `stuck`, `slow`: progress over its last 20 s and
  /// whether it stood near a doorway), and the cue that dominated its last 20 s.
  std::string end_cause;
  std::string end_detail;
};

/// The unfinished trial's cause (fills end_cause / end_detail) from its path, timeline and the
/// distance of its end to a passage middle.
void classifyEnd(TrialResult& r, double dt, double door_m);

/// The wearer of trial `seed` under `opt` (population draw, slowest decile, or opt.wearer), its
/// eye height and cruise speed for the sighted guide kept from `opt.wearer` unless drawn.
WearerParams trialWearer(const TrialOptions& opt, uint32_t seed);

/// The cue timeline of one trial (cue and drive, walking speed, heading error over time) as an
/// image: why a trial was slow is seen there.
cv::Mat timelinePlot(const TrialResult& r, const std::string& title);

/// The course of a world: its script's waypoints (start, then the places to walk through).
std::vector<Eigen::Vector2d> courseOf(const assistive_sim::World& world);

/// One trial, deterministic in `seed` (start pose, the wearer's choices). `chain`: the chain that
/// cues the wearer (nullptr: truth mode's in-process cores; required for VISION).
TrialResult runTrial(const assistive_sim::World& world, const TrialOptions& opt, uint32_t seed, int index = 0,
                     CueChain* chain = nullptr);

/// The start pose of trial `seed` (what runTrial uses): near the course's start, facing the first
/// place within +-start_yaw_deg.
BodyState trialStart(const assistive_sim::World& world, const TrialOptions& opt, uint32_t seed);

/// Heat map in the style of the seed's figures 5.9 / 5.21: the floor plan from above (obstacles
/// grey, glass blue), time spent per place in red (brighter = longer, summed over the trials),
/// collisions as yellow crosses, the course's places as green dots. `px_per_m` sets the scale.
cv::Mat heatMap(const assistive_sim::World& world, const std::vector<TrialResult>& trials, double dt, const std::string& title,
                double px_per_m = 40.0);

}  // namespace assistive_trials
