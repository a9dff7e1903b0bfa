#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include "assistive_vo/standing_detector.h"

using assistive_vo::StandingDetector;

namespace
{
/// 15 Hz frame means of the specific force (odom axes): gravity, the accelerometer's white noise
/// as the simulator has it (2e-3 m/s^2/sqrt(Hz) -> 0.0077 m/s^2 per axis on a 1/15 s mean) and
/// `a(t)`.
template <class F>
void feed(StandingDetector& d, double t0, double t1, F a, std::mt19937& rng)
{
  std::normal_distribution<double> n(0.0, 2e-3 * std::sqrt(15.0));
  const double dt = 1.0 / 15.0;
  for (double t = t0 + dt; t <= t1 + 1e-9; t += dt)
    d.add(t, dt, Eigen::Vector3d(0, 0, 9.81) + a(t) + Eigen::Vector3d(n(rng), n(rng), n(rng)));
}
}  // namespace

TEST(StandingDetector, QuietAtRestAndWhileTurningLoudWithGait)
{
  std::mt19937 rng(3);
  StandingDetector d;
  EXPECT_LT(d.statistic(), 0.0);
  feed(d, 0.0, 0.6, [](double) { return Eigen::Vector3d::Zero(); }, rng);
  EXPECT_LT(d.statistic(), 0.0) << "window not full yet";
  EXPECT_FALSE(d.quiet());
  feed(d, 0.6, 2.0, [](double) { return Eigen::Vector3d::Zero(); }, rng);
  EXPECT_TRUE(d.quiet());
  EXPECT_LT(d.statistic(), 0.03);  // the noise alone: about 0.013
  // turning on the spot at 60 deg/s with the camera 0.11 m from the axis: a centripetal 0.12 m/s^2
  // turning with the head
  feed(d, 2.0, 4.0, [](double t) {
    const double w = M_PI / 3, r = 0.11;
    return Eigen::Vector3d(-w * w * r * std::cos(w * t), -w * w * r * std::sin(w * t), 0.0);
  }, rng);
  EXPECT_TRUE(d.quiet()) << d.statistic();
  // the slowest gait the simulator walks (0.9 m/s, 0.65 m steps, 2.5 cm bob: 1.9 m/s^2 vertical)
  feed(d, 4.0, 4.4, [](double t) {
    const double f = 0.9 / 0.65;
    return Eigen::Vector3d(0, 0, 0.025 * std::pow(2 * M_PI * f, 2) * std::cos(2 * M_PI * f * t));
  }, rng);
  EXPECT_FALSE(d.quiet()) << "0.4 s of gait: " << d.statistic();
}

TEST(StandingDetector, StartOfAWalkWithoutBobAndTimeGoingBack)
{
  std::mt19937 rng(4);
  StandingDetector d;
  feed(d, 0.0, 2.0, [](double) { return Eigen::Vector3d::Zero(); }, rng);
  ASSERT_TRUE(d.quiet());
  // starting to walk at 1.2 m/s^2 without any bob (the mobility trials' IMU): loud on the 2nd frame
  feed(d, 2.0, 2.0 + 2.0 / 15.0, [](double) { return Eigen::Vector3d(1.2, 0, 0); }, rng);
  EXPECT_FALSE(d.quiet()) << d.statistic();
  // a stamp going back (bag loop) restarts the window
  d.add(1.0, 1.0 / 15.0, Eigen::Vector3d(0, 0, 9.81));
  EXPECT_LT(d.statistic(), 0.0);
}
