// The parameter table (params.h) is the only place of the defaults: the README's table and
// config/default.yaml (overrides only) must agree with it.
#include <gtest/gtest.h>

#include <assistive_common/doc_check.h>

#include "assistive_slam/params.h"

TEST(Params, ReadmeAndYamlMatchTheTable)
{
  for (const std::string& e : assistive_common::checkPackage(PKG_DIR "/README.md", PKG_DIR "/config/default.yaml", "",
                                                             assistive_slam::SlamParams(), assistive_slam::SlamNodeParams()))
    ADD_FAILURE() << e;
}
