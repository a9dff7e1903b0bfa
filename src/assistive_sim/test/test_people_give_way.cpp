// People who give way (issue 37, people_give_way.h): the minimal predicted distance against exact
// cases, a walker stepping aside for a wearer standing on its path and back onto it, one that
// emerges right beside the wearer standing while it steps aside, and those that must not move.
#include <assistive_sim/people_give_way.h>
#include <assistive_sim/world.h>

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

using namespace assistive_sim;

namespace
{
World peopleWorld(const std::string& people)
{
  return World::parse(std::string(R"(name: g
materials:
  coat: {pattern: noise, albedo: 0.3, contrast: 0.6}
floor: {min: [0, 0], max: [20, 10]}
trajectory:
  waypoints: [[1, 5], [19, 5]]
people:
)") + people,
                      "give_way.yaml");
}

/// The closest the person came to a wearer standing at `wearer` over [0, t_end] (centre to
/// centre), with give-way on the world's people when `give_way`; `last` gets its state at t_end.
double closestApproach(World& w, bool give_way, const Eigen::Vector2d& wearer, double t_end, PersonState* last = nullptr,
                       int* episodes = nullptr, const GiveWayParams& params = GiveWayParams())
{
  std::unique_ptr<PeopleGiveWay> g;
  if (give_way) g = std::make_unique<PeopleGiveWay>(w, params);
  const double dt = 1.0 / 60.0;
  double closest = 1e9;
  for (double t = 0.0; t < t_end; t += dt)
  {
    if (g) g->step(t, dt, wearer, Eigen::Vector2d::Zero());
    closest = std::min(closest, (personAt(w, 0, t + dt).position - wearer).norm());
  }
  if (last) *last = personAt(w, 0, t_end);
  if (episodes) *episodes = g ? g->episodes() : 0;
  return closest;
}
}  // namespace

TEST(PeopleGiveWay, MinimalPredictedDistanceIsExact)
{
  // head-on, 0.5 m apart sideways, closing at 2 m/s from 10 m: they pass 0.5 m apart in 5 s
  double tau = -1.0;
  EXPECT_NEAR(PeopleGiveWay::minimalPredictedDistance({ 10.0, 5.5 }, { -1.0, 0.0 }, { 0.0, 5.0 }, { 1.0, 0.0 }, &tau),
              0.5, 1e-12);
  EXPECT_NEAR(tau, 5.0, 1e-12);
  // a crossing at right angles: the person 3 m right of the wearer's line walking left across it
  // at 1 m/s, the wearer 3 m before the crossing at 1 m/s: they meet there
  EXPECT_NEAR(PeopleGiveWay::minimalPredictedDistance({ 3.0, -3.0 }, { 0.0, 1.0 }, { 0.0, 0.0 }, { 1.0, 0.0 }, &tau),
              0.0, 1e-12);
  EXPECT_NEAR(tau, 3.0, 1e-12);
  // parting: the closest is now
  EXPECT_NEAR(PeopleGiveWay::minimalPredictedDistance({ 1.0, 0.0 }, { 1.0, 0.0 }, { 0.0, 0.0 }, { 0.0, 0.0 }, &tau), 1.0,
              1e-12);
  EXPECT_DOUBLE_EQ(tau, 0.0);
}

TEST(PeopleGiveWay, AWalkerStepsAsideForAStandingWearerAndBackOntoItsPath)
{
  // straight at a wearer standing at (10, 5): scripted, it walks through it; giving way it passes
  // about the metre walkers keep (Olivier et al. 2012) and is back on its line after
  const std::string walk = "  - {name: a, radius: 0.2, material: coat, walk: {waypoints: [[2, 5], [18, 5]], speed: 1.2}}\n";
  World scripted = peopleWorld(walk);
  EXPECT_LT(closestApproach(scripted, false, { 10.0, 5.0 }, 13.0), 0.05);
  World w = peopleWorld(walk);
  PersonState end;
  int episodes = 0;
  const double closest = closestApproach(w, true, { 10.0, 5.0 }, 13.0, &end, &episodes);
  EXPECT_GT(closest, 0.85);
  EXPECT_LT(closest, 1.2);
  EXPECT_EQ(episodes, 1);
  EXPECT_NEAR(end.position.y(), 5.0, 1e-6);  // back on its path
  EXPECT_NEAR(end.position.x(), 2.0 + 1.2 * 13.0, 1e-6);  // and on time: it never stood
  // every copy of the person (the collider's, the planner's truth) shares the track
  const World copy = w;
  EXPECT_EQ((personAt(copy, 0, 8.0).position - personAt(w, 0, 8.0).position).norm(), 0.0);
  EXPECT_GT((personAt(w, 0, 8.0).position - personAt(scripted, 0, 8.0).position).norm(), 0.3);
}

