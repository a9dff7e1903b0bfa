// params.h is the only place of the defaults: README table and config/default.yaml agree with it.
#include <gtest/gtest.h>

#include <assistive_common/doc_check.h>

#include "assistive_voice/params.h"

using namespace assistive_voice;

TEST(Params, ReadmeAndYamlMatchTheTable)
{
  using namespace assistive_common;
  for (const std::string& e : checkReadme(slurp(PKG_DIR "/README.md"), readmeRows(VoiceParams()), names(VoiceParams())))
    ADD_FAILURE() << e;
  const std::string yaml = slurp(PKG_DIR "/config/default.yaml");
  ASSERT_FALSE(yaml.empty());
  for (const std::string& e : checkOverrides(yamlSection(yaml, "voice"), "voice", VoiceParams()))
    ADD_FAILURE() << e;
}
