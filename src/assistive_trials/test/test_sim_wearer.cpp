// The simulated wearer, the cane and the sighted guide against known answers; a closed-loop truth
// trial in a small world. (The body collider's own tests are assistive_sim's test_body_collider.)
#include <assistive_tactile/cue_logic.h>
#include <assistive_trials/trials.h>
#include <assistive_trials/wearer.h>

#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

using namespace assistive_sim;
using namespace assistive_trials;

namespace
{
constexpr double DEG = M_PI / 180.0;

World room(const std::string& elements, const std::string& waypoints = "[[0.5, 0.0], [8.5, 0.0]]")
{
  return World::parse("name: t\nfloor: {min: [-1, -2], max: [10, 2]}\nelements:" + (elements.empty() ? std::string(" []\n") : "\n" + elements) +
                      "trajectory:\n  waypoints: " + waypoints + "\n");
}
}  // namespace

namespace
{
/// A wearer without veering and with exact turns, so the protocol's answers are exact.
WearerParams exactWearer()
{
  WearerParams p;
  p.reaction_s = 0.5;
  p.turn_gain = 1.0;
  p.turn_gain_sd = 0.0;
  p.veer_sigma_deg = 0.0;
  p.veer_bias_deg_per_m = 0.0;
  p.intensity_levels = 4;
  return p;
}

/// Drives a wearer with motors(t) for `seconds` at dt 0.01.
template <class F>
void drive(VestWearer& w, double seconds, F motors)
{
  for (int k = 0; k < int(std::lround(seconds / 0.01)); ++k) w.step(k * 0.01, 0.01, motors(k * 0.01), nullptr);
}

std::array<float, 4> tickAt(double t, double at) { return t >= at && t < at + 0.1 ? std::array<float, 4>{ { 0.55f, 0.55f, 0.f, 0.f } } : std::array<float, 4>{}; }
}  // namespace

TEST(VestWearer, StandsUntilTheWalkOnTickThenWalksStraight)
{
  VestWearer w(exactWearer(), BodyState(), 3);
  drive(w, 2.0, [](double) { return std::array<float, 4>{}; });
  EXPECT_EQ(w.action(), VestWearer::STOPPED);
  EXPECT_DOUBLE_EQ(w.state().xy.norm(), 0.0);  // silence is never "walk on"
  VestWearer s(exactWearer(), BodyState(), 3);
  drive(s, 4.0, [](double t) { return tickAt(t, 0.0); });
  // the tick ends at 0.1 s and is felt 0.5 s later: walking from 0.6 s (accelerating at a)
  EXPECT_EQ(s.lastPercept(), VestWearer::WALK_ON);
  EXPECT_DOUBLE_EQ(s.state().yaw, 0.0);
  EXPECT_NEAR(s.state().xy.y(), 0.0, 1e-12);
  const double a = exactWearer().accel;
  EXPECT_NEAR(s.state().xy.x(), 0.5 * 1.1 * 1.1 / a + 1.1 * (3.4 - 1.1 / a), 0.03);
}

TEST(VestWearer, AVeerBurstTurnsTheWalkByItsLevelWithoutStopping)
{
  // two 0.15 s pulses on the left shoulder at level 2 (0.7): veer 30 deg while walking
  for (const auto& [drive_level, deg] : { std::pair<float, double>{ 0.4f, 15.0 }, { 0.7f, 30.0 }, { 1.0f, 45.0 } })
  {
    VestWearer w(exactWearer(), BodyState(), 5);
    drive(w, 5.0, [&](double t) {
      std::array<float, 4> m = tickAt(t, 0.0);
      const double u = t - 2.0;
      if (u >= 0.0 && u < 0.45 && std::fmod(u, 0.3) < 0.15) m[0] = drive_level;
      return m;
    });
    EXPECT_NEAR(w.state().yaw, deg * DEG, 1e-6) << drive_level;  // the second pulse belongs to the same cue
    EXPECT_NEAR(w.state().speed, 1.1, 1e-9);                    // never stopped
  }
}

