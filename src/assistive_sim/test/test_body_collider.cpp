// The body's collider (body_collider.h) against known answers: walls, glass, overhangs and
// furniture counted once per contact episode; people once per encounter, never blocking.
#include <assistive_sim/body_collider.h>

#include <gtest/gtest.h>

using namespace assistive_sim;

namespace
{
World colliderRoom(const std::string& elements, const std::string& waypoints = "[[0.5, 0.0], [8.5, 0.0]]")
{
  return World::parse("name: t\nfloor: {min: [-1, -2], max: [10, 2]}\nelements:" + (elements.empty() ? std::string(" []\n") : "\n" + elements) +
                      "trajectory:\n  waypoints: " + waypoints + "\n");
}

World colliderWorldWithPeople(const std::string& people, const std::string& waypoints = "[[0.0, 0.0], [10.0, 0.0]]")
{
  return World::parse("name: p\nfloor: {min: [-2, -6], max: [14, 6]}\ntrajectory:\n  waypoints: " + waypoints +
                      "\npeople:\n" + people);
}
}  // namespace

TEST(BodyCollider, CylinderAgainstAWallIsExactlyOneWallCollision)
{
  const World w = colliderRoom("  - {type: wall, from: [3, -2], to: [3, 2], height: 2.5, thickness: 0.2}\n");
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
  const World w = colliderRoom("  - {type: glass, from: [2, -2], to: [2, 2], bottom: 0, top: 2.5}\n"
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

TEST(BodyCollider, PersonWalkingIntoAStandingBodyCountsOncePerEncounter)
{
  // Back and forth through the body at the origin: (0, -3) <-> (0, 3) at 1 m/s, period 12 s.
  const World w = colliderWorldWithPeople("  - {radius: 0.2, walk: {waypoints: [[0, -3], [0, 3]], speed: 1.0, mode: back_and_forth}}\n");
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
