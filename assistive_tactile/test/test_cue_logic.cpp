// Table-driven tests of the cue logic: every mode switch, every intensity rule, hysteresis.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "assistive_tactile/cue_logic.h"

using namespace assistive_tactile;

namespace
{
constexpr double kDeg = M_PI / 180.0;
const double kInf = std::numeric_limits<double>::infinity();

/// On-course defaults: path straight ahead 3 m away, 5 m free ahead, 2 m free on both sides.
NavInput base()
{
  NavInput in;
  in.status = NavStatus::OK;
  in.heading = 0.3;
  in.path_heading = 0.3;
  in.waypoint_distance = 3.0;
  in.free_ahead = 5.0;
  in.free_left = 2.0;
  in.free_right = 2.0;
  return in;
}

NavInput turn(double dev_deg, double heading = 0.3)
{
  NavInput in = base();
  in.heading = heading;
  in.path_heading = heading + dev_deg * kDeg;
  return in;
}

NavInput close(double ahead, double left, double right, NavStatus st = NavStatus::OK)
{
  NavInput in = base();
  in.status = st;
  in.free_ahead = ahead;
  in.free_left = left;
  in.free_right = right;
  return in;
}

NavInput status(NavStatus st, double ahead = 5.0)
{
  NavInput in = base();
  in.status = st;
  in.free_ahead = ahead;
  return in;
}

/// update() with a camera image 50 ms old unless the input says otherwise.
Cue fresh(CueLogic& logic, NavInput in, double now)
{
  if (std::isnan(in.source_time))
    in.source_time = now - 0.05;
  return logic.update(in, now);
}

// Default params: turn on 20, off 8, full 90 deg, min intensity 0.25, proximity 1.0, alert 0.5.
float guidanceLevel(double dev_deg)
{
  const double k = std::min(1.0, (std::fabs(dev_deg) - 8.0) / (90.0 - 8.0));
  return static_cast<float>(0.25 + 0.75 * k);
}
float proximityLevel(double ahead)
{
  return static_cast<float>(0.25 + 0.75 * (1.0 - ahead) / 0.5);
}

struct Row
{
  const char* name;
  NavInput in;
  CueMode mode;
  std::array<float, 4> intensity;  // LS, RS, LW, RW
  const char* reason_has;
};

void expectCue(const Cue& c, CueMode mode, const std::array<float, 4>& inten, const char* reason_has,
               const std::string& what)
{
  EXPECT_EQ(modeName(c.mode), std::string(modeName(mode))) << what << " reason: " << c.reason;
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(c.intensity[i], inten[i], 1e-4) << what << " motor " << i;
  if (reason_has)
  {
    EXPECT_NE(c.reason.find(reason_has), std::string::npos) << what << ": '" << c.reason << "'";
  }
}

}  // namespace

