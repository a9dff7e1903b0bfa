// Motion vector and waypoint rules (seed 4.3.1).
#include <gtest/gtest.h>

#include <cmath>

#include "assistive_planner/motion_vector.h"
#include "assistive_planner/waypoint_selector.h"
#include "grid_fixtures.h"

using namespace assistive_planner;

namespace
{
constexpr double DEG = M_PI / 180.0;

// 10 m x 10 m free grid at 0.2 m, origin (-5, -5): the wearer at (0, 0) is the centre.
Grid freeGrid() { return planner_test::freeGrid(-5.0, -5.0, 50); }
using planner_test::fillRect;
}  // namespace

TEST(MotionVector, SmallHeadTurnKeepsHeadingLargeTurnMovesIt)
{
  MotionVector mv;
  mv.update({ 0, 0 }, 0.0);
  EXPECT_NEAR(mv.heading(), 0.0, 1e-12);
  EXPECT_FALSE(mv.update({ 0, 0 }, 14.0 * DEG));
  EXPECT_NEAR(mv.heading(), 0.0, 1e-12);
  EXPECT_FALSE(mv.update({ 0, 0 }, -14.0 * DEG));
  EXPECT_NEAR(mv.heading(), 0.0, 1e-12);
  EXPECT_TRUE(mv.update({ 0, 0 }, 16.0 * DEG));
  EXPECT_NEAR(mv.heading(), 16.0 * DEG, 1e-12);
  EXPECT_TRUE(mv.update({ 0, 0 }, M_PI));
  EXPECT_NEAR(std::abs(mv.heading()), M_PI, 1e-12);
}

TEST(MotionVector, PositionMovesOnlyAfterOneMetre)
{
  // the seed's rule alone (heading_chord_min 0): the heading waits for 1 m of travel
  PlannerParams p;
  p.heading_chord_min = 0.0;
  MotionVector mv(p);
  mv.update({ 0, 0 }, 0.0);
  mv.update({ 0.7, 0.7 }, 0.0);  // 0.99 m: anchor stays
  EXPECT_NEAR(mv.anchor().x, 0.0, 1e-12);
  EXPECT_NEAR(mv.heading(), 0.0, 1e-12);
  mv.update({ 0.0, 1.1 }, 0.0);  // 1.1 m to the left: heading follows the travel
  EXPECT_NEAR(mv.anchor().y, 1.1, 1e-12);
  EXPECT_NEAR(mv.heading(), M_PI_2, 1e-9);
}

TEST(MotionVector, TheWalkedChordIsTheHeadingFrom30cm)
{
  // default heading_chord_min 0.3 m: the anchor still moves only after 1 m, but the heading is the
  // walked chord as soon as it is 0.3 m long, whatever the head's yaw at the last update was
  MotionVector mv;
  mv.update({ 0, 0 }, 0.0);
  EXPECT_FALSE(mv.update({ 0.2, 0.0 }, 0.0));
  EXPECT_NEAR(mv.heading(), 0.0, 1e-12);
  EXPECT_TRUE(mv.update({ 0.2, 0.0 }, 20.0 * DEG));  // a turn caught mid-way: heading = head yaw, anchor here
  EXPECT_NEAR(mv.heading(), 20.0 * DEG, 1e-12);
  EXPECT_NEAR(mv.anchor().x, 0.2, 1e-12);
  // the body turned on to -10 deg (head within 15 deg of the last update: no head-turn update)
  const double w = -10.0 * DEG;
  EXPECT_FALSE(mv.update({ 0.2 + 0.29 * std::cos(w), 0.29 * std::sin(w) }, 8.0 * DEG));
  EXPECT_NEAR(mv.heading(), 20.0 * DEG, 1e-12);  // 0.29 m: not yet
  EXPECT_FALSE(mv.update({ 0.2 + 0.31 * std::cos(w), 0.31 * std::sin(w) }, 8.0 * DEG));
  EXPECT_NEAR(mv.heading(), w, 1e-9);  // 0.31 m: the direction actually walked
  EXPECT_NEAR(mv.anchor().x, 0.2, 1e-12);
  // an 0.7 m diagonal (0.99 m) walk: the chord, anchor unmoved
  MotionVector d;
  d.update({ 0, 0 }, 0.0);
  d.update({ 0.7, 0.7 }, 0.0);
  EXPECT_NEAR(d.heading(), M_PI_4, 1e-9);
  EXPECT_NEAR(d.anchor().x, 0.0, 1e-12);
}

