// The people keys of obstacles_benchmark (people_score.h) on hand-made truths, exact numbers.
#include <cmath>

#include <gtest/gtest.h>

#include <assistive_obstacles/people_score.h>

using namespace assistive_obstacles;

namespace
{
PersonState person(int id, double x, double y, double vx = 0, double vy = 0, double age = 0, double radius = 0.3)
{
  PersonState p;
  p.id = id;
  p.position = Eigen::Vector2d(x, y);
  p.velocity = Eigen::Vector2d(vx, vy);
  p.age = age;
  p.radius = radius;
  return p;
}
}  // namespace

TEST(PeopleScore, FrameMatchingRecallPrecisionVelocity)
{
  // Wearer at the origin. Truth: A (2, 0), B (4.8, 0), C (7, 0) beyond 5 m. Tracks: 13 at 0.1 m
  // from A, 10 at 0.3 m from A (A goes to the nearer one), 11 at (5.2, 0), 0.4 m from B but outside
  // 5 m, 12 clutter at (0, 3).
  const std::vector<PersonState> truth{person(1, 2.0, 0.0, 0.0, 1.0), person(2, 4.8, 0.0, 1.0, 0.0), person(3, 7.0, 0.0)};
  const std::vector<PersonState> tracks{person(10, 2.3, 0.0, 0.0, 1.2, 1.0), person(13, 1.9, 0.0, 0.0, 1.4, 0.5),
                                        person(11, 5.2, 0.0, 1.5, 0.0, 0.6), person(12, 0.0, 3.0, 0.0, 0.0, 2.0)};
  const PeopleFrameScore s = scorePeopleFrame(truth, tracks, Eigen::Vector2d::Zero());
  EXPECT_EQ(s.truth_in_range, 2);   // A, B
  EXPECT_EQ(s.truth_matched, 2);    // A <- 13, B <- 11 (a partner just outside the circle counts for B)
  EXPECT_EQ(s.tracks_in_range, 3);  // 10, 13, 12
  EXPECT_EQ(s.tracks_matched, 1);   // 13 (10 lost A to 13, 12 is clutter)
  ASSERT_EQ(s.velocity_n, 1);       // 13 (age 0.5 s); 11 is outside 5 m
  EXPECT_NEAR(s.velocity_err_sum, 0.4, 1e-12);
  ASSERT_EQ(s.track_to_truth.size(), 2u);
  EXPECT_EQ(s.track_to_truth.at(13), 1);
  EXPECT_EQ(s.track_to_truth.at(11), 2);
  // A younger track is left out of the velocity error; a gate of 0.05 m matches nothing.
  PeopleScoreParams p;
  p.min_age = 0.6;
  EXPECT_EQ(scorePeopleFrame(truth, tracks, Eigen::Vector2d::Zero(), p).velocity_n, 0);
  p.gate = 0.05;
  EXPECT_EQ(scorePeopleFrame(truth, tracks, Eigen::Vector2d::Zero(), p).truth_matched, 0);
}

TEST(PeopleScore, GhostCellsLeaveOutPeopleAndUnknown)
{
  // 4 x 3 cells of 1 m from the origin (row y = 0 first); wearer in cell (0, 0), radius 2.5 m; a
  // person (radius 0.3 m) at the centre of cell (2, 1): cells whose centre lies within 0.3 + 0.707 m
  // of it are left out ((2, 1), (1, 1), (2, 0); (2, 2) and (3, 1) are out of range anyway).
  GridData truth, est;
  truth.resolution = est.resolution = 1.0;
  truth.width = est.width = 4;
  truth.height = est.height = 3;
  truth.data = {0, 0, 0, 100,  //
                0, 0, 0, 0,    //
                0, 50, 0, 0};
  est.data = {0, 100, -1, 100,   //
              100, 0, 100, 100,  //
              -1, 0, 0, 100};
  // In range and truth-free: (0,0) free, (1,0) ghost, (0,1) ghost, (0,2) unknown -> not counted;
  // (1,2) is a truth step, not free.
  const GhostCount g = countGhostCells(truth, est, Eigen::Vector2d(0.5, 0.5), 2.5, {person(1, 2.5, 1.5)});
  EXPECT_EQ(g.free_known, 3);
  EXPECT_EQ(g.ghost, 2);
  // Without the person (1, 1) is known free, (2, 1) (2.24 m) a ghost, (2, 0) unknown: 5 known, 3 ghosts.
  const GhostCount g2 = countGhostCells(truth, est, Eigen::Vector2d(0.5, 0.5), 2.5, {});
  EXPECT_EQ(g2.free_known, 5);
  EXPECT_EQ(g2.ghost, 3);
}

