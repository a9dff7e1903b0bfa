// Closed-loop mobility trials (trials.h): truth mode (world occupancy -> planner core -> cue logic
// core -> vest wearer) and the cane-only baseline; the heat map.
#include <assistive_trials/trials.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <stdexcept>

#include <opencv2/imgproc.hpp>
#include <opencv2/imgcodecs.hpp>

#include <assistive_planner/planner.h>
#include <assistive_tactile/cue_logic.h>
#include <assistive_tactile/vest_gyro.h>
#include <assistive_tactile/vest_protocol.h>
#include <assistive_trials/wearer_population.h>

namespace assistive_trials
{
// The simulator's world and body (assistive_sim), named as the trials always did.
using assistive_sim::BodyCollider;
using assistive_sim::OccupancyGrid;
using assistive_sim::OccupancyParams;
using assistive_sim::PersonState;
using assistive_sim::Solid;
using assistive_sim::World;
using assistive_sim::computeOccupancy;

namespace
{
constexpr double DEG = M_PI / 180.0;

assistive_planner::Grid toPlannerGrid(const OccupancyGrid& g)
{
  assistive_planner::Grid out;
  out.width = g.width;
  out.height = g.height;
  out.resolution = g.resolution;
  out.origin_x = g.origin_x;
  out.origin_y = g.origin_y;
  out.data = g.data;
  return out;
}

/// Random start near the course's start, facing roughly the first place, not touching anything.
BodyState randomStart(const World& world, const TrialOptions& opt, const BodyCollider& body, std::mt19937& rng)
{
  const std::vector<Eigen::Vector2d> c = courseOf(world);
  const Eigen::Vector2d a = c.front(), b = c.size() > 1 ? c[1] : c.front() + Eigen::Vector2d(1, 0);
  const double yaw0 = std::atan2(b.y() - a.y(), b.x() - a.x());
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  BodyState s;
  if (std::isfinite(opt.fixed_start_yaw_deg))
  {
    s.xy = a;
    s.yaw = yaw0 + opt.fixed_start_yaw_deg * DEG;
    s.head_yaw = s.yaw;
    return s;
  }
  for (int tries = 0; tries < 200; ++tries)
  {
    const double r = opt.start_jitter_m * std::sqrt(std::abs(u(rng))), th = M_PI * u(rng);
    s.xy = a + r * Eigen::Vector2d(std::cos(th), std::sin(th));
    s.yaw = yaw0 + opt.start_yaw_deg * DEG * u(rng);
    if (tries > 100) s.xy = a;  // the script's start is collision-free by construction
    // (nor inside a person standing there when the trial starts)
    if (body.clearance(s.xy) >= 0.05 && body.personClearance(s.xy) >= 0.05) break;
  }
  s.head_yaw = s.yaw;
  return s;
}
}  // namespace

int TrialResult::totalCollisions() const
{
  int n = 0;
  for (int c : collisions) n += c;
  return n;
}

std::vector<Eigen::Vector2d> courseOf(const World& world)
{
  std::vector<Eigen::Vector2d> c = world.trajectory.waypoints;
  if (c.empty()) c.push_back(Eigen::Vector2d::Zero());
  return c;
}

VestGyroSim::VestGyroSim(const assistive_sim::ImuParams& errors, uint32_t trial_seed)
  : noise_density_(errors.gyro_noise_density), bias_walk_(errors.gyro_bias_walk), rng_(trial_seed ^ 0x5bd1e995u)
{
  bias_ = errors.gyro_bias_initial * std::normal_distribution<double>(0.0, 1.0)(rng_);
}

VestGyroSim::Sample VestGyroSim::sample(double t, const BodyState& s)
{
  std::normal_distribution<double> n01(0.0, 1.0);
  Sample out;
  bool stepping = s.speed > 0.05;
  if (std::isfinite(last_yaw_) && t > last_t_)
  {
    const double dt = t - last_t_;
    const double turn = std::atan2(std::sin(s.yaw - last_yaw_), std::cos(s.yaw - last_yaw_)) / dt;
    bias_ += bias_walk_ * std::sqrt(dt) * n01(rng_);
    out.rate_z = turn + bias_ + noise_density_ / std::sqrt(dt) * n01(rng_);
    stepping = stepping || std::fabs(turn) > kStepTurnRate;
  }
  if (stepping)
    out.accel.z() += kGaitAccelRms * std::sqrt(2.0) * std::sin(2.0 * M_PI * kStepHz * t);
  for (int i = 0; i < 3; ++i) out.accel[i] += kStillAccelSd * n01(rng_);
  last_yaw_ = s.yaw;
  last_t_ = t;
  return out;
}

namespace
{
/// Truth mode's chain: the world's occupancy (what a perfect obstacle stage would report) to the
/// planner and cue logic cores, no ROS, no latency.
class TruthChain : public CueChain
{
public:
  TruthChain(const World& world, const TrialOptions& opt, uint32_t trial_seed)
    : world_(world), opt_(opt), planner_(opt.planner), cues_(opt.cues), vest_gyro_(opt.vest_gyro_errors, trial_seed)
  {
    OccupancyParams op;
    op.head_above_eye = 0.12;
    op.resolution = opt.truth_grid_resolution;
    grid_ = toPlannerGrid(computeOccupancy(world, op));
    trace_ = std::getenv("MOBILITY_TRIALS_TRACE") != nullptr;  // per-cycle state on stderr
  }
  void setGoal(const Eigen::Vector2d& g) override { planner_.setGoal({ g.x(), g.y() }); }
  void setNextGoal(const Eigen::Vector2d* n) override
  {
    if (n)
      planner_.setNextGoal({ n->x(), n->y() });
    else
      planner_.clearNextGoal();
  }
  void observe(double t, const BodyState& s) override
  {
    if (!opt_.vest_gyro)
      return;
    const VestGyroSim::Sample v = vest_gyro_.sample(t, s);
    vest_imu_.add(t, Eigen::Vector3d(0.0, 0.0, v.rate_z), v.accel);
  }
  ChainCue frame(double t, const BodyState& s) override
  {
    // The world's people are not in grid_ (computeOccupancy leaves movers out): a perfect tracker
    // hands the planner every person, standing ones too, exactly (the ROS truth chain publishes
    // the same on obstacles/movers).
    if (!world_.people.empty())
    {
      std::vector<assistive_planner::MoverState> movers(world_.people.size());
      for (size_t i = 0; i < world_.people.size(); ++i)
      {
        const PersonState p = personAt(world_, i, t);
        movers[i].id = int(i + 1);
        movers[i].x << p.position, p.velocity;
      }
      planner_.setMovers(t, std::move(movers));
    }
    const assistive_planner::PlanOutput out =
        planner_.update(gridWithStandingPeople(t), { s.xy.x(), s.xy.y() }, s.head_yaw, t);
    assistive_tactile::NavInput in;
    in.status = out.status;
    in.message = out.message;
    in.heading = out.heading;
    in.path_heading = out.path_heading;
    in.waypoint_distance = out.waypoint_distance;
    in.free_ahead = out.free_ahead;
    in.free_left = out.free_left;
    in.free_right = out.free_right;
    in.steer_heading = out.steer_heading;
    in.walk_heading = out.walk_heading;
    in.walking_speed = out.walking_speed;
    in.head_yaw = out.head_yaw;
    if (opt_.vest_gyro)
      in.body_yaw_rate = vest_imu_.take(t);  // as the cue logic nodelet takes /vest/imu
    in.free_steer = out.free_steer;
    in.x = s.xy.x();
    in.y = s.xy.y();
    in.grid = out.grid;  // the planner's grid (planner/grid over ROS)
    for (const auto& q : assistive_planner::pathAhead(out)) in.path.push_back({ q.x, q.y });  // (path_ahead over ROS)
    const bool passage = out.status == assistive_planner::PlanStatus::OK && out.passage_distance >= 0.0;
    in.passage_distance = passage ? out.passage_distance : -1.0;  // as the state message carries it
    in.passage_heading = passage ? out.passage_heading : 0.0;
    in.passage_width = passage ? out.passage_width : 0.0;
    in.passage_x = passage ? out.passage_point.x : in.x;
    in.passage_y = passage ? out.passage_point.y : in.y;
    in.passage_axis = passage ? out.passage_axis : 0.0;
    if (passage)  // the doorways found, for the collision causes
    {
      const Eigen::Vector2d mid = s.xy + std::min(out.passage_distance, 3.0) *
                                             Eigen::Vector2d(std::cos(out.passage_heading), std::sin(out.passage_heading));
      bool known = false;
      for (const Eigen::Vector2d& m : passages_) known = known || (m - mid).norm() < 0.3;
      if (!known) passages_.push_back(mid);
    }
    in.crossing = out.crossing.advice;
    in.crossing_id = out.crossing.id;
    in.crossing_time = out.crossing.time;
    in.crossing_distance = out.crossing.distance;
    in.source_time = t;  // truth: the occupancy is current
    if (std::isfinite(opt_.unsure_at_s) && t >= opt_.unsure_at_s && t < opt_.unsure_at_s + opt_.unsure_for_s)
    {
      in.status = assistive_tactile::NavStatus::NO_POSE;  // the scripted episode: the pose is lost
      in.message = "scripted UNSURE episode";
    }
    const assistive_tactile::Cue cue = cues_.update(in, t);
    if (trace_)
      std::fprintf(stderr, "t %.2f xy %.2f %.2f yaw %.0f head %.0f | st %d wp %.2f %.2f d %.2f ph %.0f sh %.0f wh %.0f v %.2f fa %.2f fl %.2f fr %.2f | %s %s\n",
                   t, s.xy.x(), s.xy.y(), s.yaw / DEG, s.head_yaw / DEG, int(out.status), out.waypoint.x,
                   out.waypoint.y, out.waypoint_distance, out.path_heading / DEG, out.steer_heading / DEG,
                   out.walk_heading / DEG, out.walking_speed, out.free_ahead,
                   out.free_left, out.free_right, assistive_tactile::modeName(cue.mode), cue.reason.c_str());
    if (trace_ && in.passage_distance >= 0.0)
      std::fprintf(stderr, "PASSAGE t %.2f mid %.3f %.3f axis %.1f width %.2f d %.2f\n", t, in.passage_x, in.passage_y,
                   in.passage_axis / DEG, in.passage_width, in.passage_distance);
    ChainCue c;
    c.motors = cue.intensity;
    c.mode = int(cue.mode);
    c.planner_status = int(in.status);
    c.pattern_id = cue.pattern.id;
    c.pulse_on_ms = 10 * cue.pattern.on_10ms;
    c.pulse_off_ms = 10 * cue.pattern.off_10ms;
    c.pulse_count = cue.pattern.count;
    c.instruction = int(cue.instruction);
    c.level = cue.level;
    if (out.status == assistive_planner::PlanStatus::OK) c.steer_heading = out.steer_heading;
    c.passage_routine = cue.reason.find("passage") != std::string::npos;
    return c;
  }
  double passageDistance(const Eigen::Vector2d& xy) const override
  {
    double d = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector2d& m : passages_) d = std::min(d, (m - xy).norm());
    return d;
  }

private:
  /// The static grid plus every person standing still now (speed under 0.2 m/s): what the obstacle
  /// stage's map holds (a person standing still is an ordinary obstacle; walking ones are movers
  /// only). Cells whose square the body's disc overlaps become obstacles.
  const assistive_planner::Grid& gridWithStandingPeople(double t)
  {
    if (world_.people.empty()) return grid_;
    now_ = grid_;
    for (size_t i = 0; i < world_.people.size(); ++i)
    {
      const PersonState p = personAt(world_, i, t);
      if (p.velocity.norm() >= 0.2) continue;
      Solid body;  // the person's footprint, tested against cells the way computeOccupancy does
      body.shape = Solid::CYLINDER;
      body.center = p.position;
      body.radius = world_.people[i].radius;
      const double r = body.radius, h = 0.5 * now_.resolution;
      int x0, y0, x1, y1;
      now_.worldToCell(p.position.x() - r, p.position.y() - r, x0, y0);
      now_.worldToCell(p.position.x() + r, p.position.y() + r, x1, y1);
      for (int y = std::max(0, y0); y <= std::min(now_.height - 1, y1); ++y)
        for (int x = std::max(0, x0); x <= std::min(now_.width - 1, x1); ++x)
          if (body.overlapsRect(now_.cellX(x) - h, now_.cellY(y) - h, now_.cellX(x) + h, now_.cellY(y) + h))
            now_.data[size_t(now_.index(x, y))] = 100;
    }
    return now_;
  }