// One decision from a fresh logic (no history): which mode, which motor, how strong.
TEST(CueLogic, SingleDecisionTable)
{
  const float f = 1.f;
  const std::vector<Row> rows = {
    { "on course", base(), CueMode::IDLE, { 0, 0, 0, 0 }, "on course" },
    { "5 deg off: idle", turn(5), CueMode::IDLE, { 0, 0, 0, 0 }, nullptr },
    { "just under turn_on: idle", turn(19.9), CueMode::IDLE, { 0, 0, 0, 0 }, nullptr },
    { "path 30 deg left", turn(30), CueMode::GUIDANCE, { guidanceLevel(30), 0, 0, 0 }, "turn left 30" },
    { "path 30 deg right", turn(-30), CueMode::GUIDANCE, { 0, guidanceLevel(30), 0, 0 }, "turn right 30" },
    { "path 60 deg left", turn(60), CueMode::GUIDANCE, { guidanceLevel(60), 0, 0, 0 }, nullptr },
    { "90 deg: full", turn(90), CueMode::GUIDANCE, { f, 0, 0, 0 }, nullptr },
    { "150 deg right: clamped full", turn(-150), CueMode::GUIDANCE, { 0, f, 0, 0 }, nullptr },
    { "wrap: 170 -> -160 is 30 left", turn(30, 170 * kDeg), CueMode::GUIDANCE, { guidanceLevel(30), 0, 0, 0 },
      nullptr },
    { "wrap: 179 -> -179 is 2 left", turn(2, 179 * kDeg), CueMode::IDLE, { 0, 0, 0, 0 }, nullptr },
    { "waypoint 0.8 m: no guidance", [] { NavInput in = turn(45); in.waypoint_distance = 0.8; return in; }(),
      CueMode::IDLE, { 0, 0, 0, 0 }, "waypoint" },
    { "waypoint exactly 1 m: guidance", [] { NavInput in = turn(45); in.waypoint_distance = 1.0; return in; }(),
      CueMode::GUIDANCE, { guidanceLevel(45), 0, 0, 0 }, nullptr },
    { "nothing ahead (inf)", [] { NavInput in = turn(30); in.free_ahead = kInf; return in; }(), CueMode::GUIDANCE,
      { guidanceLevel(30), 0, 0, 0 }, nullptr },
    { "free 1.0 m: not proximity", close(1.0, 2, 0.1), CueMode::IDLE, { 0, 0, 0, 0 }, nullptr },
    { "0.8 m, free left", close(0.8, 1.5, 0.2), CueMode::PROXIMITY, { 0, 0, proximityLevel(0.8), 0 }, "step left" },
    { "0.8 m, free right", close(0.8, 0.2, 1.5), CueMode::PROXIMITY, { 0, 0, 0, proximityLevel(0.8) },
      "step right" },
    { "0.8 m, both free, right freer", close(0.8, 1.0, 2.0), CueMode::PROXIMITY, { 0, 0, 0, proximityLevel(0.8) },
      nullptr },
    { "0.99 m: weakest waist cue", close(0.99, 1.0, 0.1), CueMode::PROXIMITY, { 0, 0, proximityLevel(0.99), 0 },
      nullptr },
    { "0.5 m: strongest waist cue", close(0.5, 1.0, 0.1), CueMode::PROXIMITY, { 0, 0, f, 0 }, nullptr },
    { "0.8 m, nothing free: alert", close(0.8, 0.3, 0.3), CueMode::ALERT, { f, f, f, f }, "no room" },
    { "0.45 m: alert", close(0.45, 2, 2), CueMode::ALERT, { f, f, f, f }, "stop" },
    { "0 m: alert", close(0.0, 2, 2), CueMode::ALERT, { f, f, f, f }, nullptr },
    { "proximity beats a path straight on",
      [] { NavInput in = close(0.8, 1.5, 0.2); in.path_heading += 15 * kDeg; return in; }(), CueMode::PROXIMITY,
      { 0, 0, proximityLevel(0.8), 0 }, nullptr },
    { "near, path turning away 40 deg: turn on the spot, not side-step",
      [] { NavInput in = close(0.8, 1.5, 0.2); in.path_heading += 40 * kDeg; return in; }(), CueMode::GUIDANCE,
      { guidanceLevel(40), 0, 0, 0 }, "turn left 40" },
    { "alert beats a turn",
      [] { NavInput in = close(0.45, 1.5, 0.2); in.path_heading += 40 * kDeg; return in; }(), CueMode::ALERT,
      { f, f, f, f }, "stop" },
    { "no pose: quiet", status(NavStatus::NO_POSE, 0.3), CueMode::UNSURE, { 0, 0, 0, 0 }, "no pose" },
    { "no map: quiet", status(NavStatus::NO_MAP, 0.3), CueMode::UNSURE, { 0, 0, 0, 0 }, "no map" },
    { "in unknown: quiet", status(NavStatus::IN_UNKNOWN, 0.3), CueMode::UNSURE, { 0, 0, 0, 0 }, "unknown" },
    { "no path, far: unsure", status(NavStatus::NO_PATH, 3.0), CueMode::UNSURE, { 0, 0, 0, 0 }, "no path" },
    { "no waypoint, far: unsure", status(NavStatus::NO_WAYPOINT, 3.0), CueMode::UNSURE, { 0, 0, 0, 0 },
      "no waypoint" },
    { "no path, 0.3 m: alert", status(NavStatus::NO_PATH, 0.3), CueMode::ALERT, { f, f, f, f }, nullptr },
    { "no waypoint, 0.8 m free left: no side-step", close(0.8, 1.5, 0.1, NavStatus::NO_WAYPOINT), CueMode::UNSURE,
      { 0, 0, 0, 0 }, "no waypoint" },
    { "no path, 0.8 m, no room: alert", close(0.8, 0.3, 0.3, NavStatus::NO_PATH), CueMode::ALERT, { f, f, f, f },
      "no path" },
    { "NaN heading: quiet", [] { NavInput in = turn(30); in.heading = std::nan(""); return in; }(), CueMode::UNSURE,
      { 0, 0, 0, 0 }, "NaN" },
    { "NaN free distance: quiet", [] { NavInput in = base(); in.free_ahead = std::nan(""); return in; }(),
      CueMode::UNSURE, { 0, 0, 0, 0 }, "NaN" },
  };
  for (const Row& r : rows)
  {
    CueLogic logic;
    expectCue(fresh(logic, r.in, 0.0), r.mode, r.intensity, r.reason_has, r.name);
  }
}

struct Step
{
  NavInput in;
  CueMode mode;
  int motor;  // active motor index, -1 none, 4 = all four
};

