// The forward ranger fused into the map (sonar_fusion.h): a glass panel the camera sees through
// (only the floor behind it comes back) but the ranger hits.
#include <limits>

#include <gtest/gtest.h>

#include <assistive_obstacles/obstacle_map.h>
#include <assistive_obstacles/sonar_fusion.h>

#include "synthetic.h"

using namespace assistive_obstacles;
using synthetic::Points;

namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();

int8_t codeAt(const ObstacleMap& m, double x, double y)
{
  GridData g;
  m.grid(g);
  const int ix = static_cast<int>(std::floor((x - g.origin_x) / g.resolution));
  const int iy = static_cast<int>(std::floor((y - g.origin_y) / g.resolution));
  if (ix < 0 || iy < 0 || ix >= g.width || iy >= g.height) return -2;
  return g.data[iy * g.width + ix];
}

/// The ranger on the chest (1.2 m), looking along +x, pitched down by `pitch` rad.
RangeReading reading(double range, double pitch = 0.0)
{
  RangeReading r;
  r.range = range;
  r.min_range = 0.2;
  r.max_range = 4.0;
  r.field_of_view = 15.0 * M_PI / 180.0;
  r.T_world_sensor = Eigen::Translation3f(0.02f, 0.f, 1.2f) * Eigen::AngleAxisf(static_cast<float>(pitch), Eigen::Vector3f::UnitY());
  return r;
}

struct GlassScene
{
  ObstacleMap map;
  Eigen::Isometry3f T = synthetic::cameraAt(0.0, 0.0, 1.6);
  Points cam;  // the camera sees the floor through the panel at x = 2.0 .. 2.2
  GlassScene()
  {
    Points w;
    synthetic::patch(w, 0.6, 4.0, -1.4, 1.4, 0.0, 5, 0.005);
    cam = synthetic::toCamera(w, T);
  }
  void frames(int n) { for (int i = 0; i < n; ++i) map.update(cam, T); }
};
}  // namespace

TEST(SonarFusion, BadInputIsRejectedNoEchoIsNotEvidence)
{
  EXPECT_EQ(SonarFusion::check(reading(2.0)), RangeCheck::ECHO);
  EXPECT_EQ(SonarFusion::check(reading(kInf)), RangeCheck::NO_ECHO);
  EXPECT_EQ(SonarFusion::check(reading(std::nan(""))), RangeCheck::NOT_A_NUMBER);
  EXPECT_EQ(SonarFusion::check(reading(-kInf)), RangeCheck::OUT_OF_LIMITS);
  EXPECT_EQ(SonarFusion::check(reading(0.1)), RangeCheck::OUT_OF_LIMITS);
  EXPECT_EQ(SonarFusion::check(reading(4.5)), RangeCheck::OUT_OF_LIMITS);
  RangeReading r = reading(2.0);
  r.field_of_view = 0.0;
  EXPECT_EQ(SonarFusion::check(r), RangeCheck::BAD_FOV);
  r = reading(2.0);
  r.max_range = std::nan("");
  EXPECT_EQ(SonarFusion::check(r), RangeCheck::NOT_A_NUMBER);
  r = reading(2.0);
  r.min_range = 5.0;  // limits that make no sense
  EXPECT_EQ(SonarFusion::check(r), RangeCheck::OUT_OF_LIMITS);

  // Rejected readings and "no echo" change nothing.
  GlassScene s;
  s.frames(10);
  ASSERT_EQ(codeAt(s.map, 2.1, 0.1), CELL_FREE);
  for (const double bad : { std::nan(""), -kInf, 0.1, 4.5, kInf })
  {
    s.map.addRange(reading(bad));
    EXPECT_EQ(s.map.sonar().stats().arc_cells, 0) << bad;
  }
  EXPECT_EQ(s.map.sonar().stats().held, 0u);
  EXPECT_EQ(codeAt(s.map, 2.1, 0.1), CELL_FREE);
}