  const World& world_;
  assistive_planner::Grid now_;
  TrialOptions opt_;
  assistive_planner::Grid grid_;
  assistive_planner::Planner planner_;
  assistive_tactile::CueLogic cues_;
  bool trace_ = false;
  VestGyroSim vest_gyro_;
  assistive_tactile::VestGyro vest_imu_;  ///< the samples between two frames (the nodelet's adapter)
  std::vector<Eigen::Vector2d> passages_;  ///< passage middles the planner found (world frame)
};
}  // namespace

const char* collisionCauseName(CollisionCause c)
{
  static const char* names[] = { "door_walk", "door_turn", "turn_spot", "walk_wall", "walk_object", "sidestep", "explore", "people", "stop_late" };
  const size_t i = size_t(c);
  return i < sizeof(names) / sizeof(names[0]) ? names[i] : "?";
}

CollisionCause classifyCollision(int action, int kind, double door_m, double speed)
{
  if (kind == int(assistive_sim::ObstacleKind::PERSON)) return CollisionCause::PEOPLE;
  const bool moving = action == VestWearer::WALK || action == VestWearer::VEER;
  if ((action == VestWearer::STOPPED || action == VestWearer::TURN) && speed >= kBrakingMps)
    return CollisionCause::STOP_LATE;
  if (door_m < kDoorNearM) return moving ? CollisionCause::DOOR_WALK : CollisionCause::DOOR_TURN;
  if (action == VestWearer::SIDESTEP) return CollisionCause::SIDESTEP;
  if (action == VestWearer::EXPLORE) return CollisionCause::EXPLORE;
  if (!moving) return CollisionCause::TURN_SPOT;
  return kind == int(assistive_sim::ObstacleKind::FURNITURE) ? CollisionCause::WALK_OBJECT : CollisionCause::WALK_WALL;
}

