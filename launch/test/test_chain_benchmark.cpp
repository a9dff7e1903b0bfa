// chain_benchmark on the first 40 frames of the fault suite's test bag (course, rendered at build
// time): every stage runs on every frame (the obstacle stage gives a grid from its 5th fresh frame
// on, the planner a cycle per grid) and the JSON last line carries the total and every stage's
// figures.
#include <gtest/gtest.h>

#include <cstdio>
#include <regex>
#include <string>

namespace
{
std::string lastLine(const std::string& cmd)
{
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return "";
  std::string line, last;
  char buf[4096];
  while (std::fgets(buf, sizeof(buf), p))
  {
    line += buf;
    if (!line.empty() && line.back() == '\n')
    {
      last = line;
      line.clear();
    }
  }
  if (!line.empty()) last = line;
  pclose(p);
  return last;
}

double number(const std::string& json, const std::string& key)
{
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": ([-0-9.eE]+)"))) return -1.0;
  return std::stod(m[1]);
}
}  // namespace

TEST(ChainBenchmark, EveryStageRunsOnEveryFrame)
{
  const std::string json = lastLine(std::string(CHAIN_BENCHMARK) + " " + CHAIN_BAG + " --frames 40 2>/dev/null");
  ASSERT_FALSE(json.empty());
  EXPECT_EQ(number(json, "frames"), 40);
  EXPECT_EQ(number(json, "opencv_threads"), 1);
  // The VO gives a pose from the first frame; the map is published from the 5th frame on.
  EXPECT_EQ(number(json, "grids"), 36) << json;
  EXPECT_EQ(number(json, "planner_cycles"), 36) << json;
  for (const char* s : { "vo", "slam", "obstacles", "planner", "cue", "total" })
  {
    EXPECT_GE(number(json, std::string("ms_p95_") + s), 0.0) << s;
    EXPECT_GE(number(json, std::string("ms_max_") + s), number(json, std::string("ms_p95_") + s)) << s;
  }
  EXPECT_GT(number(json, "ms_p95_obstacles"), 0.0);
  EXPECT_GE(number(json, "ms_p95_total"), number(json, "ms_p95_obstacles"));
}
