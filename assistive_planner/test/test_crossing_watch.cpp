// The crossing warning on the planner's side (CrossingWatch, Planner::update with a time): hand-
// computed crossers, people walking alongside or away, stale or missing movers, a blocked side.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "assistive_planner/crossing_watch.h"
#include "assistive_planner/planner.h"

using namespace assistive_planner;

namespace
{
MoverState mover(int id, double x, double y, double vx, double vy)
{
  MoverState m;
  m.id = id;
  m.x << x, y, vx, vy;
  m.P.setZero();  // exact track: the prediction is the mean path
  return m;
}

/// The wearer walked along +x at 1 m/s and stands at (0, 0) at t = 1 s (poses at 0, 0.5, 1 s).
CrossingWatch walking(const PlannerParams& p = PlannerParams())
{
  CrossingWatch w(p);
  w.addPose(0.0, { -1.0, 0.0 });
  w.addPose(0.5, { -0.5, 0.0 });
  w.addPose(1.0, { 0.0, 0.0 });
  return w;
}

Grid freeGrid()
{
  Grid g;
  g.width = g.height = 50;
  g.resolution = 0.2;
  g.origin_x = g.origin_y = -5.0;
  g.data.assign(size_t(50 * 50), CELL_FREE);
  return g;
}
}  // namespace

TEST(CrossingWatch, WalkingSpeedFromRecentPoses)
{
  CrossingWatch w;
  EXPECT_EQ(w.speed(), 0.0);
  w.addPose(0.0, { 0.0, 0.0 });
  EXPECT_EQ(w.speed(), 0.0);               // one pose
  w.addPose(0.25, { 0.3, 0.4 });
  EXPECT_EQ(w.speed(), 0.0);               // 0.25 s < half the 1 s window
  w.addPose(0.5, { 0.6, 0.8 });
  EXPECT_NEAR(w.speed(), 2.0, 1e-12);      // 1 m in 0.5 s
  w.addPose(1.0, { 0.6, 0.8 });
  EXPECT_NEAR(w.speed(), 1.0, 1e-12);      // 1 m in 1 s (the oldest pose within the window)
  w.addPose(1.5, { 0.6, 0.8 });
  EXPECT_NEAR(w.speed(), 0.0, 1e-12);      // standing since 0.5 s
  w.addPose(1.0, { 5.0, 5.0 });            // time went back: earlier poses forgotten
  EXPECT_EQ(w.speed(), 0.0);
}

// A person 3 m to the right of the wearer's line, 2.5 m ahead, walks across at 1.2 m/s; the wearer
// walks on at 1 m/s: both reach (2.5, 0) at t + 2.5 s. r0 = (2.5, -3), vr = (-1, 1.2):
// t* = -r0.vr / |vr|^2 = (2.5 + 3.6) / 2.44 = 2.5 s, d* = 0. The person comes from the right and
// walks to the left: the wearer passes behind, to the right.
TEST(CrossingWatch, HandComputedCrosserGivesTheSideAndTime)
{
  CrossingWatch w = walking();
  EXPECT_NEAR(w.speed(), 1.0, 1e-12);
  w.setMovers(1.0, { mover(7, 2.5, -3.0, 0.0, 1.2) });
  const CrossingResult r = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_TRUE(r.movers_fresh);
  EXPECT_EQ(r.movers, 1);
  EXPECT_EQ(r.advice, CrossingAdvice::RIGHT);
  EXPECT_EQ(r.id, 7);
  EXPECT_NEAR(r.time, 2.5, 1e-12);
  EXPECT_NEAR(r.distance, 0.0, 1e-12);
  EXPECT_NEAR(r.mover_at_closest.x, 2.5, 1e-12);
  EXPECT_NEAR(r.mover_at_closest.y, 0.0, 1e-12);
  EXPECT_NEAR(r.wearer_at_closest.x, 2.5, 1e-12);

  // The mirror image (from the left, walking right): step left.
  w.setMovers(1.0, { mover(8, 2.5, 3.0, 0.0, -1.2) });
  const CrossingResult l = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_EQ(l.advice, CrossingAdvice::LEFT);
  EXPECT_EQ(l.id, 8);
  EXPECT_NEAR(l.time, 2.5, 1e-12);

  // Movers from an image 0.1 s older than the cycle are carried on to the cycle's time: the same
  // person seen 0.12 m further back gives the same answer.
  w.setMovers(0.9, { mover(7, 2.5, -3.12, 0.0, 1.2) });
  const CrossingResult c = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_EQ(c.advice, CrossingAdvice::RIGHT);
  EXPECT_NEAR(c.time, 2.5, 1e-12);
  EXPECT_NEAR(c.distance, 0.0, 1e-12);
}

