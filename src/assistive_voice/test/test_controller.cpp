// The controller: buttons and voice end in the same effects; service results and cues in replies.
#include <gtest/gtest.h>

#include <cmath>

#include "assistive_voice/controller.h"

using namespace assistive_voice;

TEST(Controller, ButtonsAndVoiceGiveTheSameEffects)
{
  VoiceController b, v;
  const Effects eb = b.onButton(BUTTON_A, PRESS_SHORT, 0.0);
  const Effects ev = v.onCommand(parseCommand("save place"), 0.0);
  ASSERT_TRUE(eb.tag && ev.tag);
  EXPECT_EQ(*eb.tag, "");
  EXPECT_EQ(*ev.tag, "");
  EXPECT_FALSE(eb.reply);  // the reply waits for the service's answer

  const Effects gb = b.onButton(BUTTON_A, PRESS_LONG, 1.0);
  const Effects gv = v.onCommand(parseCommand("take me back"), 1.0);
  ASSERT_TRUE(gb.guide && gv.guide);
  EXPECT_EQ(*gb.guide, "");
  EXPECT_EQ(*gv.guide, "");
  EXPECT_EQ(*v.onCommand(parseCommand("take me back to the door"), 1.0).guide, "door");
  EXPECT_EQ(*v.onCommand(parseCommand("save place kitchen"), 1.0).tag, "kitchen");
}

TEST(Controller, ShortBTogglesThePause)
{
  VoiceController c;
  Effects e = c.onButton(BUTTON_B, PRESS_SHORT, 0.0);
  ASSERT_TRUE(e.pause);
  EXPECT_TRUE(*e.pause);
  EXPECT_EQ(e.command.action, Action::PAUSE);
  EXPECT_EQ(e.reply->text, "cues paused");
  EXPECT_EQ(e.reply->priority, Priority::CONFIRM);
  e = c.onButton(BUTTON_B, PRESS_SHORT, 1.0);
  EXPECT_FALSE(*e.pause);
  EXPECT_EQ(e.reply->text, "cues resumed");
  e = c.onCommand(parseCommand("pause"), 2.0);
  EXPECT_TRUE(*e.pause);
  EXPECT_TRUE(c.paused());
  e = c.onCommand(parseCommand("resume"), 3.0);
  EXPECT_FALSE(*e.pause);
}

TEST(Controller, ServiceResultsBecomeReplies)
{
  VoiceController c;
  EXPECT_EQ(c.onTagResult(false, "", std::nullopt, 0.0).reply->text, "I cannot save this place yet");
  EXPECT_EQ(c.onGuideResult(false, "", 0.0).reply->text, "no place is saved");
  EXPECT_EQ(c.onTagResult(true, "place2", Pose2{1, 2, 0}, 0.0).reply->text, "place two saved");
  EXPECT_EQ(c.onGuideResult(true, "", 1.0).reply->text, "guiding back to place two");
  EXPECT_EQ(c.onTagResult(true, "door", Pose2{5, 2, 0}, 2.0).reply->text, "door saved");
  EXPECT_EQ(c.onGuideResult(true, "", 3.0).reply->text, "guiding back to the door");
  EXPECT_EQ(c.onGuideResult(true, "place2", 3.0).reply->text, "guiding back to place two");
  EXPECT_EQ(c.onGuideResult(false, "office", 3.0).reply->text, "I cannot guide you back");
}

TEST(Controller, WhereAmI)
{
  VoiceController c;
  EXPECT_EQ(c.onButton(BUTTON_B, PRESS_LONG, 0.0).reply->text, "I do not know where I am");
  c.setPose(Pose2{0, 0, 0});
  EXPECT_EQ(c.whereAmI(), "no place is saved");
  c.onTagResult(true, "door", Pose2{0, 0, 0}, 0.0);
  c.onTagResult(true, "place3", Pose2{10, 10, 0}, 0.0);
  EXPECT_EQ(c.whereAmI(), "you are at the door");
  c.setPose(Pose2{-3.2, 0, 0});  // facing +x: the door 3.2 m ahead
  EXPECT_EQ(c.whereAmI(), "the door is three metres ahead");
  c.setPose(Pose2{0, -4, 0});  // facing +x, the door at +y: to the left
  EXPECT_EQ(c.whereAmI(), "the door is four metres to your left");
  c.setPose(Pose2{0, 1, 0});
  EXPECT_EQ(c.whereAmI(), "the door is one metre to your right");
  c.setPose(Pose2{2, 0, 0});
  EXPECT_EQ(c.whereAmI(), "the door is two metres behind you");
  c.setPose(Pose2{9.2, 9, M_PI / 2});  // place3 at (+0.8, +1): 39 deg right of +y
  EXPECT_EQ(c.whereAmI(), "place three is one metre ahead");
  EXPECT_EQ(c.onCommand(parseCommand("where am i"), 0.0).reply->priority, Priority::INFO);
}

