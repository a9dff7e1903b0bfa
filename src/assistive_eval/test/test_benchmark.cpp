// The benchmark helper (benchmark.h) against known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <assistive_eval/benchmark.h>

using namespace assistive_eval;

TEST(Statistics, PercentilesKnownAnswers)
{
  const std::vector<double> v{4, 1, 3, 2};  // sorted: 1 2 3 4
  EXPECT_DOUBLE_EQ(percentile(v, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(percentile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(percentile(v, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(percentile(v, 0.95), 3.85);  // 0.95 * 3 = 2.85: 3 + 0.85 * (4 - 3)
  EXPECT_DOUBLE_EQ(median(v), 2.5);
  EXPECT_DOUBLE_EQ(median({5, 1, 3}), 3.0);
  EXPECT_DOUBLE_EQ(percentileNearestRank(v, 0.5), 2.0);   // ceil(0.5 * 4) = 2nd
  EXPECT_DOUBLE_EQ(percentileNearestRank(v, 0.95), 4.0);  // ceil(3.8) = 4th
  EXPECT_DOUBLE_EQ(percentileNearestRank(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(mean(v), 2.5);
  EXPECT_TRUE(std::isnan(percentile({}, 0.5)));
  EXPECT_TRUE(std::isnan(percentileNearestRank({}, 0.5)));
  EXPECT_TRUE(std::isnan(mean({})));
}

TEST(Timing, StopwatchCountsCpuOfThisThread)
{
  const Stopwatch sw;
  volatile double x = 0.0;
  for (int i = 0; i < 2000000; ++i)
    x = x + std::sqrt(static_cast<double>(i));
  EXPECT_GT(sw.cpuMs(), 0.0);
  EXPECT_GE(sw.wallMs(), 0.0);
  int calls = 0;
  EXPECT_GE(medianWallMs([&] { ++calls; }, 3), 0.0);
  EXPECT_EQ(calls, 3);
}

TEST(JsonLine, NumbersAndOrder)
{
  EXPECT_EQ(jsonNumber(1.23456789, 4), "1.235");
  EXPECT_EQ(jsonNumber(NAN), "null");
  EXPECT_EQ(jsonFixed(2.0, 3), "2.000");
  EXPECT_EQ(jsonFixed(INFINITY, 3), "null");
  JsonLine js;
  js.add("frames", 12).add("drift_pct", jsonNumber(0.5, 4)).addNull("peer").add("gt_depth", false);
  js.add("n", 7ULL).add(std::string("pair") + "_ms", jsonFixed(1.0, 1));
  EXPECT_EQ(js.str(), "{\"frames\": 12, \"drift_pct\": 0.5, \"peer\": null, \"gt_depth\": false, \"n\": 7, "
                      "\"pair_ms\": 1.0}");
  EXPECT_EQ(JsonLine().str(), "{}");
}

namespace
{
/// parse() on a list of arguments (argv[0] = "prog").
int parse(const CommandLine& cl, std::vector<std::string> args)
{
  args.insert(args.begin(), "prog");
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(&a[0]);
  return cl.parse(static_cast<int>(argv.size()), argv.data());
}
}  // namespace

TEST(CommandLine, OptionsPositionalAndSets)
{
  std::string bag, png;
  bool peer = true;
  long frames = -1;
  double t = 0.15;
  CommandLine::Sets sets;
  CommandLine cl("prog", "usage: prog FILE.bag\n");
  cl.positional(&bag, "bag", true).flag("--no-peer", &peer, false).count("--frames", &frames, 0L).text("--png", &png)
      .number("--max-t", &t).sets(&sets);
  EXPECT_EQ(parse(cl, {"a.bag", "--no-peer", "--frames", "20", "--png", "x.png", "--max-t", "0.5", "--set",
                       "min_tracks=40", "--set", "name=a=b"}),
            -1);
  EXPECT_EQ(bag, "a.bag");
  EXPECT_FALSE(peer);
  EXPECT_EQ(frames, 20);
  EXPECT_EQ(png, "x.png");
  EXPECT_DOUBLE_EQ(t, 0.5);
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_EQ(sets[0], std::make_pair(std::string("min_tracks"), std::string("40")));
  EXPECT_EQ(sets[1], std::make_pair(std::string("name"), std::string("a=b")));  // first '=' splits
}

TEST(CommandLine, HelpAndUsageErrors)
{
  std::string bag;
  int reps = 5;
  unsigned long long seed = 1;
  CommandLine::Sets sets;
  CommandLine cl("prog", "usage: prog FILE.bag\n");
  cl.positional(&bag, "bag", true).count("--reps", &reps, 1).count("--seed", &seed).sets(&sets);
  EXPECT_EQ(parse(cl, {"--help"}), 0);
  EXPECT_EQ(parse(cl, {"-h", "--no-such"}), 0);  // help first: nothing else is looked at
  EXPECT_EQ(parse(cl, {}), 2);                    // no bag given
  EXPECT_EQ(parse(cl, {"a.bag", "b.bag"}), 2);    // one bag only
  EXPECT_EQ(parse(cl, {"a.bag", "-q"}), 2);       // unknown option
  EXPECT_EQ(parse(cl, {"a.bag", "--reps"}), 2);   // needs a value
  EXPECT_EQ(parse(cl, {"a.bag", "--reps", "0"}), 2);
  EXPECT_EQ(parse(cl, {"a.bag", "--reps", "3x"}), 2);
  EXPECT_EQ(parse(cl, {"a.bag", "--seed", "-1"}), 2);
  EXPECT_EQ(parse(cl, {"a.bag", "--set", "novalue"}), 2);
  EXPECT_EQ(parse(cl, {"a.bag", "--set", "=1"}), 2);
  EXPECT_EQ(reps, 5);  // malformed values leave the default
  EXPECT_EQ(parse(cl, {"a.bag", "--reps", "3", "--seed", "18446744073709551615"}), -1);
  EXPECT_EQ(reps, 3);
  EXPECT_EQ(seed, 18446744073709551615ULL);
  std::string dir;
  CommandLine none("prog", "usage: prog\n");
  EXPECT_EQ(parse(none, {"stray"}), 2);  // no positional argument declared
  CommandLine optional_dir("prog", "usage: prog [DIR]\n");
  optional_dir.positional(&dir, "DIR", false);
  EXPECT_EQ(parse(optional_dir, {}), -1);
  EXPECT_TRUE(dir.empty());
}