void classifyEnd(TrialResult& r, double dt, double door_m)
{
  r.end_cause.clear();
  r.end_detail.clear();
  if (r.completed || r.path.empty()) return;
  const size_t back = size_t(std::lround(20.0 / std::max(1e-6, dt)));
  const Eigen::Vector2d from = r.path[r.path.size() > back ? r.path.size() - 1 - back : 0];
  const double progress = (r.path.back() - from).norm();
  std::array<int, 8> ins{};
  int n = 0, passage = 0;
  for (auto it = r.timeline.rbegin(); it != r.timeline.rend() && it->t >= r.time_s - 20.0; ++it, ++n)
  {
    ++ins[size_t(std::min(7, std::max(0, it->instruction)))];
    passage += it->passage_routine;
  }
  r.end_cause = progress >= 2.0 ? "slow" : door_m < 1.5 ? "stuck_door" : "stuck";
  static const char* names[] = { "none", "walk_on", "veer", "turn", "sidestep", "stop", "unsure", "?" };
  const size_t top = size_t(std::max_element(ins.begin(), ins.end()) - ins.begin());
  char buf[200];
  std::snprintf(buf, sizeof(buf), "last 20 s: %.1f m progress, cue %s %.0f %% (turn %.0f %%), doorway routine %.0f %%, %.1f m from a passage middle",
                progress, names[top], n ? 100.0 * ins[top] / n : 0.0, n ? 100.0 * ins[3] / n : 0.0, n ? 100.0 * passage / n : 0.0,
                door_m);
  r.end_detail = buf;
}