TEST(Controller, WhatIsAheadAndWarnings)
{
  VoiceController c(2.0);
  EXPECT_EQ(c.whatIsAhead(), "I have no cues yet");
  c.onCue(CUE_IDLE, "", 0.0);
  EXPECT_EQ(c.onCommand(parseCommand("what is ahead"), 0.0).reply->text, "the way ahead is clear");
  c.onCue(CUE_PROXIMITY, "wall 0.8 m ahead", 0.1);
  EXPECT_EQ(c.whatIsAhead(), "wall 0.8 metres ahead");
  c.onCue(CUE_GUIDANCE, "turn left 35 deg", 0.2);
  EXPECT_EQ(c.whatIsAhead(), "turn left 35 degrees");
  c.onCue(CUE_ALERT, "wall 0.3 m ahead", 0.3);
  EXPECT_EQ(c.whatIsAhead(), "stop");
  // UNSURE for 2 s: one WARNING per episode
  EXPECT_FALSE(c.onCue(CUE_UNSURE, "vo lost", 1.0).reply);
  EXPECT_FALSE(c.onCue(CUE_UNSURE, "vo lost", 2.9).reply);
  const Effects w = c.onCue(CUE_UNSURE, "vo lost", 3.0);
  ASSERT_TRUE(w.reply);
  EXPECT_EQ(w.reply->text, "I am not sure of the way");
  EXPECT_EQ(w.reply->priority, Priority::WARNING);
  EXPECT_FALSE(c.onCue(CUE_UNSURE, "vo lost", 9.0).reply);
  c.onCue(CUE_IDLE, "", 9.1);
  EXPECT_FALSE(c.onCue(CUE_UNSURE, "vo lost", 9.2).reply);
  EXPECT_TRUE(c.onCue(CUE_UNSURE, "vo lost", 11.2).reply);
}

TEST(Controller, GuideBackByVoiceWaitsForYes)
{
  VoiceController c(2.0, 6.0);
  Effects e = c.onVoiceCommand(parseCommand("take me back to the door"), 10.0);
  EXPECT_FALSE(e.guide) << "nothing is done before the answer";
  EXPECT_EQ(e.command.action, Action::NONE);
  EXPECT_TRUE(e.listen);
  EXPECT_EQ(e.reply->text, "take me back to the door? say yes or press a button");
  EXPECT_EQ(e.reply->priority, Priority::CONFIRM);
  EXPECT_TRUE(c.awaitingConfirmation());
  e = c.onVoiceCommand(parseCommand("yes"), 12.0);
  ASSERT_TRUE(e.guide);
  EXPECT_EQ(*e.guide, "door");
  EXPECT_EQ(e.command, (Command{Action::GUIDE_BACK, "door"}));
  EXPECT_FALSE(c.awaitingConfirmation());
  EXPECT_FALSE(c.onVoiceCommand(parseCommand("yes"), 13.0).guide) << "a yes, no question: nothing";
}

TEST(Controller, AnyButtonConfirmsNoOrSilenceCancels)
{
  VoiceController c(2.0, 6.0);
  EXPECT_EQ(c.onVoiceCommand(parseCommand("take me back"), 0.0).reply->text,
            "take me back to the last place? say yes or press a button");
  Effects e = c.onButton(BUTTON_B, PRESS_SHORT, 1.0);  // short B would toggle the pause otherwise
  ASSERT_TRUE(e.guide);
  EXPECT_EQ(*e.guide, "");
  EXPECT_FALSE(e.pause);

  c.onVoiceCommand(parseCommand("take me back to car"), 20.0);
  e = c.onVoiceCommand(parseCommand("no"), 21.0);
  EXPECT_FALSE(e.guide);
  EXPECT_EQ(e.reply->text, "cancelled");
  EXPECT_FALSE(c.awaitingConfirmation());

  c.onVoiceCommand(parseCommand("take me back to car"), 30.0);
  EXPECT_FALSE(c.onTime(35.9).reply) << "still waiting";
  e = c.onTime(36.0);
  EXPECT_EQ(e.reply->text, "cancelled");
  EXPECT_FALSE(e.guide);
  EXPECT_FALSE(c.onVoiceCommand(parseCommand("yes"), 36.5).guide) << "too late";
}

TEST(Controller, OtherCommandsActAtOnceAndReplaceAQuestion)
{
  VoiceController c(2.0, 6.0);
  EXPECT_EQ(*c.onVoiceCommand(parseCommand("save place kitchen"), 0.0).tag, "kitchen");
  EXPECT_TRUE(*c.onVoiceCommand(parseCommand("pause"), 1.0).pause);
  c.onVoiceCommand(parseCommand("take me back"), 2.0);
  const Effects e = c.onVoiceCommand(parseCommand("where am i"), 3.0);
  EXPECT_EQ(e.command.action, Action::WHERE_AM_I);
  EXPECT_FALSE(c.awaitingConfirmation());
  EXPECT_FALSE(c.onVoiceCommand(parseCommand("yes"), 4.0).guide);
  EXPECT_TRUE(c.onRejected(5.0).reply);
  EXPECT_FALSE(c.onRejected(5.0).listen);
  c.onVoiceCommand(parseCommand("take me back"), 6.0);
  const Effects r = c.onRejected(7.0);
  EXPECT_EQ(r.reply->text, "say again");
  EXPECT_TRUE(r.listen) << "the question stays open";
  VoiceController now(2.0, 0.0);  // confirm_s 0: at once
  EXPECT_EQ(*now.onVoiceCommand(parseCommand("take me back to the door"), 0.0).guide, "door");
}