TEST(VestWearer, ALongBuzzStopsAndTurnsOnTheSpotAsLongAsItLasts)
{
  // right shoulder for 1.25 s: told apart from a veer after 0.25 s, so 1.0 s of turning at
  // 90 deg/s: the reaction cancels (turning starts and stops 0.5 s late)
  VestWearer w(exactWearer(), BodyState(), 7);
  drive(w, 4.0, [](double t) {
    std::array<float, 4> m = tickAt(t, 0.0);
    if (t >= 2.0 && t < 3.25) m[1] = 1.f;
    return m;
  });
  EXPECT_NEAR(w.state().yaw, -90.0 * DEG, 1.0 * DEG);
  EXPECT_EQ(w.action(), VestWearer::STOPPED);  // after a turn: stands until the next tick
  EXPECT_NEAR(w.state().speed, 0.0, 1e-9);
}

TEST(VestWearer, WaistSideStepsStopAndUnsureStopAndSilenceStops)
{
  WearerParams p = exactWearer();
  p.reaction_s = 0.0;
  VestWearer w(p, BodyState(), 5);
  drive(w, 1.0, [](double) { return std::array<float, 4>{ { 0.f, 0.f, 1.f, 0.f } }; });
  EXPECT_NEAR(w.state().xy.y(), 0.3, 1e-6);  // 1 s at 0.3 m/s to the left
  EXPECT_EQ(w.action(), VestWearer::SIDESTEP);
  // walking, then all four: stops (and does not go on by itself)
  VestWearer a(p, BodyState(), 5);
  drive(a, 6.0, [](double t) {
    return t >= 3.0 ? std::array<float, 4>{ { 1.f, 1.f, 1.f, 1.f } } : tickAt(t, 0.0);
  });
  EXPECT_EQ(a.lastPercept(), VestWearer::STOP);
  EXPECT_NEAR(a.state().speed, 0.0, 1e-9);
  // walking, then the UNSURE pattern (three quick pulses on both waists) and silence: stops
  VestWearer u(p, BodyState(), 5);
  drive(u, 6.0, [](double t) {
    std::array<float, 4> m = tickAt(t, 0.0);
    const double v = t - 3.0;
    if (v >= 0.0 && v < 0.5 && std::fmod(v, 0.2) < 0.1) m[2] = m[3] = 1.f;
    return m;
  });
  EXPECT_EQ(u.lastPercept(), VestWearer::UNSURE);
  EXPECT_NEAR(u.state().speed, 0.0, 1e-9);
  const double x_unsure = u.state().xy.x();
  // the silence rule: a vest that stops ticking (link lost) stops the wearer after silence_stop_s
  VestWearer q(p, BodyState(), 5);
  drive(q, 10.0, [](double t) { return tickAt(t, 0.0); });
  EXPECT_NEAR(q.state().speed, 0.0, 1e-9);
  EXPECT_GT(q.state().xy.x(), x_unsure);  // it walked on until the silence limit
}

TEST(CaneWalker, MissesAHeadHeightSignButFeelsABox)
{
  const World sign = room("  - {type: sign, center: [1.0, 0], size: [0.1, 1.0], bottom: 1.45, top: 1.85}\n");
  const World box = room("  - {type: box, center: [1.0, 0], size: [0.1, 1.0, 0.8]}\n");
  BodyState s;
  for (const World* w : { &sign, &box })
  {
    BodyCollider body(*w, 0.25, 1.72);
    CaneWalker cane(WearerParams(), CaneParams(), s, 1);
    EXPECT_EQ(cane.caneContact(body, 0.0), w == &box);
  }
  // walking at the sign: the cane never warns, the head hits it
  BodyCollider body(sign, 0.25, 1.72);
  CaneParams cp;
  cp.heading_noise_deg = 0.0;
  CaneWalker cane(WearerParams(), cp, s, 1);
  for (int k = 0; k < 200; ++k) cane.step(k * 0.02, 0.02, { 8.5, 0.0 }, body);
  EXPECT_EQ(body.collisions()[size_t(ObstacleKind::OVERHANG)], 1);
  EXPECT_EQ(cane.contacts(), 0);
}

