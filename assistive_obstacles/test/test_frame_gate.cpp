// FrameGate: the obstacle stage's rule for when its map may be trusted.
#include <gtest/gtest.h>

#include <assistive_obstacles/frame_gate.h>

using assistive_obstacles::FrameGate;
using assistive_obstacles::FrameGateParams;
using V = FrameGate::Verdict;

namespace
{
FrameGateParams params()
{
  FrameGateParams p;
  p.max_frame_gap_s = 0.5;
  p.rebuild_frames = 3;
  p.min_fresh_points = 100;
  return p;
}

// Feeds frames at 15 Hz from t0; returns the verdict of the last one.
V feed(FrameGate& g, double& t, int n, std::size_t points)
{
  V v = V::REBUILDING;
  for (int i = 0; i < n; ++i, t += 1.0 / 15.0)
  {
    g.clearBefore(t);
    v = g.verdict(points);
  }
  return v;
}
}  // namespace

TEST(FrameGate, StartsEmptyAndPublishesAfterRebuildFrames)
{
  FrameGate g(params());
  EXPECT_TRUE(g.clearBefore(10.0));  // the first frame starts an empty map
  EXPECT_EQ(g.verdict(5000), V::REBUILDING);
  EXPECT_FALSE(g.clearBefore(10.066));
  EXPECT_EQ(g.verdict(5000), V::REBUILDING);
  EXPECT_FALSE(g.clearBefore(10.133));
  EXPECT_EQ(g.verdict(5000), V::FRESH);
  EXPECT_TRUE(g.reason().empty());
  EXPECT_EQ(g.clears(), 0);
}

TEST(FrameGate, FramesWithoutDepthRefreshNothing)
{
  FrameGate g(params());
  double t = 0.0;
  ASSERT_EQ(feed(g, t, 5, 5000), V::FRESH);
  // black frames: a handful of points from noise, well below min_fresh_points
  EXPECT_EQ(feed(g, t, 30, 12), V::NO_DEPTH);
  EXPECT_EQ(g.noDepthFrames(), 30);
  EXPECT_NE(g.reason().find("no depth"), std::string::npos);
  // frames keep coming at 15 Hz, so no gap: depth back -> fresh at once (the map was kept,
  // but nothing stale was ever published as fresh)
  EXPECT_EQ(feed(g, t, 1, 5000), V::FRESH);
  EXPECT_EQ(g.clears(), 0);
}

TEST(FrameGate, GapClearsTheMapAndHoldsItBackUntilRebuilt)
{
  FrameGate g(params());
  double t = 0.0;
  ASSERT_EQ(feed(g, t, 5, 5000), V::FRESH);
  t += 0.6;  // frames stop for 0.6 + 1/15 s
  EXPECT_TRUE(g.clearBefore(t));
  EXPECT_NE(g.reason().find("without frames"), std::string::npos);
  EXPECT_EQ(g.verdict(5000), V::REBUILDING);
  t += 1.0 / 15.0;
  EXPECT_EQ(feed(g, t, 1, 5000), V::REBUILDING);
  EXPECT_EQ(feed(g, t, 1, 5000), V::FRESH);
  EXPECT_EQ(g.clears(), 1);
}

TEST(FrameGate, GapJustBelowTheLimitKeepsTheMap)
{
  FrameGate g(params());
  double t = 0.0;
  ASSERT_EQ(feed(g, t, 5, 5000), V::FRESH);
  t += 0.4;
  EXPECT_FALSE(g.clearBefore(t));
  EXPECT_EQ(g.verdict(5000), V::FRESH);
}

TEST(FrameGate, TimeGoingBackClearsTheMap)
{
  FrameGate g(params());
  double t = 100.0;
  ASSERT_EQ(feed(g, t, 5, 5000), V::FRESH);
  EXPECT_TRUE(g.clearBefore(100.0));  // bag loop
  EXPECT_NE(g.reason().find("time went back"), std::string::npos);
  EXPECT_EQ(g.verdict(5000), V::REBUILDING);
  EXPECT_EQ(g.clears(), 1);
}

TEST(FrameGate, NoDepthFramesDoNotCountTowardsTheRebuild)
{
  FrameGate g(params());
  double t = 0.0;
  ASSERT_EQ(feed(g, t, 5, 5000), V::FRESH);
  t += 2.0;
  EXPECT_EQ(feed(g, t, 10, 0), V::NO_DEPTH);  // the gap clears, then only black frames
  EXPECT_EQ(feed(g, t, 2, 5000), V::REBUILDING);
  EXPECT_EQ(feed(g, t, 1, 5000), V::FRESH);
}

TEST(FrameGate, UntrustedPoseClearsTheMapAtTheNextFrame)
{
  FrameGate g(params());
  double t = 0.0;
  ASSERT_EQ(feed(g, t, 5, 5000), V::FRESH);
  g.poseUntrusted();  // e.g. 4 s blind: the pose kept, the wearer walked on
  EXPECT_TRUE(g.clearBefore(t));
  EXPECT_NE(g.reason().find("lost its pose"), std::string::npos);
  EXPECT_EQ(g.verdict(5000), V::REBUILDING);
  t += 1.0 / 15.0;
  EXPECT_FALSE(g.clearBefore(t));  // once per report
  EXPECT_EQ(g.verdict(5000), V::REBUILDING);
  t += 1.0 / 15.0;
  EXPECT_EQ(feed(g, t, 1, 5000), V::FRESH);
  EXPECT_EQ(g.clears(), 1);
}

// Evidence stamped before the map's last clear (a ranger reading queued through a black-out whose
// pose tf would interpolate across the untrusted spell) does not belong to the new map.
TEST(FrameGate, EvidenceFromBeforeAClearIsOutOfTheEpoch)
{
  FrameGate g(params());
  EXPECT_FALSE(g.inEpoch(10.0));  // no frame yet: no map to put anything in
  double t = 10.0;
  feed(g, t, 10, 5000);  // frames 10.0 .. 10.6
  EXPECT_TRUE(g.inEpoch(10.0));
  EXPECT_TRUE(g.inEpoch(10.3));
  EXPECT_FALSE(g.inEpoch(9.99));
  // The VO loses its pose for 4 s (black frames), then trusts it again: the next frame clears.
  g.poseUntrusted();
  EXPECT_TRUE(g.clearBefore(14.6));
  EXPECT_FALSE(g.inEpoch(12.0)) << "a reading stamped during the black-out";
  EXPECT_FALSE(g.inEpoch(14.59));
  EXPECT_TRUE(g.inEpoch(14.6));
  EXPECT_TRUE(g.inEpoch(14.9));
  EXPECT_FALSE(g.inEpoch(15.2)) << "beyond the newest frame by more than max_frame_gap_s";
  // A bag loop: time goes back; readings of the first pass (later stamps) are out too.
  EXPECT_TRUE(g.clearBefore(10.0));
  EXPECT_TRUE(g.inEpoch(10.2));
  EXPECT_FALSE(g.inEpoch(14.7));
}
