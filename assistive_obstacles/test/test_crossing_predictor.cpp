// Crossing predictor: hand-computed closest approaches (wearer at the origin walking +x at 1 m/s).
#include <cmath>

#include <gtest/gtest.h>

#include <assistive_common/crossing_predictor.h>
#include <assistive_obstacles/mover_tracker.h>

using namespace assistive_common;
using namespace assistive_obstacles;

namespace
{
MoverTrack mover(double x, double y, double vx, double vy, int id = 1)
{
  MoverTrack t;
  t.id = id;
  t.x << x, y, vx, vy;
  t.P.setZero();
  t.confirmed = true;
  return t;
}

Wearer wearer(double speed = 1.0)
{
  Wearer w;
  w.speed = speed;
  return w;
}
}  // namespace

TEST(CrossingPredictor, PerpendicularCrosserOnCollisionCourse)
{
  // 3 m to the left, 2.5 m ahead, crossing at 1.2 m/s: both reach (2.5, 0) at t = 2.5 s.
  // r0 = (2.5, 3), vr = (-1, -1.2): t* = (2.5 + 3.6) / 2.44 = 2.5, d* = 0.
  CrossingPredictor cp;
  const CrossingPrediction p = cp.predict(wearer(), mover(2.5, 3.0, 0.0, -1.2));
  EXPECT_NEAR(p.t_closest, 2.5, 1e-12);
  EXPECT_NEAR(p.d_closest, 0.0, 1e-12);
  EXPECT_NEAR(p.closing_speed, 6.1 / std::hypot(2.5, 3.0), 1e-12);
  EXPECT_TRUE(p.warn);
  EXPECT_FALSE(p.head_on);
  EXPECT_EQ(p.side, AvoidSide::LEFT);  // it walks to the right: pass behind it
  // Warned 2.5 s ahead: 1 s later it is 1.5 s ahead, still a side; at 0.8 s ahead, STOP.
  Wearer w = wearer();
  w.position = Eigen::Vector2d(1.7, 0.0);
  const CrossingPrediction late = cp.predict(w, mover(2.5, 3.0 - 1.2 * 1.7, 0.0, -1.2));
  EXPECT_NEAR(late.t_closest, 0.8, 1e-12);
  EXPECT_EQ(late.side, AvoidSide::STOP);
  // The side it would take is blocked: STOP.
  w = wearer();
  w.left_blocked = true;
  EXPECT_EQ(cp.predict(w, mover(2.5, 3.0, 0.0, -1.2)).side, AvoidSide::STOP);
}

TEST(CrossingPredictor, PerpendicularCrosserThatMisses)
{
  // 3.5 m ahead instead: t* = (3.5 + 3.6) / 2.44, d* = |r0 x vr| / |vr| = 1.2 / sqrt(2.44) = 0.768 m.
  CrossingPredictor cp;
  const CrossingPrediction p = cp.predict(wearer(), mover(3.5, 3.0, 0.0, -1.2));
  EXPECT_NEAR(p.t_closest, 7.1 / 2.44, 1e-12);
  EXPECT_NEAR(p.d_closest, 1.2 / std::sqrt(2.44), 1e-12);
  EXPECT_FALSE(p.warn);
  EXPECT_EQ(p.side, AvoidSide::NONE);
  // With the track's uncertainty counted (1 sigma of 0.3 m across): it warns.
  CrossingParams cautious;
  cautious.sigma_scale = 1.0;
  MoverTrack m = mover(3.5, 3.0, 0.0, -1.2);
  m.P.topLeftCorner<2, 2>() = 0.09 * Eigen::Matrix2d::Identity();
  const CrossingPrediction pc = CrossingPredictor(cautious).predict(wearer(), m);
  EXPECT_NEAR(pc.sigma, 0.3, 1e-12);
  EXPECT_TRUE(pc.warn);
}

TEST(CrossingPredictor, CrosserBeyondTheHorizonIsSilent)
{
  // Collision course at t = 4 s (both at (4, 0)): beyond the 3 s horizon. At 3 s it is still
  // sqrt(1 + 1.44) = 1.56 m away.
  CrossingPredictor cp;
  const CrossingPrediction p = cp.predict(wearer(), mover(4.0, 4.8, 0.0, -1.2));
  EXPECT_NEAR(p.t_closest, 3.0, 1e-12);
  EXPECT_NEAR(p.d_closest, std::sqrt(2.44), 1e-12);
  EXPECT_FALSE(p.warn);
  CrossingParams longer;
  longer.horizon = 5.0;
  const CrossingPrediction q = CrossingPredictor(longer).predict(wearer(), mover(4.0, 4.8, 0.0, -1.2));
  EXPECT_NEAR(q.t_closest, 4.0, 1e-12);
  EXPECT_TRUE(q.warn);
}

TEST(CrossingPredictor, HeadOnWithinOneMetreWarns)
{
  // 4 m ahead, 0.8 m to the left, walking towards the wearer at 1.2 m/s: t* = 4 / 2.2 s,
  // d* = 0.8 (above 0.5, below the 1 m head-on distance). It passes on the left: step right.
  CrossingPredictor cp;
  const CrossingPrediction p = cp.predict(wearer(), mover(4.0, 0.8, -1.2, 0.0));
  EXPECT_NEAR(p.t_closest, 4.0 / 2.2, 1e-12);
  EXPECT_NEAR(p.d_closest, 0.8, 1e-12);
  EXPECT_TRUE(p.head_on);
  EXPECT_TRUE(p.warn);
  EXPECT_EQ(p.side, AvoidSide::RIGHT);
  // Passing on the right: step left; dead centre: keep right.
  EXPECT_EQ(cp.predict(wearer(), mover(4.0, -0.3, -1.2, 0.0)).side, AvoidSide::LEFT);
  EXPECT_EQ(cp.predict(wearer(), mover(4.0, 0.0, -1.2, 0.0)).side, AvoidSide::RIGHT);
  // 1.2 m to the side: passes by, silent.
  EXPECT_FALSE(cp.predict(wearer(), mover(4.0, 1.2, -1.2, 0.0)).warn);
  // 0.8 m off but crossing (not head-on): only the 0.5 m rule applies, silent.
  const CrossingPrediction c = cp.predict(wearer(), mover(2.0 + 0.8 / std::sqrt(2.44) * 1.2, 2.4, 0.0, -1.2));
  EXPECT_FALSE(c.head_on);
}

