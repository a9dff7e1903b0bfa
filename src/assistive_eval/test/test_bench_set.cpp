// The set run's shared logic (bench_set.h): JSON reading, mean/worst aggregation with the worst
// bag named, the set's JSON keys, and the command line's pass-through of options to each bag.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <assistive_eval/bench_set.h>
#include <assistive_eval/benchmark.h>

using namespace assistive_eval;

namespace
{
BagResult bag(const std::string& name, std::map<std::string, double> v, bool ok = true)
{
  BagResult b;
  b.bag = "/x/" + name + ".bag";
  b.name = name;
  b.ok = ok;
  b.values = std::move(v);
  return b;
}
const double NaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

TEST(BenchSet, ParsesAFlatJsonLine)
{
  std::map<std::string, double> v;
  ASSERT_TRUE(parseJsonNumbers(
      R"({"frames": 184, "drift_pct": 0.6437, "x": -1.5e-3, "peer": null, "gt_depth": false, "ok": true, )"
      R"("world": "a \"b\", c", "list": [1, {"q": 2}], "after": 7})",
      &v));
  EXPECT_DOUBLE_EQ(v.at("frames"), 184);
  EXPECT_DOUBLE_EQ(v.at("drift_pct"), 0.6437);
  EXPECT_DOUBLE_EQ(v.at("x"), -0.0015);
  EXPECT_TRUE(std::isnan(v.at("peer")));
  EXPECT_DOUBLE_EQ(v.at("gt_depth"), 0.0);
  EXPECT_DOUBLE_EQ(v.at("ok"), 1.0);
  EXPECT_EQ(v.count("world"), 0u);  // strings are skipped
  EXPECT_EQ(v.count("list"), 0u);
  EXPECT_DOUBLE_EQ(v.at("after"), 7);
  std::map<std::string, double> w;
  EXPECT_FALSE(parseJsonNumbers("not json", &w));
  EXPECT_FALSE(parseJsonNumbers(R"({"a": })", &w));
  EXPECT_EQ(lastJsonLine("table\n{\"a\": 1}\nmore\n{\"b\": 2}\n"), "{\"b\": 2}");
  EXPECT_EQ(lastJsonLine("no json here\n"), "");
  EXPECT_EQ(bagStem("/tmp/set/gen12.bag"), "gen12");
}

TEST(BenchSet, MeanAndWorstWithTheWorstBagNamed)
{
  const std::vector<BagResult> bags{
      bag("gen1", {{"recall_3m", 0.9}, {"drift_pct", 0.5}, {"free_where_obstacle_cells", 0}}),
      bag("gen2", {{"recall_3m", 0.6}, {"drift_pct", 2.5}, {"free_where_obstacle_cells", 31}}),
      bag("gen3", {{"recall_3m", 0.75}, {"drift_pct", NaN}, {"free_where_obstacle_cells", 41}}),
      bag("gen4", {{"recall_3m", 0.0}, {"drift_pct", 99}}, false)};  // failed run: left out
  const std::vector<SetFigure> figs{{"recall_3m", true}, {"drift_pct"}, {"free_where_obstacle_cells", false, true},
                                    {"absent"}};
  const std::vector<SetAggregate> a = aggregateSet(bags, figs);
  ASSERT_EQ(a.size(), 4u);
  EXPECT_NEAR(a[0].mean, 0.75, 1e-12);  // (0.9 + 0.6 + 0.75) / 3
  EXPECT_DOUBLE_EQ(a[0].worst, 0.6);    // higher is better: the minimum
  EXPECT_EQ(a[0].worst_bag, "gen2");
  EXPECT_EQ(a[0].n, 3);
  EXPECT_DOUBLE_EQ(a[1].mean, 1.5);  // null left out: (0.5 + 2.5) / 2
  EXPECT_DOUBLE_EQ(a[1].worst, 2.5);
  EXPECT_EQ(a[1].worst_bag, "gen2");
  EXPECT_EQ(a[1].n, 2);
  EXPECT_EQ(a[1].missing, 1);
  EXPECT_DOUBLE_EQ(a[2].worst, 41);
  EXPECT_EQ(a[2].worst_bag, "gen3");
  EXPECT_NEAR(a[2].mean, 24.0, 1e-12);
  EXPECT_TRUE(std::isnan(a[3].mean));
  EXPECT_TRUE(a[3].worst_bag.empty());

  // Equal worst figures: the first bag in the set's order keeps the name.
  const auto tie = aggregateSet({bag("a", {{"k", 3}}), bag("b", {{"k", 3}})}, {{"k"}});
  EXPECT_EQ(tie[0].worst_bag, "a");

  const std::string js = setJson(bags, figs, a);
  std::map<std::string, double> v;
  ASSERT_TRUE(parseJsonNumbers(js, &v)) << js;
  EXPECT_DOUBLE_EQ(v.at("bags"), 4);
  EXPECT_DOUBLE_EQ(v.at("bags_failed"), 1);
  EXPECT_DOUBLE_EQ(v.at("recall_3m_worst"), 0.6);
  EXPECT_DOUBLE_EQ(v.at("recall_3m_mean"), 0.75);
  EXPECT_DOUBLE_EQ(v.at("drift_pct_worst"), 2.5);
  EXPECT_DOUBLE_EQ(v.at("free_where_obstacle_cells_max"), 41);
  EXPECT_EQ(v.count("drift_pct_max"), 0u);  // _max only where asked
  EXPECT_TRUE(std::isnan(v.at("absent_mean")));
  EXPECT_NE(js.find("\"recall_3m_worst_bag\": \"gen2\""), std::string::npos) << js;
  EXPECT_NE(js.find("\"absent_worst_bag\": null"), std::string::npos) << js;

  const std::string table = setTable(bags, figs, a);
  EXPECT_NE(table.find("gen4    (failed: no result)"), std::string::npos) << table;
  EXPECT_NE(table.find("mean"), std::string::npos);
  EXPECT_NE(table.find("worst"), std::string::npos);
}

