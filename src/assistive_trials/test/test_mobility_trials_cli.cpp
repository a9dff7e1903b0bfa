// The closed loop in CI (issue 19, short version): the simulated wearer walks the glass corridor
// on the real planner's and cue logic's cues (truth mode) without a collision and gets through;
// with the cue stage removed from the chain (--no-cues) the same wearer collides, so this test
// fails when the cues stop reaching the wearer. A few seconds, no roscore. `--generated` scores a
// generated set: one row and one heat map per world, the set's mean and worst in the JSON line.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <assistive_eval/bench_set.h>

namespace
{
/// The CLI's JSON line (its last line starting with '{') in a captured output file.
std::string lastLine(const std::string& path)
{
  return assistive_eval::lastJsonLine(assistive_eval::readTextFile(path));
}
double key(const std::string& json, const std::string& k)
{
  return assistive_eval::jsonNumber(json, k);
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

// (A named namespace: the tests derive from the fixture, and in the unity build this file is
// included, where a base with internal linkage draws -Wsubobject-linkage.)
namespace mobility_trials_cli_test
{
/// A passing test leaves nothing in the temporary folder: the files the CLI wrote there under
/// this file's names (logs, heat maps per world) go; a failing one keeps them to look at. (Only
/// these names: test_mobility_vision writes its own mobility_vision_* files there meanwhile.)
class MobilityTrials : public ::testing::Test
{
protected:
  void TearDown() override
  {
    if (HasFailure())
      return;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(::testing::TempDir(), ec))
    {
      const std::string name = e.path().filename().string();
      for (const char* mine : { "mobility_cues", "mobility_nocues", "mobility_set", "mobility_homes_", "mobility_unsure" })
        if (name.rfind(mine, 0) == 0 && e.is_regular_file(ec))
          std::filesystem::remove(e.path(), ec);
    }
  }
};
}  // namespace mobility_trials_cli_test
using mobility_trials_cli_test::MobilityTrials;

TEST_F(MobilityTrials, CuesKeepTheWearerClearAndWithoutThemItCollides)
{
  // the typical wearer (reaction 0.6 s); the population's figures are the trials' to report
  const std::string with = run("--world glass --trials 3 --seed 7 --mode truth --wearer typical", "cues");
  ASSERT_NE(with.find("\"trials\": 3"), std::string::npos) << with;
  EXPECT_EQ(key(with, "collisions_per_trial"), 0.0) << with;
  EXPECT_EQ(key(with, "completion_rate"), 1.0) << with;
  EXPECT_GT(key(with, "ppws_pct"), 30.0) << with;
  EXPECT_GT(key(with, "walking_pct"), 0.0) << with;
  const std::string without = run("--world glass --trials 3 --seed 7 --mode truth --wearer typical --no-cues", "nocues");
  EXPECT_GE(key(without, "collisions_per_trial"), 1.0) << without;
}

TEST_F(MobilityTrials, UsageAndUnknownWorld)
{
  const int rc = std::system((std::string(MOBILITY_TRIALS_EXE) + " > /dev/null 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  const int rc2 = std::system((std::string(MOBILITY_TRIALS_EXE) + " --world nosuchworld > /dev/null 2>&1").c_str());
  EXPECT_EQ(WEXITSTATUS(rc2), 2);
}

namespace
{
std::string slurp(const std::string& path)
{
  return assistive_eval::readTextFile(path);
}
bool has(const std::string& json, const std::string& k) { return json.find("\"" + k + "\": ") != std::string::npos; }
/// The JSON line without its wall-clock figures.
std::string withoutTimes(std::string json)
{
  for (const std::string k : {"\"generate_s\": ", "\"trials_s\": "})
  {
    const size_t p = json.find(k);
    if (p == std::string::npos) continue;
    const size_t e = json.find_first_of(",}", p);
    json.erase(p, e - p);
  }
  return json;
}
}  // namespace

TEST_F(MobilityTrials, GeneratedSetOneRowAndHeatMapPerWorldMeanAndWorst)
{
  // Two small generated homes (seeds 1001, 1002), one truth trial each.
  const std::string dir = ::testing::TempDir(), prefix = dir + "mobility_set", out = dir + "mobility_set.txt",
                    err = dir + "mobility_set.err";
  for (const char* w : {"gen_home_1001", "gen_home_1002"}) std::remove((prefix + "_" + w + ".png").c_str());
  const std::string cmd = std::string(MOBILITY_TRIALS_EXE) + " --generated 2 --kind home --trials 1 --mode truth --plot " +
                          prefix + ".png > " + out + " 2> " + err;
  int rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0) << cmd << "\n" << slurp(err);
  const std::string text = slurp(out), json = lastLine(out);
  // one row per world, progress on stderr
  EXPECT_NE(text.find("\ngen_home_1001 "), std::string::npos) << text;
  EXPECT_NE(text.find("\ngen_home_1002 "), std::string::npos) << text;
  EXPECT_NE(slurp(err).find("world 2/2"), std::string::npos) << slurp(err);
  // the JSON line: the single world's keys as set means, and the worst world's
  EXPECT_EQ(key(json, "worlds"), 2.0) << json;
  EXPECT_EQ(key(json, "seed_base"), 1001.0) << json;
  EXPECT_EQ(key(json, "trials"), 2.0) << json;
  EXPECT_EQ(key(json, "trials_per_world"), 1.0) << json;
  for (const char* k : {"collisions_per_trial", "completion_rate", "ppws_pct", "mean_clearance_m", "latency_ms_p99",
                        "wall_collisions_per_trial", "glass_collisions_per_trial", "collisions_worst",
                        "collisions_per_trial_worst", "completion_rate_worst", "ppws_pct_worst", "worlds_without_completion",
                        "generate_s", "trials_s", "walking_pct", "stop_turns_per_trial", "stops_per_trial"})
    EXPECT_TRUE(has(json, k)) << k << " missing: " << json;
  // where the wearers' time went, in the summary and the JSON line
  EXPECT_NE(text.find("wearer's time        walking "), std::string::npos) << text;
  EXPECT_GT(key(json, "walking_pct"), 0.0) << json;
  EXPECT_LT(key(json, "walking_pct"), 100.0) << json;
  EXPECT_GE(key(json, "collisions_per_trial_worst"), key(json, "collisions_per_trial")) << json;
  EXPECT_LE(key(json, "completion_rate_worst"), key(json, "completion_rate")) << json;
  EXPECT_GE(key(json, "collisions_worst"), key(json, "collisions_per_trial_worst")) << json;
  // a heat map per world next to --plot's prefix
  for (const char* w : {"gen_home_1001", "gen_home_1002"})
  {
    struct stat st;
    EXPECT_EQ(stat((prefix + "_" + w + ".png").c_str(), &st), 0) << prefix << "_" << w << ".png";
  }
  // the same set again: the same figures
  rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0);
  EXPECT_EQ(withoutTimes(lastLine(out)), withoutTimes(json));
}

// --mode floor (issue 33): the same trials walked with every cue at the best moment; on glass (a
// straight corridor: no corner) the floor is the guide's walk plus the first go (89-97 % of the
// guide's pace), above what the guidance reaches on the same wearers, and no collision.
TEST_F(MobilityTrials, TheFloorIsAboveTheGuidanceOnTheSameTrials)
{
  const std::string floor = run("--world glass --trials 3 --seed 7 --mode floor", "set_floor");
  ASSERT_NE(floor.find("\"mode\": \"floor\""), std::string::npos) << floor;
  EXPECT_EQ(key(floor, "completion_rate"), 1.0) << floor;
  EXPECT_EQ(key(floor, "collisions_per_trial"), 0.0) << floor;
  EXPECT_GT(key(floor, "ppws_pct"), 85.0) << floor;
  EXPECT_LT(key(floor, "ppws_pct"), 100.0) << floor;  // the first go's reaction is never free
  const std::string truth = run("--world glass --trials 3 --seed 7 --mode truth", "set_floor_truth");
  EXPECT_LT(key(truth, "ppws_pct"), key(floor, "ppws_pct")) << truth;
}

TEST_F(MobilityTrials, UsageErrors)
{
  const std::string exe = std::string(MOBILITY_TRIALS_EXE) + " ";
  auto code = [&](const std::string& args) {
    const int rc = std::system((exe + args + " > /dev/null 2>&1").c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  };
  EXPECT_EQ(code("--generated 2 --world glass"), 2);
  EXPECT_EQ(code("--world glass --mode guess"), 2);
  EXPECT_EQ(code("--generated 2 --kind castle"), 2);
  EXPECT_EQ(code("--generated -1"), 2);
  EXPECT_EQ(code("--world glass --kind home"), 2);
  EXPECT_EQ(code("--world glass --people 4"), 2);
  EXPECT_EQ(code("--generated 1 --people 101"), 2);
  EXPECT_EQ(code("--world glass --trials 1 --cue no_such_parameter=1"), 2);
  EXPECT_EQ(code("--world glass --trials 1 --grid-resolution 0"), 2);  // the perfect map's cell: 0.02-1 m
  EXPECT_EQ(code("--world glass --trials 1 --grid-resolution 5"), 2);
  EXPECT_EQ(code("--world glass --trials 1 --mode cane --grid-resolution 0.1"), 2);  // truth mode's alone
  EXPECT_EQ(code("--world glass --trials 1 --record " + ::testing::TempDir() + "mobility_set_rec"), 2);  // vision's alone
  // a heat map's name without an image extension is refused before the trials, not after them
  EXPECT_EQ(code("--world glass --trials 1 --plot " + ::testing::TempDir() + "mobility_set_noext"), 2);
}

TEST_F(MobilityTrials, GeneratedBusySetHasItsPeople)
{
  // --people N: each generated world gets N people (generate_world --people), who give way
  const std::string dir = ::testing::TempDir() + "mobility_busy_set", out = dir + ".txt", err = dir + ".err";
  const std::string cmd = std::string(MOBILITY_TRIALS_EXE) + " --generated 1 --seed-base 6111 --people 4 --trials 1 " +
                          "--mode truth --keep " + dir + " --plot " + dir + ".png > " + out + " 2> " + err;
  const int rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0) << cmd << "\n" << slurp(err);
  const std::string text = slurp(out);
  EXPECT_NE(text.find("4 people each"), std::string::npos) << text;
  EXPECT_NE(text.find("people "), std::string::npos) << text;
  EXPECT_TRUE(has(lastLine(out), "people_collisions_per_trial")) << lastLine(out);
  const std::string yaml = slurp(dir + "/gen_lobby_6111.yaml");
  EXPECT_NE(yaml.find("people:"), std::string::npos) << "gen_lobby_6111.yaml:\n" << yaml.substr(0, 300);
}

// CI's homes (issue 33): truth trials on three small generated homes with 0.80-0.90 m doorways,
// wearers drawn from the population. The targets (0 collisions, every trial completed) are not
// met today (see the closing note); what is asserted is what the cue stage must at least
// do: fewer collisions than a vest that only says "walk on".
TEST_F(MobilityTrials, HomesWithOrdinaryDoorwaysCuesBeatAWalkOnOnlyVest)
{
  const std::string args = "--generated 3 --kind home --seed-base 4001 --trials 2 --mode truth";
  const std::string with = run(args, "homes_cues");
  const std::string without = run(args + " --no-cues", "homes_nocues");
  ASSERT_TRUE(has(with, "collisions_per_trial")) << with;
  EXPECT_EQ(key(with, "worlds"), 3.0) << with;
  EXPECT_EQ(key(with, "trials"), 6.0) << with;
  EXPECT_LT(key(with, "collisions_per_trial"), key(without, "collisions_per_trial")) << with << "\n" << without;
}

// The UNSURE episode (the pose lost for 3 s, 6 s into the walk): the vest's three pulses stop the
// wearer within its reaction, the pulses and its stop: the typical wearer (1.1 m/s, 0.6 s)
// walks at most 1.1 x (0.6 + 0.1) + 1.1^2 / (2 x 2.4) = 1.02 m; the 0.5 m lies below
// that floor.
TEST_F(MobilityTrials, AnUnsureEpisodeStopsTheWearerWithinItsReaction)
{
  const std::string r = run("--world glass --trials 2 --mode truth --wearer typical --unsure-at 6 --unsure-for 3", "unsure");
  const double walked = key(r, "unsure_walked_m_max");
  EXPECT_GT(walked, 0.3) << r;  // it was walking when the episode began
  EXPECT_LE(walked, 1.05) << r;
  // its unsure cues are put down to the lost pose, none to the map (truth mode has no map gaps)
  const std::string log = assistive_eval::readTextFile(::testing::TempDir() + "mobility_unsure.txt");
  const size_t at = log.rfind("unsure for");
  ASSERT_NE(at, std::string::npos) << log;
  const std::string why = log.substr(at, log.find('\n', at) - at);
  double no_pose = -1, no_map = -1, unknown = -1;
  ASSERT_EQ(std::sscanf(why.c_str(), "unsure for no pose %lf %%, no map %lf %%, in unknown space %lf", &no_pose, &no_map,
                        &unknown),
            3)
      << why;
  EXPECT_GT(no_pose, 0.0) << why;
  EXPECT_EQ(no_map, 0.0) << why;
  EXPECT_EQ(unknown, 0.0) << why;
}