TEST(SightedGuide, TimeOfAStraightAndOfADetourWalk)
{
  WearerParams p;
  const World empty = room("");
  const double t = sightedGuideTime(empty, p, { 0.5, 0.0 }, { { 8.5, 0.0 } });
  const double ramp = p.walk_speed / p.accel, ramp_len = 0.5 * p.walk_speed * ramp;
  EXPECT_NEAR(t, ramp + (8.0 - ramp_len) / p.walk_speed, 1e-6);
  // a wall across the middle with a gap at one side: the walk goes round, and takes longer
  const World wall = room("  - {type: wall, from: [4, -2], to: [4, 0.8], height: 2.5}\n");
  std::vector<Eigen::Vector2d> path;
  const double t2 = sightedGuideTime(wall, p, { 0.5, 0.0 }, { { 8.5, 0.0 } }, &path);
  EXPECT_GT(t2, t + 0.2);  // round the end at y = 0.8: about 0.33 m longer
  BodyCollider body(wall, p.body_radius, 1.72);
  for (size_t i = 1; i < path.size(); ++i)
    for (double f = 0; f <= 1.0; f += 0.02) EXPECT_GE(body.clearance(path[i - 1] + f * (path[i] - path[i - 1])), 0.0);
}

TEST(WalkFloor, AStraightWalkCostsTheFirstGoAndATurnToItsLeg)
{
  WearerParams p;
  const World empty = room("");
  BodyState facing;
  facing.xy = { 0.5, 0.0 };
  const WalkFloor f = wearerFloor(empty, p, facing, { { 8.5, 0.0 } });
  EXPECT_NEAR(f.guide_time_s, sightedGuideTime(empty, p, facing.xy, { { 8.5, 0.0 } }), 1e-9);
  EXPECT_NEAR(f.start_s, p.reaction_s + p.min_pulse_s, 1e-9);  // the go felt, the tick's pulse
  EXPECT_EQ(f.corners, 0);
  EXPECT_NEAR(f.time_s, f.guide_time_s + f.start_s, 1e-9);
  BodyState across = facing;
  across.yaw = 90.0 * DEG;  // the first leg to its right: a turn on the spot first
  const WalkFloor g = wearerFloor(empty, p, across, { { 8.5, 0.0 } });
  EXPECT_NEAR(g.start_s, p.reaction_s + p.min_pulse_s + 0.25 + 90.0 / p.turn_rate_deg, 1e-6);
}

TEST(WalkFloor, ACornerInTheOpenIsVeeredInStrideAndInACorridorAfterBraking)
{
  WearerParams p;
  BodyState start;
  start.xy = { 0.5, 0.0 };
  // a left corner at (5, 0), a place of the route: in the open the cruise arc (radius
  // 1.1 / 60 deg/s = 1.05 m) pushed out through the corner has room
  const std::vector<Eigen::Vector2d> route{ { 5.0, 0.0 }, { 5.0, 1.8 } };
  const WalkFloor open = wearerFloor(room(""), p, start, route);
  EXPECT_EQ(open.corners, 1);
  EXPECT_EQ(open.in_stride, 1);
  EXPECT_NEAR(open.turns_s, 0.0, 1e-9);
  // an L-shaped corridor whose outer walls lie 0.5 m beyond the legs: that arc leaves its legs
  // 0.31 m outside them, the body (0.25 m) does not fit; braking to a tighter arc costs a few
  // tenths of a second, less than a turn on the spot (about 1.4 s for 90 deg)
  const World corridor = room("  - {type: wall, from: [-1, -0.575], to: [5.575, -0.575], height: 2.5}\n"
                              "  - {type: wall, from: [5.575, -0.575], to: [5.575, 2], height: 2.5}\n");
  const WalkFloor tight = wearerFloor(corridor, p, start, route);
  EXPECT_EQ(tight.corners, 1);
  EXPECT_EQ(tight.in_stride, 0);
  EXPECT_GT(tight.turns_s, 0.05);
  EXPECT_LT(tight.turns_s, 0.8);
  EXPECT_NEAR(tight.time_s, tight.guide_time_s + tight.start_s + tight.turns_s, 1e-9);
}