TEST(MotionVector, ATurnOnTheSpotStartsTheNextChordThere)
{
  // walk 0.9 m along x, turn on the spot to +90 deg, walk 1.05 m along y: the heading is the
  // direction walked since the turn, not the chord across it (atan2(1.05, 0.9) = 49 deg)
  MotionVector mv;
  mv.update({ 0, 0 }, 0.0);
  mv.update({ 0.9, 0 }, 0.0);
  EXPECT_TRUE(mv.update({ 0.9, 0 }, M_PI_2));
  EXPECT_NEAR(mv.anchor().x, 0.9, 1e-12);
  EXPECT_TRUE(mv.update({ 0.9, 1.05 }, M_PI_2));
  EXPECT_NEAR(mv.heading(), M_PI_2, 1e-9);
}

TEST(Triangle, FarthestFreeCellAndUnknownIsNotFree)
{
  Grid g = freeGrid();
  const auto s = searchTriangle(g, { 0.1, 0.1 }, 0.0, 3.0, 30.0 * DEG);
  ASSERT_TRUE(s.found);
  EXPECT_NEAR(g.cellX(s.x), 3.1, 0.11);
  EXPECT_NEAR(g.cellY(s.y), 0.1, 0.11);
  // unknown beyond 1.5 m ahead: the waypoint stays in known free space
  fillRect(g, 1.5, -5, 5, 5, CELL_UNKNOWN);
  const auto u = searchTriangle(g, { 0.1, 0.1 }, 0.0, 3.0, 30.0 * DEG);
  ASSERT_TRUE(u.found);
  EXPECT_LT(g.cellX(u.x), 1.5);
  EXPECT_LT(u.area, s.area);
}

TEST(WaypointSelector, HeadTurnUnder15DegreesDoesNotMoveWaypoint)
{
  Grid g = freeGrid();
  PlannerParams p;
  MotionVector mv(p);
  WaypointSelector ws(p);
  const Point2 w{ 0.1, 0.1 };
  mv.update(w, 0.0);
  ASSERT_TRUE(ws.update(g, w, mv.heading()));
  const Point2 first = ws.waypoint();
  EXPECT_GT(first.x, 3.5);
  for (double yaw : { 5.0, 10.0, 14.5, -14.5 })
  {
    mv.update(w, yaw * DEG);
    ASSERT_TRUE(ws.update(g, w, mv.heading()));
    EXPECT_FALSE(ws.switched()) << yaw;
    EXPECT_DOUBLE_EQ(ws.waypoint().x, first.x);
    EXPECT_DOUBLE_EQ(ws.waypoint().y, first.y);
  }
}

TEST(WaypointSelector, TurnAroundMovesWaypoint)
{
  Grid g = freeGrid();
  // a corridor along x: walls at |y| > 0.7
  fillRect(g, -5, 0.8, 5, 5, CELL_OBSTACLE);
  fillRect(g, -5, -5, 5, -0.8, CELL_OBSTACLE);
  PlannerParams p;
  MotionVector mv(p);
  WaypointSelector ws(p);
  const Point2 w{ 0.1, 0.1 };
  mv.update(w, 0.0);
  ASSERT_TRUE(ws.update(g, w, mv.heading()));
  EXPECT_GT(ws.waypoint().x, 3.0);
  mv.update(w, M_PI);  // turn around
  ASSERT_TRUE(ws.update(g, w, mv.heading()));
  EXPECT_TRUE(ws.switched());
  EXPECT_LT(ws.waypoint().x, -3.0);
}