TEST(PeopleScore, CrossingWarnedInTimeAndFalseWarnings)
{
  // A standing wearer at the origin, t = 0..10 s every 1 s (10 s = 1/6 min).
  //   person 1: distance |t - 5| + 0.2 (closest 0.2 m at t = 5): track 7, warned at t = 2, 3 -> in time (<= 3.5)
  //   person 3: distance |t - 8| + 0.3 (closest 0.3 m at t = 8): track 8, warned at t = 7 only -> too late
  //   person 4: distance |t - 3| + 0.7 (closest 0.7 m): track 30 warned at t = 2 -> neither crossing nor false
  //   person 2: distance |t - 5| + 2 (never within 1 m): track 9 warned at t = 4 and t = 6 -> 2 false onsets
  //   track 20 matched to no one, warned at t = 1 -> 1 false onset
  //   person 6: standing (speed 0) 0.1 m from the wearer's path at t = 9: no crossing (nothing to warn of)
  // People 1-4 walk at 1 m/s.
  CrossingScore cs;
  for (int k = 0; k <= 10; ++k)
  {
    const double t = k;
    const std::vector<PersonState> truth{person(1, std::abs(t - 5) + 0.2, 0.0, 1.0), person(2, std::abs(t - 5) + 2.0, 0.0, 1.0),
                                         person(3, 0.0, std::abs(t - 8) + 0.3, 0.0, 1.0),
                                         person(4, 0.0, -(std::abs(t - 3) + 0.7), 0.0, 1.0),
                                         person(6, -(std::abs(t - 9) + 0.1), 0.0)};
    const std::map<int, int> match{{7, 1}, {8, 3}, {9, 2}, {30, 4}};
    std::set<int> warned;
    if (k == 2 || k == 3) warned.insert(7);
    if (k == 7) warned.insert(8);
    if (k == 2) warned.insert(30);
    if (k == 4 || k == 6) warned.insert(9);
    if (k == 1) warned.insert(20);
    cs.addFrame(t, Eigen::Vector2d::Zero(), truth, warned, match);
  }
  EXPECT_EQ(cs.crossings(), 2);
  EXPECT_EQ(cs.crossingsWarned(), 1);
  EXPECT_DOUBLE_EQ(cs.warnedPct(), 50.0);
  EXPECT_EQ(cs.falseWarnings(), 3);
  EXPECT_DOUBLE_EQ(cs.minutes(), 10.0 / 60.0);
  EXPECT_NEAR(cs.falseWarningsPerMin(), 18.0, 1e-12);
  // No crossing at all: the share is undefined (NaN -> null in the JSON).
  CrossingScore empty;
  empty.addFrame(0.0, Eigen::Vector2d::Zero(), {person(5, 3.0, 0.0)}, {}, {});
  EXPECT_TRUE(std::isnan(empty.warnedPct()));
}

TEST(PeopleScore, CrossingVisibleInTimeIsTheCamerasFloor)
{
  // A standing wearer at the origin, t = 0..10 s every 0.5 s; two crossings at t = 6 (closest 0.2 m):
  //   person 1 in the camera's view at t = 1.5, 2, 2.5 (3 frames between lookback 1 s and lead 4.5 s)
  //     and warned at t = 2: visible in time, warned;
  //   person 2 in view only at t = 4, 4.5 (2 frames before the lead) and 5, 5.5 (after it): not
  //     visible in time (no camera could have warned it), and not warned.
  CrossingScore cs;
  for (int k = 0; k <= 20; ++k)
  {
    const double t = 0.5 * k;
    const std::vector<PersonState> truth{person(1, std::abs(t - 6) + 0.2, 0.0, 1.0),
                                         person(2, 0.0, std::abs(t - 6) + 0.2, 0.0, 1.0)};
    std::set<int> visible;
    if (t >= 1.5 && t <= 2.5) visible.insert(1);
    if (t >= 4.0 && t <= 5.5) visible.insert(2);
    cs.addVisible(t, visible);
    cs.addFrame(t, Eigen::Vector2d::Zero(), truth, k == 4 ? std::set<int>{7} : std::set<int>{}, {{7, 1}});
  }
  EXPECT_EQ(cs.crossings(), 2);
  EXPECT_EQ(cs.crossingsWarned(), 1);
  EXPECT_EQ(cs.crossingsVisible(), 1);
  EXPECT_EQ(cs.crossingsWarnedVisible(), 1);
  for (const CrossingScore::CrossingDetail& d : cs.details())
  {
    EXPECT_EQ(d.visible, d.id == 1);
    EXPECT_DOUBLE_EQ(d.first_visible, d.id == 1 ? 1.5 : 4.0);
  }
}

TEST(PeopleScore, StandingPersonHeldWhenAnObstacleCellLiesUnderThem)
{
  // 0.2 m cells from the origin, 10 x 10, one obstacle cell (5, 5) (centre 1.1, 1.1). A person of
  // radius 0.25 m holds it when the cell's centre lies within 0.25 + 0.141 m of theirs.
  GridData est;
  est.resolution = 0.2;
  est.width = est.height = 10;
  est.data.assign(100, CELL_FREE);
  est.data[5 * 10 + 5] = CELL_OBSTACLE;
  EXPECT_TRUE(heldByMap(est, person(1, 1.1 + 0.30, 1.1, 0, 0, 0, 0.25)));
  EXPECT_TRUE(heldByMap(est, person(1, 1.1, 1.1 - 0.38, 0, 0, 0, 0.25)));
  EXPECT_FALSE(heldByMap(est, person(1, 1.1 + 0.40, 1.1, 0, 0, 0, 0.25)));
  // An unknown or free cell under them is not holding them.
  est.data[5 * 10 + 5] = CELL_UNKNOWN;
  EXPECT_FALSE(heldByMap(est, person(1, 1.1, 1.1, 0, 0, 0, 0.25)));
  // Off the grid: nothing holds them.
  est.data[5 * 10 + 5] = CELL_OBSTACLE;
  EXPECT_FALSE(heldByMap(est, person(1, -3.0, -3.0, 0, 0, 0, 0.25)));
}