TEST(Trials, TruthModeGoesRoundABoxWithoutCollisionAndWithoutCuesHitsIt)
{
  const World w = room("  - {type: box, center: [4.5, 0.0], size: [0.8, 1.2, 1.0]}\n");
  TrialOptions opt;
  opt.population = false;  // the typical wearer (reaction 0.6 s), turning exactly, walking straight
  opt.wearer.turn_gain_sd = 0.0;
  opt.wearer.veer_sigma_deg = 0.0;
  opt.start_jitter_m = 0.0;
  opt.start_yaw_deg = 0.0;
  const TrialResult r = runTrial(w, opt, 11);
  EXPECT_TRUE(r.completed);
  EXPECT_EQ(r.totalCollisions(), 0);
  EXPECT_GT(r.ppws_pct, 30.0);
  EXPECT_LE(r.ppws_pct, 100.0 + 1e-6);
  // where its time went: every body step in one action, the walk the most of it; the vest began
  // a go (walk-on) and, round the box, a veer or a turn
  const double accounted = std::accumulate(r.action_s.begin(), r.action_s.end(), 0.0);
  EXPECT_NEAR(accounted, r.time_s, 2.0 * opt.dt);
  EXPECT_GT(r.action_s[VestWearer::WALK] + r.action_s[VestWearer::VEER], 0.5 * r.time_s);
  // its standing, by what it stood for, is all of its standing
  EXPECT_NEAR(std::accumulate(r.standing_s.begin(), r.standing_s.end(), 0.0), r.action_s[VestWearer::STOPPED], 1e-9);
  EXPECT_GE(r.cues_begun[size_t(assistive_tactile::Instruction::WALK_ON)], 1);
  EXPECT_GE(r.cues_begun[size_t(assistive_tactile::Instruction::VEER)] + r.cues_begun[size_t(assistive_tactile::Instruction::TURN)], 1);
  EXPECT_EQ(r.doorway_turns, 0);  // no doorway in the room
  opt.cues_enabled = false;
  const TrialResult n = runTrial(w, opt, 11);
  EXPECT_EQ(n.collisions[size_t(ObstacleKind::FURNITURE)], 1);
}

// ---- people (issue 22)

namespace
{
World withPeople(const std::string& people, const std::string& waypoints = "[[0.0, 0.0], [10.0, 0.0]]")
{
  return World::parse("name: p\nfloor: {min: [-2, -6], max: [14, 6]}\ntrajectory:\n  waypoints: " + waypoints +
                      "\npeople:\n" + people);
}
}  // namespace

TEST(People, CaneFeelsAPersonAhead)
{
  const World w = withPeople("  - {stand: {at: [0.8, 0.0]}}\n");
  BodyCollider body(w, 0.25, 1.72);
  BodyState s;  // at the origin facing +x
  const CaneWalker cane(WearerParams(), CaneParams(), s, 1);
  EXPECT_FALSE(cane.caneContact(body, 0.0));  // the static world: nothing
  body.setTime(0.0);
  EXPECT_TRUE(cane.caneContact(body, 0.0));   // the person's legs within the cane's 1 m
  EXPECT_FALSE(cane.caneContact(body, M_PI));  // behind: not felt
  EXPECT_NEAR(body.personClearance(Eigen::Vector2d::Zero()), 0.8 - 0.25 - 0.22, 1e-12);
}

TEST(People, TrialCountsAHeadOnWalkerAsAPeopleCollision)
{
  // The wearer walks along +x from the origin (no cues: straight on); a person comes head-on along
  // the same line at 1 m/s, passes, and turns off to the side at x = 3. One collision with a
  // person, nothing else; the static truth grid has no obstacle at all.
  const World w = withPeople("  - {radius: 0.22, walk: {waypoints: [[10, 0], [3, 0], [3, 5]], speed: 1.0}}\n");
  TrialOptions opt;
  opt.mode = TrialMode::TRUTH;
  opt.cues_enabled = false;  // the vest ticks "walk on" only
  opt.population = false;
  opt.wearer.veer_sigma_deg = 0.0;
  opt.fixed_start_yaw_deg = 0.0;
  opt.people_give_way = false;  // the script alone: it walks through the wearer
  const TrialResult r = runTrial(w, opt, 5);
  EXPECT_EQ(r.give_way_episodes, 0);
  EXPECT_EQ(r.collisions[size_t(ObstacleKind::PERSON)], 1);
  EXPECT_EQ(r.totalCollisions(), 1);
  ASSERT_EQ(r.collision_places.size(), 1u);
  // They meet where the wearer (starting 0.7 s late on the first tick, 0 -> 1.1 m/s in 0.92 s)
  // and the person close the 10 m, near x = 4.3.
  EXPECT_NEAR(r.collision_places[0].x(), 4.3, 0.3);
  EXPECT_LT(r.min_person_clearance_m, 0.0);
  for (int8_t c : computeOccupancy(w).data) EXPECT_NE(c, 100);
}

