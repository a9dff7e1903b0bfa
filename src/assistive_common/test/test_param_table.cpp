// The table machinery on a toy table: defaults, dependent ranges, clamping, --set parsing, the
// README rows and the yaml override check.
#include <gtest/gtest.h>

#include "assistive_common/doc_check.h"
#include "assistive_common/param_table.h"

namespace
{
// clang-format off
#define TOY_PARAMS(X) \
  X(double, min_depth, "min_depth", 0.3, 0.05, 10.0, "m", "closer points are dropped") \
  X(double, max_depth, "max_depth", 6.0, min_depth + 0.1, 50.0, "m", "farther points are dropped") \
  X(int, stride, "stride", 2, 1, 16, "", "every n-th pixel") \
  X(bool, enabled, "enabled", true, {}, {}, "", "switch") \
  X(std::string, path, "path", "a.bt", {}, {}, "", "where to save")
// clang-format on
struct Toy
{
  ASSISTIVE_PARAMS_BODY(TOY_PARAMS)
};
}  // namespace

using namespace assistive_common;

TEST(ParamTable, DefaultsComeFromTheTable)
{
  const Toy t;
  EXPECT_EQ(t.min_depth, 0.3);
  EXPECT_EQ(t.max_depth, 6.0);
  EXPECT_EQ(t.stride, 2);
  EXPECT_TRUE(t.enabled);
  EXPECT_EQ(t.path, "a.bt");
  EXPECT_EQ(names(t), (std::vector<std::string>{ "min_depth", "max_depth", "stride", "enabled", "path" }));
  Toy c = t;
  EXPECT_TRUE(clampToTable(c).empty());
}

TEST(ParamTable, ClampsInTableOrderWithDependentRanges)
{
  Toy t;
  t.min_depth = 20.0;  // -> 10, then max_depth must be >= 10.1
  t.max_depth = 1.0;
  t.stride = 0;
  const auto msgs = clampToTable(t);
  ASSERT_EQ(msgs.size(), 3u);
  EXPECT_EQ(t.min_depth, 10.0);
  EXPECT_DOUBLE_EQ(t.max_depth, 10.1);
  EXPECT_EQ(t.stride, 1);
  EXPECT_NE(msgs[1].find("max_depth = 1 out of [min_depth + 0.1, 50.0]"), std::string::npos) << msgs[1];
  t.min_depth = std::nan("");
  t.max_depth = 1e9;
  clampToTable(t);
  EXPECT_EQ(t.min_depth, 0.05);
  EXPECT_EQ(t.max_depth, 50.0);
}

TEST(ParamTable, SetFromTextAcceptsTheNamesAndTypes)
{
  Toy t;
  std::string err;
  EXPECT_TRUE(applyOverrides(t, { "min_depth=0.5", "stride=4", "enabled=0", "path=b.bt" }, &err)) << err;
  EXPECT_EQ(t.min_depth, 0.5);
  EXPECT_EQ(t.stride, 4);
  EXPECT_FALSE(t.enabled);
  EXPECT_EQ(t.path, "b.bt");
  EXPECT_FALSE(setFromText(t, "stride", "2.5", &err));
  EXPECT_NE(err.find("not a valid int"), std::string::npos);
  EXPECT_FALSE(setFromText(t, "enabled", "maybe", &err));
  EXPECT_FALSE(setFromText(t, "min_depth", "1x", &err));
  EXPECT_FALSE(setFromText(t, "nope", "1", &err));
  EXPECT_EQ(err, "unknown parameter 'nope'");
  EXPECT_FALSE(applyOverrides(t, { "min_depth" }, &err));
  std::vector<std::string> msgs;
  EXPECT_TRUE(applyOverrides(t, { "stride=99" }, &err, &msgs));
  EXPECT_EQ(t.stride, 16);
  EXPECT_EQ(msgs.size(), 1u);
}

TEST(DocCheck, ReadmeRowsAndUnknownRows)
{
  const Toy t;
  const auto rows = readmeRows(t);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[1], "| `max_depth` | double | 6 | [`min_depth` + 0.1, 50.0] | m | farther points are dropped |");
  EXPECT_EQ(rows[3], "| `enabled` | bool | true | - | - | switch |");
  EXPECT_EQ(rows[4], "| `path` | string | `a.bt` | - | - | where to save |");
  std::string readme = readmeHeader() + "\n";
  for (const auto& r : rows)
    readme += r + "\n";
  EXPECT_TRUE(checkReadme(readme, rows, names(t)).empty());
  EXPECT_EQ(checkReadme(readme + "| `old` | int | 1 | - | - | gone |\n", rows, names(t)).size(), 1u);
  std::string changed = readme;
  changed.replace(changed.find("| 6 |"), 5, "| 7 |");
  EXPECT_EQ(checkReadme(changed, rows, names(t)).size(), 1u);
}

TEST(DocCheck, YamlCarriesOverridesOnly)
{
  const std::string yaml = "# comment\nmin_depth: 0.5  # m\nstride: 2\nnode:\n  enabled: false\n  path: \"a.bt\"\n";
  const auto top = yamlSection(yaml);
  EXPECT_EQ(top.size(), 3u);  // min_depth, stride, node
  EXPECT_EQ(top.at("min_depth"), "0.5");
  const auto node = yamlSection(yaml, "node");
  EXPECT_EQ(node.size(), 2u);
  EXPECT_EQ(node.at("path"), "a.bt");
  std::map<std::string, std::string> y = top;
  y.erase("node");
  const auto e = checkOverrides(y, "top", Toy());
  ASSERT_EQ(e.size(), 1u);  // stride: 2 is the default
  EXPECT_NE(e[0].find("stride"), std::string::npos);
  EXPECT_EQ(checkOverrides(node, "node", Toy()).size(), 1u);  // path is the default
  EXPECT_EQ(checkOverrides({ { "stride", "40" } }, "x", Toy()).size(), 1u);  // out of range
  EXPECT_EQ(checkOverrides({ { "what", "1" } }, "x", Toy()).size(), 1u);
}