// Seen in the busy corridor's truth trials: a head-on walker met while the wearer's heading is
// turned 24 deg (sidestepping) has a lateral speed of 0.49 m/s across that heading; it is still
// head-on and passed by its side, and stopping (it walks on into the wearer) is never the advice.
TEST(CrossingPredictor, HeadOnAndOvertakingKeepTheirSideWhenClose)
{
  CrossingPredictor cp;
  Wearer w = wearer();
  w.heading = -24.0 * M_PI / 180.0;
  // 2 m ahead along x, 0.23 m to the left of the wearer, walking -x at 1.2 m/s
  const CrossingPrediction p = cp.predict(w, mover(2.0, 0.23, -1.2, 0.0));
  EXPECT_TRUE(p.head_on);
  EXPECT_TRUE(p.warn);
  // h = (cos, sin)(-24 deg); vr = (-1.2, 0) - h; offset of the closest approach across h
  const Eigen::Vector2d h(std::cos(w.heading), std::sin(w.heading));
  const Eigen::Vector2d r0(2.0, 0.23), vr = Eigen::Vector2d(-1.2, 0.0) - h;
  const double ts = -r0.dot(vr) / vr.squaredNorm();
  const Eigen::Vector2d rc = r0 + ts * vr;
  ASSERT_GT(h.x() * rc.y() - h.y() * rc.x(), 0.0);  // it passes on the wearer's left
  EXPECT_NEAR(p.t_closest, ts, 1e-12);
  EXPECT_EQ(p.side, AvoidSide::RIGHT);
  // 0.8 s from the closest approach (under stop_time): still the side, not STOP
  const CrossingPrediction late = cp.predict(wearer(), mover(1.76, 0.2, -1.2, 0.0));
  EXPECT_NEAR(late.t_closest, 0.8, 1e-12);
  EXPECT_EQ(late.side, AvoidSide::RIGHT);
  // ... unless that side is blocked
  w = wearer();
  w.right_blocked = true;
  EXPECT_EQ(cp.predict(w, mover(1.76, 0.2, -1.2, 0.0)).side, AvoidSide::STOP);
  // Overtaker from behind, 0.62 s away, walking at 30 deg across the heading (lateral 0.75 m/s):
  // not a crosser to pass behind (it is behind): it passes on the left, step right, no STOP.
  const CrossingPrediction o = cp.predict(wearer(), mover(-0.6, -0.3, 1.5 * std::cos(M_PI / 6), 0.75));
  EXPECT_TRUE(o.warn);
  EXPECT_FALSE(o.head_on);
  EXPECT_LT(o.t_closest, 1.0);
  EXPECT_EQ(o.side, AvoidSide::RIGHT);
}

TEST(CrossingPredictor, AlongsideAndAwayAreSilent)
{
  CrossingPredictor cp;
  // Alongside at 0.4 m, same speed and direction: no relative motion.
  CrossingPrediction p = cp.predict(wearer(), mover(0.0, 0.4, 1.0, 0.0));
  EXPECT_NEAR(p.t_closest, 0.0, 1e-12);
  EXPECT_NEAR(p.d_closest, 0.4, 1e-12);
  EXPECT_FALSE(p.warn);
  // Alongside, slightly slower or drifting: closing slower than 0.1 m/s.
  EXPECT_FALSE(cp.predict(wearer(), mover(0.3, 0.45, 0.95, -0.02)).warn);
  // Ahead and faster (walking away), behind and slower, to the side and diverging.
  EXPECT_FALSE(cp.predict(wearer(), mover(1.0, 0.1, 1.5, 0.0)).warn);
  EXPECT_FALSE(cp.predict(wearer(), mover(-1.0, 0.1, 0.8, 0.0)).warn);
  EXPECT_FALSE(cp.predict(wearer(), mover(1.0, 0.4, 1.0, 0.8)).warn);
  // Overtaken from behind by a faster walker on the same line: warns, step aside (it passes on the left).
  const CrossingPrediction o = cp.predict(wearer(), mover(-2.0, 0.2, 2.0, 0.0));
  EXPECT_NEAR(o.t_closest, 2.0, 1e-12);
  EXPECT_TRUE(o.warn);
  EXPECT_EQ(o.side, AvoidSide::RIGHT);
}

TEST(CrossingPredictor, MostUrgentIsTheSoonestWarning)
{
  CrossingPredictor cp;
  const std::vector<MoverTrack> tracks = {mover(3.5, 3.0, 0.0, -1.2, 1),   // misses (0.77 m)
                                          mover(2.5, 3.0, 0.0, -1.2, 2),   // collision at 2.5 s
                                          mover(4.0, 0.3, -1.2, 0.0, 3)};  // head-on at 1.82 s
  const std::vector<CrossingPrediction> p = cp.predict(wearer(), tracks);
  ASSERT_EQ(p.size(), 3u);
  const CrossingPrediction* u = CrossingPredictor::mostUrgent(p);
  ASSERT_NE(u, nullptr);
  EXPECT_EQ(u->track_id, 3);
  EXPECT_EQ(CrossingPredictor::mostUrgent({p[0]}), nullptr);
}