TEST(People, AHeadOnWalkerGivesWayToTheWearer)
{
  // The same encounter with people who give way (issue 37, the default): the walker steps aside
  // (its minimal predicted distance under 1 m) and passes the wearer, which walks straight on.
  const World w = withPeople("  - {radius: 0.22, walk: {waypoints: [[10, 0], [3, 0], [3, 5]], speed: 1.0}}\n");
  TrialOptions opt;
  opt.mode = TrialMode::TRUTH;
  opt.cues_enabled = false;
  opt.population = false;
  opt.wearer.veer_sigma_deg = 0.0;
  opt.fixed_start_yaw_deg = 0.0;
  const TrialResult r = runTrial(w, opt, 5);
  EXPECT_TRUE(r.people_give_way);
  EXPECT_EQ(r.give_way_episodes, 1);
  EXPECT_EQ(r.totalCollisions(), 0);
  EXPECT_GT(r.min_person_clearance_m, 0.2);  // about the metre centre to centre, less the bodies
  // and the cane's walker (its sense of the route's direction exact: it meets the person) meets
  // the same person aside
  opt.mode = TrialMode::CANE;
  opt.cane.heading_noise_deg = 0.0;
  const TrialResult c = runTrial(w, opt, 5);
  EXPECT_EQ(c.collisions[size_t(ObstacleKind::PERSON)], 0);
  EXPECT_EQ(c.give_way_episodes, 1);
}

TEST(People, TheStartIsClearOfAPersonStandingThere)
{
  // a person standing 0.45 m ahead of the course's start: a start within 0.3 m of it that
  // overlaps the person is redrawn, as one inside a solid is
  const World w = withPeople("  - {radius: 0.22, stand: {at: [0.45, 0.0]}}\n");
  TrialOptions opt;
  opt.population = false;
  for (uint32_t seed = 1; seed <= 40; ++seed)
  {
    const BodyState s = trialStart(w, opt, seed);
    EXPECT_GE((s.xy - Eigen::Vector2d(0.45, 0.0)).norm() - 0.22 - opt.wearer.body_radius, 0.05) << "seed " << seed;
  }
}

