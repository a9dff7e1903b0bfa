// The simulated wearer, the body collider, the cane and the sighted guide against known answers;
// a closed-loop truth trial in a small world.
#include <assistive_sim/trials.h>
#include <assistive_sim/wearer.h>

#include <cmath>

#include <gtest/gtest.h>

using namespace assistive_sim;

namespace
{
constexpr double DEG = M_PI / 180.0;

World room(const std::string& elements, const std::string& waypoints = "[[0.5, 0.0], [8.5, 0.0]]")
{
  return World::parse("name: t\nfloor: {min: [-1, -2], max: [10, 2]}\nelements:" + (elements.empty() ? std::string(" []\n") : "\n" + elements) +
                      "trajectory:\n  waypoints: " + waypoints + "\n");
}
}  // namespace

TEST(VestWearer, ShoulderCueTurnsByIntensityTimesDurationPlusOverturn)
{
  WearerParams p;  // reaction 0.3 s, 90 deg/s at intensity 1, over-turn 0.2 s
  for (const float intensity : { 0.5f, 1.0f })
  {
    VestWearer w(p, BodyState(), 7);
    const double dt = 0.01;
    for (int k = 0; k < 300; ++k)
    {
      const double t = k * dt;
      const bool on = t < 1.0 - 1e-9;  // the left shoulder buzzes for 1 s
      w.step(t, dt, { { on ? intensity : 0.f, 0.f, 0.f, 0.f } }, nullptr);
    }
    // felt from 0.3 s to 1.3 s, then turning on until 1.5 s: 1.2 s at intensity x 90 deg/s
    EXPECT_NEAR(w.state().yaw, 1.2 * intensity * 90.0 * DEG, 1e-6) << intensity;
  }
}

TEST(VestWearer, RightShoulderTurnsRightAndNoCueWalksStraight)
{
  WearerParams p;
  p.overturn_s = 0.0;
  VestWearer w(p, BodyState(), 3);
  for (int k = 0; k < 100; ++k) w.step(k * 0.01, 0.01, { { 0.f, 1.f, 0.f, 0.f } }, nullptr);
  EXPECT_NEAR(w.state().yaw, -0.7 * 90.0 * DEG, 1e-6);  // felt after 0.3 s
  VestWearer s(p, BodyState(), 3);
  for (int k = 0; k < 500; ++k) s.step(k * 0.01, 0.01, { { 0.f, 0.f, 0.f, 0.f } }, nullptr);
  EXPECT_DOUBLE_EQ(s.state().yaw, 0.0);
  EXPECT_NEAR(s.state().xy.y(), 0.0, 1e-12);
  EXPECT_NEAR(s.state().speed, p.walk_speed, 1e-9);
  // 5 s: accelerating to 1.1 m/s at 1.2 m/s^2 takes 0.917 s (0.504 m), then 4.083 s at cruise
  EXPECT_NEAR(s.state().xy.x(), 0.5 * 1.1 * 1.1 / 1.2 + 1.1 * (5.0 - 1.1 / 1.2), 0.02);
}

TEST(VestWearer, WaistCueSideStepsAndAlertStopsAndExplores)
{
  WearerParams p;
  p.reaction_s = 0.0;
  VestWearer w(p, BodyState(), 5);
  for (int k = 0; k < 100; ++k) w.step(k * 0.01, 0.01, { { 0.f, 0.f, 1.f, 0.f } }, nullptr);
  EXPECT_NEAR(w.state().xy.y(), 0.3, 1e-6);  // 1 s at 0.3 m/s to the left
  EXPECT_NEAR(w.state().xy.x(), 0.0, 1e-9);
  EXPECT_EQ(w.action(), VestWearer::SIDESTEP);
  VestWearer a(p, BodyState(), 5);
  for (int k = 0; k < 100; ++k) a.step(k * 0.01, 0.01, { { 1.f, 1.f, 1.f, 1.f } }, nullptr);
  EXPECT_EQ(a.action(), VestWearer::EXPLORE);
  EXPECT_NEAR(a.state().xy.norm(), 0.0, 1e-9);
  EXPECT_NEAR(std::abs(a.state().yaw), 40.0 * DEG, 1e-6);  // explores at 40 deg/s, one side
}

TEST(BodyCollider, CylinderAgainstAWallIsExactlyOneWallCollision)
{
  const World w = room("  - {type: wall, from: [3, -2], to: [3, 2], height: 2.5, thickness: 0.2}\n");
  BodyCollider body(w, 0.25, 1.72);
  Eigen::Vector2d p(0, 0);
  bool bumped = false;
  for (int k = 0; k < 50; ++k) p = body.move(p, p + Eigen::Vector2d(0.1, 0), bumped);
  EXPECT_TRUE(bumped);
  EXPECT_EQ(body.collisions()[size_t(ObstacleKind::WALL)], 1);
  EXPECT_EQ(body.totalCollisions(), 1);
  EXPECT_NEAR(p.x(), 3.0 - 0.1 - 0.25, 0.021);  // stopped at the face, within a 2 cm step
  EXPECT_NEAR(body.clearance(p), 0.0, 0.021);
  // leaving by more than 5 cm and coming back is a second collision
  p = body.move(p, p - Eigen::Vector2d(0.2, 0), bumped);
  EXPECT_FALSE(bumped);
  for (int k = 0; k < 5; ++k) p = body.move(p, p + Eigen::Vector2d(0.1, 0), bumped);
  EXPECT_EQ(body.collisions()[size_t(ObstacleKind::WALL)], 2);
}

