// The planning cycle: statuses, paths around obstacles, unknown handling, scrolling windows.
#include <gtest/gtest.h>

#include <cmath>

#include "assistive_planner/cost_model.h"
#include "assistive_planner/planner.h"
#include "grid_fixtures.h"

using namespace assistive_planner;

namespace
{
Grid makeGrid(double ox, double oy, int n = 50) { return planner_test::freeGrid(ox, oy, n); }
using planner_test::fillRect;
using planner_test::plannedCell;
}  // namespace

// A doorway of 0.8 m of free cells in a wall across the path, the path 0.2 m off its middle:
// found 2 m along, its middle on the 5 cm field (not on the 0.2 m cells the path runs on), 1.0 m
// wide (the jambs fill the cells they touch: their faces lie half a cell in on average); a wall
// on one side only and a 1.2 m gap of free cells (1.4 m) are no passage.
TEST(Planner, FindPassageFindsADoorwaysMiddle)
{
  Grid g = makeGrid(-5, -5);
  fillRect(g, 1.89, -5.0, 2.11, -0.29, CELL_OBSTACLE);  // cells up to y = -0.3: edge at -0.2
  fillRect(g, 1.89, 0.69, 2.11, 5.0, CELL_OBSTACLE);  // cells from y = 0.7: edge at 0.6
  const std::vector<Point2> path{ { 0.0, 0.0 }, { 4.0, 0.0 } };
  const Passage p = Planner::findPassage(g, path, 0.0, 3.0, 1.1);
  ASSERT_TRUE(p.found);
  EXPECT_NEAR(p.middle.y, 0.2, 0.03);
  EXPECT_NEAR(p.middle.x, 2.0, 0.15);  // in the wall's 0.2 m depth
  EXPECT_NEAR(p.along, p.middle.x, 1e-9);
  EXPECT_NEAR(p.width, 1.0, 0.05);
  EXPECT_NEAR(p.axis, 0.0, 1e-6);
  // beyond the search range, or started past it: none
  EXPECT_FALSE(Planner::findPassage(g, path, 0.0, 1.0, 1.1).found);
  EXPECT_FALSE(Planner::findPassage(g, path, 2.8, 1.2, 1.1).found);

  Grid one = makeGrid(-5, -5);
  fillRect(one, -5.0, 0.49, 5.0, 5.0, CELL_OBSTACLE);  // a wall 0.4 m beside the path, nothing on the other side
  EXPECT_FALSE(Planner::findPassage(one, path, 0.0, 3.0, 1.1).found);

  Grid wide = makeGrid(-5, -5);
  fillRect(wide, 1.89, -5.0, 2.11, -0.69, CELL_OBSTACLE);  // edge at -0.6
  fillRect(wide, 1.89, 0.69, 2.11, 5.0, CELL_OBSTACLE);  // edge at 0.6: 1.2 m of free cells, 1.4 m
  EXPECT_FALSE(Planner::findPassage(wide, path, 0.0, 3.0, 1.3).found);
  EXPECT_TRUE(Planner::findPassage(wide, path, 0.0, 3.0, 1.5).found);
}

// The passage's axis is the doorway's own (across its jamb-to-jamb line), not the path's: a path
// that crosses a doorway in a wall along y on the slant (40 deg) gets the wall's normal, the way
// the path goes; an aisle between two long shelves gets the aisle's direction. The cue logic
// squares the wearer up on it.
TEST(Planner, FindPassageGivesTheDoorwaysOwnAxis)
{
  Grid g = makeGrid(-5, -5);
  fillRect(g, 1.89, -5.0, 2.11, -0.29, CELL_OBSTACLE);
  fillRect(g, 1.89, 0.69, 2.11, 5.0, CELL_OBSTACLE);
  for (double slant_deg : { 40.0, -40.0 })
  {
    const double a = slant_deg * M_PI / 180.0;
    const Point2 mid{ 2.0, 0.2 };
    // through the middle on the slant, both ways
    const std::vector<Point2> fwd{ { mid.x - 1.5 * std::cos(a), mid.y - 1.5 * std::sin(a) },
                                   { mid.x + 1.5 * std::cos(a), mid.y + 1.5 * std::sin(a) } };
    const Passage p = Planner::findPassage(g, fwd, 0.0, 3.0, 1.1);
    ASSERT_TRUE(p.found) << slant_deg;
    EXPECT_NEAR(p.axis, 0.0, 3.0 * M_PI / 180.0) << slant_deg;
    const std::vector<Point2> back{ fwd[1], fwd[0] };
    const Passage q = Planner::findPassage(g, back, 0.0, 3.0, 1.1);
    ASSERT_TRUE(q.found) << slant_deg;
    EXPECT_NEAR(std::fabs(q.axis), M_PI, 3.0 * M_PI / 180.0) << slant_deg;
  }
  // an aisle 1.0 m of free cells wide along y, 4 m long: its axis runs along it
  Grid aisle = makeGrid(-5, -5);
  fillRect(aisle, -1.11, -2.0, -0.51, 2.0, CELL_OBSTACLE);
  fillRect(aisle, 0.49, -2.0, 1.11, 2.0, CELL_OBSTACLE);
  const Passage r = Planner::findPassage(aisle, { { 0.0, -3.0 }, { 0.2, 3.0 } }, 0.0, 3.0, 1.3);
  ASSERT_TRUE(r.found);
  EXPECT_NEAR(r.axis, M_PI / 2.0, 3.0 * M_PI / 180.0);
}