void runSequence(const char* name, const std::vector<Step>& steps)
{
  CueLogic logic;
  double t = 0.0;
  for (size_t i = 0; i < steps.size(); ++i)
  {
    const Cue c = fresh(logic, steps[i].in, t += 0.1);
    const std::string what = std::string(name) + " step " + std::to_string(i) + " (" + c.reason + ")";
    EXPECT_EQ(std::string(modeName(c.mode)), modeName(steps[i].mode)) << what;
    for (int m = 0; m < 4; ++m)
    {
      const bool on = steps[i].motor == 4 || steps[i].motor == m;
      EXPECT_EQ(c.intensity[m] > 0.f, on) << what << " motor " << m;
    }
  }
}

// Mode switches over time, including the hysteresis that keeps cues from chattering.
TEST(CueLogic, SequenceTable)
{
  using M = CueMode;
  runSequence("turn until lined up",
              { { turn(30), M::GUIDANCE, 0 }, { turn(15), M::GUIDANCE, 0 }, { turn(9), M::GUIDANCE, 0 },
                { turn(7), M::IDLE, -1 }, { turn(15), M::IDLE, -1 }, { turn(21), M::GUIDANCE, 0 } });
  runSequence("noise at the turn threshold",
              { { turn(19.5), M::IDLE, -1 }, { turn(20.5), M::GUIDANCE, 0 }, { turn(19.5), M::GUIDANCE, 0 },
                { turn(20.5), M::GUIDANCE, 0 }, { turn(19.0), M::GUIDANCE, 0 } });
  runSequence("overshoot a left turn",
              { { turn(30), M::GUIDANCE, 0 }, { turn(-15), M::IDLE, -1 }, { turn(-25), M::GUIDANCE, 1 } });
  runSequence("right turn",
              { { turn(-45), M::GUIDANCE, 1 }, { turn(-10), M::GUIDANCE, 1 }, { turn(-5), M::IDLE, -1 } });
  runSequence("waypoint hysteresis",
              { { turn(45), M::GUIDANCE, 0 },
                { [] { NavInput in = turn(45); in.waypoint_distance = 0.95; return in; }(), M::GUIDANCE, 0 },
                { [] { NavInput in = turn(45); in.waypoint_distance = 0.85; return in; }(), M::IDLE, -1 },
                { [] { NavInput in = turn(45); in.waypoint_distance = 0.95; return in; }(), M::IDLE, -1 } });
  runSequence("proximity enter / leave",
              { { close(1.05, 2, 0.1), M::IDLE, -1 }, { close(0.95, 2, 0.1), M::PROXIMITY, 2 },
                { close(1.05, 2, 0.1), M::PROXIMITY, 2 }, { close(1.15, 2, 0.1), M::IDLE, -1 },
                { close(1.05, 2, 0.1), M::IDLE, -1 } });
  runSequence("alert enter / leave",
              { { close(0.8, 2, 0.1), M::PROXIMITY, 2 }, { close(0.45, 2, 0.1), M::ALERT, 4 },
                { close(0.55, 2, 0.1), M::ALERT, 4 }, { close(0.65, 2, 0.1), M::PROXIMITY, 2 },
                { close(0.55, 2, 0.1), M::PROXIMITY, 2 } });
  runSequence("waist side sticks unless the other is clearly freer",
              { { close(0.8, 1.0, 0.9), M::PROXIMITY, 2 }, { close(0.8, 1.0, 1.1), M::PROXIMITY, 2 },
                { close(0.8, 1.0, 1.3), M::PROXIMITY, 3 }, { close(0.8, 1.1, 1.3), M::PROXIMITY, 3 } });
  runSequence("waist side kept down to side_free - hysteresis",
              { { close(0.8, 0.7, 0.0), M::PROXIMITY, 2 }, { close(0.8, 0.55, 0.0), M::PROXIMITY, 2 },
                { close(0.8, 0.45, 0.0), M::ALERT, 4 } });
  runSequence("losing the pose silences a turn, and resets hysteresis",
              { { turn(30), M::GUIDANCE, 0 }, { status(NavStatus::NO_POSE), M::UNSURE, -1 },
                { turn(15), M::IDLE, -1 } });
  runSequence("map lost during alert",
              { { close(0.3, 1, 1), M::ALERT, 4 }, { status(NavStatus::NO_MAP, 0.3), M::UNSURE, -1 },
                { close(0.55, 2, 0.1), M::PROXIMITY, 2 } });
  runSequence("clear of the obstacle, then guided",
              { { close(0.8, 2, 0.1), M::PROXIMITY, 2 },
                { [] { NavInput in = turn(-40); in.free_ahead = 3; return in; }(), M::GUIDANCE, 1 } });
}

