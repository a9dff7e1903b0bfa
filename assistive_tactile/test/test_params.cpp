// The parameter tables (params.h) are the only place of the defaults: the README's tables and
// config/default.yaml (overrides only, per nodelet section) must agree with them.
#include <gtest/gtest.h>

#include <assistive_common/doc_check.h>

#include "assistive_tactile/params.h"

using namespace assistive_tactile;

TEST(Params, ReadmeAndYamlMatchTheTables)
{
  // One README with both nodelets' tables; the yaml has a section per nodelet.
  for (const std::string& e :
       assistive_common::checkPackage(PKG_DIR "/README.md", PKG_DIR "/config/default.yaml", "cue_logic", CueParams(),
                                      BridgeParams()))
    ADD_FAILURE() << e;
  const std::string yaml = assistive_common::slurp(PKG_DIR "/config/default.yaml");
  for (const std::string& e :
       assistive_common::checkOverrides(assistive_common::yamlSection(yaml, "vest_bridge"), "vest_bridge", BridgeParams()))
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
