// The wearer's motion: consistent with the worlds (never inside an obstacle, sensible eye height
// and speeds), head-turn rate bands present, IMU consistent with the poses, determinism.
#include <assistive_sim/motion.h>

#include <gtest/gtest.h>

using namespace assistive_sim;


class ShippedWorld : public ::testing::TestWithParam<const char*>
{
};

TEST_P(ShippedWorld, TrajectoryConsistentWithWorld)
{
  const World w = World::load(resolveWorldPath(GetParam(), ASSISTIVE_SIM_SOURCE_WORLDS));
  const WearerMotion m(w.trajectory, 1);
  const OccupancyGrid g = computeOccupancy(w);
  ASSERT_GT(m.duration(), 5.0);
  double min_clear = 1e9;
  double max_speed = 0.0;
  for (double t = 0.0; t <= m.duration(); t += 0.05)
  {
    const Eigen::Isometry3d T = m.linkPose(t);
    const Eigen::Vector3d c = T.translation();
    // Eye height above the floor.
    const double eye = c.z() - w.floorHeight(c.x(), c.y());
    EXPECT_GT(eye, 1.3) << GetParam() << " t=" << t;
    EXPECT_LT(eye, 1.9) << GetParam() << " t=" << t;
    // Inside the floor, on a free cell, away from every obstacle (camera and body).
    EXPECT_EQ(g.atWorld(c.x(), c.y()), CELL_FREE) << GetParam() << " t=" << t << " at " << c.transpose();
    for (const Solid& s : w.solids)
    {
      if (s.walkable) continue;
      if (s.z1 <= 0.02 || s.z0 >= c.z() + 0.3) continue;  // overhead things above the head
      double lo = 0.0, hi = 2.0;  // clearance by bisection on the inflation
      if (s.containsXY(c.x(), c.y(), 0.0))
      {
        min_clear = 0.0;
        continue;
      }
      for (int it = 0; it < 20; ++it)
      {
        const double mid = 0.5 * (lo + hi);
        (s.containsXY(c.x(), c.y(), mid) ? hi : lo) = mid;
      }
      min_clear = std::min(min_clear, lo);
    }
    // Pitch down within the script's range (+ gait nod).
    const Eigen::Vector3d fwd = T.linear().col(0);
    const double pitch = std::asin(-fwd.z());
    EXPECT_GT(pitch, w.trajectory.pitch_min - 0.03) << t;
    EXPECT_LT(pitch, w.trajectory.pitch_max + 0.03) << t;
    const Eigen::Vector3d v = m.velocity(t);
    max_speed = std::max(max_speed, v.head<2>().norm());
    if (t > w.trajectory.start_still + 2.0 && t < m.duration() - 0.2)
    {
      EXPECT_GT(m.speed(t), 0.8 * 0.95) << t;
      EXPECT_LT(m.speed(t), 1.4 * 1.05) << t;
    }
  }
  EXPECT_GT(min_clear, 0.3) << GetParam();
  EXPECT_LT(max_speed, 1.8) << GetParam();
  EXPECT_NEAR(m.speed(0.5), 0.0, 1e-9);  // standing still at the start
}

INSTANTIATE_TEST_SUITE_P(Worlds, ShippedWorld, ::testing::Values("course", "corridor", "parking", "glass", "plaza"));

TEST(Motion, StartsAtFirstWaypointEndsAtLast)
{
  const World w = World::load(resolveWorldPath("course", ASSISTIVE_SIM_SOURCE_WORLDS));
  const WearerMotion m(w.trajectory, 3);
  EXPECT_LT((m.pathPoint(0.0) - w.trajectory.waypoints.front()).norm(), 1e-6);
  EXPECT_LT((m.pathPoint(m.pathLength()) - w.trajectory.waypoints.back()).norm(), 1e-6);
  EXPECT_NEAR(m.distance(m.duration()), m.pathLength(), 1e-3);
  // Arc-length parametrisation: points 0.1 m apart along s are ~0.1 m apart in space.
  for (double s = 0.0; s + 0.1 < m.pathLength(); s += 0.37)
    EXPECT_NEAR((m.pathPoint(s + 0.1) - m.pathPoint(s)).norm(), 0.1, 2e-3) << s;
}