// The guidance cue fades as the wearer lines up (seed 5.5.3: constant buzz -> over-turning).
TEST(CueLogic, IntensityFallsToZeroAsWearerLinesUp)
{
  CueLogic logic;
  float prev = 2.f;
  double t = 0.0;
  for (double dev = 120.0; dev > 8.0; dev -= 4.0)
  {
    const Cue c = fresh(logic, turn(dev), t += 0.05);
    ASSERT_EQ(c.mode, CueMode::GUIDANCE) << dev;
    EXPECT_LE(c.intensity[LEFT_SHOULDER], prev) << dev;
    if (dev < 90.0)
    {
      EXPECT_LT(c.intensity[LEFT_SHOULDER], prev) << dev;
    }
    EXPECT_NEAR(c.intensity[LEFT_SHOULDER], guidanceLevel(dev), 1e-4) << dev;
    prev = c.intensity[LEFT_SHOULDER];
  }
  EXPECT_NEAR(prev, 0.25f + 0.75f * (12.f - 8.f) / 82.f, 1e-4);
  const Cue lined_up = fresh(logic, turn(6.0), t += 0.05);
  EXPECT_EQ(lined_up.mode, CueMode::IDLE);
  EXPECT_FLOAT_EQ(lined_up.intensity[LEFT_SHOULDER], 0.f);
}

// The waist cue grows as the obstacle gets closer, up to full at the alert distance.
TEST(CueLogic, ProximityIntensityGrowsWhenCloser)
{
  CueLogic logic;
  float prev = 0.f;
  double t = 0.0;
  for (double d = 0.98; d > 0.5; d -= 0.04)
  {
    const Cue c = fresh(logic, close(d, 0.1, 2.0), t += 0.05);
    ASSERT_EQ(c.mode, CueMode::PROXIMITY) << d;
    EXPECT_GT(c.intensity[RIGHT_WAIST], prev) << d;
    EXPECT_NEAR(c.intensity[RIGHT_WAIST], proximityLevel(d), 1e-4) << d;
    prev = c.intensity[RIGHT_WAIST];
  }
}

TEST(CueLogic, StaleStateGoesQuiet)
{
  CueParams p;
  p.state_timeout_s = 0.5;
  p.max_input_age_s = 1.0;  // this test is about the state's own age, not its camera image's
  CueLogic logic(p);
  EXPECT_TRUE(logic.stale(0.0));
  EXPECT_NE(logic.staleCue(0.0).reason.find("no planner state"), std::string::npos);
  EXPECT_EQ(fresh(logic, turn(30), 10.0).mode, CueMode::GUIDANCE);
  EXPECT_FALSE(logic.stale(10.4));
  EXPECT_TRUE(logic.stale(10.6));
  const Cue c = logic.staleCue(10.6);
  EXPECT_EQ(c.mode, CueMode::UNSURE);
  for (float v : c.intensity)
    EXPECT_EQ(v, 0.f);
  EXPECT_NE(c.reason.find("stale"), std::string::npos);
  // After a stale period the turn must be re-entered from scratch (no hysteresis carry-over).
  EXPECT_EQ(fresh(logic, turn(15), 11.0).mode, CueMode::IDLE);
}

// Never guide on a guess: a state decided from a camera image older than max_input_age_s (or
// with no camera stamp) gives UNSURE with motors off, whatever it says.
TEST(CueLogic, OldInputIsUnsure)
{
  const std::vector<std::pair<const char*, NavInput>> inputs = {
    { "turn", turn(45) }, { "side-step", close(0.8, 1.5, 0.2) }, { "alert", close(0.3, 2, 2) },
    { "on course", base() }, { "no path, blocked", status(NavStatus::NO_PATH, 0.3) },
  };
  for (const auto& r : inputs)
  {
    struct Age
    {
      double age;  // now - source_time; NaN = no stamp
      bool fresh;
      const char* reason_has;
    };
    const double max_age = CueParams().max_input_age_s;
    for (const Age& a : { Age{ 0.0, true, nullptr }, Age{ max_age - 1e-9, true, nullptr }, Age{ max_age + 0.01, false, "too old" },
                          Age{ 1.42, false, "too old" }, Age{ 10.0, false, "too old" },
                          Age{ std::nan(""), false, "no camera stamp" }, Age{ -0.6, false, "future" } })
    {
      CueLogic logic;
      NavInput in = r.second;
      in.source_time = 100.0 - a.age;
      const Cue c = logic.update(in, 100.0);
      const std::string what = std::string(r.first) + " age " + std::to_string(a.age) + ": " + c.reason;
      if (a.fresh)
      {
        EXPECT_NE(c.mode, CueMode::UNSURE) << what;
        continue;
      }
      EXPECT_EQ(c.mode, CueMode::UNSURE) << what;
      for (float v : c.intensity)
        EXPECT_EQ(v, 0.f) << what;
      EXPECT_NE(c.reason.find(a.reason_has), std::string::npos) << what;
    }
  }
}

