// generate_world from the command line: usage and exit codes, the JSON line, the file parses and
// is the same for the same seed, and render_bag renders it (the end-to-end path of issue 17).
#include <assistive_sim/world.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <assistive_eval/bench_set.h>

using namespace assistive_sim;

namespace
{
int run(const std::string& args, const std::string& log)
{
  const std::string cmd = std::string(GENERATE_WORLD_EXE) + " " + args + " > " + log + " 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
std::string slurp(const std::string& path)
{
  return assistive_eval::readTextFile(path);
}
/// The CLI's JSON line (its last line starting with '{') in a captured output file.
std::string lastLine(const std::string& path)
{
  return assistive_eval::lastJsonLine(assistive_eval::readTextFile(path));
}
}  // namespace

TEST(GenerateWorldCli, UsageAndExitCodes)
{
  const std::string log = std::string(::testing::TempDir()) + "gen_cli_usage.log";
  EXPECT_EQ(run("--help", log), 0);
  EXPECT_NE(slurp(log).find("usage: generate_world"), std::string::npos);
  EXPECT_EQ(run("", log), 2);                                  // --seed and --out missing
  EXPECT_EQ(run("--seed 1", log), 2);                          // --out missing
  EXPECT_EQ(run("--seed x --out /dev/null", log), 2);          // bad number
  EXPECT_EQ(run("--seed 1 --kind castle --out /dev/null", log), 2);
  EXPECT_EQ(run("--seed 1 --frobnicate --out /dev/null", log), 2);
}

TEST(GenerateWorldCli, WritesParsableDeterministicWorldThatRenders)
{
  const std::string dir = ::testing::TempDir();
  const std::string a = dir + "gen_cli_a.yaml", b = dir + "gen_cli_b.yaml", log = dir + "gen_cli.log";
  ASSERT_EQ(run("--seed 5 --kind hall --out " + a, log), 0) << slurp(log);
  const std::string json = lastLine(log);
  EXPECT_EQ(json.front(), '{');
  EXPECT_NE(json.find("\"seed\": 5"), std::string::npos) << json;
  EXPECT_NE(json.find("\"kind\": \"hall\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"elements\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"walk_length_m\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"out\": \"" + a + "\""), std::string::npos) << json;
  const World w = World::load(a);
  EXPECT_EQ(w.name, "gen_hall_5");
  ASSERT_EQ(run("--seed 5 --kind hall --out " + b, log), 0);
  EXPECT_EQ(slurp(a), slurp(b));
  // End to end: the file renders to a bag.
  const std::string bag = dir + "gen_cli.bag";
  const std::string cmd = std::string(RENDER_BAG_EXE) + " --world " + a + " --out " + bag +
                          " --frames 3 --width 160 --height 120 > " + log + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_NE(lastLine(log).find("\"frames\": 3"), std::string::npos) << lastLine(log);
}

TEST(GenerateWorldCli, PeopleOptionDeterministicAndZeroIsUnchanged)
{
  const std::string dir = ::testing::TempDir();
  const std::string plain = dir + "gen_cli_p0.yaml", zero = dir + "gen_cli_pz.yaml", a = dir + "gen_cli_pa.yaml",
                    b = dir + "gen_cli_pb.yaml", log = dir + "gen_cli_p.log";
  ASSERT_EQ(run("--seed 7 --out " + plain, log), 0) << slurp(log);
  ASSERT_EQ(run("--seed 7 --people 0 --out " + zero, log), 0) << slurp(log);
  EXPECT_EQ(slurp(plain), slurp(zero));  // --people 0 (the default): the world of before
  ASSERT_EQ(run("--seed 7 --people 4 --out " + a, log), 0) << slurp(log);
  EXPECT_NE(lastLine(log).find("\"people\": 4"), std::string::npos) << lastLine(log);
  ASSERT_EQ(run("--seed 7 --people 4 --out " + b, log), 0);
  EXPECT_EQ(slurp(a), slurp(b));
  const World w = World::load(a), w0 = World::load(plain);
  EXPECT_EQ(w.people.size(), 4u);
  EXPECT_EQ(w.solids.size(), w0.solids.size());
  EXPECT_EQ(w.trajectory.waypoints, w0.trajectory.waypoints);
  EXPECT_EQ(run("--seed 7 --people -1 --out " + b, log), 2);
}