TEST(Motion, ParkingLoopIsWalkedTwice)
{
  const World w = World::load(resolveWorldPath("parking", ASSISTIVE_SIM_SOURCE_WORLDS));
  const WearerMotion m(w.trajectory, 1);
  const double L = m.pathLength();
  // Each loop passes the start again.
  EXPECT_LT((m.pathPoint(L / 2) - w.trajectory.waypoints.front()).norm(), 0.5);  // corner rounding
  EXPECT_LT((m.pathPoint(L) - w.trajectory.waypoints.front()).norm(), 1e-6);
  EXPECT_GT(L, 80.0);
}

TEST(Motion, HeadTurnRateBandsPresent)
{
  const World w = World::load(resolveWorldPath("corridor", ASSISTIVE_SIM_SOURCE_WORLDS));
  const WearerMotion m(w.trajectory, 1);
  // Time spent in each yaw-rate band (deg/s) while walking.
  double slow = 0, medium = 0, fast = 0, jerk = 0;
  const double dt = 0.02;
  for (double t = 0; t + dt < m.duration(); t += dt)
  {
    const double r = std::abs(m.angularVelocity(t).z()) * 180.0 / M_PI;
    (r < 5 ? slow : r < 20 ? medium : r <= 30 ? fast : jerk) += dt;
  }
  EXPECT_GT(slow, 2.0);
  EXPECT_GT(medium, 1.0);
  EXPECT_GT(fast, 0.2);
  EXPECT_GT(jerk, 0.05);
  EXPECT_FALSE(m.headTurns().empty());
}