// Any status but OK: UNSURE with motors off, or ALERT only for NO_PATH / NO_WAYPOINT ("nothing
// free") from fresh input when the way ahead is blocked. Never GUIDANCE or PROXIMITY.
TEST(CueLogic, StatusNotOkNeverGuides)
{
  for (NavStatus st : { NavStatus::NO_POSE, NavStatus::NO_MAP, NavStatus::IN_UNKNOWN, NavStatus::NO_PATH,
                        NavStatus::NO_WAYPOINT })
    for (double ahead : { 5.0, 0.95, 0.8, 0.45, 0.0 })
      for (double side : { 0.0, 0.3, 2.0 })
        for (double dev : { 0.0, 45.0, -90.0 })
          for (double age : { 0.05, 0.7 })
            for (bool after_guidance : { false, true })
            {
              CueLogic logic;
              if (after_guidance)  // hysteresis state from a turn / side-step must not leak through
              {
                fresh(logic, turn(dev), 99.8);
                fresh(logic, close(0.8, side, 2.0 - side), 99.9);
              }
              NavInput in = close(ahead, side, side, st);
              in.path_heading = in.heading + dev * kDeg;
              in.source_time = 100.0 - age;
              const Cue c = logic.update(in, 100.0);
              const std::string what = "status " + std::to_string(static_cast<int>(st)) + " ahead " +
                                       std::to_string(ahead) + " side " + std::to_string(side) + " age " +
                                       std::to_string(age) + ": " + modeName(c.mode) + " " + c.reason;
              const bool nothing_free = st == NavStatus::NO_PATH || st == NavStatus::NO_WAYPOINT;
              const bool blocked = ahead < 0.5 || (ahead < 1.0 && side < 0.6);
              if (c.mode == CueMode::ALERT)
              {
                EXPECT_TRUE(nothing_free && age <= CueParams().max_input_age_s && blocked) << what;
                for (float v : c.intensity)
                  EXPECT_EQ(v, 1.f) << what;
                continue;
              }
              EXPECT_EQ(c.mode, CueMode::UNSURE) << what;
              EXPECT_FALSE(nothing_free && age <= CueParams().max_input_age_s && blocked) << what << " (should stop the wearer)";
              for (float v : c.intensity)
                EXPECT_EQ(v, 0.f) << what;
              EXPECT_FALSE(c.reason.empty());
            }
}

// The heartbeat asks stale(): once the camera image behind the last cue is older than
// max_input_age_s, the old GUIDANCE is not repeated; the stale cue is UNSURE.
TEST(CueLogic, HeartbeatDoesNotRepeatOldGuidance)
{
  CueLogic logic;
  const double max_age = logic.params().max_input_age_s;
  ASSERT_LT(max_age - 0.1 + 0.01, logic.params().state_timeout_s);
  NavInput in = turn(45);
  in.source_time = 9.9;
  EXPECT_EQ(logic.update(in, 10.0).mode, CueMode::GUIDANCE);
  EXPECT_FALSE(logic.stale(10.2));
  EXPECT_FALSE(logic.stale(9.9 + max_age - 1e-9));   // image just max_input_age_s old
  // 10 ms later: the state arrived less than state_timeout_s ago, but its image is too old
  EXPECT_TRUE(logic.stale(9.9 + max_age + 0.01));
  const Cue c = logic.staleCue(9.9 + max_age + 0.01);
  EXPECT_EQ(c.mode, CueMode::UNSURE);
  EXPECT_NE(c.reason.find("too old"), std::string::npos) << c.reason;
  for (float v : c.intensity)
    EXPECT_EQ(v, 0.f);
  // A state without a camera stamp is stale at once.
  NavInput unknown = turn(45);
  EXPECT_EQ(logic.update(unknown, 11.0).mode, CueMode::UNSURE);
  EXPECT_TRUE(logic.stale(11.0));
}

// ---- People crossing (NavigationState.crossing, issue 22) ----
namespace
{
NavInput crossing(NavInput in, CrossingAdvice a, double t, int id = 3)
{
  in.crossing = a;
  in.crossing_id = id;
  in.crossing_time = t;
  in.crossing_distance = 0.1;
  return in;
}
// Default params: crossing_near_s 1, crossing_far_s 3, min intensity 0.25.
float crossingLevel(double t)
{
  return static_cast<float>(0.25 + 0.75 * std::min(1.0, std::max(0.0, (3.0 - t) / 2.0)));
}
}  // namespace