TEST(SonarFusion, RangerHitCellIsNeverFreedByCameraRays)
{
  GlassScene s;
  s.frames(20);  // the camera sees through the panel: free
  ASSERT_EQ(codeAt(s.map, 2.1, 0.1), CELL_FREE);
  // Echo at 2.1 m: the arc crosses x in [2.08, 2.1], y in +-0.28 at 0.9-1.5 m height.
  for (int i = 0; i < 30; ++i)
  {
    s.map.addRange(reading(2.1));
    s.frames(1);
  }
  EXPECT_GT(s.map.sonar().stats().arc_cells, 0);
  for (const double y : { -0.3, -0.1, 0.1, 0.3 }) EXPECT_EQ(codeAt(s.map, 2.1, y), CELL_OBSTACLE) << y;
  EXPECT_EQ(codeAt(s.map, 2.1, 0.9), CELL_FREE);  // outside the cone
  EXPECT_EQ(codeAt(s.map, 1.5, 0.1), CELL_FREE);  // in front of the arc
  // Hundreds of camera frames through the panel, and "no echo" readings (a grazing look): held.
  for (int i = 0; i < 300; ++i)
  {
    if (i % 3 == 0) s.map.addRange(reading(kInf));
    s.frames(1);
    ASSERT_EQ(codeAt(s.map, 2.1, 0.1), CELL_OBSTACLE) << "frame " << i;
  }
  EXPECT_TRUE(s.map.sonar().held(10, 0));
  // The ranger sees through it (echoes from 3.5 m): released after sonar_release_readings; then
  // the camera's free votes win again.
  const ObstaclesParams p;
  for (int i = 0; i < p.sonar_release_readings - 1; ++i) s.map.addRange(reading(3.5));
  EXPECT_TRUE(s.map.sonar().held(10, 0));
  s.map.addRange(reading(3.5));
  EXPECT_FALSE(s.map.sonar().held(10, 0));
  s.frames(200);
  EXPECT_EQ(codeAt(s.map, 2.1, 0.1), CELL_FREE);
}

TEST(SonarFusion, EchoTheMapAlreadyExplainsAddsNothing)
{
  // A wall the camera maps at x = 2.1 .. 2.2: the echo at 2.1 m is that wall; the arc's other
  // cells (free space in front of an oblique wall, in general) are not held.
  ObstacleMap m;
  const Eigen::Isometry3f T = synthetic::cameraAt(0.0, 0.0, 1.6);
  Points w;
  synthetic::patch(w, 0.6, 2.1, -1.4, 1.4, 0.0, 5, 0.005);
  synthetic::wallX(w, 2.15, -1.4, 1.4, 0.0, 1.9);
  const Points cam = synthetic::toCamera(w, T);
  for (int i = 0; i < 10; ++i) m.update(cam, T);
  ASSERT_EQ(codeAt(m, 2.15, 0.1), CELL_OBSTACLE);
  m.addRange(reading(2.1));
  EXPECT_TRUE(m.sonar().stats().explained);
  EXPECT_EQ(m.sonar().stats().arc_cells, 0);
  EXPECT_EQ(m.sonar().stats().held, 0u);
}

TEST(SonarFusion, EchoThatMayBeTheFloorIsNoEvidenceElseTheArcAboveItCounts)
{
  GlassScene s;
  s.frames(10);
  // Pitched down 45 deg: the cone's steepest ray (52.5 deg, above sonar_floor_echo_deg) meets the
  // floor at about 1.51 m: the echo at 1.6 m may be the floor.
  s.map.addRange(reading(1.6, 45.0 * M_PI / 180.0));
  EXPECT_TRUE(s.map.sonar().stats().floor_ambiguous);
  EXPECT_EQ(s.map.sonar().stats().arc_cells, 0);
  EXPECT_EQ(s.map.sonar().stats().held, 0u);
  // Pitched down 20 deg (27.5 at the rim: the floor sends the echo away), echo at 2.6 m: the part
  // of the arc under the step height is dropped, the rest counts.
  s.map.addRange(reading(2.6, 20.0 * M_PI / 180.0));
  EXPECT_FALSE(s.map.sonar().stats().floor_ambiguous);
  EXPECT_GT(s.map.sonar().stats().arc_cells, 0);
}

TEST(SonarFusion, DisabledTakesNoEvidence)
{
  ObstaclesParams p;
  p.sonar_enabled = false;
  GlassScene s;
  s.map.setParams(p);
  s.frames(10);
  for (int i = 0; i < 20; ++i) s.map.addRange(reading(2.1));
  EXPECT_EQ(s.map.sonar().stats().held, 0u);
  EXPECT_EQ(codeAt(s.map, 2.1, 0.1), CELL_FREE);
}