namespace
{
/// Marks every cell whose square overlaps [x0, x1] x [y0, y1] an obstacle, as the truth map and
/// the obstacle stage do (a solid fills every cell it touches).
void fillSolid(Grid& g, double x0, double y0, double x1, double y1)
{
  const double h = 0.5 * g.resolution;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x)
      if (g.cellX(x) + h > x0 && g.cellX(x) - h < x1 && g.cellY(y) + h > y0 && g.cellY(y) - h < y1)
        g.data[size_t(g.index(x, y))] = CELL_OBSTACLE;
}

/// A 0.1 m wall across x = 2 with a doorway [lo, hi] in it, drawn on 0.2 m cells.
Grid doorwayGrid(double lo, double hi)
{
  Grid g = makeGrid(-5, -5);
  fillSolid(g, 1.95, -5.0, 2.05, lo);
  fillSolid(g, 1.95, hi, 2.05, 5.0);
  return g;
}

/// Where the polyline crosses x = `at` (NaN when it does not).
double crossingY(const std::vector<Point2>& path, double at)
{
  for (size_t i = 1; i < path.size(); ++i)
  {
    const Point2 &a = path[i - 1], &b = path[i];
    if ((a.x - at) * (b.x - at) <= 0.0 && std::abs(b.x - a.x) > 1e-9)
      return a.y + (b.y - a.y) * (at - a.x) / (b.x - a.x);
  }
  return std::nan("");
}
}  // namespace

// Issue 33: an 0.80 m doorway drawn on 0.2 m cells leaves 0.6 m of free cells wherever its jambs
// fall in the cells; the planner reports it 0.80 m wide (within 0.1 m), its middle within half a
// cell, and the path runs through that middle, not along the cells' centres.
TEST(Planner, AnEightyCentimetreDoorwayIsReportedEightyWideAndPassedThroughItsMiddle)
{
  for (double lo : { -0.39, -0.33, -0.27, -0.22, -0.11, 0.03, 0.17 })
  {
    const double hi = lo + 0.80, middle = lo + 0.40;
    const Grid g = doorwayGrid(lo, hi);
    const std::vector<Point2> line{ { 0.0, middle }, { 4.0, middle } };
    const Passage ps = Planner::findPassage(g, line, 0.0, 3.0, 1.1);
    ASSERT_TRUE(ps.found) << lo;
    EXPECT_NEAR(ps.width, 0.80, 0.1) << lo;
    EXPECT_NEAR(ps.middle.y, middle, 0.1) << lo;
    EXPECT_NEAR(ps.middle.x, 2.0, 0.15) << lo;

    Planner pl;
    pl.setGoal({ 4.0, middle });
    const PlanOutput o = pl.update(g, { 0.0, middle }, 0.0);
    ASSERT_EQ(o.status, PlanStatus::OK) << o.message;
    const double y = crossingY(o.path, 2.0);
    ASSERT_TRUE(std::isfinite(y)) << lo;
    EXPECT_NEAR(y, middle, 0.1) << lo;  // through the doorway's middle (within half a cell)
    EXPECT_GE(o.passage_distance, 0.0) << lo;
    EXPECT_NEAR(o.passage_width, 0.80, 0.1) << lo;
  }
  // 0.85 and 0.90 m: 0.6 or 0.8 m of free cells, depending on where the jambs fall; reported
  // within half a cell either way (0.80 or 1.00 m)
  for (double w : { 0.85, 0.90 })
    for (double lo : { -0.39, -0.30, -0.22, -0.11 })
    {
      const Passage ps = Planner::findPassage(doorwayGrid(lo, lo + w), { { 0.0, lo + 0.5 * w }, { 4.0, lo + 0.5 * w } },
                                              0.0, 3.0, 1.1);
      ASSERT_TRUE(ps.found) << w << " " << lo;
      EXPECT_NEAR(ps.width, w, 0.15 + 1e-9) << w << " " << lo;
    }
}