TEST(PeopleGiveWay, OneEmergingBesideTheWearerStandsWhileItStepsAside)
{
  // out of a door 0.5 m from the wearer, walking straight at it: it stands (its script waits)
  // instead of walking through, then walks on round it
  const std::string door = "  - {name: d, radius: 0.2, material: coat, walk: {waypoints: [[10, 5.5], [10, 1]], speed: 0.8}}\n";
  GiveWayParams never_stands;
  never_stands.stop_gap_m = 0.0;
  World w0 = peopleWorld(door);
  EXPECT_LT(closestApproach(w0, true, { 10.0, 5.0 }, 12.0, nullptr, nullptr, never_stands), 0.45);  // it bumps
  World w = peopleWorld(door);
  PersonState end;
  const double closest = closestApproach(w, true, { 10.0, 5.0 }, 12.0, &end);
  EXPECT_GT(closest, 0.45 + 0.02);  // never touching: 0.2 + 0.25 m bodies
  double delay = 0.0;
  w.people[0].give_way->at(12.0, nullptr, &delay);
  EXPECT_GT(delay, 0.1);  // it stood a while
  EXPECT_NEAR(end.position.y(), 1.0, 1e-6);  // and still got where it was going
}

TEST(PeopleGiveWay, PeoplePassingWideAndStandingPeopleDoNotMove)
{
  // 1.5 m beside the wearer: over the metre, no adaptation (Olivier et al.: only under about 1 m)
  World wide = peopleWorld("  - {name: a, radius: 0.2, material: coat, walk: {waypoints: [[2, 6.5], [18, 6.5]], speed: 1.2}}\n");
  int episodes = -1;
  EXPECT_NEAR(closestApproach(wide, true, { 10.0, 5.0 }, 13.0, nullptr, &episodes), 1.5, 1e-3);
  EXPECT_EQ(episodes, 0);
  // standing on the wearer's spot's doorstep: stays put
  World stand = peopleWorld("  - {name: s, radius: 0.2, material: coat, stand: {at: [10.5, 5]}}\n");
  PersonState end;
  closestApproach(stand, true, { 10.0, 5.0 }, 5.0, &end);
  EXPECT_DOUBLE_EQ(end.position.x(), 10.5);
  EXPECT_DOUBLE_EQ(end.position.y(), 5.0);
  EXPECT_DOUBLE_EQ(end.velocity.norm(), 0.0);
}

TEST(PeopleGiveWay, ATrackRefusesKnotsThatAreNotFiniteAndKeepsItsLastOffset)
{
  GiveWayTrack track;
  EXPECT_TRUE(track.append(1.0, {0.2, -0.1}, 0.5));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(track.append(2.0, {nan, 0.0}, 0.0));
  EXPECT_FALSE(track.append(2.0, {0.0, inf}, 0.0));
  EXPECT_FALSE(track.append(2.0, {0.0, 0.0}, nan));
  EXPECT_FALSE(track.append(nan, {0.0, 0.0}, 0.0));
  EXPECT_FALSE(track.append(1.0, {0.0, 0.0}, 0.0));  // not after the last knot
  EXPECT_EQ(track.t.size(), 1u);
  double delay = -1.0;
  const Eigen::Vector2d o = track.at(3.0, nullptr, &delay);
  EXPECT_TRUE(o.isApprox(Eigen::Vector2d(0.2, -0.1)));
  EXPECT_DOUBLE_EQ(delay, 0.5);
  // a finite knot after it is taken
  EXPECT_TRUE(track.append(2.0, {0.0, 0.0}, 0.5));
  EXPECT_EQ(track.t.size(), 2u);
}
