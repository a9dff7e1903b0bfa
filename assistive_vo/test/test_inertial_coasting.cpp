#include <gtest/gtest.h>
#include <cmath>
#include "assistive_vo/imu_buffer.h"
#include "assistive_vo/inertial_coasting.h"

using namespace assistive_vo;

namespace
{
/// A synthetic walk in a z-up world (known accelerations and rotation rates): forward along x at
/// up to 1.2 m/s, a stop, sway and head bob, yaw and pitch of the head.
struct Walk
{
  double v = 1.2, stop_at = 2.0, stop_len = 1.0;
  Eigen::Vector3d g{0, 0, -9.81};
  // forward speed: ramp up over [0, 0.5], steady, ramp down over [stop_at, stop_at + stop_len], still
  double speed(double t) const
  {
    if (t < 0.5) return v * 0.5 * (1 - std::cos(M_PI * t / 0.5));
    if (t < stop_at) return v;
    if (t < stop_at + stop_len) return v * 0.5 * (1 + std::cos(M_PI * (t - stop_at) / stop_len));
    return 0.0;
  }
  double speedDot(double t) const
  {
    if (t < 0.5) return v * 0.5 * M_PI / 0.5 * std::sin(M_PI * t / 0.5);
    if (t < stop_at) return 0.0;
    if (t < stop_at + stop_len) return -v * 0.5 * M_PI / stop_len * std::sin(M_PI * (t - stop_at) / stop_len);
    return 0.0;
  }
  double forward(double t) const
  {
    // closed-form integral of speed()
    auto up = [&](double s) { return v * 0.5 * (s - 0.5 / M_PI * std::sin(M_PI * s / 0.5)); };
    auto down = [&](double s) { return v * 0.5 * (s + stop_len / M_PI * std::sin(M_PI * s / stop_len)); };
    if (t < 0.5) return up(t);
    if (t < stop_at) return up(0.5) + v * (t - 0.5);
    const double a = up(0.5) + v * (stop_at - 0.5);
    if (t < stop_at + stop_len) return a + down(t - stop_at);
    return a + down(stop_len);
  }
  Eigen::Vector3d position(double t) const
  {
    return Eigen::Vector3d(forward(t), 0.03 * std::sin(2 * M_PI * 1.0 * t), 1.6 + 0.02 * std::sin(2 * M_PI * 2.0 * t));
  }
  Eigen::Vector3d acceleration(double t) const
  {
    const double w1 = 2 * M_PI * 1.0, w2 = 2 * M_PI * 2.0;
    return Eigen::Vector3d(speedDot(t), -0.03 * w1 * w1 * std::sin(w1 * t), -0.02 * w2 * w2 * std::sin(w2 * t));
  }
  Eigen::Vector3d velocity(double t) const
  {
    const double w1 = 2 * M_PI * 1.0, w2 = 2 * M_PI * 2.0;
    return Eigen::Vector3d(speed(t), 0.03 * w1 * std::cos(w1 * t), 0.02 * w2 * std::cos(w2 * t));
  }
  // head: yaw psi(t) = 0.4 t + 0.2 sin(3 t) (a turn), pitch theta(t) = 0.1 sin(2 t); R = Rz(psi) Ry(theta)
  double psi(double t) const { return 0.4 * t + 0.2 * std::sin(3 * t); }
  double theta(double t) const { return 0.1 * std::sin(2 * t); }
  Eigen::Matrix3d rotation(double t) const
  {
    return (Eigen::AngleAxisd(psi(t), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(theta(t), Eigen::Vector3d::UnitY()))
        .toRotationMatrix();
  }
  Eigen::Vector3d gyro(double t) const  // body rates: Ry(theta)^T (0, 0, psi') + (0, theta', 0)
  {
    const double psid = 0.4 + 0.6 * std::cos(3 * t), thd = 0.2 * std::cos(2 * t);
    return Eigen::AngleAxisd(theta(t), Eigen::Vector3d::UnitY()).toRotationMatrix().transpose() *
               Eigen::Vector3d(0, 0, psid) + Eigen::Vector3d(0, thd, 0);
  }
  Eigen::Vector3d accel(double t) const { return rotation(t).transpose() * (acceleration(t) - g); }
  ImuBuffer imu(double t_end, double rate, const Eigen::Vector3d& accel_bias = Eigen::Vector3d::Zero()) const
  {
    ImuBuffer b(t_end + 1.0);
    for (int i = 0; i * (1.0 / rate) <= t_end + 1e-9; ++i)
      b.add(i / rate, gyro(i / rate), accel(i / rate) + accel_bias);
    return b;
  }
};
}  // namespace

TEST(ImuPreintegration, ExactOnASyntheticWalk)
{
  // Preintegration frame to frame (15 Hz) from a 1 kHz IMU, chained from the true state at 0.4 s
  // over 3 s of walking, stopping and turning, against the known pose: p1 = p + v T + g T^2 / 2 +
  // R dp, v1 = v + g T + R dv, R1 = R dR.
  const Walk w;
  const ImuBuffer b = w.imu(4.0, 1000.0);
  double t = 0.4;
  Eigen::Matrix3d R = w.rotation(t);
  Eigen::Vector3d p = w.position(t), v = w.velocity(t);
  for (int k = 0; k < 45; ++k)
  {
    const double t1 = t + 1.0 / 15.0;
    Eigen::Quaterniond dR;
    Eigen::Vector3d dv, dp;
    ASSERT_TRUE(b.integrate(t, t1, dR, dv, dp));
    const double T = t1 - t;
    p += v * T + 0.5 * w.g * T * T + R * dp;
    v += w.g * T + R * dv;
    R = R * dR.toRotationMatrix();
    t = t1;
  }
  EXPECT_LT((p - w.position(t)).norm(), 1e-4) << (p - w.position(t)).transpose();
  EXPECT_LT((v - w.velocity(t)).norm(), 1e-4);
  EXPECT_LT(Eigen::AngleAxisd(R.transpose() * w.rotation(t)).angle(), 1e-5);
  // the walk did move, turn and stop
  EXPECT_GT((w.position(t) - w.position(0.4)).norm(), 2.0);
  EXPECT_NEAR(w.velocity(t).x(), 0.0, 1e-12);
}

namespace
{
/// Feeds the coaster tracked frames (true poses at 15 Hz) over [t0, t_lost], then coasts to
/// t_lost + coast_s on the IMU alone; the position error at the end.
double coastError(const Walk& w, const ImuBuffer& b, double t0, double t_lost, double coast_s, InertialCoaster& c,
                  std::vector<double>* sigmas = nullptr)
{
  const double h = 1.0 / 15.0;
  double t = t0;
  auto pose = [&](double s) {
    Eigen::Isometry3d P = Eigen::Isometry3d::Identity();
    P.linear() = w.rotation(s);
    P.translation() = w.position(s);
    return P;
  };
  c.addTracked(t, pose(t), nullptr);
  for (; t + h <= t_lost + 1e-9;)
  {
    ImuDelta d;
    Eigen::Quaterniond dR;
    EXPECT_TRUE(b.integrate(t, t + h, dR, d.dv, d.dp));
    d.dt = h;
    t += h;
    c.addTracked(t, pose(t), &d);
  }
  EXPECT_TRUE(c.available());
  EXPECT_TRUE(c.start());
  Eigen::Vector3d p = pose(t).translation();
  const double t_end = t + coast_s;
  for (; t + h <= t_end + 1e-9;)
  {
    ImuDelta d;
    Eigen::Quaterniond dR;
    EXPECT_TRUE(b.integrate(t, t + h, dR, d.dv, d.dp));
    d.dt = h;
    p += c.step(w.rotation(t), d);  // orientation: the gyro chain's (exact here)
    t += h;
    if (sigmas)
      sigmas->push_back(std::sqrt(c.positionVariance(c.coastTime())));
  }
  return (p - w.position(t)).norm();
}
}  // namespace

TEST(InertialCoasting, CarriesTheWalkOverTwoSeconds)
{
  // Velocity fitted to 1.5 s of tracked poses, then 2 s of IMU alone over walking, stopping and
  // turning: the exact synthetic IMU gives millimetres.
  const Walk w;
  const ImuBuffer b = w.imu(5.0, 200.0);
  InertialCoaster c;
  std::vector<double> sig;
  const double e = coastError(w, b, 0.2, 1.8, 2.0, c, &sig);
  EXPECT_LT(e, 1e-3) << e;  // 6e-5 m
  EXPECT_NEAR(c.velocity().norm(), 0.0, 0.3);  // standing still again (head bob remains)
  // the published uncertainty grows over the coast
  ASSERT_GE(sig.size(), 29u);
  for (size_t i = 1; i < sig.size(); ++i)
    EXPECT_GT(sig[i], sig[i - 1]);
}

TEST(InertialCoasting, FitsTheAccelerometerBias)
{
  // A constant accelerometer bias (0.08 m/s^2 on each axis, 1.6 x the simulator's sigma):
  // unfitted it would cost 0.5 * 0.14 * 2^2 = 0.28 m over 2 s.
  Walk w;
  w.stop_at = 2.8;
  const ImuBuffer b = w.imu(6.0, 200.0, Eigen::Vector3d(0.08, -0.08, 0.08));
  InertialCoaster c;
  const double e = coastError(w, b, 0.2, 2.0, 2.0, c);
  EXPECT_LT(e, 0.09) << e;  // 0.075 m: the head turned too little in the window to separate bias and tilt fully
  EXPECT_GT(c.accelBias().norm(), 0.05);
  // a too short window cannot coast
  InertialCoaster s;
  s.addTracked(0.0, Eigen::Isometry3d::Identity(), nullptr);
  EXPECT_FALSE(s.available());
  EXPECT_FALSE(s.start());
}

TEST(InertialCoasting, AfterALongCoastTwoTrackedFramesCoastAgainOnItsVelocity)
{
  // A plain wall coming into view: tracked 0.2-1.0 s, lost 0.6 s (IMU coast), tracked for two
  // frames, lost again for 0.6 s into the stop. Without the first coast's velocity the two frames
  // could not fit one (min_window_s); with it the second coast carries the walk as the first did.
  const Walk w;
  const ImuBuffer b = w.imu(5.0, 200.0);
  const double h = 1.0 / 15.0;
  auto pose = [&](double s) {
    Eigen::Isometry3d P = Eigen::Isometry3d::Identity();
    P.linear() = w.rotation(s);
    P.translation() = w.position(s);
    return P;
  };
  auto delta = [&](double t) {
    ImuDelta d;
    Eigen::Quaterniond dR;
    EXPECT_TRUE(b.integrate(t, t + h, dR, d.dv, d.dp));
    d.dt = h;
    return d;
  };
  InertialCoaster c;
  double t = 0.2;
  c.addTracked(t, pose(t), nullptr);
  for (; t + h <= 1.0 + 1e-9; t += h)
  {
    const ImuDelta d = delta(t);
    c.addTracked(t + h, pose(t + h), &d);
  }
  ASSERT_TRUE(c.start());
  for (int k = 0; k < 9; ++k, t += h)  // 0.6 s coasted: beyond max_bridge_s, the window restarts
    c.step(w.rotation(t), delta(t));
  for (int k = 0; k < 2; ++k, t += h)
  {
    const ImuDelta d = delta(t);
    c.addTracked(t + h, pose(t + h), &d);
  }
  ASSERT_FALSE(c.coasting());
  EXPECT_TRUE(c.available());
  ASSERT_TRUE(c.start());
  EXPECT_LT((c.velocity() - w.velocity(t)).norm(), 0.02) << c.velocity().transpose();
  Eigen::Vector3d p = pose(t).translation();
  for (int k = 0; k < 9; ++k, t += h)  // into the stop (from 2.0 s)
    p += c.step(w.rotation(t), delta(t));
  const double sigma = std::sqrt(c.positionVariance(c.coastTime()));
  EXPECT_LT((p - w.position(t)).norm(), 0.01) << (p - w.position(t)).transpose();
  EXPECT_LT((p - w.position(t)).norm(), 3.0 * sigma);
  EXPECT_LT(sigma, 0.15);  // within the VO's imu_coast_max_sigma: still trusted

  // the same two frames after a gap without a coast (no IMU over it) have no velocity to start from
  InertialCoaster d;
  d.addTracked(1.0, pose(1.0), nullptr);
  const ImuDelta d1 = delta(1.0);
  d.addTracked(1.0 + h, pose(1.0 + h), &d1);
  EXPECT_FALSE(d.available());
}