TEST(Planner, NoMapAndInUnknownAtStartUp)
{
  Planner pl;
  EXPECT_EQ(pl.update(Grid(), { 0, 0 }, 0.0).status, PlanStatus::NO_MAP);
  Grid g = makeGrid(-5, -5);
  fillRect(g, -1, -1, 1, 1, CELL_UNKNOWN);
  const PlanOutput o = pl.update(g, { 0.1, 0.1 }, 0.0);
  EXPECT_EQ(o.status, PlanStatus::IN_UNKNOWN);
  EXPECT_TRUE(o.path.empty());
}

TEST(Planner, PathAroundWallToWaypoint)
{
  PlannerParams p;
  p.clearance_weight = 0.0;
  Planner pl(p);
  Grid g = makeGrid(-5, -5);
  fillRect(g, 1.5, -1.0, 1.7, 1.0, CELL_OBSTACLE);  // a wall across the way ahead
  const PlanOutput o = pl.update(g, { 0.1, 0.1 }, 0.0);
  ASSERT_EQ(o.status, PlanStatus::OK) << o.message;
  EXPECT_GT(o.waypoint.x, 3.0);
  ASSERT_GE(o.path.size(), 3u);
  EXPECT_NEAR(o.path.back().x, o.waypoint.x, 1e-9);
  for (const auto& q : o.path)
  {
    int x, y;
    ASSERT_TRUE(g.worldToCell(q.x, q.y, x, y));
    EXPECT_NE(g.at(x, y), CELL_OBSTACLE);
  }
  EXPECT_GT(o.path_length, o.waypoint_distance);
  EXPECT_GT(std::abs(o.path_heading), 0.2);  // the path bends around the wall
  // standing: what lies ahead is judged along the steering heading (round the wall's end)
  EXPECT_GT(std::abs(o.steer_heading), 0.2);
  EXPECT_GT(o.free_ahead, 1.5);
  // walking straight at the wall (poses 0.4 s apart): along the walk, the wall starts at 1.5 m
  // (cell edges at 1.4)
  Planner w(p);
  w.update(g, { -0.3, 0.1 }, 0.0, 10.0);
  const PlanOutput ow = w.update(g, { 0.1, 0.1 }, 0.0, 10.4);
  EXPECT_NEAR(ow.walking_speed, 1.0, 1e-9);
  EXPECT_NEAR(ow.walk_heading, 0.0, 1e-9);
  EXPECT_NEAR(ow.free_ahead, 1.3, 0.2);
}

TEST(Planner, UnmappedFloorCloseAheadIsUnknownNotAnObstacle)
{
  // After a map reset the floor just ahead is still unmapped: closer than unknown_ahead_m it gives
  // IN_UNKNOWN (vest quiet), not a free distance the cue logic would read as an obstacle. A real
  // obstacle at the same distance still gives OK with that free distance, and unmapped floor
  // farther away than unknown_ahead_m changes nothing.
  Grid g = makeGrid(-5, -5);
  fillRect(g, 0.7, -1.0, 1.1, 1.0, CELL_UNKNOWN);
  PlanOutput o = Planner().update(g, { 0.1, 0.1 }, 0.0);
  EXPECT_EQ(o.status, PlanStatus::IN_UNKNOWN) << o.message;
  EXPECT_NE(o.message.find("unmapped floor"), std::string::npos) << o.message;
  EXPECT_NEAR(o.free_ahead, 0.5, 0.1);
  PlannerParams off;
  off.unknown_ahead_m = 0.0;
  EXPECT_NE(Planner(off).update(g, { 0.1, 0.1 }, 0.0).status, PlanStatus::IN_UNKNOWN);

  Grid wall = makeGrid(-5, -5);
  fillRect(wall, 0.7, -1.0, 1.1, 1.0, CELL_OBSTACLE);
  Planner walker;  // walking at it (the free distance ahead is the walk's)
  walker.update(wall, { -0.3, 0.1 }, 0.0, 10.0);
  o = walker.update(wall, { 0.1, 0.1 }, 0.0, 10.4);
  EXPECT_EQ(o.status, PlanStatus::OK) << o.message;
  EXPECT_NEAR(o.free_ahead, 0.5, 0.1);

  Grid far = makeGrid(-5, -5);
  fillRect(far, 1.5, -1.0, 1.9, 1.0, CELL_UNKNOWN);
  o = Planner().update(far, { 0.1, 0.1 }, 0.0);
  EXPECT_EQ(o.status, PlanStatus::OK) << o.message;
  EXPECT_NEAR(o.free_ahead, 1.3, 0.1);
}