TEST(WaypointSelector, SmallerFreeAreaDoesNotReplaceWaypoint)
{
  Grid g = freeGrid();
  PlannerParams p;
  MotionVector mv(p);
  WaypointSelector ws(p);
  const Point2 w{ 0.1, 0.1 };
  // wide open ahead (+x); to the left (+y) a narrow 0.4 m slot between obstacles
  fillRect(g, -5, 0.5, -0.5, 5, CELL_OBSTACLE);
  fillRect(g, 0.7, 0.5, 5, 5, CELL_OBSTACLE);
  mv.update(w, 0.0);
  ASSERT_TRUE(ws.update(g, w, mv.heading()));
  const Point2 first = ws.waypoint();
  const double first_area = ws.area();
  EXPECT_GT(first.x, 3.0);
  // the wearer turns 60 degrees left: the heading moves (> 15 deg), the candidate lies in the slot
  mv.update(w, 60.0 * DEG);
  EXPECT_NEAR(mv.heading(), 60.0 * DEG, 1e-12);
  ASSERT_TRUE(ws.update(g, w, mv.heading()));
  const auto& cand = ws.lastSearch();
  ASSERT_TRUE(cand.found);
  EXPECT_GT(g.cellY(cand.y), 1.0);  // the candidate is up the slot...
  EXPECT_FALSE(ws.switched());      // ...but its free area is smaller: the waypoint stays
  EXPECT_DOUBLE_EQ(ws.waypoint().x, first.x);
  EXPECT_DOUBLE_EQ(ws.waypoint().y, first.y);
  EXPECT_NEAR(ws.area(), first_area, 1e-9);
  // and a larger area does replace it: open the slot wide
  fillRect(g, -5, 0.5, 5, 5, CELL_FREE);
  fillRect(g, -5, -5, 5, -0.3, CELL_OBSTACLE);
  ASSERT_TRUE(ws.update(g, w, mv.heading()));
  EXPECT_TRUE(ws.switched());
  EXPECT_GT(ws.waypoint().y, 1.5);
}

TEST(WaypointSelector, ReachedWaypointIsReplaced)
{
  Grid g = freeGrid();
  WaypointSelector ws;
  ASSERT_TRUE(ws.update(g, { 0.1, 0.1 }, 0.0));
  const Point2 wp = ws.waypoint();
  ASSERT_TRUE(ws.update(g, { wp.x - 0.2, wp.y }, 0.0));  // 0.2 m short: reached; the next one is ahead/inside
  EXPECT_TRUE(ws.switched());
}

TEST(WaypointSelector, KeptUntilTheWearerMovesOneMetre)
{
  Grid g = freeGrid();
  PlannerParams p;
  MotionVector mv(p);
  WaypointSelector ws(p);
  ASSERT_TRUE(ws.update(g, { 0.1, 0.1 }, mv.heading(), mv.update({ 0.1, 0.1 }, 0.0)));
  const Point2 first = ws.waypoint();
  // 0.6 m forward: the motion vector does not update, the waypoint stays although a farther one exists
  const bool moved = mv.update({ 0.7, 0.1 }, 0.0);
  EXPECT_FALSE(moved);
  ASSERT_TRUE(ws.update(g, { 0.7, 0.1 }, mv.heading(), moved));
  EXPECT_FALSE(ws.switched());
  EXPECT_DOUBLE_EQ(ws.waypoint().x, first.x);
  // 1.2 m forward: the motion vector updates and the farther waypoint with the larger free area wins
  const bool moved2 = mv.update({ 1.3, 0.1 }, 0.0);
  EXPECT_TRUE(moved2);
  ASSERT_TRUE(ws.update(g, { 1.3, 0.1 }, mv.heading(), moved2));
  EXPECT_TRUE(ws.switched());
  EXPECT_GT(ws.waypoint().x, first.x + 0.5);
}

TEST(TriangleSearch, FreeFloorBeyondUnmappedFloorIsNotWalledOff)
{
  // After a map reset the floor at the feet lies below the camera's view: free floor 1-3 m ahead,
  // an unmapped band between it and the wearer. Its cells are not reachable over mapped floor, but
  // not walled off either: "free space but no path" (an ALERT) would be a guess.
  Grid g = freeGrid();
  fillRect(g, -5.0, -5.0, 5.0, 5.0, CELL_UNKNOWN);
  fillRect(g, -0.1, -0.1, 0.1, 0.1, CELL_FREE);  // the wearer's footprint
  fillRect(g, 1.0, -1.0, 3.0, 1.0, CELL_FREE);
  const TriangleSearch open = searchTriangle(g, { 0.0, 0.0 }, 0.0, 4.0, 30.0 * DEG);
  EXPECT_FALSE(open.found);
  EXPECT_GT(open.free_behind_unknown, 0u);
  EXPECT_EQ(open.unreachable_free, 0u);
  // the same free floor behind a wall across the whole window: walled off
  fillRect(g, 0.5, -5.0, 0.7, 5.0, CELL_OBSTACLE);
  const TriangleSearch walled = searchTriangle(g, { 0.0, 0.0 }, 0.0, 4.0, 30.0 * DEG);
  EXPECT_EQ(walled.free_behind_unknown, 0u);
  EXPECT_GT(walled.unreachable_free, 0u);
  EXPECT_EQ(open.free_behind_unknown, walled.unreachable_free);
}