// One decision from a fresh logic: the crossing cue and its place among the others.
TEST(CueLogic, CrossingDecisionTable)
{
  using A = CrossingAdvice;
  const float f = 1.f;
  const std::vector<Row> rows = {
    { "person, step right in 1.8 s", crossing(base(), A::RIGHT, 1.8), CueMode::PROXIMITY, { 0, 0, 0, 0.7f },
      "person crossing, step right 1.8 s" },
    { "person, step left in 1.8 s", crossing(base(), A::LEFT, 1.8), CueMode::PROXIMITY, { 0, 0, 0.7f, 0 },
      "person crossing, step left 1.8 s" },
    { "3 s away: weakest", crossing(base(), A::LEFT, 3.0), CueMode::PROXIMITY, { 0, 0, 0.25f, 0 }, "3.0 s" },
    { "2 s away", crossing(base(), A::RIGHT, 2.0), CueMode::PROXIMITY, { 0, 0, 0, crossingLevel(2.0) }, "2.0 s" },
    { "0.9 s away: full", crossing(base(), A::LEFT, 0.9), CueMode::PROXIMITY, { 0, 0, f, 0 }, "0.9 s" },
    { "stop", crossing(base(), A::STOP, 0.8), CueMode::ALERT, { f, f, f, f }, "person crossing, stop 0.8 s" },
    { "no advice: as before", crossing(base(), A::NONE, 0.0), CueMode::IDLE, { 0, 0, 0, 0 }, "on course" },
    { "crossing beats a turn", crossing(turn(45), A::RIGHT, 1.8), CueMode::PROXIMITY, { 0, 0, 0, 0.7f },
      "person crossing" },
    { "crossing side beats the obstacle's side-step", crossing(close(0.8, 1.0, 1.5), A::LEFT, 1.8),
      CueMode::PROXIMITY, { 0, 0, 0.7f, 0 }, "person crossing, step left" },
    { "crossing stop during an obstacle side-step", crossing(close(0.8, 1.5, 0.2), A::STOP, 1.2), CueMode::ALERT,
      { f, f, f, f }, "person crossing, stop 1.2 s" },
    { "obstacle under 0.5 m stays first", crossing(close(0.45, 2, 2), A::LEFT, 1.8), CueMode::ALERT, { f, f, f, f },
      "obstacle 0.45 m ahead: stop" },
    { "obstacle, no room: stays first", crossing(close(0.8, 0.3, 0.3), A::RIGHT, 1.8), CueMode::ALERT,
      { f, f, f, f }, "no room" },
    { "obstacle under 0.5 m over a crossing stop", crossing(close(0.3, 2, 2), A::STOP, 0.5), CueMode::ALERT,
      { f, f, f, f }, "obstacle 0.30 m ahead" },
    { "no pose: quiet", crossing(status(NavStatus::NO_POSE), A::STOP, 0.8), CueMode::UNSURE, { 0, 0, 0, 0 },
      "no pose" },
    { "no map: quiet", crossing(status(NavStatus::NO_MAP), A::LEFT, 1.8), CueMode::UNSURE, { 0, 0, 0, 0 }, "no map" },
    { "in unknown: quiet", crossing(status(NavStatus::IN_UNKNOWN), A::RIGHT, 1.8), CueMode::UNSURE, { 0, 0, 0, 0 },
      "unknown" },
    { "no path: no side-step for a person", crossing(status(NavStatus::NO_PATH), A::LEFT, 1.8), CueMode::UNSURE,
      { 0, 0, 0, 0 }, "no path" },
    { "no waypoint: no stop for a person", crossing(status(NavStatus::NO_WAYPOINT), A::STOP, 0.8), CueMode::UNSURE,
      { 0, 0, 0, 0 }, "no waypoint" },
    { "no path, obstacle 0.3 m: the obstacle's stop", crossing(status(NavStatus::NO_PATH, 0.3), A::LEFT, 1.8),
      CueMode::ALERT, { f, f, f, f }, "no path, obstacle" },
    { "NaN crossing time: quiet", crossing(base(), A::LEFT, std::nan("")), CueMode::UNSURE, { 0, 0, 0, 0 }, "NaN" },
  };
  for (const Row& r : rows)
  {
    CueLogic logic;
    expectCue(fresh(logic, r.in, 0.0), r.mode, r.intensity, r.reason_has, r.name);
  }
  // an old camera image: no crossing cue either
  CueLogic logic;
  NavInput in = crossing(base(), CrossingAdvice::STOP, 0.8);
  in.source_time = -1.0;
  expectCue(logic.update(in, 0.0), CueMode::UNSURE, { 0, 0, 0, 0 }, "too old", "old image");
}