TEST(BenchSet, CommandLinePassesOptionsButNotBagsOrSetOptionsToEachBag)
{
  int frames = 0;
  bool no_imu = false;
  std::string plot;
  CommandLine::Sets sets;
  SetOptions so;
  CommandLine cl("bench", "usage: bench\n");
  so.addTo(cl);
  cl.count("--frames", &frames, 0).flag("--no-imu", &no_imu).text("--plot", &plot).sets(&sets);
  const char* args[] = {"bench", "a.bag", "--frames", "150", "b.bag", "--generated", "3", "--kinds", "office,hall",
                        "--no-imu", "--plot", "out", "--set", "x=1", "--imperfect"};
  const int argc = static_cast<int>(sizeof args / sizeof *args);
  ASSERT_EQ(cl.parse(argc, const_cast<char**>(args)), -1);
  EXPECT_EQ(so.bags, (std::vector<std::string>{"a.bag", "b.bag"}));
  EXPECT_EQ(so.generated, 3);
  EXPECT_TRUE(so.imperfect);
  EXPECT_TRUE(so.isSet());
  EXPECT_EQ(splitList(so.kinds), (std::vector<std::string>{"office", "hall"}));
  const std::vector<std::string> pass =
      cl.passthrough(argc, const_cast<char**>(args), {"--generated", "--kinds", "--imperfect", "--keep", "--plot"});
  EXPECT_EQ(pass, (std::vector<std::string>{"--frames", "150", "--no-imu", "--set", "x=1"}));

  // One bag: not a set; no bag at all: a usage error (exit 2).
  SetOptions one;
  CommandLine c1("bench", "usage: bench\n");
  one.addTo(c1);
  const char* a1[] = {"bench", "only.bag"};
  ASSERT_EQ(c1.parse(2, const_cast<char**>(a1)), -1);
  EXPECT_FALSE(one.isSet());
  SetOptions none;
  CommandLine c0("bench", "usage: bench\n");
  none.addTo(c0);
  const char* a0[] = {"bench", "--generated", "0"};
  EXPECT_EQ(c0.parse(3, const_cast<char**>(a0)), 2);  // --generated needs N >= 1
}

TEST(BenchSet, ParseGivesTheOneBagOrRunsTheSet)
{
  int set_runs = 0;
  const auto run_set = [&] { ++set_runs; return 7; };
  auto parse = [&](std::vector<const char*> args, std::string& bag) {
    SetOptions so;
    CommandLine cl("bench", "usage: bench\n");
    so.addTo(cl);
    return so.parse(cl, static_cast<int>(args.size()), const_cast<char**>(args.data()), run_set, bag);
  };
  std::string bag;
  EXPECT_EQ(parse({"bench", "only.bag"}, bag), -1);  // one bag: the program runs it
  EXPECT_EQ(bag, "only.bag");
  EXPECT_EQ(set_runs, 0);
  EXPECT_EQ(parse({"bench", "a.bag", "b.bag"}, bag), 7);  // a set: run_set's exit code
  EXPECT_EQ(set_runs, 1);
  EXPECT_EQ(parse({"bench"}, bag), 2);  // no bag: a usage error
  EXPECT_EQ(parse({"bench", "--help"}, bag), 0);
  EXPECT_EQ(set_runs, 1);
}

TEST(BenchSet, RunCaptureReturnsTheChildsStdoutAndExitCode)
{
  std::string out;
  EXPECT_EQ(runCapture({"/bin/sh", "-c", "echo table; echo '{\"k\": 2}'; exit 3"}, &out), 3);
  EXPECT_EQ(lastJsonLine(out), "{\"k\": 2}");
  EXPECT_NE(runCapture({"/nonexistent/program"}, &out), 0);
}
