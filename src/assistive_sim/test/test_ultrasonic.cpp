// The ultrasonic ranger against known geometry (issue 20): normal incidence on glass returns its
// distance, a grazing panel returns nothing, a wall behind glass is not heard through it, the
// floor ahead of a level sensor is not an echo, and the noise model is unbiased and seeded.
#include <assistive_sim/ultrasonic.h>

#include <gtest/gtest.h>

using namespace assistive_sim;

namespace
{
World worldWith(const std::string& elements)
{
  return World::parse("name: t\nfloor: {min: [-1, -5], max: [10, 5]}\nelements:\n" + elements +
                          "trajectory: {waypoints: [[0, 0], [1, 0]]}\n",
                      "ultrasonic test");
}

/// Sensor at chest height (1.2 m) at the origin, looking along +x rotated by yaw (deg).
Eigen::Isometry3d sensorPose(double yaw_deg = 0.0)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0, 0, 1.2);
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}
}  // namespace

TEST(Ultrasonic, NormalIncidenceOnGlassReturnsItsDistance)
{
  const World w = worldWith("  - {type: glass, from: [2, -3], to: [2, 3], top: 2.5, thickness: 0.02}\n");
  const UltrasonicRanger r(w, UltrasonicParams(), 1);
  const auto range = r.idealRange(sensorPose());
  ASSERT_TRUE(range.has_value());
  EXPECT_NEAR(*range, 2.0 - 0.01, 1e-9);  // the panel's near face
  // Turned 30 deg (inside max_incidence 40): the nearest echo is the cone's edge ray closest to
  // the normal, 30 - 7.5 = 22.5 deg off it.
  const auto turned = r.idealRange(sensorPose(30.0));
  ASSERT_TRUE(turned.has_value());
  EXPECT_NEAR(*turned, 1.99 / std::cos(22.5 * M_PI / 180), 1e-9);
  // Turned 50 deg: even the cone's nearest edge is 42.5 deg off the normal: no echo.
  EXPECT_FALSE(r.idealRange(sensorPose(50.0)).has_value());
}

TEST(Ultrasonic, GrazingPanelReturnsNothing)
{
  // A panel along the walk, 0.3 m to the side: the cone's edge meets it at 82.5 deg incidence.
  const World w = worldWith("  - {type: glass, from: [0, 0.3], to: [9, 0.3], top: 2.5}\n");
  const UltrasonicRanger r(w, UltrasonicParams(), 1);
  EXPECT_FALSE(r.idealRange(sensorPose()).has_value());
  // The same panel straight ahead returns.
  EXPECT_TRUE(r.idealRange(sensorPose(90.0)).has_value());
}

TEST(Ultrasonic, WallBehindGlassIsNotHeardThroughIt)
{
  // A wall at x = 3 alone returns 3 m; with a glass panel across the path in front of it at 30 deg
  // to the walk (60 deg from its normal), the sound glances off the glass (no echo) and never
  // reaches the wall.
  const World wall = worldWith("  - {type: wall, from: [3, -3], to: [3, 3], height: 2.7, thickness: 0.1}\n");
  const auto alone = UltrasonicRanger(wall, UltrasonicParams(), 1).idealRange(sensorPose());
  ASSERT_TRUE(alone.has_value());
  EXPECT_NEAR(*alone, 3.0 - 0.05, 1e-9);
  const World both = worldWith("  - {type: wall, from: [3, -3], to: [3, 3], height: 2.7, thickness: 0.1}\n"
                               "  - {type: glass, from: [-1.4641, -2], to: [5.4641, 2], top: 2.5}\n");
  EXPECT_FALSE(UltrasonicRanger(both, UltrasonicParams(), 1).idealRange(sensorPose()).has_value());
}

TEST(Ultrasonic, LevelSensorDoesNotHearTheFloorAndRespectsLimits)
{
  const World empty = worldWith("  []\n");
  const UltrasonicRanger r(empty, UltrasonicParams(), 1);
  EXPECT_FALSE(r.idealRange(sensorPose()).has_value());  // floor at 82.5 deg incidence, beyond 4 m
  // Pointing straight down: the floor at normal incidence, 1.2 m.
  Eigen::Isometry3d down = sensorPose();
  down.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  ASSERT_TRUE(r.idealRange(down).has_value());
  EXPECT_NEAR(*r.idealRange(down), 1.2, 1e-9);
  // A wall closer than min_range or beyond max_range returns nothing.
  const World near = worldWith("  - {type: wall, from: [0.15, -3], to: [0.15, 3], height: 2.7, thickness: 0.02}\n");
  EXPECT_FALSE(UltrasonicRanger(near, UltrasonicParams(), 1).idealRange(sensorPose()).has_value());
  const World far = worldWith("  - {type: wall, from: [5, -3], to: [5, 3], height: 2.7}\n");
  EXPECT_FALSE(UltrasonicRanger(far, UltrasonicParams(), 1).idealRange(sensorPose()).has_value());
}

TEST(Ultrasonic, NoiseIsUnbiasedSeededAndDropsOut)
{
  const World w = worldWith("  - {type: wall, from: [2, -3], to: [2, 3], height: 2.7, thickness: 0.1}\n");
  UltrasonicParams p;
  UltrasonicRanger a(w, p, 7), b(w, p, 7);
  const double truth = 2.0 - 0.05, sigma = p.noise_sigma + p.noise_relative * truth;
  int returns = 0;
  double sum = 0, sum2 = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i)
  {
    const auto ra = a.ping(sensorPose()), rb = b.ping(sensorPose());
    ASSERT_EQ(ra.has_value(), rb.has_value());
    if (!ra) continue;
    EXPECT_DOUBLE_EQ(*ra, *rb);
    ++returns;
    sum += *ra - truth;
    sum2 += (*ra - truth) * (*ra - truth);
  }
  EXPECT_NEAR(static_cast<double>(n - returns) / n, p.dropout, 0.01);
  EXPECT_NEAR(sum / returns, 0.0, 4 * sigma / std::sqrt(returns));
  EXPECT_NEAR(std::sqrt(sum2 / returns), sigma, 0.1 * sigma);
}
