// The grammar-to-action table: every sentence of the grammar and every button press, exact answers.
#include <gtest/gtest.h>

#include "assistive_voice/commands.h"

using namespace assistive_voice;

namespace
{
Command cmd(Action a, const std::string& n = "") { return Command{a, n}; }
}  // namespace

TEST(Commands, EverySentenceOfTheGrammarMapsToItsAction)
{
  EXPECT_EQ(parseCommand("save place"), cmd(Action::SAVE_PLACE));
  EXPECT_EQ(parseCommand("save place door"), cmd(Action::SAVE_PLACE, "door"));
  EXPECT_EQ(parseCommand("save place bus stop"), cmd(Action::SAVE_PLACE, "bus stop"));
  EXPECT_EQ(parseCommand("take me back"), cmd(Action::GUIDE_BACK));
  EXPECT_EQ(parseCommand("take me back to the door"), cmd(Action::GUIDE_BACK, "door"));
  EXPECT_EQ(parseCommand("take me back to kitchen"), cmd(Action::GUIDE_BACK, "kitchen"));
  EXPECT_EQ(parseCommand("take me back to the bus stop"), cmd(Action::GUIDE_BACK, "bus stop"));
  EXPECT_EQ(parseCommand("pause"), cmd(Action::PAUSE));
  EXPECT_EQ(parseCommand("resume"), cmd(Action::RESUME));
  EXPECT_EQ(parseCommand("where am i"), cmd(Action::WHERE_AM_I));
  EXPECT_EQ(parseCommand("yes"), cmd(Action::YES));  // answers (confirmGrammar), not commands
  EXPECT_EQ(parseCommand("no"), cmd(Action::NO));
  EXPECT_EQ(confirmGrammar(), "#JSGF V1.0;\ngrammar confirm;\npublic <answer> = yes | no;\n");
  EXPECT_EQ(commandGrammar().find("yes"), std::string::npos);
  EXPECT_EQ(parseCommand("what is ahead"), cmd(Action::WHAT_IS_AHEAD));
}

TEST(Commands, RecogniserOutputIsNormalised)
{
  // pocketsphinx's alternates and fillers, case and punctuation of typed text
  EXPECT_EQ(parseCommand("<s> take me back to the(2) door </s>"), cmd(Action::GUIDE_BACK, "door"));
  EXPECT_EQ(parseCommand("Where am I?"), cmd(Action::WHERE_AM_I));
  EXPECT_EQ(parseCommand("  save   place  [noise] Office "), cmd(Action::SAVE_PLACE, "office"));
  EXPECT_EQ(normalizeText("<sil> What  IS ahead. "), "what is ahead");
}

TEST(Commands, SentencesOutsideTheGrammarAreNoCommand)
{
  for (const char* s : {"", "hello", "take me", "take me back home", "take me back to", "take me back to the",
                        "pause the music", "where am", "what is", "save", "saved place door", "resume now"})
    EXPECT_EQ(parseCommand(s).action, Action::NONE) << "'" << s << "'";
}

TEST(Commands, ButtonTable)
{
  EXPECT_EQ(buttonAction(BUTTON_A, PRESS_SHORT), Action::SAVE_PLACE);
  EXPECT_EQ(buttonAction(BUTTON_A, PRESS_LONG), Action::GUIDE_BACK);
  EXPECT_EQ(buttonAction(BUTTON_B, PRESS_SHORT), Action::TOGGLE_PAUSE);
  EXPECT_EQ(buttonAction(BUTTON_B, PRESS_LONG), Action::WHERE_AM_I);
  EXPECT_EQ(buttonAction(BUTTON_A, PRESS_NONE), Action::NONE);
  EXPECT_EQ(buttonAction(BUTTON_B, PRESS_NONE), Action::NONE);
  EXPECT_EQ(buttonAction(2, PRESS_SHORT), Action::NONE);
  EXPECT_EQ(buttonAction(BUTTON_A, 3), Action::NONE);
}

TEST(Commands, GrammarIsJsgfWithEveryName)
{
  const std::string g = commandGrammar({"door", "bus stop"});
  EXPECT_EQ(g,
            "#JSGF V1.0;\n"
            "grammar vest;\n"
            "public <command> = <save> | <back> | pause | resume | where am i | what is ahead;\n"
            "<save> = save place [<name>];\n"
            "<back> = take me back [to [the] <name>];\n"
            "<name> = door | bus stop;\n");
  for (const std::string& n : defaultPlaceNames())
  {
    EXPECT_NE(commandGrammar().find(n), std::string::npos) << n;
    EXPECT_EQ(parseCommand("save place " + n), cmd(Action::SAVE_PLACE, n));
    EXPECT_EQ(parseCommand("take me back to the " + n), cmd(Action::GUIDE_BACK, n));
  }
}

TEST(Commands, SpokenNames)
{
  EXPECT_EQ(spokenName("place2"), "place two");
  EXPECT_EQ(spokenName("place21"), "place twenty one");
  EXPECT_EQ(spokenName("bus_stop"), "bus stop");
  EXPECT_EQ(spokenName("door"), "door");
  EXPECT_EQ(numberWords(0), "zero");
  EXPECT_EQ(numberWords(40), "forty");
  EXPECT_EQ(numberWords(100), "100");
  EXPECT_STREQ(actionName(Action::GUIDE_BACK), "guide_back");
}