WearerParams trialWearer(const TrialOptions& opt, uint32_t seed)
{
  WearerParams w = opt.wearer;
  if (!opt.population) return w;
  const WearerPopulation pop;
  const uint32_t s = seed ^ 0x5bd1e995u;  // not the start's or the wearer's own random stream
  const WearerTraits tr = opt.slowest_decile ? pop.drawSlowest(s, 0.1) : pop.draw(s);
  w.walk_speed = tr.preferred_speed_mps;
  w.reaction_s = tr.reaction_s;
  w.turn_gain = tr.turn_gain;
  w.veer_sigma_deg = tr.veer_sigma_deg_per_sqrt_m;
  w.veer_bias_deg_per_m = tr.veer_bias_deg_per_m;
  w.intensity_levels = tr.intensity_levels;
  w.min_pulse_s = tr.min_pulse_s;
  w.body_radius = tr.body_radius_m;
  w.accel = tr.gait_accel_mps2;
  if (std::isfinite(opt.fix_reaction_s)) w.reaction_s = opt.fix_reaction_s;
  if (std::isfinite(opt.fix_turn_gain)) w.turn_gain = opt.fix_turn_gain;
  if (std::isfinite(opt.fix_veer_sigma)) w.veer_sigma_deg = opt.fix_veer_sigma;
  if (std::isfinite(opt.fix_veer_bias)) w.veer_bias_deg_per_m = opt.fix_veer_bias;
  if (opt.fix_levels > 0) w.intensity_levels = opt.fix_levels;
  return w;
}

BodyState trialStart(const World& world, const TrialOptions& opt, uint32_t seed)
{
  std::mt19937 rng(seed);
  BodyCollider body(world, trialWearer(opt, seed).body_radius, opt.wearer.eye_height + 0.12);
  body.setTime(0.0);
  return randomStart(world, opt, body, rng);
}

