// People (issue 22): the `people:` world format, personAt() against exact scripted positions and
// velocities, the random walk's determinism, errors with line and field, and that people never
// enter the static truth grid.
#include <assistive_sim/renderer.h>
#include <assistive_sim/ultrasonic.h>
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

// ---- rendering and the ranger ------------------------------------------------------------

namespace
{
// A person crossing the camera's view from right to left 4 m ahead: at (4, 0) at t = 3 s.
const char* CROSSING = R"(name: crossing
materials:
  coat: {pattern: noise, albedo: 0.3, contrast: 0.8, scale: 0.05}
floor: {min: [-1, -5], max: [10, 5]}
elements:
  - {type: wall, from: [9, -5], to: [9, 5], height: 3}
trajectory:
  waypoints: [[0, 0], [1, 0]]
people:
  - {radius: 0.2, height: 1.9, material: coat, walk: {waypoints: [[4, -3], [4, 3]], speed: 1.0}}
)";

CameraParams smallCamera()
{
  CameraParams c;
  c.calib.width = 160;
  c.calib.height = 120;
  c.calib.fx = c.calib.fy = 125.0;
  c.calib.cx = 79.5;
  c.calib.cy = 59.5;
  c.noise_sigma = 0.0;
  c.exposure_variation = 0.0;  // the gain does not depend on the stamp
  return c;
}

/// The left optical frame at (0, 0, 1.5), looking along +x, level.
Eigen::Isometry3d levelPose()
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0, 0, 1.5);
  return T * linkToLeftOptical();
}
}  // namespace

TEST(People, RenderedAtTheFramesTimeWithTheirDepth)
{
  const World w = World::parse(CROSSING, "crossing");
  StereoRenderer r(w, smallCamera());
  RenderOutput at3, at0, again;
  r.render(levelPose(), 3.0, 0, at3);
  // Pixel (row 80, col 80) looks 0.16 rad down, straight ahead: the body's front at x = 4 - 0.2
  // (a 16-sided cylinder: within 1 cm of the circle). The right camera (0.12 m to the right, the
  // pixel's ray 0.5 px further right: y = -0.135 at the body) sees the circle at 4 - sqrt(r^2 - y^2).
  EXPECT_NEAR(at3.depth_left.at<float>(80, 80), 3.8f, 0.01f);
  const double y_r = 0.12 + 0.5 / 125.0 * 3.85;
  EXPECT_NEAR(at3.depth_right.at<float>(80, 80), 4.0 - std::sqrt(0.04 - y_r * y_r), 0.01);
  // The person is 0.4 m wide: 125 * 0.4 / 3.8 = 13 px; 10 px to either side is the wall.
  EXPECT_NEAR(at3.depth_left.at<float>(80, 70), 8.925f, 1e-3f);
  EXPECT_NEAR(at3.depth_left.at<float>(80, 90), 8.925f, 1e-3f);
  // At t = 0 the person stands 3 m to the right: straight ahead is the wall.
  r.render(levelPose(), 0.0, 1, at0);
  EXPECT_NEAR(at0.depth_left.at<float>(80, 80), 8.925f, 1e-3f);
  // Deterministic: back at t = 3, the same images.
  r.render(levelPose(), 3.0, 0, again);
  EXPECT_EQ(cv::countNonZero(again.left != at3.left), 0);
  EXPECT_EQ(cv::countNonZero(again.right != at3.right), 0);
  // setPeopleTime overrides the stamp.
  r.setPeopleTime(3.0);
  r.render(levelPose(), 0.0, 0, again);
  EXPECT_EQ(cv::countNonZero(again.left != at3.left), 0);
  // The person's texture is there (not a flat patch): contrast across the body.
  double lo, hi;
  cv::minMaxLoc(at3.left(cv::Rect(76, 70, 8, 30)), &lo, &hi);
  EXPECT_GT(hi - lo, 10.0);
}

TEST(People, StaticWorldRendersAsWithoutPeopleSupport)
{
  // A world without people renders exactly as the same world text always did: the images do not
  // depend on a people scene (none is created). Same world with a person far behind the camera:
  // every pixel the same too (the person is never seen).
  const std::string base = std::string(CROSSING).substr(0, std::string(CROSSING).find("people:"));
  const World none = World::parse(base, "none");
  const World behind = World::parse(base + "people:\n  - {stand: {at: [-0.8, 4.5]}}\n", "behind");
  StereoRenderer a(none, smallCamera()), b(behind, smallCamera());
  RenderOutput oa, ob;
  a.render(levelPose(), 2.0, 3, oa);
  b.render(levelPose(), 2.0, 3, ob);
  EXPECT_EQ(cv::countNonZero(oa.left != ob.left), 0);
  EXPECT_EQ(cv::countNonZero(oa.depth_left != ob.depth_left), 0);
}

TEST(People, RangerEchoesAPersonInFront)
{
  const World w = World::parse(CROSSING, "crossing");
  const UltrasonicRanger r(w, UltrasonicParams(), 1);
  Eigen::Isometry3d s = Eigen::Isometry3d::Identity();
  s.translation() = Eigen::Vector3d(0, 0, 1.2);
  // At t = 3 the body is straight ahead: the axis ray meets its circle at x = 3.8 (normal incidence).
  const auto at3 = r.idealRange(s, 3.0);
  ASSERT_TRUE(at3.has_value());
  EXPECT_NEAR(*at3, 3.8, 1e-9);
  // At t = 0 (3 m to the right) and without a time (the static world): the wall is beyond 4 m.
  EXPECT_FALSE(r.idealRange(s, 0.0).has_value());
  EXPECT_FALSE(r.idealRange(s).has_value());
  const auto hit = castRay(w, s.translation(), Eigen::Vector3d::UnitX(), 10.0, 3.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->person, 0);
  EXPECT_NEAR(hit->normal.x(), -1.0, 1e-9);
}
