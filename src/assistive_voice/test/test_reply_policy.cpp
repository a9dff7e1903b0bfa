// The reply policy: priorities, rate limit, repeats, age, silence during alerts, switched off.
#include <gtest/gtest.h>

#include "assistive_voice/reply_policy.h"

using namespace assistive_voice;

namespace
{
std::string next(ReplyPolicy& p, double t)
{
  const auto r = p.next(t);
  return r ? r->text : "-";
}
}  // namespace

TEST(ReplyPolicy, SpeaksAtOnceThenRateLimits)
{
  ReplyPolicy p;  // min_interval 2 s
  EXPECT_TRUE(p.offer("place two saved", Priority::CONFIRM, 10.0));
  EXPECT_EQ(next(p, 10.0), "place two saved");
  EXPECT_EQ(next(p, 10.05), "-");
  EXPECT_TRUE(p.offer("cues paused", Priority::CONFIRM, 10.5));
  EXPECT_EQ(next(p, 11.9), "-");  // 1.9 s after the last start
  EXPECT_EQ(next(p, 12.0), "cues paused");
}

TEST(ReplyPolicy, HigherPriorityWinsTheSlot)
{
  ReplyPolicy p;
  EXPECT_EQ((p.offer("a", Priority::INFO, 0.0), next(p, 0.0)), "a");
  EXPECT_TRUE(p.offer("the way ahead is clear", Priority::INFO, 0.5));
  EXPECT_TRUE(p.offer("I am not sure of the way", Priority::WARNING, 0.6));  // replaces the INFO
  EXPECT_FALSE(p.offer("cues paused", Priority::CONFIRM, 0.7));              // lower than the waiting WARNING
  EXPECT_TRUE(p.offer("vest link lost", Priority::WARNING, 0.8));            // same priority: the newer
  EXPECT_EQ(next(p, 2.0), "vest link lost");
  EXPECT_FALSE(p.waiting());
  EXPECT_EQ(p.dropped(), 3);
}

TEST(ReplyPolicy, NoRepeatWithinRepeatS)
{
  ReplyPolicy p;  // repeat_s 10
  p.offer("cues paused", Priority::CONFIRM, 0.0);
  EXPECT_EQ(next(p, 0.0), "cues paused");
  EXPECT_FALSE(p.offer("cues paused", Priority::CONFIRM, 9.9));
  EXPECT_TRUE(p.offer("cues paused", Priority::CONFIRM, 10.0));
  EXPECT_EQ(next(p, 10.0), "cues paused");
}

TEST(ReplyPolicy, StaleRepliesAreDropped)
{
  ReplyPolicy p;  // max_age 5
  p.offer("a", Priority::INFO, 0.0);
  EXPECT_EQ(next(p, 0.0), "a");
  p.offer("b", Priority::INFO, 1.0);
  EXPECT_EQ(next(p, 6.01), "-");
  EXPECT_FALSE(p.waiting());
}

TEST(ReplyPolicy, NeverOverAnAlert)
{
  ReplyPolicy p;  // alert_hold 1.5
  EXPECT_TRUE(p.alert(5.0));  // speech must stop now
  EXPECT_TRUE(p.silenced(5.0));
  p.offer("guiding back to the door", Priority::CONFIRM, 5.1);
  EXPECT_EQ(next(p, 5.2), "-");
  EXPECT_TRUE(p.alert(6.0));  // the alert goes on
  EXPECT_EQ(next(p, 7.4), "-");
  EXPECT_TRUE(p.silenced(7.49));
  EXPECT_FALSE(p.silenced(7.5));
  EXPECT_EQ(next(p, 7.5), "guiding back to the door");  // held, not lost
  // an alert holds even a WARNING
  p.alert(20.0);
  p.offer("I am not sure of the way", Priority::WARNING, 20.0);
  EXPECT_EQ(next(p, 21.0), "-");
  EXPECT_EQ(next(p, 21.5), "I am not sure of the way");
}

TEST(ReplyPolicy, AlertSilenceSwitchedOff)
{
  ReplyPolicyConfig c;
  c.silence_on_alert = false;
  ReplyPolicy p(c);
  EXPECT_FALSE(p.alert(1.0));
  p.offer("cues paused", Priority::CONFIRM, 1.0);
  EXPECT_EQ(next(p, 1.0), "cues paused");
}

TEST(ReplyPolicy, SwitchedOffSpeaksNothing)
{
  ReplyPolicyConfig c;
  c.enabled = false;
  ReplyPolicy p(c);
  EXPECT_FALSE(p.offer("place two saved", Priority::WARNING, 0.0));
  EXPECT_EQ(next(p, 1.0), "-");
}