TEST(BodyCollider, ClassifiesGlassOverhangAndFurniture)
{
  const World w = room("  - {type: glass, from: [2, -2], to: [2, 2], bottom: 0, top: 2.5}\n"
                       "  - {type: sign, center: [0, 1.0], size: [0.8, 0.05], bottom: 1.45, top: 1.85}\n"
                       "  - {type: table, center: [0, -1.2], size: [1.2, 0.6], height: 0.75}\n"
                       "  - {type: sign, center: [5, 0], size: [0.8, 0.8], bottom: 1.9, top: 2.0}\n");
  BodyCollider body(w, 0.25, 1.72);
  bool b;
  body.move({ 0, 0 }, { 3, 0 }, b);
  body.move({ 0, 0 }, { 0, 2 }, b);
  body.move({ 0, 0 }, { 0, -2 }, b);
  EXPECT_EQ(body.collisions()[size_t(ObstacleKind::GLASS)], 1);
  EXPECT_EQ(body.collisions()[size_t(ObstacleKind::OVERHANG)], 1);
  EXPECT_EQ(body.collisions()[size_t(ObstacleKind::FURNITURE)], 1);  // one table, though five solids
  EXPECT_TRUE(body.free({ 5, 0 }));  // above the head (1.72 m)
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

TEST(Trials, TruthModeGoesRoundABoxWithoutCollisionAndWithoutCuesHitsIt)
{
  const World w = room("  - {type: box, center: [4.5, 0.0], size: [0.8, 1.2, 1.0]}\n");
  TrialOptions opt;
  opt.start_jitter_m = 0.0;
  opt.start_yaw_deg = 0.0;
  const TrialResult r = runTrial(w, opt, 11);
  EXPECT_TRUE(r.completed);
  EXPECT_EQ(r.totalCollisions(), 0);
  EXPECT_GT(r.ppws_pct, 30.0);
  EXPECT_LE(r.ppws_pct, 100.0 + 1e-6);
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

TEST(People, PersonWalkingIntoAStandingBodyCountsOncePerEncounter)
{
  // Back and forth through the body at the origin: (0, -3) <-> (0, 3) at 1 m/s, period 12 s.
  const World w = withPeople("  - {radius: 0.2, walk: {waypoints: [[0, -3], [0, 3]], speed: 1.0, mode: back_and_forth}}\n");
  BodyCollider body(w, 0.25, 1.72);
  EXPECT_EQ(body.personContacts(Eigen::Vector2d::Zero()).size(), 0u);  // no clock set: no people
  int bumps = 0;
  double first = -1.0;
  for (int k = 0; k < 1200; ++k)  // 12 s in 10 ms steps: the person passes twice
  {
    const double t = (k + 1) * 0.01;
    body.setTime(t);
    bool bumped = false;
    const Eigen::Vector2d at = body.move(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), bumped);
    EXPECT_EQ(at, Eigen::Vector2d::Zero());  // people never block or push
    if (bumped && first < 0) first = t;
    bumps += bumped;
  }
  EXPECT_EQ(body.collisions()[size_t(ObstacleKind::PERSON)], 2);
  EXPECT_EQ(body.totalCollisions(), 2);
  EXPECT_EQ(bumps, 2);  // one bump at the start of each encounter
  // Contact when the centres are 0.45 m apart: the person at y = -0.45, 2.55 s after the start.
  EXPECT_NEAR(first, 2.56, 0.011);
  EXPECT_STREQ(kindName(ObstacleKind::PERSON), "people");
}

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
  opt.cues_enabled = false;
  opt.fixed_start_yaw_deg = 0.0;
  const TrialResult r = runTrial(w, opt, 5);
  EXPECT_EQ(r.collisions[size_t(ObstacleKind::PERSON)], 1);
  EXPECT_EQ(r.totalCollisions(), 1);
  ASSERT_EQ(r.collision_places.size(), 1u);
  // They meet where the wearer (0 -> 1.1 m/s in 0.92 s) and the person close the 10 m, near x = 4.7.
  EXPECT_NEAR(r.collision_places[0].x(), 4.6, 0.3);
  EXPECT_LT(r.min_person_clearance_m, 0.0);
  for (int8_t c : computeOccupancy(w).data) EXPECT_NE(c, 100);
}