TEST(Planner, NeverThroughUnknownWhenKnownPathExists)
{
  PlannerParams p;
  p.clearance_weight = 0.0;
  Planner pl(p);
  Grid g = makeGrid(-5, -5);
  fillRect(g, 1.5, -3.0, 1.7, 3.0, CELL_OBSTACLE);
  fillRect(g, 1.5, -0.3, 1.7, 0.3, CELL_UNKNOWN);  // a short unknown gap in the wall
  const PlanOutput o = pl.update(g, { 0.1, 0.1 }, 0.0);
  ASSERT_EQ(o.status, PlanStatus::OK);
  EXPECT_FALSE(o.path_through_unknown);
  for (const auto& q : o.path)
  {
    int x, y;
    g.worldToCell(q.x, q.y, x, y);
    EXPECT_NE(g.at(x, y), CELL_UNKNOWN);
  }
  // close the known way round: now the unknown gap is the only way and the status says so
  fillRect(g, 1.5, -5, 1.7, 5, CELL_OBSTACLE);
  fillRect(g, 1.5, -0.3, 1.7, 0.3, CELL_UNKNOWN);
  // the waypoint stays beyond the wall only if reachable through known cells: it is not, so a new one is chosen
  const PlanOutput o2 = pl.update(g, { 0.1, 0.1 }, 0.0);
  EXPECT_EQ(o2.status, PlanStatus::OK);
  EXPECT_LT(o2.waypoint.x, 1.5);
  EXPECT_FALSE(o2.path_through_unknown);
}

TEST(Planner, ScrollingWindowKeepsOptimalPath)
{
  PlannerParams p;
  Planner pl(p);
  for (int i = 0; i < 12; ++i)
  {
    const double shift = 0.2 * i;  // the window follows the wearer cell by cell
    Grid g = makeGrid(-5 + shift, -5);
    fillRect(g, 2.0, -1.0, 2.2, 1.0, CELL_OBSTACLE);  // fixed in the world
    const Point2 w{ 0.1 + shift, 0.1 };
    const PlanOutput o = pl.update(g, w, 0.0);
    if (2.0 - w.x < 0.3)
      continue;
    ASSERT_EQ(o.status, PlanStatus::OK) << i;
    EXPECT_TRUE(i == 0 || o.scrolled) << i;
    // optimal cost against Dijkstra on the same weights
    CostGrid cg(g.width, g.height);
    cg.w = cellWeights(g, p);
    const DStarLite& d = pl.dstar();
    const auto dist = dijkstraCostToGoal(cg, d.goalX(), d.goalY());
    EXPECT_NEAR(d.startCost(), dist[size_t(cg.index(d.startX(), d.startY()))], 1e-9) << i;
  }
}

