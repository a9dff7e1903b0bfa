// InputMonitor: the planner decides nothing from a pose the VO does not trust or a map that no
// longer follows the camera.
#include <gtest/gtest.h>

#include "assistive_planner/input_monitor.h"

using assistive_planner::InputMonitor;
using assistive_planner::PlanStatus;

namespace
{
constexpr double kDt = 1.0 / 15.0;
}

TEST(InputMonitor, NothingYetMeansNoPoseThenNoMap)
{
  InputMonitor m(0.5, 0.5);
  EXPECT_EQ(m.check().status, PlanStatus::NO_POSE);
  EXPECT_FALSE(m.onPose(1.0, true));
  EXPECT_EQ(m.check().status, PlanStatus::NO_MAP);
  EXPECT_TRUE(m.onGrid(1.0));
  EXPECT_TRUE(m.check().ok());
}

TEST(InputMonitor, UntrustedPoseIsNoPoseAtOnce)
{
  InputMonitor m(0.5, 0.5);
  double t = 0.0;
  for (int i = 0; i < 10; ++i, t += kDt)
  {
    m.onPose(t, true);
    m.onGrid(t);
  }
  ASSERT_TRUE(m.check().ok());
  m.onPose(t, false);  // VO lost beyond its coast, frozen camera, ...
  const auto v = m.check();
  EXPECT_EQ(v.status, PlanStatus::NO_POSE);
  EXPECT_NE(v.reason.find("cannot trust"), std::string::npos);
  m.onGrid(t);  // even a fresh grid does not help without a pose
  EXPECT_EQ(m.check().status, PlanStatus::NO_POSE);
  // trusted again: the pose may have jumped against the old map, so reset and wait for a new grid
  EXPECT_TRUE(m.onPose(t + kDt, true));
  EXPECT_EQ(m.check().status, PlanStatus::NO_MAP);
  EXPECT_TRUE(m.onGrid(t + kDt));
  EXPECT_TRUE(m.check().ok());
}

TEST(InputMonitor, MapNotRefreshedBecomesNoMapAfterMaxAge)
{
  InputMonitor m(0.5, 0.5);
  double t = 0.0;
  for (int i = 0; i < 10; ++i, t += kDt)
  {
    m.onPose(t, true);
    m.onGrid(t);
  }
  const double last_grid = t - kDt;
  // frames keep coming with trusted poses (e.g. gyro coast), but no depth: no new grid
  int frames_ok = 0;
  for (; t - last_grid <= 1.0; t += kDt)
  {
    m.onPose(t, true);
    if (m.check().ok())
      ++frames_ok;
    else
      break;
  }
  EXPECT_EQ(m.check().status, PlanStatus::NO_MAP);
  EXPECT_GT(t - last_grid, 0.5);
  EXPECT_LE(t - last_grid, 0.5 + kDt + 1e-9);
  EXPECT_EQ(frames_ok, 7);  // 7 frames of 1/15 s = 0.467 s still within the age limit
}

TEST(InputMonitor, PoseLaggingTheGridIsNoPose)
{
  InputMonitor m(0.5, 2.0);
  m.onPose(0.0, true);
  m.onGrid(0.0);
  ASSERT_TRUE(m.check().ok());
  m.onGrid(0.6);  // VO stopped publishing, the map still comes (e.g. from another pose source)
  EXPECT_EQ(m.check().status, PlanStatus::NO_POSE);
}

TEST(InputMonitor, GapResetsAndForgetsTheGrid)
{
  InputMonitor m(0.5, 0.5);
  double t = 0.0;
  for (int i = 0; i < 10; ++i, t += kDt)
  {
    m.onPose(t, true);
    m.onGrid(t);
  }
  t += 1.0;
  EXPECT_TRUE(m.onPose(t, true));  // reset the planner
  EXPECT_EQ(m.resets(), 1);
  EXPECT_EQ(m.check().status, PlanStatus::NO_MAP);
  EXPECT_FALSE(m.onGrid(t - 1.0 - kDt));  // a late grid from before the gap is ignored
  EXPECT_EQ(m.check().status, PlanStatus::NO_MAP);
  EXPECT_TRUE(m.onGrid(t));
  EXPECT_TRUE(m.check().ok());
}

TEST(InputMonitor, BagLoopResetsAndIgnoresGridsFromBeforeTheLoop)
{
  InputMonitor m(0.5, 0.5);
  double t = 100.0;
  for (int i = 0; i < 10; ++i, t += kDt)
  {
    m.onPose(t, true);
    m.onGrid(t);
  }
  EXPECT_TRUE(m.onPose(100.0, true));  // time went back
  EXPECT_EQ(m.check().status, PlanStatus::NO_MAP);
  EXPECT_FALSE(m.onGrid(t - kDt));  // the last grid of the previous loop, delivered late
  EXPECT_EQ(m.check().status, PlanStatus::NO_MAP);
  EXPECT_TRUE(m.onGrid(100.0));
  EXPECT_TRUE(m.check().ok());
}

TEST(InputMonitor, WithoutPoseRequirementOnlyTheGridCounts)
{
  InputMonitor m(0.5, 0.5);
  EXPECT_EQ(m.check(false).status, PlanStatus::NO_MAP);
  m.onGrid(3.0);
  EXPECT_TRUE(m.check(false).ok());
}