TEST(Motion, ImuConsistentWithPoses)
{
  const World w = World::load(resolveWorldPath("course", ASSISTIVE_SIM_SOURCE_WORLDS));
  const WearerMotion m(w.trajectory, 2);
  // At rest: specific force = gravity seen in the tilted head frame, no rotation.
  const ImuSample rest = m.idealImu(0.2);
  EXPECT_NEAR(rest.accel.norm(), 9.81, 0.05);
  EXPECT_LT(rest.gyro.norm(), 0.5);  // only the slow pitch/scan motion
  // Integrating the gyro reproduces the orientation change (C2 motion: small error).
  const double t0 = 3.0, t1 = 5.0, dt = 0.001;
  Eigen::Matrix3d R = m.linkPose(t0).linear();
  for (double t = t0; t < t1 - 1e-9; t += dt)
  {
    const Eigen::Vector3d w1 = m.angularVelocity(t + dt / 2);
    R = R * Eigen::AngleAxisd(w1.norm() * dt, w1.norm() > 0 ? w1.normalized() : Eigen::Vector3d::UnitX());
  }
  const Eigen::AngleAxisd err(R.transpose() * m.linkPose(t1).linear());
  EXPECT_LT(err.angle(), 1e-3);
  // Integrating the accelerometer (with the true orientation) reproduces the velocity change.
  Eigen::Vector3d v = m.velocity(t0);
  for (double t = t0; t < t1 - 1e-9; t += dt)
  {
    const ImuSample s = m.idealImu(t + dt / 2);
    v += (m.linkPose(t + dt / 2).linear() * s.accel - Eigen::Vector3d(0, 0, 9.81)) * dt;
  }
  EXPECT_LT((v - m.velocity(t1)).norm(), 0.01);
  // Walking: vertical bob shows in the accelerometer.
  double zmin = 1e9, zmax = -1e9;
  for (double t = 4.0; t < 6.0; t += 0.01)
  {
    const double z = m.linkPose(t).translation().z();
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  EXPECT_GT(zmax - zmin, 0.02);
}

TEST(Motion, NoisyImuDeterministicAndBiased)
{
  const World w = World::load(resolveWorldPath("course", ASSISTIVE_SIM_SOURCE_WORLDS));
  const WearerMotion m(w.trajectory, 1);
  ImuSimulator a(ImuParams{}, 5), b(ImuParams{}, 5), c(ImuParams{}, 6);
  for (int i = 0; i < 50; ++i)
  {
    const ImuSample sa = a.next(m), sb = b.next(m), sc = c.next(m);
    EXPECT_EQ(sa.gyro, sb.gyro);
    EXPECT_EQ(sa.accel, sb.accel);
    EXPECT_NE(sa.gyro, sc.gyro);
    EXPECT_NEAR(sa.stamp, i / 200.0, 1e-12);
  }
  EXPECT_GT(a.gyroBias().norm(), 0.0);
  // Noise is small next to the signal.
  const ImuSample ideal = m.idealImu(50 / 200.0);
  const ImuSample noisy = a.next(m);
  EXPECT_LT((noisy.accel - ideal.accel).norm(), 0.5);
  EXPECT_LT((noisy.gyro - ideal.gyro).norm(), 0.05);
  // Same seed, same head turns; different seed, different turns.
  EXPECT_EQ(WearerMotion(w.trajectory, 1).headTurns().size(), m.headTurns().size());
  EXPECT_NE(WearerMotion(w.trajectory, 9).linkPose(8.0).linear(), m.linkPose(8.0).linear());
}

TEST(Motion, HairpinStopsAndTurnsOnTheSpot)
{
  // Out 4 m, straight back, then off at 45 deg: the reversal is a stop and a turn on the spot (the
  // curve's tangent would otherwise flip 180 deg between two frames); the 45 deg corner is walked
  // as a curve.
  TrajectoryScript sc;
  sc.waypoints = {{0, 0}, {4, 0}, {0.5, 0}, {0.5 - 3 * M_SQRT1_2, 3 * M_SQRT1_2}};
  sc.auto_head_turns = false;
  sc.scan_amplitude = 0.0;
  sc.start_still = 0.5;
  const WearerMotion m(sc, 1);
  EXPECT_NEAR(m.pathLength(), 4.0 + 3.5 + 3.0, 0.2);
  EXPECT_LT((m.pathPoint(m.pathLength()) - sc.waypoints.back()).norm(), 1e-6);
  // Where the walk reaches (4, 0) it stands still; the heading turns by pi there, smoothly.
  double t_far = -1.0, max_step = 0.0;
  for (double t = 0.0; t + 1.0 / 15 <= m.duration(); t += 1.0 / 15)
  {
    const Eigen::Isometry3d a = m.linkPose(t), b = m.linkPose(t + 1.0 / 15);
    max_step = std::max(max_step, Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle());
    if (t_far < 0 && m.distance(t) > 4.0 - 1e-6) t_far = t;
  }
  ASSERT_GT(t_far, 0.0);
  EXPECT_LT(max_step, 8.0 * M_PI / 180.0);  // 60 deg/s peak turn rate: 4 deg per frame
  EXPECT_NEAR(m.speed(t_far + 0.5), 0.0, 1e-6);
  const auto yawAt = [&](double t) {
    const Eigen::Vector3d x = m.linkPose(t).linear().col(0);
    return std::atan2(x.y(), x.x());
  };
  EXPECT_NEAR(std::abs(yawAt(t_far - 1.0)), 0.0, 0.05);
  // 180 deg at 60 deg/s peak takes 5.6 s, between pauses of 0.3 s.
  EXPECT_NEAR(std::abs(yawAt(t_far + 6.3)), M_PI, 0.05);
  EXPECT_GT(m.speed(t_far + 6.3 + 2.0), 0.3);  // walking back
  // The gyro says the same as the poses through the turn.
  Eigen::Matrix3d R = m.linkPose(t_far).linear();
  const double dt = 0.001;
  for (double t = t_far; t < t_far + 6.3 - 1e-9; t += dt)
  {
    const Eigen::Vector3d w1 = m.angularVelocity(t + dt / 2);
    R = R * Eigen::AngleAxisd(w1.norm() * dt, w1.norm() > 0 ? w1.normalized() : Eigen::Vector3d::UnitX());
  }
  EXPECT_LT(Eigen::AngleAxisd(R.transpose() * m.linkPose(t_far + 6.3).linear()).angle(), 2e-3);
  // The 45 deg corner (gentler than turn_on_spot_above and max_walk_turn_rate) is walked without
  // stopping.
  double min_speed = 1e9;
  const double s_corner = 4.0 + 3.5;
  for (double t = 0.0; t < m.duration(); t += 0.02)
    if (std::abs(m.distance(t) - s_corner) < 0.5) min_speed = std::min(min_speed, m.speed(t));
  EXPECT_GT(min_speed, 0.5);
}