TrialResult runTrial(const World& world, const TrialOptions& opt, uint32_t seed, int index, CueChain* chain)
{
  TrialResult r;
  r.index = index;
  r.seed = seed;
  std::mt19937 rng(seed);
  const WearerParams wp = trialWearer(opt, seed);
  r.wearer = wp;
  const double body_height = wp.eye_height + 0.12;
  // People who give way (issue 37) on the trial's own copy of the world: the collider, the cane
  // and the chain (the truth planner, or the renderer sent their tracks) meet the same people aside.
  const bool giving_way = opt.people_give_way && !world.people.empty();
  World moved;
  std::unique_ptr<assistive_sim::PeopleGiveWay> give_way;
  if (giving_way)
  {
    moved = world;
    give_way = std::make_unique<assistive_sim::PeopleGiveWay>(moved, opt.give_way);
  }
  const World& trial_world = giving_way ? moved : world;
  BodyCollider body(trial_world, wp.body_radius, body_height);
  body.setTime(0.0);  // (the people where they stand when the trial starts)
  r.start = randomStart(world, opt, body, rng);
  std::vector<Eigen::Vector2d> route = courseOf(world);
  route.erase(route.begin());
  if (route.empty()) route.push_back(r.start.xy + Eigen::Vector2d(cos(r.start.yaw), sin(r.start.yaw)) * 5.0);
  // The trial ends within goal_radius of the exit: so does the guide's walk (its last metre is
  // not walked, at cruise speed).
  // (mode FLOOR: the floor walks the guide's path, whose time it gives too)
  const bool floor = opt.mode == TrialMode::FLOOR;
  const WalkFloor f = floor ? wearerFloor(world, wp, r.start, route) : WalkFloor();
  r.guide_time_s = floor ? f.guide_time_s : sightedGuideTime(world, wp, r.start.xy, route);
  if (r.guide_time_s > 0.0)
    r.guide_time_s = std::max(0.5 * r.guide_time_s, r.guide_time_s - opt.goal_radius_m / wp.walk_speed);
  const double timeout = opt.timeout_factor * std::max(r.guide_time_s, 5.0) + 20.0;
  if (floor)
  {
    // the same start, route and wearer as the trial; the same last metre left unwalked
    r.completed = f.time_s > 0.0;
    r.time_s = r.completed ? r.guide_time_s + f.start_s + f.turns_s : 0.0;
    r.ppws_pct = r.completed ? 100.0 * r.guide_time_s / r.time_s : 0.0;
    r.floor = f;
    return r;
  }

  const bool vest = opt.mode != TrialMode::CANE;
  std::unique_ptr<TruthChain> truth;
  if (vest && !chain)
  {
    if (opt.mode == TrialMode::VISION) throw std::invalid_argument("runTrial: vision mode needs a ROS chain");
    TrialOptions chain_opt = opt;
    // the oracle lead: where the walk takes this wearer by the time a veer acts (it is understood
    // when its first 0.15 s pulse ends, then felt one reaction time late)
    constexpr double kVeerPulseS = 0.15;
    if (opt.lead_from_true_reaction) chain_opt.planner.steer_lead_s = wp.reaction_s + kVeerPulseS;
    truth = std::make_unique<TruthChain>(trial_world, chain_opt, seed);
    chain = truth.get();
  }
  VestWearer wearer(wp, r.start, seed ^ 0x9e3779b9u);
  CaneWalker cane(wp, opt.cane, r.start, seed ^ 0x7f4a7c15u);

  size_t next = 0;
  if (vest)
  {
    if (!truth) chain->setPeople(trial_world);
    chain->reset(r.start);
    chain->setGoal(route[0]);
    chain->setNextGoal(route.size() > 1 ? &route[1] : nullptr);
  }
  // The vest as the firmware drives it: the last cue's pattern, from when its id first came.
  ChainCue playing;
  double playing_since = 0.0;
  auto drive = [&](double now) {
    std::array<float, 4> m{ { 0.f, 0.f, 0.f, 0.f } };
    vest_pattern_t pat{ playing.pattern_id, uint8_t(std::min(255, playing.pulse_on_ms / 10)),
                        uint8_t(std::min(255, playing.pulse_off_ms / 10)), uint8_t(playing.pulse_count) };
    if (!opt.cues_enabled)
    {
      // the cue stage removed: the vest only ticks "walk on" by itself (a silent vest would only
      // stop the wearer, which shows nothing): the negative control walks straight on
      const float k = 0.7f;
      if (std::fmod(now, opt.cues.tick_period_s) < 0.1) m = { { k, k, 0.f, 0.f } };
      return m;
    }
    if (vest_pattern_on(&pat, uint32_t(std::max(0.0, now - playing_since) * 1000.0 + 0.5)))
      m = playing.motors;
    return m;
  };
  const double period = 1.0 / opt.rate_hz;
  bool unsure_started = false, unsure_done = false;
  VestWearer::Percept last_percept = VestWearer::NOTHING;
  VestWearer::Action last_action = VestWearer::STOPPED;
  double last_turn_end = -1.0;  // when its last turn on the spot ended (-1: it walked since, or never turned)
  Eigen::Vector2d unsure_from = Eigen::Vector2d::Zero();
  double next_plan = 0.0, clear_sum = 0.0;
  r.min_clearance_m = 1e9;
  r.min_person_clearance_m = std::numeric_limits<double>::infinity();
  long steps = 0;
  const bool trace = std::getenv("MOBILITY_TRIALS_TRACE") != nullptr;
  int reported = 0;
  if (trace)
    std::fprintf(stderr, "TRIAL %d wearer reaction %.2f s accel %.2f stop %.2f m/s^2 speed %.2f radius %.2f turn_gain %.2f\n",
                 index, wp.reaction_s, wp.accel, wp.stopDecel(), wp.walk_speed, wp.body_radius, wp.turn_gain);
  double t = 0.0;
  for (; t < timeout; t += opt.dt)
  {
    const BodyState& s = vest ? wearer.state() : cane.state();
    // The people (issue 22) where they are at the end of this step: the collider counts contacts
    // with them and the cane feels them; they follow their scripts on the trial's clock, stepping
    // aside for the wearer as it walks now.
    if (give_way)
      give_way->step(t, opt.dt, s.xy, s.speed * Eigen::Vector2d(std::cos(s.yaw), std::sin(s.yaw)));
    body.setTime(t + opt.dt);
    // progress along the course: the experimenter's route (the system's explicit goal)
    while (next < route.size() && (s.xy - route[next]).norm() < opt.goal_radius_m)
    {
      ++next;
      if (trace)
        std::fprintf(stderr, "PLACE t %.2f reached %zu at %.2f %.2f\n", t, next - 1, s.xy.x(), s.xy.y());
      if (next < route.size() && vest)
      {
        chain->setGoal(route[next]);
        chain->setNextGoal(next + 1 < route.size() ? &route[next + 1] : nullptr);
      }
    }
    if (next >= route.size())
    {
      r.completed = true;
      break;
    }
    if (vest)
    {
      if (t + 1e-9 >= next_plan)
      {
        next_plan += period;
        const ChainCue cue = chain->frame(t, s);
        if (chain->stopped())
          throw std::runtime_error("the chain stopped answering at t = " + std::to_string(t) +
                                   " s (no cue, rendered image or planner state for the chain's stopped_after_s of wall time: the "
                                   "pipeline died?)");
        if (cue.received)
        {
          ++r.cue_modes[size_t(std::min(4, std::max(0, cue.mode)))];
          if (cue.mode == 4)
          {
            // the last slot: no status known (-1) or one out of range
            const size_t last = r.unsure_by_status.size() - 1;
            const size_t st = cue.planner_status < 0 ? last : std::min(last, size_t(cue.planner_status));
            ++r.unsure_by_status[st];
          }
          // the vest restarts a pattern when any of its bytes changes (vest_protocol.h, version 4)
          if (cue.pattern_id != playing.pattern_id || cue.pulse_on_ms != playing.pulse_on_ms ||
              cue.pulse_off_ms != playing.pulse_off_ms || cue.pulse_count != playing.pulse_count)
          {
            playing_since = t;
            ++r.cues_begun[size_t(std::min(6, std::max(0, cue.instruction)))];
            r.doorway_turns += cue.instruction == int(assistive_tactile::Instruction::TURN) && cue.passage_routine;
          }
          playing = cue;
        }
        else
          ++r.missed_cues;
        if (cue.latency_ms >= 0.0) r.latency_ms.push_back(cue.latency_ms);
        TimelineSample ts;
        ts.t = t;
        ts.mode = playing.mode;
        ts.instruction = playing.instruction;
        ts.level = playing.level;
        ts.passage_routine = cue.passage_routine;
        ts.speed = s.speed;
        ts.heading_error_deg = std::isfinite(cue.steer_heading) ?
                                   std::atan2(std::sin(s.yaw - cue.steer_heading), std::cos(s.yaw - cue.steer_heading)) / DEG :
                                   std::numeric_limits<double>::quiet_NaN();
        r.timeline.push_back(ts);
      }
      const std::array<float, 4> m = drive(t);
      if (!r.timeline.empty())
        r.timeline.back().drive = std::max(r.timeline.back().drive, *std::max_element(m.begin(), m.end()));
      // the scripted UNSURE episode: how far the wearer walks from its start until it stands
      if (std::isfinite(opt.unsure_at_s) && t >= opt.unsure_at_s)
      {
        if (!unsure_started)
        {
          unsure_started = true;
          unsure_from = s.xy;
          r.unsure_walked_m = 0.0;
        }
        if (!unsure_done)
        {
          r.unsure_walked_m = std::max(r.unsure_walked_m, (s.xy - unsure_from).norm());
          unsure_done = (s.speed <= 1e-6 && t > opt.unsure_at_s) || t >= opt.unsure_at_s + opt.unsure_for_s;
        }
      }
      const int action_before = int(wearer.action()), before = body.totalCollisions();
      const double speed_before = wearer.state().speed;
      const std::array<int, size_t(assistive_sim::ObstacleKind::NUM_KINDS)> kinds_before = body.collisions();
      wearer.step(t, opt.dt, m, &body);
      r.action_s[size_t(wearer.action())] += opt.dt;
      if (wearer.action() == VestWearer::TURN)
        last_turn_end = t + opt.dt;
      else if (wearer.action() != VestWearer::STOPPED)
        last_turn_end = -1.0;  // it moved on since
      if (wearer.action() == VestWearer::STOPPED)
      {
        // a turn cue begun since its last turn ended waits for the turn; else a turn just done waits for the go
        const bool turn_asked =
            playing.instruction == int(assistive_tactile::Instruction::TURN) && playing_since >= last_turn_end;
        const TrialResult::Standing why = turn_asked ? TrialResult::BEFORE_TURN :
                                          last_turn_end >= 0.0 ? TrialResult::AFTER_TURN :
                                                                 TrialResult::OTHER_STAND;
        r.standing_s[size_t(why)] += opt.dt;
      }
      if (body.totalCollisions() > before)
        for (size_t k = 0; k < kinds_before.size(); ++k)
          for (int j = kinds_before[k]; j < body.collisions()[k]; ++j)
          {
            CollisionEvent e;
            e.t = t;
            e.xy = wearer.state().xy;
            e.kind = int(k);
            e.action = action_before;
            e.instruction = playing.instruction;
            e.door_m = chain->passageDistance(e.xy);
            e.speed = speed_before;
            e.cause = classifyCollision(e.action, e.kind, e.door_m, e.speed);
            r.collision_events.push_back(e);
          }
      if (trace && (wearer.lastPercept() != last_percept || wearer.action() != last_action))
      {
        last_percept = wearer.lastPercept();
        last_action = wearer.action();
        std::fprintf(stderr, "WEARER t %.2f percept %d level %d action %d motors %.2f %.2f %.2f %.2f\n", t,
                     int(last_percept), wearer.lastLevel(), int(last_action), m[0], m[1], m[2], m[3]);
      }
      chain->observe(t + opt.dt, wearer.state());
    }
    else
    {
      cane.step(t, opt.dt, route[next], body);
    }
    const BodyState& now = vest ? wearer.state() : cane.state();
    if (trace && int(body.collisionPlaces().size()) > reported)
    {
      reported = int(body.collisionPlaces().size());
      // the nearest person's surface (issue 22: who walked into whom)
      std::string who = "-";
      double gap = std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < world.people.size(); ++i)
      {
        const PersonState p = personAt(trial_world, i, t + opt.dt);
        const double g = (p.position - now.xy).norm() - world.people[i].radius - opt.wearer.body_radius;
        if (g < gap)
        {
          gap = g;
          who = world.people[i].name + " v " + std::to_string(p.velocity.norm()).substr(0, 4);
        }
      }
      std::fprintf(stderr, "COLLISION t %.2f at %.2f %.2f yaw %.0f speed %.2f | nearest person %s gap %.2f\n", t,
                   now.xy.x(), now.xy.y(), now.yaw / DEG, now.speed, who.c_str(), gap);
    }
    r.path.push_back(now.xy);
    const double c = body.clearance(now.xy);
    r.min_person_clearance_m = std::min(r.min_person_clearance_m, body.personClearance(now.xy));
    clear_sum += c;
    r.min_clearance_m = std::min(r.min_clearance_m, c);
    ++steps;
  }
  r.time_s = t;
  r.people_give_way = giving_way;
  if (giving_way) r.people = moved.people;
  r.give_way_episodes = give_way ? give_way->episodes() : 0;
  r.ppws_pct = r.completed && r.time_s > 0.0 ? 100.0 * r.guide_time_s / r.time_s : 0.0;
  r.collisions = body.collisions();
  r.collision_places = body.collisionPlaces();
  r.mean_clearance_m = steps ? clear_sum / double(steps) : 0.0;
  if (!steps) r.min_clearance_m = 0.0;
  if (vest && !r.completed && !r.path.empty()) classifyEnd(r, opt.dt, chain->passageDistance(r.path.back()));
  return r;
}