// Head-on: a person 4 m ahead, 0.3 m to the left, walking towards the wearer at 1 m/s.
// vr = (-2, 0): t* = 8 / 4 = 2 s, d* = 0.3 m (< 1 m head-on): it passes on the left, step right.
TEST(CrossingWatch, HeadOnPassesOnTheLeftStepRight)
{
  CrossingWatch w = walking();
  w.setMovers(1.0, { mover(3, 4.0, 0.3, -1.0, 0.0) });
  const CrossingResult r = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_EQ(r.advice, CrossingAdvice::RIGHT);
  EXPECT_NEAR(r.time, 2.0, 1e-12);
  EXPECT_NEAR(r.distance, 0.3, 1e-12);
}

TEST(CrossingWatch, APersonKeepsTheSideItWasGiven)
{
  // Head-on 0.1 m to the left: step right. A cycle later its track jitters to 0.1 m to the right,
  // which alone says step left: the person keeps "right" while the warning goes on, unless the
  // right is blocked, and a new encounter after crossing_sticky_s is judged afresh.
  CrossingWatch w = walking();
  w.setMovers(1.0, { mover(3, 4.0, 0.1, -1.0, 0.0) });
  EXPECT_EQ(w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::RIGHT);
  w.setMovers(1.1, { mover(3, 3.9, -0.1, -1.0, 0.0) });
  const CrossingResult kept = w.check(1.1, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_EQ(kept.advice, CrossingAdvice::RIGHT);
  EXPECT_EQ(kept.id, 3);
  // another person there is judged on its own
  w.setMovers(1.2, { mover(4, 3.8, -0.1, -1.0, 0.0) });
  EXPECT_EQ(w.check(1.2, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::LEFT);
  // person 3 within crossing_sticky_s (3 s) of its last warning: still right
  w.setMovers(4.0, { mover(3, 3.9, -0.1, -1.0, 0.0) });
  EXPECT_EQ(w.check(4.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::RIGHT);
  // ... unless the right is blocked
  EXPECT_EQ(w.check(4.0, { 0.0, 0.0 }, 0.0, 2.0, 0.4).advice, CrossingAdvice::LEFT);
  // after more than 3 s without a warning: judged afresh
  w.setMovers(1.0, { mover(5, 4.0, 0.1, -1.0, 0.0) });
  EXPECT_EQ(w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::RIGHT);  // (time went back: forgotten)
  w.setMovers(4.5, { mover(5, 3.9, -0.1, -1.0, 0.0) });
  EXPECT_EQ(w.check(4.5, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::LEFT);
  // and with crossing_sticky_s 0 every cycle is judged afresh
  PlannerParams p;
  p.crossing_sticky_s = 0.0;
  CrossingWatch fresh = walking(p);
  fresh.setMovers(1.0, { mover(3, 4.0, 0.1, -1.0, 0.0) });
  EXPECT_EQ(fresh.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::RIGHT);
  fresh.setMovers(1.1, { mover(3, 3.9, -0.1, -1.0, 0.0) });
  EXPECT_EQ(fresh.check(1.1, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::LEFT);
}

// People walking alongside, ahead and faster, away, or standing well aside: no advice.
TEST(CrossingWatch, AlongsideOrAwayGivesNone)
{
  CrossingWatch w = walking();
  const std::vector<std::pair<const char*, MoverState>> cases = {
    { "alongside, 1 m to the left, same speed", mover(1, 0.0, 1.0, 1.0, 0.0) },
    { "alongside, 0.6 m to the right, same speed", mover(2, 0.5, -0.6, 1.0, 0.0) },
    { "ahead, walking away faster", mover(3, 2.0, 0.0, 1.5, 0.0) },
    { "behind, walking away", mover(4, -2.0, 0.2, -1.0, 0.0) },
    { "crossing far ahead (passes 2 m in front)", mover(5, 4.5, -3.0, 0.0, 1.2) },
    { "standing 2 m to the side", mover(6, 2.0, 2.0, 0.0, 0.0) },
  };
  for (const auto& c : cases)
  {
    w.setMovers(1.0, { c.second });
    const CrossingResult r = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
    EXPECT_TRUE(r.movers_fresh) << c.first;
    EXPECT_EQ(r.advice, CrossingAdvice::NONE) << c.first << " t " << r.time;
    EXPECT_EQ(r.id, 0) << c.first;
    EXPECT_EQ(r.time, 0.0) << c.first;
  }
  // all of them at once, and nobody at all: still none
  std::vector<MoverState> all;
  for (const auto& c : cases) all.push_back(c.second);
  w.setMovers(1.0, all);
  EXPECT_EQ(w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::NONE);
  w.setMovers(1.0, {});
  const CrossingResult none = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_TRUE(none.movers_fresh);
  EXPECT_EQ(none.advice, CrossingAdvice::NONE);
}

// Never a stale warning: movers never received, older or newer than crossing_max_age_s (0.5 s)
// against the cycle's time, or cleared give none; exactly 0.5 s old still counts.
TEST(CrossingWatch, StaleOrMissingMoversGiveNone)
{
  CrossingWatch w = walking();
  CrossingResult r = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_FALSE(r.movers_fresh);
  EXPECT_EQ(r.advice, CrossingAdvice::NONE);

  struct Age
  {
    double stamp;
    bool fresh;
  };
  // the crosser of HandComputedCrosser, placed where it was at `stamp` so that it is exact at t = 1
  for (const Age& a : { Age{ 1.0, true }, Age{ 0.5, true }, Age{ 0.49, false }, Age{ 0.0, false },
                        Age{ 1.5, true }, Age{ 1.51, false }, Age{ -30.0, false } })
  {
    w.setMovers(a.stamp, { mover(7, 2.5, -3.0 - 1.2 * (1.0 - a.stamp), 0.0, 1.2) });
    r = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
    EXPECT_EQ(r.movers_fresh, a.fresh) << a.stamp;
    EXPECT_EQ(r.advice, a.fresh ? CrossingAdvice::RIGHT : CrossingAdvice::NONE) << a.stamp;
    if (a.fresh)
    {
      EXPECT_NEAR(r.time, 2.5, 1e-9) << a.stamp;
    }
  }
  w.setMovers(1.0, { mover(7, 2.5, -3.0, 0.0, 1.2) });
  w.clearMovers();
  EXPECT_EQ(w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::NONE);
  w.setMovers(std::nan(""), { mover(7, 2.5, -3.0, 0.0, 1.2) });
  EXPECT_EQ(w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0).advice, CrossingAdvice::NONE);
  // a mover with a non-finite state is dropped, the others judged
  w.setMovers(1.0, { mover(9, std::nan(""), 0.0, 0.0, 0.0), mover(7, 2.5, -3.0, 0.0, 1.2) });
  r = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_EQ(r.movers, 1);
  EXPECT_EQ(r.advice, CrossingAdvice::RIGHT);
}

// The side to pass behind the crosser (the right) has only 0.5 m of free floor (< 0.6 m): stop.
// The other side being blocked changes nothing. Closer than the predictor's stop_time (1 s): stop.
TEST(CrossingWatch, BlockedSideGivesStop)
{
  CrossingWatch w = walking();
  w.setMovers(1.0, { mover(7, 2.5, -3.0, 0.0, 1.2) });
  CrossingResult r = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 0.5);
  EXPECT_EQ(r.advice, CrossingAdvice::STOP);
  EXPECT_EQ(r.id, 7);
  EXPECT_NEAR(r.time, 2.5, 1e-12);
  EXPECT_EQ(w.check(1.0, { 0.0, 0.0 }, 0.0, 0.5, 2.0).advice, CrossingAdvice::RIGHT);
  EXPECT_EQ(w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 0.6).advice, CrossingAdvice::RIGHT);  // 0.6 m is room

  // 0.8 s away (both reach (0.8, 0)): r0 = (0.8, -0.96), vr = (-1, 1.2): t* = 0.8 s < 1 s
  w.setMovers(1.0, { mover(4, 0.8, -0.96, 0.0, 1.2) });
  r = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_EQ(r.advice, CrossingAdvice::STOP);
  EXPECT_NEAR(r.time, 0.8, 1e-12);
}

// The most urgent of several: the sooner closest approach wins.
TEST(CrossingWatch, MostUrgentWins)
{
  CrossingWatch w = walking();
  w.setMovers(1.0, { mover(7, 2.5, -3.0, 0.0, 1.2), mover(8, 2.0, 2.4, 0.0, -1.2), mover(9, 0.0, 1.0, 1.0, 0.0) });
  const CrossingResult r = w.check(1.0, { 0.0, 0.0 }, 0.0, 2.0, 2.0);
  EXPECT_EQ(r.movers, 3);
  EXPECT_EQ(r.id, 8);  // from the left, meets at (2, 0) after 2 s
  EXPECT_EQ(r.advice, CrossingAdvice::LEFT);
  EXPECT_NEAR(r.time, 2.0, 1e-12);
}

// The planning cycle fills PlanOutput.crossing: heading from the motion vector, speed from the poses
// it was given, blocked sides from its own grid; no time, no advice.
TEST(CrossingWatch, PlannerCycleFillsTheAdvice)
{
  Grid g = freeGrid();
  Planner pl;
  pl.update(g, { -1.0, 0.0 }, 0.0, 0.0);
  pl.update(g, { -0.5, 0.0 }, 0.0, 0.5);
  pl.setMovers(1.0, { mover(7, 2.5, -3.0, 0.0, 1.2) });
  PlanOutput o = pl.update(g, { 0.0, 0.0 }, 0.0, 1.0);
  ASSERT_EQ(o.status, PlanStatus::OK) << o.message;
  EXPECT_NEAR(o.heading, 0.0, 1e-12);
  EXPECT_EQ(o.crossing.advice, CrossingAdvice::RIGHT);
  EXPECT_EQ(o.crossing.id, 7);
  EXPECT_NEAR(o.crossing.time, 2.5, 1e-12);
  EXPECT_NEAR(o.crossing.distance, 0.0, 1e-12);
  EXPECT_NEAR(o.crossing.wearer_speed, 1.0, 1e-12);

  // without a time the cycle gives no advice
  EXPECT_EQ(pl.update(g, { 0.0, 0.0 }, 0.0).crossing.advice, CrossingAdvice::NONE);

  // a box 0.4 m to the right of the wearer: free_right 0.4 m < 0.6 m: stop
  Grid b = g;
  for (int y = 0; y < b.height; ++y)
    for (int x = 0; x < b.width; ++x)
      if (std::abs(b.cellX(x)) < 0.3 && b.cellY(y) < -0.4 && b.cellY(y) > -0.8)
        b.data[size_t(b.index(x, y))] = CELL_OBSTACLE;
  Planner pb;
  pb.update(b, { -1.0, 0.0 }, 0.0, 0.0);
  pb.update(b, { -0.5, 0.0 }, 0.0, 0.5);
  pb.setMovers(1.0, { mover(7, 2.5, -3.0, 0.0, 1.2) });
  o = pb.update(b, { 0.0, 0.0 }, 0.0, 1.0);
  EXPECT_LT(o.free_right, 0.6);
  EXPECT_EQ(o.crossing.advice, CrossingAdvice::STOP);
  EXPECT_NEAR(o.crossing.time, 2.5, 1e-12);

  // movers 0.6 s older than the cycle: none
  pb.setMovers(0.4, { mover(7, 2.5, -3.72, 0.0, 1.2) });
  o = pb.update(b, { 0.0, 0.0 }, 0.0, 1.0);
  EXPECT_EQ(o.crossing.advice, CrossingAdvice::NONE);
  EXPECT_FALSE(o.crossing.movers_fresh);
}