// Glass (issue 20): the camera sees the floor beyond a panel, the ranger reports the panel solid,
// and the map holds the cells it hit as obstacles (assistive_obstacles SonarFusion). The floor
// seen only through the panel must never become the wearer's way: no path crosses the panel, and
// a panel across the whole corridor leaves no path to anything beyond it.
TEST(Planner, NeverThroughAPanelTheRangerReportsSolid)
{
  for (const bool gap : { false, true })
  {
    PlannerParams p;
    Planner pl(p);
    Grid g = makeGrid(-5, -5);
    // (bounds between cell centres: the centres are 0.1 + 0.2 k)
    fillRect(g, -5, -5, 5, -1.05, CELL_OBSTACLE);   // corridor walls: cells y = -1.2 .. -1.0 and 1.0 .. 1.2
    fillRect(g, -5, 1.05, 5, 5, CELL_OBSTACLE);
    fillRect(g, 2.05, -1.05, 2.15, 1.05, CELL_OBSTACLE);  // the panel (cells x 2.0 .. 2.2), the ranger-held cells
    if (gap) fillRect(g, 2.05, 0.35, 2.15, 1.05, CELL_FREE);  // an open door beside the panel (y 0.4 .. 1.0: a body fits)
    const PlanOutput o = pl.update(g, { 0.1, 0.1 }, 0.0);
    for (const auto& q : o.path)
    {
      int x, y;
      ASSERT_TRUE(g.worldToCell(q.x, q.y, x, y));
      EXPECT_NE(g.at(x, y), CELL_OBSTACLE) << "gap " << gap << " path at " << q.x << ", " << q.y;
      if (!gap)
      {
        EXPECT_LT(q.x, 2.0) << "path beyond the panel at " << q.x;
      }
      else if (q.x >= 2.0 && q.x <= 2.2)
      {
        EXPECT_GE(q.y, 0.4) << "through the panel, not the door";
      }
    }
    if (!gap)
    {
      EXPECT_FALSE(o.has_waypoint && !o.path.empty() && o.waypoint.x >= 2.0) << "led beyond the panel";
      EXPECT_LT(o.free_ahead, 2.0);  // the cue logic's proximity / alert see the panel
    }
    else
    {
      ASSERT_EQ(o.status, PlanStatus::OK) << o.message;
      EXPECT_GT(o.waypoint.x, 2.2);  // beyond, through the door
    }
  }
}

TEST(Planner, ExplicitGoalOverridesWaypoint)
{
  Planner pl;
  Grid g = makeGrid(-5, -5);
  pl.setGoal({ -3.0, 2.0 });
  const PlanOutput o = pl.update(g, { 0.1, 0.1 }, 0.0);
  ASSERT_EQ(o.status, PlanStatus::OK);
  EXPECT_TRUE(o.explicit_goal);
  EXPECT_NEAR(o.waypoint.x, -3.0, 0.15);
  EXPECT_NEAR(o.waypoint.y, 2.0, 0.15);
  // a goal outside the window: the reachable free cell nearest to it
  pl.setGoal({ -20.0, 0.1 });
  const PlanOutput o2 = pl.update(g, { 0.1, 0.1 }, 0.0);
  ASSERT_EQ(o2.status, PlanStatus::OK);
  EXPECT_LT(o2.waypoint.x, -4.7);
}

// A goal beyond a wall whose only gap (one cell, 0.2 m) is narrower than the body: the free cell
// nearest the goal lies beyond the gap, where no path goes. The wearer is sent as near the goal as
// the body can get (in front of the wall) instead of standing on "no path" for good; once there,
// it is told "no path" (no target a step away).
TEST(Planner, AGoalBehindAGapTooNarrowForTheBodyIsApproachedAsNearAsTheBodyCanGet)
{
  Planner pl;
  Grid g = makeGrid(-5, -5);
  fillRect(g, 2.0, -5.0, 2.2, -0.01, CELL_OBSTACLE);  // a wall across the window at x = 2.0-2.2 m ...
  fillRect(g, 2.0, 0.21, 2.2, 5.0, CELL_OBSTACLE);    // ... with a gap of one cell at y = 0.0-0.2 m
  int gx, gy;
  ASSERT_TRUE(g.worldToCell(2.1, 0.1, gx, gy));
  ASSERT_EQ(g.at(gx, gy), CELL_FREE);
  pl.setGoal({ 20.0, 0.1 });
  const PlanOutput o = pl.update(g, { 0.1, 0.1 }, 0.0);
  ASSERT_EQ(o.status, PlanStatus::OK) << o.message;
  EXPECT_TRUE(o.explicit_goal);
  EXPECT_LT(o.waypoint.x, 2.0);  // in front of the wall ...
  EXPECT_GT(o.waypoint.x, 1.0);  // ... as near it as the body's clearance allows
  for (const auto& q : o.path)
    EXPECT_LT(q.x, 2.0);
  // already there (a step from the wall): no target a step away, "no path" as before
  Planner there;
  there.setGoal({ 20.0, 0.1 });
  const PlanOutput ot = there.update(g, o.waypoint, 0.0);
  EXPECT_EQ(ot.status, PlanStatus::NO_PATH) << ot.message << " waypoint " << ot.waypoint.x;
}

