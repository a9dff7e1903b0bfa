#include <gtest/gtest.h>

#include <assistive_obstacles/temporal_filter.h>

using namespace assistive_obstacles;

TEST(TemporalFilter, UndecidedUntilFiveObservations)
{
  TemporalFilter f;
  f.resize(52);
  EXPECT_EQ(f.code(3, 4), CELL_UNKNOWN);
  for (int i = 0; i < 4; ++i) f.vote(3, 4, FrameLabel::FREE);
  EXPECT_EQ(f.code(3, 4), CELL_UNKNOWN);
  f.vote(3, 4, FrameLabel::NONE);  // no vote
  EXPECT_EQ(f.code(3, 4), CELL_UNKNOWN);
  f.vote(3, 4, FrameLabel::FREE);
  EXPECT_EQ(f.code(3, 4), CELL_FREE);
  // Majority rule: O/(O+S) > 0.5 -> obstacle.
  for (int i = 0; i < 5; ++i) f.vote(3, 4, FrameLabel::OBSTACLE);
  EXPECT_EQ(f.code(3, 4), CELL_FREE);  // 5/10 is not > 0.5
  f.vote(3, 4, FrameLabel::OBSTACLE);
  EXPECT_EQ(f.code(3, 4), CELL_OBSTACLE);
  EXPECT_EQ(f.find(3, 4)->flips, 1);
}

TEST(TemporalFilter, InferredVotesNeverDecide)
{
  TemporalFilter f;
  f.resize(10);
  for (int i = 0; i < 20; ++i) f.vote(1, 1, FrameLabel::OBSTACLE, 1, false);
  EXPECT_EQ(f.code(1, 1), CELL_UNKNOWN);
  EXPECT_EQ(f.find(1, 1)->votes, 0);
  for (int i = 0; i < 5; ++i) f.vote(1, 1, FrameLabel::FREE, 4);  // observed: 20 free vs 20 inferred obstacle
  EXPECT_EQ(f.code(1, 1), CELL_FREE);
}

TEST(TemporalFilter, StepVotesGiveStepCode)
{
  TemporalFilter f;
  f.resize(10);
  for (int i = 0; i < 6; ++i) f.vote(0, 0, FrameLabel::STEP);
  EXPECT_EQ(f.code(0, 0), CELL_STEP);
}

TEST(TemporalFilter, FlickeringCellBecomesPermanentObstacleAfter15Flips)
{
  TemporalFilter f;
  f.resize(52);
  // Settle near 50 %, then alternate: every vote flips the label.
  int votes = 0;
  for (int i = 0; i < 3; ++i, ++votes) f.vote(7, -2, FrameLabel::OBSTACLE);
  for (int i = 0; i < 2; ++i, ++votes) f.vote(7, -2, FrameLabel::FREE);
  ASSERT_EQ(f.code(7, -2), CELL_OBSTACLE);
  int flips_seen = 0;
  bool alt = false;
  while (!f.find(7, -2)->permanent && votes < 200)
  {
    f.vote(7, -2, alt ? FrameLabel::OBSTACLE : FrameLabel::FREE);
    alt = !alt;
    ++votes;
    flips_seen = f.find(7, -2)->flips;
    if (!f.find(7, -2)->permanent)
    {
      EXPECT_LT(flips_seen, 15);
    }
  }
  ASSERT_TRUE(f.find(7, -2)->permanent);
  EXPECT_EQ(f.find(7, -2)->flips, 15);
  EXPECT_EQ(f.code(7, -2), CELL_OBSTACLE);
  for (int i = 0; i < 100; ++i) f.vote(7, -2, FrameLabel::FREE);
  EXPECT_EQ(f.code(7, -2), CELL_OBSTACLE);  // for good
}

TEST(TemporalFilter, RingSlotReusedForAnotherCellStartsUnknown)
{
  TemporalFilter f;
  f.resize(10);
  for (int i = 0; i < 6; ++i) f.vote(1, 1, FrameLabel::OBSTACLE);
  EXPECT_EQ(f.code(1, 1), CELL_OBSTACLE);
  EXPECT_EQ(f.code(11, 1), CELL_UNKNOWN);  // same slot, other cell: not inherited
  f.vote(11, 1, FrameLabel::FREE);
  EXPECT_EQ(f.code(1, 1), CELL_UNKNOWN);   // scrolled out
  EXPECT_EQ(f.code(-9, 1), CELL_UNKNOWN);
}

TEST(TemporalFilter, MoverCellsNeitherVoteNorFlip)
{
  // Same flicker as above, but the obstacle frames are a person walking through (a mover cell
  // then): the cell never flips, never locks. A static flicker beside it still locks, a steady
  // obstacle is one.
  TemporalFilter f;
  f.resize(52);
  EXPECT_FALSE(f.moverCell(7, -2));
  for (int i = 0; i < 3; ++i) f.vote(9, 9, FrameLabel::OBSTACLE);
  for (int i = 0; i < 2; ++i) f.vote(9, 9, FrameLabel::FREE);
  for (int i = 0; i < 5; ++i) f.vote(7, -2, FrameLabel::FREE);
  for (int i = 0; i < 200; ++i)
  {
    const bool person = i % 2 == 1;  // starts free, as the flicker above
    f.setMoverCells(person ? std::vector<std::pair<int, int>>{{7, -2}, {7, -1}} : std::vector<std::pair<int, int>>{});
    EXPECT_EQ(f.moverCell(7, -2), person);
    EXPECT_FALSE(f.moverCell(9, 9));
    f.vote(7, -2, person ? FrameLabel::OBSTACLE : FrameLabel::FREE);
    f.vote(9, 9, person ? FrameLabel::OBSTACLE : FrameLabel::FREE);
    f.vote(2, 2, FrameLabel::OBSTACLE);
  }
  f.clearMoverCells();
  EXPECT_FALSE(f.moverCell(7, -2));
  ASSERT_NE(f.find(7, -2), nullptr);
  EXPECT_EQ(f.find(7, -2)->flips, 0);
  EXPECT_FALSE(f.find(7, -2)->permanent);
  EXPECT_EQ(f.find(7, -2)->o, 0);
  EXPECT_EQ(f.code(7, -2), CELL_FREE);
  EXPECT_TRUE(f.find(9, 9)->permanent);
  EXPECT_EQ(f.code(2, 2), CELL_OBSTACLE);
}