struct CrossStep
{
  double t;     // s
  NavInput in;
  CueMode mode;
  int motor;    // active motor, -1 none, 4 all four
  const char* reason_has;
};

void runCrossing(const char* name, const CueParams& p, const std::vector<CrossStep>& steps)
{
  CueLogic logic(p);
  for (size_t i = 0; i < steps.size(); ++i)
  {
    const Cue c = fresh(logic, steps[i].in, steps[i].t);
    const std::string what = std::string(name) + " step " + std::to_string(i) + " t " + std::to_string(steps[i].t) +
                             " (" + modeName(c.mode) + " " + c.reason + ")";
    EXPECT_EQ(std::string(modeName(c.mode)), modeName(steps[i].mode)) << what;
    for (int m = 0; m < 4; ++m)
    {
      const bool on = steps[i].motor == 4 || steps[i].motor == m;
      EXPECT_EQ(c.intensity[m] > 0.f, on) << what << " motor " << m;
    }
    if (steps[i].reason_has)
    {
      EXPECT_NE(c.reason.find(steps[i].reason_has), std::string::npos) << what;
    }
  }
}

// The crossing cue holds (no flicker), escalates at once, swaps sides only after the hold, and
// ends when the advice ends. Frames every 0.125 s (exact in binary), hold 0.5 s, release 0.25 s.
TEST(CueLogic, CrossingHoldAndRelease)
{
  using A = CrossingAdvice;
  using M = CueMode;
  CueParams p;
  p.crossing_hold_s = 0.5;
  p.crossing_release_s = 0.25;
  const NavInput b = base();
  runCrossing("flicker, side swap, escalation, end", p,
              { { 0.000, crossing(b, A::LEFT, 2.0), M::PROXIMITY, LEFT_WAIST, "step left 2.0 s" },
                { 0.125, crossing(b, A::NONE, 0.0), M::PROXIMITY, LEFT_WAIST, "step left 1.9 s" },  // held, counting down
                { 0.250, crossing(b, A::RIGHT, 1.75), M::PROXIMITY, LEFT_WAIST, "step left" },     // no swap within the hold
                { 0.375, crossing(b, A::LEFT, 1.625), M::PROXIMITY, LEFT_WAIST, "step left 1.6 s" },
                { 0.500, crossing(b, A::RIGHT, 1.5), M::PROXIMITY, RIGHT_WAIST, "step right 1.5 s" },  // held 0.5 s: swap
                { 0.625, crossing(b, A::STOP, 1.0), M::ALERT, 4, "person crossing, stop 1.0 s" },     // escalation at once
                { 0.750, crossing(b, A::RIGHT, 1.2), M::ALERT, 4, "stop" },    // STOP held 0.125 s < 0.5 s
                { 0.875, crossing(b, A::NONE, 0.0), M::ALERT, 4, "stop 0.8 s" },
                { 1.000, crossing(b, A::NONE, 0.0), M::ALERT, 4, nullptr },
                { 1.125, crossing(b, A::NONE, 0.0), M::IDLE, -1, "on course" } });  // held 0.5 s, advice gone 0.5 s
  runCrossing("the cue ends with the advice (after the hold)", p,
              { { 0.000, crossing(b, A::RIGHT, 2.8), M::PROXIMITY, RIGHT_WAIST, nullptr },
                { 0.125, crossing(b, A::RIGHT, 2.7), M::PROXIMITY, RIGHT_WAIST, nullptr },
                { 0.250, crossing(b, A::RIGHT, 2.5), M::PROXIMITY, RIGHT_WAIST, nullptr },
                { 0.500, crossing(b, A::RIGHT, 2.3), M::PROXIMITY, RIGHT_WAIST, nullptr },
                { 0.875, crossing(b, A::RIGHT, 1.9), M::PROXIMITY, RIGHT_WAIST, "1.9 s" },
                { 1.000, crossing(b, A::NONE, 0.0), M::PROXIMITY, RIGHT_WAIST, "1.8 s" },  // 0.125 s < release
                { 1.125, crossing(b, A::NONE, 0.0), M::IDLE, -1, nullptr },                // 0.25 s: ended
                { 1.250, crossing(b, A::RIGHT, 1.5), M::PROXIMITY, RIGHT_WAIST, "1.5 s" } });  // a new warning at once
  runCrossing("guidance resumes after the crossing cue", p,
              { { 0.000, turn(45), M::GUIDANCE, LEFT_SHOULDER, "turn left" },
                { 0.125, crossing(turn(45), A::RIGHT, 2.0), M::PROXIMITY, RIGHT_WAIST, "person" },
                { 0.250, crossing(turn(15), A::RIGHT, 1.9), M::PROXIMITY, RIGHT_WAIST, "person" },
                { 0.750, turn(15), M::GUIDANCE, LEFT_SHOULDER, "turn left 15" } });  // the turn's hysteresis kept
  runCrossing("losing the pose drops a held crossing cue", p,
              { { 0.000, crossing(b, A::LEFT, 2.0), M::PROXIMITY, LEFT_WAIST, nullptr },
                { 0.125, status(NavStatus::NO_POSE), M::UNSURE, -1, "no pose" },
                { 0.250, b, M::IDLE, -1, "on course" } });
  runCrossing("no path drops a held crossing cue", p,
              { { 0.000, crossing(b, A::STOP, 0.9), M::ALERT, 4, nullptr },
                { 0.125, crossing(status(NavStatus::NO_PATH), A::STOP, 0.8), M::UNSURE, -1, "no path" },
                { 0.250, b, M::IDLE, -1, "on course" } });
}