TEST(Planner, AGoalWithinTheBodysRadiusOfAWallReportsTheCellPlannedTo)
{
  // The goal's cell (centre y = 0.5) is free but 0.2 m from the wall's first cell (centre 0.7),
  // inside the body's radius plus half a cell (0.35 m): the path ends at the nearest cell the body
  // fits in (y = 0.3), and the waypoint and its distance say that cell, not the goal's.
  Planner pl;
  Grid g = makeGrid(-5, -5);
  fillRect(g, -5, 0.6, 5, 5, CELL_OBSTACLE);
  pl.setGoal({ 3.1, 0.5 });
  const PlanOutput o = pl.update(g, { 0.1, 0.1 }, 0.0);
  ASSERT_EQ(o.status, PlanStatus::OK) << o.message;
  EXPECT_NEAR(o.waypoint.x, 3.1, 1e-6);
  EXPECT_NEAR(o.waypoint.y, 0.3, 1e-6);
  EXPECT_NEAR(o.waypoint_distance, std::hypot(3.0, 0.2), 1e-6);
}

TEST(Planner, ClearanceCostKeepsPathOffWalls)
{
  Grid g = makeGrid(-5, -5);
  fillRect(g, -5, 0.6, 5, 5, CELL_OBSTACLE);  // a wall along the left side, 0.3 m from the wearer
  PlannerParams p;
  p.clearance_weight = 0.0;
  Planner a(p);
  a.setGoal({ 4.1, 0.3 });
  const PlanOutput oa = a.update(g, { 0.1, 0.3 }, 0.0);
  p.clearance_weight = 5.0;
  Planner b(p);
  b.setGoal({ 4.1, 0.3 });
  const PlanOutput ob = b.update(g, { 0.1, 0.3 }, 0.0);
  ASSERT_EQ(oa.status, PlanStatus::OK);
  ASSERT_EQ(ob.status, PlanStatus::OK);
  // the D* Lite cells (the output path is then smoothed: between a start and a goal both close
  // to the wall a straight line at their clearance is as good as the dip)
  auto meanY = [&g](const Planner& pl) {
    double s = 0;
    const std::vector<int> cells = pl.dstar().path();
    for (int c : cells)
      s += g.cellY(c / g.width);
    return s / double(std::max<size_t>(1, cells.size()));
  };
  EXPECT_LT(meanY(b), meanY(a) - 0.1);  // further from the wall
}

TEST(Planner, WearerOnObstacleCellStartsFromNearestFreeCell)
{
  Planner pl;
  Grid g = makeGrid(-5, -5);
  ASSERT_EQ(pl.update(g, { 0.1, 0.1 }, 0.0).status, PlanStatus::OK);
  fillRect(g, 0.0, 0.0, 0.2, 0.2, CELL_OBSTACLE);  // the wearer's own cell
  const PlanOutput o = pl.update(g, { 0.1, 0.1 }, 0.0);
  ASSERT_EQ(o.status, PlanStatus::OK) << o.message;
  ASSERT_GE(o.path.size(), 3u);
  int x, y;
  ASSERT_TRUE(g.worldToCell(o.path[1].x, o.path[1].y, x, y));
  EXPECT_NE(g.at(x, y), CELL_OBSTACLE);
  // walled in completely: no path
  fillRect(g, -0.6, -0.6, 0.8, 0.8, CELL_OBSTACLE);
  EXPECT_EQ(pl.update(g, { 0.1, 0.1 }, 0.0).status, PlanStatus::NO_PATH);
}

