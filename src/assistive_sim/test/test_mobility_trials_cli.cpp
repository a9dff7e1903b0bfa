// The closed loop in CI (issue 19, short version): the simulated wearer walks the glass corridor
// on the real planner's and cue logic's cues (truth mode) without a collision and gets through;
// with the cue stage removed from the chain (--no-cues) the same wearer collides, so this test
// fails when the cues stop reaching the wearer. A few seconds, no roscore.
#include <cstdlib>
#include <fstream>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>

namespace
{
std::string lastLine(const std::string& path)
{
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}
double key(const std::string& json, const std::string& k)
{
  const size_t p = json.find("\"" + k + "\": ");
  if (p == std::string::npos) return -1.0;
  return std::atof(json.c_str() + p + k.size() + 4);
}
std::string run(const std::string& args, const std::string& tag)
{
  const std::string log = ::testing::TempDir() + "mobility_" + tag + ".txt";
  const std::string cmd = std::string(MOBILITY_TRIALS_EXE) + " " + args + " --plot " + ::testing::TempDir() +
                          "mobility_" + tag + ".png > " + log + " 2>/dev/null";
  const int rc = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0) << cmd;
  return lastLine(log);
}
}  // namespace

TEST(MobilityTrials, CuesKeepTheWearerClearAndWithoutThemItCollides)
{
  const std::string with = run("--world glass --trials 3 --seed 7 --mode truth", "cues");
  ASSERT_NE(with.find("\"trials\": 3"), std::string::npos) << with;
  EXPECT_EQ(key(with, "collisions_per_trial"), 0.0) << with;
  EXPECT_EQ(key(with, "completion_rate"), 1.0) << with;
  EXPECT_GT(key(with, "ppws_pct"), 30.0) << with;
  const std::string without = run("--world glass --trials 3 --seed 7 --mode truth --no-cues", "nocues");
  EXPECT_GE(key(without, "collisions_per_trial"), 1.0) << without;
}

TEST(MobilityTrials, UsageAndUnknownWorld)
{
  const int rc = std::system((std::string(MOBILITY_TRIALS_EXE) + " > /dev/null 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  const int rc2 = std::system((std::string(MOBILITY_TRIALS_EXE) + " --world nosuchworld > /dev/null 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(rc2), 2);
}
