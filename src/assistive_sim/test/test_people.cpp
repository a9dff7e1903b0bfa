// People (issue 22): the `people:` world format, personAt() against exact scripted positions and
// velocities, the random walk's determinism, errors with line and field, and that people never
// enter the static truth grid.
#include <assistive_sim/world.h>

#include <cmath>

#include <gtest/gtest.h>

using namespace assistive_sim;

namespace
{
const char* BASE = R"(name: p
materials:
  coat: {pattern: noise, albedo: 0.3, contrast: 0.6}
floor: {min: [0, 0], max: [20, 10]}
trajectory:
  waypoints: [[1, 5], [19, 5]]
)";

World withPeople(const std::string& people) { return World::parse(std::string(BASE) + people, "people.yaml"); }

std::string errorOf(const std::string& people)
{
  try
  {
    withPeople(people);
  }
  catch (const WorldError& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(People, ScriptedWalkIsExact)
{
  // 3-4-5 legs: (2,2) -> (5,6) is 5 m, -> (5,9) 3 m; 1.25 m/s, starts at 2 s, once.
  const World w = withPeople(R"(people:
  - {name: a, radius: 0.2, height: 1.8, material: coat, walk: {waypoints: [[2, 2], [5, 6], [5, 9]], speed: 1.25, start: 2.0}}
)");
  ASSERT_EQ(w.people.size(), 1u);
  const Person& p = w.people[0];
  EXPECT_EQ(p.name, "a");
  EXPECT_DOUBLE_EQ(p.radius, 0.2);
  EXPECT_DOUBLE_EQ(p.height, 1.8);
  EXPECT_EQ(p.material, 1);
  // Before the start: standing at the first waypoint, facing the first leg.
  PersonState s = personAt(w, 0, 1.0);
  EXPECT_DOUBLE_EQ(s.position.x(), 2.0);
  EXPECT_DOUBLE_EQ(s.position.y(), 2.0);
  EXPECT_DOUBLE_EQ(s.velocity.norm(), 0.0);
  EXPECT_NEAR(s.yaw, std::atan2(4.0, 3.0), 1e-12);
  // 2 s into the first leg: 2.5 m along (0.6, 0.8).
  s = personAt(w, 0, 4.0);
  EXPECT_NEAR(s.position.x(), 2.0 + 1.5, 1e-12);
  EXPECT_NEAR(s.position.y(), 2.0 + 2.0, 1e-12);
  EXPECT_NEAR(s.velocity.x(), 0.75, 1e-12);
  EXPECT_NEAR(s.velocity.y(), 1.0, 1e-12);
  // The first leg takes 4 s; 1 s into the second: (5, 7.25), velocity (0, 1.25).
  s = personAt(w, 0, 7.0);
  EXPECT_NEAR(s.position.x(), 5.0, 1e-12);
  EXPECT_NEAR(s.position.y(), 7.25, 1e-12);
  EXPECT_NEAR(s.velocity.x(), 0.0, 1e-12);
  EXPECT_NEAR(s.velocity.y(), 1.25, 1e-12);
  EXPECT_NEAR(s.yaw, M_PI / 2, 1e-12);
  // Arrived at 2 + 4 + 2.4 s: standing at the end, facing the last leg.
  s = personAt(w, 0, 100.0);
  EXPECT_DOUBLE_EQ(s.position.x(), 5.0);
  EXPECT_DOUBLE_EQ(s.position.y(), 9.0);
  EXPECT_DOUBLE_EQ(s.velocity.norm(), 0.0);
  EXPECT_NEAR(s.yaw, M_PI / 2, 1e-12);
}

TEST(People, LoopAndBackAndForthRepeat)
{
  const World w = withPeople(R"(people:
  - {walk: {waypoints: [[2, 2], [6, 2], [6, 5]], speed: 1.0, mode: loop}}
  - {walk: {waypoints: [[10, 1], [10, 9]], speed: 0.8, mode: back_and_forth, start: 1.0, pause: 0.5}}
)");
  // Loop: 4 + 3 + 5 = 12 m, period 12 s. At t = 12 + 10: on the closing leg (6,5) -> (2,2), 3 m in.
  EXPECT_DOUBLE_EQ(w.people[0].period, 12.0);
  PersonState s = personAt(w, 0, 22.0);
  EXPECT_NEAR(s.position.x(), 6.0 - 0.8 * 3.0, 1e-9);
  EXPECT_NEAR(s.position.y(), 5.0 - 0.6 * 3.0, 1e-9);
  EXPECT_NEAR(s.velocity.x(), -0.8, 1e-9);
  EXPECT_NEAR(s.velocity.y(), -0.6, 1e-9);
  // Back and forth: 8 m at 0.8 m/s = 10 s each way, 0.5 s pause at both ends: period 21 s.
  EXPECT_DOUBLE_EQ(w.people[1].period, 21.0);
  s = personAt(w, 1, 1.0 + 10.2);  // pausing at the far end, facing up
  EXPECT_NEAR(s.position.y(), 9.0, 1e-9);
  EXPECT_DOUBLE_EQ(s.velocity.norm(), 0.0);
  EXPECT_NEAR(s.yaw, M_PI / 2, 1e-12);
  s = personAt(w, 1, 1.0 + 10.5 + 2.5);  // walking back, 2 m down
  EXPECT_NEAR(s.position.y(), 7.0, 1e-9);
  EXPECT_NEAR(s.velocity.y(), -0.8, 1e-9);
  EXPECT_NEAR(s.yaw, -M_PI / 2, 1e-12);
  s = personAt(w, 1, 1.0 + 21.0 * 3 + 4.0);  // third repetition, 3.2 m up
  EXPECT_NEAR(s.position.y(), 1.0 + 3.2, 1e-9);
  EXPECT_NEAR(s.velocity.y(), 0.8, 1e-9);
}

TEST(People, StandingPerson)
{
  const World w = withPeople("people:\n  - {stand: {at: [4, 4], yaw: 90}, height: 1.6}\n");
  for (double t : {0.0, 5.0, 1e4})
  {
    const PersonState s = personAt(w, 0, t);
    EXPECT_EQ(s.position, Eigen::Vector2d(4, 4));
    EXPECT_EQ(s.velocity, Eigen::Vector2d::Zero());
    EXPECT_NEAR(s.yaw, M_PI / 2, 1e-12);
  }
}

TEST(People, RandomWalkIsDeterministicPerSeed)
{
  const std::string pts = "points: [[2, 2], [18, 2], [18, 8], [2, 8]], speed: 1.1";
  const World a = withPeople("people:\n  - {random_walk: {" + pts + ", seed: 4}}\n");
  const World b = withPeople("people:\n  - {random_walk: {" + pts + ", seed: 4}}\n");
  const World c = withPeople("people:\n  - {random_walk: {" + pts + ", seed: 5}}\n");
  bool differs = false;
  for (double t = 0.37; t < 200; t += 0.37)
  {
    const PersonState sa = personAt(a, 0, t), sb = personAt(b, 0, t), sc = personAt(c, 0, t);
    EXPECT_EQ(sa.position, sb.position);
    EXPECT_EQ(sa.velocity, sb.velocity);
    differs |= (sa.position - sc.position).norm() > 0.5;
    // Always walking at 1.1 m/s between the given points (no pause), inside their hull.
    EXPECT_NEAR(sa.velocity.norm(), 1.1, 1e-9);
    EXPECT_GE(sa.position.x(), 2 - 1e-9);
    EXPECT_LE(sa.position.x(), 18 + 1e-9);
  }
  EXPECT_TRUE(differs);
  // Every knot is one of the points and none repeats its predecessor.
  const Person& p = a.people[0];
  for (size_t k = 1; k < p.knot_p.size(); ++k) EXPECT_GT((p.knot_p[k] - p.knot_p[k - 1]).norm(), 1.0);
}

TEST(People, ErrorsNameLineAndField)
{
  std::string e = errorOf("people:\n  - {walk: {waypoints: [[1, 1], [2, 2]], speed: fast}}\n");
  EXPECT_NE(e.find("people.yaml:8: field 'people[0].walk.speed': expected a number"), std::string::npos) << e;
  e = errorOf("people:\n  - {name: x}\n  - {stand: {at: [1, 1]}, walk: {waypoints: [[1, 1], [2, 2]]}}\n");
  EXPECT_NE(e.find("people.yaml:8: field 'people[0]': expected exactly one of walk, random_walk, stand"), std::string::npos) << e;
  e = errorOf("people:\n  - {stand: {at: [1, 1]}}\n  - {stand: {at: [1, 1]}, material: wool}\n");
  EXPECT_NE(e.find("people.yaml:9: field 'people[1].material': unknown material 'wool'"), std::string::npos) << e;
  e = errorOf("people:\n  - {walk: {waypoints: [[1, 1], [2, 2]], mode: circle}}\n");
  EXPECT_NE(e.find("field 'people[0].walk.mode': unknown mode 'circle'"), std::string::npos) << e;
  e = errorOf("people:\n  - {walk: {waypoints: [[1, 1]]}}\n");
  EXPECT_NE(e.find("field 'people[0].walk.waypoints': expected a list of at least 2 [x, y] points"), std::string::npos) << e;
  e = errorOf("people:\n  - {stand: {at: [1, 1]}, radius: 0.9}\n");
  EXPECT_NE(e.find("field 'people[0].radius': value 0.9 outside [0.1, 0.4]"), std::string::npos) << e;
  e = errorOf("people:\n  - {stand: {at: [1, 1]}, hat: true}\n");
  EXPECT_NE(e.find("field 'people[0].hat': unknown field"), std::string::npos) << e;
}

TEST(People, NotInTheStaticTruthGrid)
{
  const World none = World::parse(BASE, "static.yaml");
  const World busy = withPeople(R"(people:
  - {stand: {at: [4, 4]}}
  - {stand: {at: [4.5, 4]}}
  - {walk: {waypoints: [[2, 2], [18, 8]], speed: 1.0, mode: loop}}
)");
  const OccupancyGrid a = computeOccupancy(none), b = computeOccupancy(busy);
  EXPECT_EQ(a.data, b.data);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(busy.solids.size(), none.solids.size());
}