TEST(Planner, FreeFloorBeyondUnmappedFloorIsUnknownNotNoPath)
{
  // Issue 31 (a bag loop on `course`): after a map reset a standing wearer's footprint is free, the
  // floor just ahead unmapped and free floor beyond it: IN_UNKNOWN (cannot tell), not NO_PATH
  // (which the cue logic turns into "obstacle ahead: stop").
  Planner pl;
  ASSERT_EQ(pl.update(makeGrid(-5, -5), { 0.1, 0.1 }, 0.0).status, PlanStatus::OK);  // it has planned before
  Grid g = makeGrid(-5, -5);
  fillRect(g, -5, -5, 5, 5, CELL_UNKNOWN);
  fillRect(g, 1.2, -1.2, 3.2, 1.4, CELL_FREE);
  const PlanOutput o = pl.update(g, { 0.1, 0.1 }, 0.0);
  EXPECT_EQ(o.status, PlanStatus::IN_UNKNOWN) << o.message;
  EXPECT_FALSE(o.has_waypoint);
  // walled in (obstacles all round the footprint, as in WearerOnObstacleCellStartsFromNearestFreeCell):
  // that floor cannot be reached at all: no path
  fillRect(g, -0.6, -0.6, 0.8, 0.8, CELL_OBSTACLE);
  EXPECT_EQ(pl.update(g, { 0.1, 0.1 }, 0.0).status, PlanStatus::NO_PATH);
}

TEST(Planner, WalkedFloorIsTheFootprintAndTheTrailNeverAhead)
{
  // 0.2 m cells, origin 0: the wearer at (1.1, 1.1) stands on the centre of cell (5, 5). Within
  // 0.25 m lie the centres of (5, 5) and its 4 neighbours (0.2 m); the diagonals are 0.283 m away.
  Grid g = makeGrid(0.0, 0.0, 20);
  g.data.assign(g.data.size(), CELL_UNKNOWN);
  g.data[size_t(g.index(4, 5))] = CELL_OBSTACLE;  // an obstacle under the footprint stays one
  std::vector<Point2> walked{ { 1.1, 1.1 } };
  Grid m = g;
  EXPECT_EQ(markWalkedFloor(m, walked, 0.25), 4);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x)
    {
      const bool foot = (x == 5 && y == 5) || (x == 6 && y == 5) || (x == 5 && y == 4) || (x == 5 && y == 6);
      EXPECT_EQ(m.at(x, y), x == 4 && y == 5 ? CELL_OBSTACLE : foot ? CELL_FREE : CELL_UNKNOWN) << x << "," << y;
    }
  // a trail: walking 0.4 m on along +x adds the cells under the body there, and nothing else
  walked.push_back({ 1.5, 1.1 });
  m = g;
  EXPECT_EQ(markWalkedFloor(m, walked, 0.25), 8);  // (5..8, 5), (5, 4), (5, 6), (7, 4), (7, 6)
  EXPECT_EQ(m.at(8, 5), CELL_FREE);                  // centre 1.7: 0.2 m from where it stood
  EXPECT_EQ(m.at(9, 5), CELL_UNKNOWN);               // centre 1.9: 0.4 m ahead, never stood on
  EXPECT_EQ(markWalkedFloor(m, walked, 0.0), 0);

  // The planner at the start of a walk: only the footprint is known, the floor seen by the camera
  // begins 1.5 m ahead (x >= 2.6). Before: "stands in unmapped space". Now the wearer's cell is
  // floor; the ray ahead (body_half_width 0: the line) still ends at unseen floor 0.30 m ahead (cell
  // (7, 5) starts at x = 1.4): IN_UNKNOWN for that, never a free distance through it. The body's
  // strip (0.25 m either side) meets the unseen diagonal cells (6, 4), (6, 6): centres 0.2 m ahead
  // and 0.2 m aside, in the strip and ahead of the front arc (0.15 m there), near edges 0.10 m ahead.
  Grid start = makeGrid(0.0, 0.0, 40);
  fillRect(start, 0.0, 0.0, 2.5, 8.0, CELL_UNKNOWN);
  PlannerParams line;
  line.body_half_width = 0.0;
  Planner pl(line);
  PlanOutput o = pl.update(start, { 1.1, 1.1 }, 0.0);
  EXPECT_EQ(o.status, PlanStatus::IN_UNKNOWN);
  EXPECT_NE(o.message.find("unmapped floor"), std::string::npos) << o.message;
  EXPECT_GE(o.free_ahead, 0.25 - 1e-9);  // the cell edge at 0.30 m, to the ray's 0.05 m step
  EXPECT_LE(o.free_ahead, 0.30 + 1e-9);
  PlannerParams strip;
  strip.body_half_width = 0.25;
  o = Planner(strip).update(start, { 1.1, 1.1 }, 0.0);
  EXPECT_EQ(o.status, PlanStatus::IN_UNKNOWN);
  EXPECT_NEAR(o.free_ahead, 0.10, 1e-9);
  PlannerParams off = line;
  off.footprint_radius_m = 0.0;
  EXPECT_NE(Planner(off).update(start, { 1.1, 1.1 }, 0.0).message.find("stands in unmapped space"), std::string::npos);
  // When the seen floor begins right at the footprint's edge, the planner guides from the first
  // step: OK, free ahead to the window's edge (the ray's 5 m), a path.
  Grid near = makeGrid(0.0, 0.0, 40);
  fillRect(near, 0.0, 0.0, 1.2, 8.0, CELL_UNKNOWN);  // cells up to x = 1.2 unseen, (6, 5) at 1.3 seen
  o = Planner().update(near, { 1.1, 1.1 }, 0.0);
  EXPECT_EQ(o.status, PlanStatus::OK) << o.message;
  EXPECT_NEAR(o.free_ahead, 5.0, 0.05 + 1e-9);
  EXPECT_FALSE(o.path.empty());
  EXPECT_EQ(Planner(off).update(near, { 1.1, 1.1 }, 0.0).status, PlanStatus::IN_UNKNOWN);
}

