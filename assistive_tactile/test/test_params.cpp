// The parameter tables (params.h) are the only place of the defaults: the README's tables and
// config/default.yaml (overrides only, per nodelet section) must agree with them.
#include <gtest/gtest.h>

#include <assistive_common/doc_check.h>

#include "assistive_tactile/params.h"

using namespace assistive_tactile;

TEST(Params, ReadmeAndYamlMatchTheTables)
{
  using namespace assistive_common;
  // One README with both nodelets' tables; the yaml has a section per nodelet.
  std::vector<std::string> rows = readmeRows(CueParams()), all = names(CueParams());
  for (const std::string& r : readmeRows(BridgeParams()))
    rows.push_back(r);
  for (const std::string& n : names(BridgeParams()))
    all.push_back(n);
  for (const std::string& e : checkReadme(slurp(PKG_DIR "/README.md"), rows, all))
    ADD_FAILURE() << e;
  const std::string yaml = slurp(PKG_DIR "/config/default.yaml");
  ASSERT_FALSE(yaml.empty());
  for (const std::string& e : checkOverrides(yamlSection(yaml, "cue_logic"), "cue_logic", CueParams()))
    ADD_FAILURE() << e;
  for (const std::string& e : checkOverrides(yamlSection(yaml, "vest_bridge"), "vest_bridge", BridgeParams()))
    ADD_FAILURE() << e;
}

TEST(Params, BridgeClampKeepsASupportedBaud)
{
  BridgeParams p;
  EXPECT_TRUE(clampParams(p).empty());
  p.baud = 12345;  // in range, but no standard rate
  p.stale_s = 0.0;
  EXPECT_EQ(clampParams(p).size(), 2u);
  EXPECT_EQ(p.baud, 57600);
  EXPECT_EQ(p.stale_s, 0.05);
}