cv::Mat timelinePlot(const TrialResult& r, const std::string& title)
{
  // three stacked strips over the trial's time: the cue (colour = instruction, height = drive),
  // the walking speed, the heading error against the steering point
  const int W = 900, strip = 90, top = 24, gap = 16, left = 60;
  const int H = top + 3 * (strip + gap);
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(250, 250, 250));
  const double T = r.timeline.empty() ? 1.0 : std::max(1.0, r.timeline.back().t);
  auto X = [&](double t) { return left + int(std::lround((W - left - 10) * t / T)); };
  const cv::Scalar colour[] = { cv::Scalar(180, 180, 180), cv::Scalar(90, 170, 60), cv::Scalar(200, 120, 30),
                                cv::Scalar(30, 30, 200), cv::Scalar(160, 60, 160), cv::Scalar(0, 0, 230),
                                cv::Scalar(0, 140, 255) };
  const char* names[] = { "none", "walk on", "veer", "stop+turn", "side-step", "stop", "unsure" };
  auto frame = [&](int k, const char* label, const char* lo, const char* hi) {
    const int y0 = top + k * (strip + gap);
    cv::rectangle(img, cv::Point(left, y0), cv::Point(W - 10, y0 + strip), cv::Scalar(120, 120, 120), 1);
    cv::putText(img, label, cv::Point(4, y0 + strip / 2), cv::FONT_HERSHEY_SIMPLEX, 0.38, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    cv::putText(img, hi, cv::Point(left - 30, y0 + 10), cv::FONT_HERSHEY_SIMPLEX, 0.32, cv::Scalar(80, 80, 80), 1, cv::LINE_AA);
    cv::putText(img, lo, cv::Point(left - 30, y0 + strip), cv::FONT_HERSHEY_SIMPLEX, 0.32, cv::Scalar(80, 80, 80), 1, cv::LINE_AA);
    return y0;
  };
  const int yc = frame(0, "cue", "0", "1"), yv = frame(1, "speed", "0", "1.5"), ye = frame(2, "error", "-90", "+90");
  cv::line(img, cv::Point(left, ye + strip / 2), cv::Point(W - 10, ye + strip / 2), cv::Scalar(200, 200, 200), 1);
  for (size_t i = 0; i + 1 < r.timeline.size(); ++i)
  {
    const TimelineSample& a = r.timeline[i];
    const TimelineSample& b = r.timeline[i + 1];
    const int x0 = X(a.t), x1 = std::max(x0 + 1, X(b.t));
    const int ins = std::min(6, std::max(0, a.instruction));
    const int h = int(std::lround(strip * std::min(1.f, a.drive)));
    if (h > 0) cv::rectangle(img, cv::Point(x0, yc + strip - h), cv::Point(x1, yc + strip), colour[ins], cv::FILLED);
    cv::line(img, cv::Point(x0, yv + strip - int(strip * std::min(1.5, a.speed) / 1.5)),
             cv::Point(x1, yv + strip - int(strip * std::min(1.5, b.speed) / 1.5)), cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
    if (std::isfinite(a.heading_error_deg) && std::isfinite(b.heading_error_deg))
    {
      auto ey = [&](double e) { return ye + strip / 2 - int(std::lround(0.5 * strip * std::clamp(e, -90.0, 90.0) / 90.0)); };
      cv::line(img, cv::Point(x0, ey(a.heading_error_deg)), cv::Point(x1, ey(b.heading_error_deg)), cv::Scalar(200, 80, 0), 1,
               cv::LINE_AA);
    }
  }
  for (int k = 1; k <= 6; ++k)
  {
    const int x = left + (k - 1) * 135;
    cv::rectangle(img, cv::Point(x, 6), cv::Point(x + 10, 16), colour[k], cv::FILLED);
    cv::putText(img, names[k], cv::Point(x + 14, 16), cv::FONT_HERSHEY_SIMPLEX, 0.38, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  cv::putText(img, title + "  (" + std::to_string(int(std::lround(T))) + " s)", cv::Point(left, H - 4),
              cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  return img;
}

cv::Mat heatMap(const World& world, const std::vector<TrialResult>& trials, double dt, const std::string& title,
                double px_per_m)
{
  const double x0 = world.floor_min.x(), y1 = world.floor_max.y();
  const int W = std::max(1, int(std::ceil((world.floor_max.x() - x0) * px_per_m)));
  const int H = std::max(1, int(std::ceil((y1 - world.floor_min.y()) * px_per_m)));
  const int top = 28;
  auto px = [&](const Eigen::Vector2d& p) {
    return cv::Point(int(std::lround((p.x() - x0) * px_per_m)), top + int(std::lround((y1 - p.y()) * px_per_m)));
  };
  cv::Mat img(H + top, W, CV_8UC3, cv::Scalar(20, 20, 20));
  // obstacles at body height, from above (grey; glass blue; overhangs hatched lighter)
  for (const Solid& s : world.solids)
  {
    if (s.walkable || s.z0 >= 2.0) continue;
    const cv::Scalar col = s.glass || s.glazing ? cv::Scalar(200, 120, 40) : s.z0 >= 1.0 ? cv::Scalar(170, 170, 170)
                                                                            : cv::Scalar(110, 110, 110);
    if (s.shape == Solid::CYLINDER)
    {
      cv::circle(img, px(s.center), std::max(1, int(s.radius * px_per_m)), col, cv::FILLED);
      continue;
    }
    const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
    std::vector<cv::Point> poly;
    for (int k = 0; k < 4; ++k)
    {
      const double lx = (k == 0 || k == 3 ? 1 : -1) * s.half.x(), ly = (k < 2 ? 1 : -1) * s.half.y();
      poly.push_back(px(s.center + Eigen::Vector2d(c * lx - sn * ly, sn * lx + c * ly)));
    }
    cv::fillConvexPoly(img, poly, col);
  }
  // time spent per 5 cm cell, summed over the trials
  const double cell = 0.05;
  const int cw = int(std::ceil(W / (cell * px_per_m))) + 1, ch = int(std::ceil(H / (cell * px_per_m))) + 1;
  std::vector<double> acc(size_t(cw) * ch, 0.0);
  for (const TrialResult& t : trials)
    for (const Eigen::Vector2d& p : t.path)
    {
      const int cx = int((p.x() - x0) / cell), cy = int((y1 - p.y()) / cell);
      if (cx >= 0 && cy >= 0 && cx < cw && cy < ch) acc[size_t(cy) * cw + cx] += dt;
    }
  double mx = 0.0;
  for (double v : acc) mx = std::max(mx, v);
  if (mx > 0.0)
  {
    cv::Mat heat(ch, cw, CV_32F, cv::Scalar(0));
    for (int y = 0; y < ch; ++y)
      for (int x = 0; x < cw; ++x) heat.at<float>(y, x) = float(std::log1p(acc[size_t(y) * cw + x]) / std::log1p(mx));
    cv::Mat big;
    cv::resize(heat, big, cv::Size(int(cw * cell * px_per_m), int(ch * cell * px_per_m)), 0, 0, cv::INTER_NEAREST);
    cv::GaussianBlur(big, big, cv::Size(0, 0), 0.08 * px_per_m);
    double bmax;
    cv::minMaxLoc(big, nullptr, &bmax);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W && x < big.cols && y < big.rows; ++x)
      {
        const float v = bmax > 0 ? float(big.at<float>(y, x) / bmax) : 0.f;
        if (v < 0.02f) continue;
        cv::Vec3b& d = img.at<cv::Vec3b>(y + top, x);
        d[2] = cv::saturate_cast<uchar>(d[2] * (1 - v) + 255 * std::sqrt(v));
        d[1] = cv::saturate_cast<uchar>(d[1] * (1 - v) + 60 * v * v);
        d[0] = cv::saturate_cast<uchar>(d[0] * (1 - v));
      }
  }
  for (const Eigen::Vector2d& p : courseOf(world)) cv::circle(img, px(p), 4, cv::Scalar(60, 220, 60), cv::FILLED);
  for (const TrialResult& t : trials)
    for (const Eigen::Vector2d& p : t.collision_places)
    {
      const cv::Point q = px(p);
      cv::line(img, q + cv::Point(-5, -5), q + cv::Point(5, 5), cv::Scalar(0, 255, 255), 2);
      cv::line(img, q + cv::Point(-5, 5), q + cv::Point(5, -5), cv::Scalar(0, 255, 255), 2);
    }
  cv::putText(img, title, cv::Point(6, 20), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(240, 240, 240), 1, cv::LINE_AA);
  return img;
}

}  // namespace assistive_trials