// A curb across the way (step cells: floor the wearer can climb) ends what lies ahead, so a walker
// is stopped before it; standing there, the wearer is sent over it after step_stand_s (held for
// good, phantom steps of a plain floor's stereo stood wearers there until the trial's end). An
// obstacle in their place holds the stop; crossed cells are dropped once the wearer is far, and a
// crossed cell the map makes an obstacle ends the way again.
TEST(Planner, AStandingWearerIsSentOverAStepItWasStoppedAt)
{
  Grid g = makeGrid(0.0, 0.0, 40);
  fillRect(g, 1.45, 0.0, 1.75, 8.0, CELL_STEP);  // the curb: cells x 1.4-1.8 (centres 1.5, 1.7)
  const Point2 w{ 1.1, 4.1 };
  const PlannerParams p;
  ASSERT_GT(p.step_stand_s, 0.0);
  Planner pl(p);
  pl.setGoal({ 3.5, 4.1 });
  PlanOutput o;
  double t = 10.0;
  for (; t < 10.0 + p.step_stand_s - 0.15; t += 0.1)
  {
    o = pl.update(g, w, 0.0, t);
    ASSERT_EQ(o.status, PlanStatus::OK) << o.message;
    ASSERT_NEAR(o.free_ahead, 0.3, 0.06) << "at " << t << ": the curb ends the way ahead";
    ASSERT_EQ(o.crossed_step_cells, 0);
  }
  for (int i = 0; i < 5; ++i, t += 0.1)
    o = pl.update(g, w, 0.0, t);
  EXPECT_GT(o.crossed_step_cells, 0);
  EXPECT_GT(o.free_ahead, 2.0) << "sent over the curb";
  EXPECT_NE(o.message.find("step cells crossed after a stop"), std::string::npos) << o.message;
  EXPECT_EQ(plannedCell(o, 1.5, 4.1), CELL_FREE);
  EXPECT_EQ(plannedCell(o, 1.5, 1.3), CELL_STEP) << "beyond step_cross_m the curb stays";

  // the map makes a crossed cell an obstacle: it stays one
  Grid solid = g;
  fillRect(solid, 1.45, 3.9, 1.55, 4.3, CELL_OBSTACLE);
  o = pl.update(solid, w, 0.0, t);
  EXPECT_EQ(plannedCell(o, 1.5, 4.1), CELL_OBSTACLE);
  // far away the crossed cells are dropped; back at the curb it stops the wearer again
  o = pl.update(g, { 1.1, 7.7 }, 0.0, t + 3.0);
  o = pl.update(g, { 1.1, 1.2 }, 0.0, t + 6.0);
  EXPECT_EQ(o.crossed_step_cells, 0);
  o = pl.update(g, w, 0.0, t + 9.0);
  EXPECT_NEAR(o.free_ahead, 0.3, 0.06);

  // control: a walker nearing the curb (0.3 m/s) is never sent over it: it is stopped first
  Planner q(p);
  q.setGoal({ 3.5, 4.1 });
  for (double s = 0.0; s < 3.0; s += 0.1)
  {
    o = q.update(g, { 0.1 + 0.3 * s, 4.1 }, 0.0, 10.0 + s);
    ASSERT_EQ(o.crossed_step_cells, 0) << "at " << s;
  }
  EXPECT_LT(o.free_ahead, 0.6);
}