// With the shipped defaults (hold 0.5 s, release 0.1 s) at the camera's 15 Hz: one frame without
// the advice is bridged, two end the cue; a cue raised once lasts 0.5 s.
TEST(CueLogic, CrossingDefaultsAt15Hz)
{
  using A = CrossingAdvice;
  const double dt = 1.0 / 15.0;
  CueLogic logic;
  const NavInput b = base();
  for (int k = 0; k < 15; ++k)  // warned for 1 s
    ASSERT_EQ(fresh(logic, crossing(b, A::LEFT, 2.5 - k * dt), k * dt).mode, CueMode::PROXIMITY) << k;
  EXPECT_EQ(fresh(logic, crossing(b, A::NONE, 0.0), 15 * dt).mode, CueMode::PROXIMITY);  // bridged
  EXPECT_EQ(fresh(logic, crossing(b, A::LEFT, 1.4), 16 * dt).mode, CueMode::PROXIMITY);
  EXPECT_EQ(fresh(logic, crossing(b, A::NONE, 0.0), 17 * dt).mode, CueMode::PROXIMITY);
  EXPECT_EQ(fresh(logic, crossing(b, A::NONE, 0.0), 18 * dt).mode, CueMode::IDLE);  // 0.133 s without: ended

  CueLogic once;
  EXPECT_EQ(fresh(once, crossing(b, A::RIGHT, 2.0), 10.0).mode, CueMode::PROXIMITY);  // a one-frame warning ...
  for (int k = 1; k <= 7; ++k)  // ... lasts 0.5 s (k = 7: 0.467 s)
    EXPECT_EQ(fresh(once, b, 10.0 + k * dt).mode, CueMode::PROXIMITY) << k;
  EXPECT_EQ(fresh(once, b, 10.0 + 8 * dt).mode, CueMode::IDLE);  // 0.533 s
}

// Whatever the crossing advice, a status other than OK never gives a waist or shoulder cue, and
// an ALERT only where the obstacle rule gives one (the crossing adds nothing to a guess).
TEST(CueLogic, StatusNotOkNeverCuesACrossing)
{
  for (NavStatus st : { NavStatus::NO_POSE, NavStatus::NO_MAP, NavStatus::IN_UNKNOWN, NavStatus::NO_PATH,
                        NavStatus::NO_WAYPOINT })
    for (CrossingAdvice a : { CrossingAdvice::LEFT, CrossingAdvice::RIGHT, CrossingAdvice::STOP })
      for (double ahead : { 5.0, 0.8, 0.3 })
        for (bool held_before : { false, true })
        {
          CueLogic logic;
          if (held_before)
            fresh(logic, crossing(base(), a, 2.0), 99.9);
          const Cue c = fresh(logic, crossing(close(ahead, 2.0, 2.0, st), a, 1.5), 100.0);
          const std::string what = "status " + std::to_string(static_cast<int>(st)) + " advice " + crossingName(a) +
                                   " ahead " + std::to_string(ahead) + ": " + modeName(c.mode) + " " + c.reason;
          const bool obstacle_stop = (st == NavStatus::NO_PATH || st == NavStatus::NO_WAYPOINT) && ahead < 0.5;
          EXPECT_EQ(c.mode, obstacle_stop ? CueMode::ALERT : CueMode::UNSURE) << what;
          EXPECT_EQ(c.reason.find("person"), std::string::npos) << what;
        }
}

TEST(CueLogic, WrapAngle)
{
  const std::vector<std::pair<double, double>> table = { { 0, 0 },           { M_PI, M_PI },
                                                         { -M_PI, M_PI },    { 3 * M_PI, M_PI },
                                                         { 1.5 * M_PI, -0.5 * M_PI }, { -0.25, -0.25 } };
  for (const auto& r : table)
    EXPECT_NEAR(wrapAngle(r.first), r.second, 1e-12) << r.first;
}
