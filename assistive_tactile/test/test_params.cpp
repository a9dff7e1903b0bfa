// The parameter defaults live in params.h; config/default.yaml and the README's parameter lists
// must say the same (they are what people read and load).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "assistive_tactile/params.h"

using namespace assistive_tactile;

namespace
{
std::string num(double v)
{
  std::ostringstream s;
  s << v;
  return s.str();
}

/// name -> default as text, from the structs' initializers.
std::map<std::string, std::map<std::string, std::string>> defaults()
{
  const CueParams c;
  const BridgeParams b;
  return { { "cue_logic",
             { { "guidance_min_waypoint_m", num(c.guidance_min_waypoint_m) },
               { "turn_on_deg", num(c.turn_on_deg) },
               { "turn_off_deg", num(c.turn_off_deg) },
               { "turn_full_deg", num(c.turn_full_deg) },
               { "min_intensity", num(c.min_intensity) },
               { "proximity_m", num(c.proximity_m) },
               { "alert_m", num(c.alert_m) },
               { "hysteresis_m", num(c.hysteresis_m) },
               { "side_free_m", num(c.side_free_m) },
               { "side_switch_m", num(c.side_switch_m) },
               { "state_timeout_s", num(c.state_timeout_s) },
               { "max_input_age_s", num(c.max_input_age_s) },
               { "heartbeat_hz", num(c.heartbeat_hz) },
               { "body_frame", c.body_frame } } },
           { "vest_bridge",
             { { "port", b.port },
               { "baud", num(b.baud) },
               { "resend_hz", num(b.resend_hz) },
               { "stale_s", num(b.stale_s) },
               { "max_source_age_s", num(b.max_source_age_s) },
               { "reopen_s", num(b.reopen_s) },
               { "link_timeout_s", num(b.link_timeout_s) },
               { "realtime_priority", num(b.realtime_priority) } } } };
}

/// A number's text normalised ("1.0" -> "1"); other text unchanged.
std::string norm(const std::string& v)
{
  try
  {
    size_t used = 0;
    const double d = std::stod(v, &used);
    if (used == v.size())
      return num(d);
  }
  catch (...)
  {
  }
  return v;
}

std::string slurp(const std::string& path)
{
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
}  // namespace

TEST(Params, DefaultYamlMatchesParamsH)
{
  std::ifstream f(TACTILE_SOURCE_DIR "/config/default.yaml");
  ASSERT_TRUE(f.good());
  std::map<std::string, std::map<std::string, std::string>> yaml;
  std::string line, section;
  const std::regex sec("^(\\w+):\\s*$"), kv("^\\s+(\\w+):\\s*(\\S+)\\s*$");
  std::smatch m;
  while (std::getline(f, line))
  {
    if (std::regex_match(line, m, sec))
      section = m[1];
    else if (std::regex_match(line, m, kv))
      yaml[section][m[1]] = norm(m[2]);
  }
  const auto want = defaults();
  for (const auto& s : want)
    for (const auto& p : s.second)
      EXPECT_EQ(yaml[s.first][p.first], p.second) << s.first << "/" << p.first;
  for (const auto& s : yaml)
    for (const auto& p : s.second)
      EXPECT_TRUE(want.count(s.first) && want.at(s.first).count(p.first))
          << s.first << "/" << p.first << " is in default.yaml but not in params.h";
}

TEST(Params, ReadmeMatchesParamsH)
{
  const std::string readme = slurp(TACTILE_SOURCE_DIR "/README.md");
  ASSERT_FALSE(readme.empty());
  // "- `name` (type, default, unit)" entries, several per line allowed.
  std::map<std::string, std::string> doc;
  const std::regex entry("`(\\w+)` \\((double|int|string), `?([^,`)]+)`?[,)]");
  for (auto it = std::sregex_iterator(readme.begin(), readme.end(), entry); it != std::sregex_iterator(); ++it)
    doc[(*it)[1]] = norm((*it)[3]);
  for (const auto& s : defaults())
    for (const auto& p : s.second)
    {
      ASSERT_TRUE(doc.count(p.first)) << p.first << " is not documented in the README";
      EXPECT_EQ(doc[p.first], p.second) << p.first;
    }
}