TEST(CollisionCause, TableOfWhatTheWearerDidAndWhere)
{
  using K = assistive_sim::ObstacleKind;
  const double inf = std::numeric_limits<double>::infinity();
  // at a doorway (within kDoorNearM of a passage middle): walking or veering vs anything else
  EXPECT_EQ(classifyCollision(VestWearer::WALK, int(K::WALL), 0.3, 0.0), CollisionCause::DOOR_WALK);
  EXPECT_EQ(classifyCollision(VestWearer::VEER, int(K::FURNITURE), 0.99, 0.0), CollisionCause::DOOR_WALK);
  EXPECT_EQ(classifyCollision(VestWearer::TURN, int(K::WALL), 0.2, 0.0), CollisionCause::DOOR_TURN);
  EXPECT_EQ(classifyCollision(VestWearer::STOPPED, int(K::WALL), 0.2, 0.0), CollisionCause::DOOR_TURN);
  // elsewhere
  EXPECT_EQ(classifyCollision(VestWearer::WALK, int(K::WALL), 1.0, 0.0), CollisionCause::WALK_WALL);
  EXPECT_EQ(classifyCollision(VestWearer::VEER, int(K::GLASS), inf, 0.0), CollisionCause::WALK_WALL);
  EXPECT_EQ(classifyCollision(VestWearer::WALK, int(K::FURNITURE), inf, 0.0), CollisionCause::WALK_OBJECT);
  EXPECT_EQ(classifyCollision(VestWearer::TURN, int(K::WALL), inf, 0.0), CollisionCause::TURN_SPOT);
  EXPECT_EQ(classifyCollision(VestWearer::STOPPED, int(K::FURNITURE), inf, 0.0), CollisionCause::TURN_SPOT);
  EXPECT_EQ(classifyCollision(VestWearer::SIDESTEP, int(K::WALL), inf, 0.0), CollisionCause::SIDESTEP);
  EXPECT_EQ(classifyCollision(VestWearer::EXPLORE, int(K::WALL), inf, 0.0), CollisionCause::EXPLORE);
  EXPECT_EQ(classifyCollision(VestWearer::WALK, int(K::PERSON), 0.1, 0.0), CollisionCause::PEOPLE);
  // stopping or turning while still braking, anywhere: the stop came too late; walking at speed,
  // or stopped below kBrakingMps, stays what it was
  EXPECT_EQ(classifyCollision(VestWearer::STOPPED, int(K::FURNITURE), inf, 0.89), CollisionCause::STOP_LATE);
  EXPECT_EQ(classifyCollision(VestWearer::STOPPED, int(K::WALL), 0.2, kBrakingMps), CollisionCause::STOP_LATE);
  EXPECT_EQ(classifyCollision(VestWearer::TURN, int(K::WALL), inf, 0.5), CollisionCause::STOP_LATE);
  EXPECT_EQ(classifyCollision(VestWearer::STOPPED, int(K::WALL), 0.2, 0.19), CollisionCause::DOOR_TURN);
  EXPECT_EQ(classifyCollision(VestWearer::STOPPED, int(K::FURNITURE), inf, 0.1), CollisionCause::TURN_SPOT);
  EXPECT_EQ(classifyCollision(VestWearer::WALK, int(K::WALL), 0.3, 1.2), CollisionCause::DOOR_WALK);
  EXPECT_EQ(classifyCollision(VestWearer::VEER, int(K::FURNITURE), inf, 1.0), CollisionCause::WALK_OBJECT);
  EXPECT_EQ(classifyCollision(VestWearer::SIDESTEP, int(K::WALL), inf, 0.5), CollisionCause::SIDESTEP);
  EXPECT_EQ(classifyCollision(VestWearer::STOPPED, int(K::PERSON), inf, 0.8), CollisionCause::PEOPLE);
  EXPECT_STREQ(collisionCauseName(CollisionCause::STOP_LATE), "stop_late");
  EXPECT_STREQ(collisionCauseName(CollisionCause::DOOR_WALK), "door_walk");
  EXPECT_STREQ(collisionCauseName(CollisionCause::PEOPLE), "people");
}

TEST(CollisionCause, UnfinishedTrialStuckAtADoorOrSlow)
{
  // 30 s at 60 Hz: standing still for the last 20 s, turn cues throughout
  TrialResult r;
  r.completed = false;
  r.time_s = 30.0;
  for (int i = 0; i < 1800; ++i) r.path.push_back(Eigen::Vector2d(i < 600 ? i * 0.005 : 3.0, 0.0));
  for (int i = 0; i < 450; ++i)
  {
    TimelineSample s;
    s.t = i / 15.0;
    s.instruction = 3;  // stop and turn
    s.passage_routine = i % 2 == 0;
    r.timeline.push_back(s);
  }
  classifyEnd(r, 1.0 / 60.0, 0.4);
  EXPECT_EQ(r.end_cause, "stuck_door");
  EXPECT_NE(r.end_detail.find("cue turn 100 %"), std::string::npos) << r.end_detail;
  EXPECT_NE(r.end_detail.find("doorway routine 50 %"), std::string::npos) << r.end_detail;
  classifyEnd(r, 1.0 / 60.0, 5.0);
  EXPECT_EQ(r.end_cause, "stuck");
  // walking on over the last 20 s: slow, not stuck
  for (int i = 600; i < 1800; ++i) r.path[size_t(i)] = Eigen::Vector2d(i * 0.005, 0.0);
  classifyEnd(r, 1.0 / 60.0, 0.4);
  EXPECT_EQ(r.end_cause, "slow");
  // a completed trial has no end cause
  r.completed = true;
  classifyEnd(r, 1.0 / 60.0, 0.4);
  EXPECT_TRUE(r.end_cause.empty());
}
