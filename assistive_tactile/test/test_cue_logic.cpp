// Table-driven tests of the cue logic: every mode switch, every intensity rule, hysteresis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "assistive_tactile/cue_logic.h"

using namespace assistive_tactile;

namespace
{
constexpr double kDeg = M_PI / 180.0;
const double kInf = std::numeric_limits<double>::infinity();

/// On-course defaults: walking at the walking threshold (`walking_speed_mps`, 0.25 m/s: the stop
/// and side-step distances grow by 0.17 m), steering point straight ahead, the path 3 m away,
/// 5 m free ahead, 2 m free on both sides.
NavInput base()
{
  NavInput in;
  in.status = NavStatus::OK;
  in.heading = 0.3;
  in.path_heading = 0.3;
  in.steer_heading = 0.3;
  in.walk_heading = 0.3;
  in.head_yaw = 0.3;
  in.walking_speed = CueParams().walking_speed_mps;
  in.waypoint_distance = 3.0;
  in.free_ahead = 5.0;
  in.free_left = 2.0;
  in.free_right = 2.0;
  return in;
}

/// The steering point `dev_deg` off the walk (+ = left).
NavInput turn(double dev_deg, double heading = 0.3)
{
  NavInput in = base();
  in.heading = in.walk_heading = in.head_yaw = heading;
  in.path_heading = in.steer_heading = heading + dev_deg * kDeg;
  return in;
}

NavInput standing(NavInput in)
{
  in.walking_speed = 0.0;
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

// Default params: levels 0.4 / 0.7 / 1.0; stop under 0.5 m and side-step under 1.0 m plus the
// walk during 0.6 s of reaction and the stop (v^2 / 4) at the input's speed.
float level(int k) { return static_cast<float>(0.4 + 0.3 * (k - 1)); }
const float kTick = 0.7f;  // the walk-on tick's drive (halfway between weakest and full)
double reach(double v) { return v * 0.6 + v * v / 4.0; }
float proximityLevel(double ahead, double v = CueParams().walking_speed_mps)
{
  (void)v;  // the side-step distance is the protocol's 1 m, not grown by the walk
  return static_cast<float>(0.4 + 0.6 * std::clamp((1.0 - ahead) / 0.5, 0.0, 1.0));
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

/// UNSURE's opening pattern: three quick pulses on both waist motors, nothing on the shoulders.
void expectUnsurePattern(const Cue& c, const std::string& what)
{
  EXPECT_EQ(c.instruction, Instruction::UNSURE) << what;
  EXPECT_EQ(c.intensity[LEFT_SHOULDER], 0.f) << what;
  EXPECT_EQ(c.intensity[RIGHT_SHOULDER], 0.f) << what;
  EXPECT_GT(c.intensity[LEFT_WAIST], 0.f) << what;
  EXPECT_GT(c.intensity[RIGHT_WAIST], 0.f) << what;
  EXPECT_EQ(c.pattern.count, 3) << what;
}

/// UNSURE as silence (a fresh logic) or its opening pattern (after a cue): never a shoulder.
void expectSilentOrUnsurePattern(const Cue& c, const std::string& what)
{
  if (c.intensity[LEFT_WAIST] > 0.f || c.intensity[RIGHT_WAIST] > 0.f)
    expectUnsurePattern(c, what);
  else
    for (float v : c.intensity)
      EXPECT_EQ(v, 0.f) << what;
}

}  // namespace

// One decision from a fresh logic (no history): which mode, which motor, how strong, which pattern.
TEST(CueLogic, SingleDecisionTable)
{
  const float f = 1.f;
  const float t = kTick;
  const std::vector<Row> rows = {
    { "on course: the walk-on tick", base(), CueMode::IDLE, { t, t, 0, 0 }, "on course" },
    { "9 deg off: walk on", turn(9), CueMode::IDLE, { t, t, 0, 0 }, nullptr },
    { "12 deg left: veer level 1", turn(12), CueMode::GUIDANCE, { level(1), 0, 0, 0 }, "veer left 15" },
    { "30 deg right: veer level 2", turn(-30), CueMode::GUIDANCE, { 0, level(2), 0, 0 }, "veer right 30" },
    { "50 deg left: veer level 3", turn(50), CueMode::GUIDANCE, { level(3), 0, 0, 0 }, "veer left 45" },
    { "70 deg left walking: stop and turn", turn(70), CueMode::GUIDANCE, { level(2), 0, 0, 0 }, "stop, turn left 70" },
    { "wrap: 170 -> -160 is 30 left", turn(30, 170 * kDeg), CueMode::GUIDANCE, { level(2), 0, 0, 0 }, "veer left" },
    { "standing, 14 deg off in the open: walk on (veer once walking)", standing(turn(14)), CueMode::IDLE,
      { t, t, 0, 0 }, nullptr },
    { "standing, 30 deg off: turn on the spot first", standing(turn(30)), CueMode::GUIDANCE, { level(1), 0, 0, 0 },
      "stop, turn left 30" },
    { "standing, 14 deg off, a side under side_free_m: turn first",
      [] { NavInput in = standing(turn(14)); in.free_right = 0.4; return in; }(), CueMode::GUIDANCE,
      { level(1), 0, 0, 0 }, "stop, turn left 14" },
    { "standing, 14 deg off, 2 m ahead: turn first",
      [] { NavInput in = standing(turn(14)); in.free_ahead = 2.0; return in; }(), CueMode::GUIDANCE,
      { level(1), 0, 0, 0 }, "stop, turn left 14" },
    { "standing, 40 deg right: turn on the spot", standing(turn(-40)), CueMode::GUIDANCE, { 0, level(1), 0, 0 },
      "stop, turn right 40" },
    { "waypoint 0.2 m: walk on", [] { NavInput in = turn(45); in.waypoint_distance = 0.2; return in; }(),
      CueMode::IDLE, { t, t, 0, 0 }, "waypoint" },
    { "nothing ahead (inf)", [] { NavInput in = turn(30); in.free_ahead = kInf; return in; }(), CueMode::GUIDANCE,
      { level(2), 0, 0, 0 }, nullptr },
    { "free beyond the side-step distance (1 m, not grown by the walk)", close(1.01, 2, 0.1), CueMode::IDLE,
      { t, t, 0, 0 }, nullptr },
    { "walking fast, 1.5 m ahead: stop, not side-step",
      [] { NavInput in = close(1.5, 2, 0.1); in.walking_speed = 1.2; return in; }(), CueMode::ALERT,
      { f, f, f, f }, "stop" },
    { "0.8 m, free left", close(0.8, 1.5, 0.2), CueMode::PROXIMITY, { 0, 0, proximityLevel(0.8), 0 }, "step left" },
    { "0.8 m, free right", close(0.8, 0.2, 1.5), CueMode::PROXIMITY, { 0, 0, 0, proximityLevel(0.8) }, "step right" },
    { "0.8 m, both free, right freer", close(0.8, 1.0, 2.0), CueMode::PROXIMITY, { 0, 0, 0, proximityLevel(0.8) },
      nullptr },
    { "0.8 m, nothing free: stop", close(0.8, 0.3, 0.3), CueMode::ALERT, { f, f, f, f }, "no room" },
    { "0.6 m: stop", close(0.6, 2, 2), CueMode::ALERT, { f, f, f, f }, "stop" },
    { "0 m: stop", close(0.0, 2, 2), CueMode::ALERT, { f, f, f, f }, nullptr },
    { "standing at 0.3 m with room: step out, not stop again", standing(close(0.3, 2, 0.2)), CueMode::PROXIMITY,
      { 0, 0, f, 0 }, "step left" },
    { "standing at 0.3 m, no room: stop", standing(close(0.3, 0.2, 0.2)), CueMode::ALERT, { f, f, f, f }, nullptr },
    { "side-step beats a steering point straight on",
      [] { NavInput in = close(0.8, 1.5, 0.2); in.steer_heading += 8 * kDeg; return in; }(), CueMode::PROXIMITY,
      { 0, 0, proximityLevel(0.8), 0 }, nullptr },
    { "near, steering point 40 deg left and clear: veer, not side-step",
      [] { NavInput in = close(0.8, 1.5, 0.2); in.steer_heading += 40 * kDeg; return in; }(), CueMode::GUIDANCE,
      { level(3), 0, 0, 0 }, "veer left" },
    { "steering point clear but under the side-step distance: side-step",
      [] { NavInput in = close(0.8, 1.5, 0.2); in.steer_heading += 40 * kDeg; in.free_steer = 0.9; return in; }(),
      CueMode::PROXIMITY, { 0, 0, proximityLevel(0.8), 0 }, nullptr },
    { "stop beats a veer inside the no-reaction distance",
      [] { NavInput in = close(0.45, 1.5, 0.2); in.steer_heading += 40 * kDeg; return in; }(), CueMode::ALERT,
      { f, f, f, f }, "stop" },
    { "no pose: quiet", status(NavStatus::NO_POSE, 0.3), CueMode::UNSURE, { 0, 0, 0, 0 }, "no pose" },
    { "no map: quiet", status(NavStatus::NO_MAP, 0.3), CueMode::UNSURE, { 0, 0, 0, 0 }, "no map" },
    { "in unknown: quiet", status(NavStatus::IN_UNKNOWN, 0.3), CueMode::UNSURE, { 0, 0, 0, 0 }, "unknown" },
    { "no path, far: unsure", status(NavStatus::NO_PATH, 3.0), CueMode::UNSURE, { 0, 0, 0, 0 }, "no path" },
    { "no waypoint, far: unsure", status(NavStatus::NO_WAYPOINT, 3.0), CueMode::UNSURE, { 0, 0, 0, 0 },
      "no waypoint" },
    { "no path, 0.3 m: stop", status(NavStatus::NO_PATH, 0.3), CueMode::ALERT, { f, f, f, f }, nullptr },
    { "no waypoint, 0.8 m free left: no side-step", close(0.8, 1.5, 0.1, NavStatus::NO_WAYPOINT), CueMode::UNSURE,
      { 0, 0, 0, 0 }, "no waypoint" },
    { "no path, 0.8 m, no room: stop", close(0.8, 0.3, 0.3, NavStatus::NO_PATH), CueMode::ALERT, { f, f, f, f },
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

// The patterns the vest plays (renderCue is what the vest does with them).
TEST(CueLogic, PatternsOfTheProtocol)
{
  CueLogic logic;
  const Cue tick = fresh(logic, base(), 0.0);
  EXPECT_EQ(tick.instruction, Instruction::WALK_ON);
  EXPECT_EQ(tick.pattern.on_10ms, 10);
  EXPECT_EQ(tick.pattern.count, 1);
  EXPECT_FLOAT_EQ(renderCue(tick, 0.05)[LEFT_SHOULDER], kTick);
  EXPECT_FLOAT_EQ(renderCue(tick, 0.05)[RIGHT_SHOULDER], kTick);
  EXPECT_FLOAT_EQ(renderCue(tick, 0.15)[LEFT_SHOULDER], 0.f);  // one 0.1 s tick

  const Cue veer = fresh(logic, turn(30), 1.0);
  EXPECT_EQ(veer.instruction, Instruction::VEER);
  EXPECT_EQ(veer.level, 2);
  EXPECT_NE(veer.pattern.id, tick.pattern.id);
  for (const auto& [t, on] : { std::pair<double, bool>{ 0.0, true }, { 0.14, true }, { 0.16, false }, { 0.31, true },
                              { 0.44, true }, { 0.46, false }, { 1.0, false } })
    EXPECT_EQ(renderCue(veer, t)[LEFT_SHOULDER] > 0.f, on) << t;

  // stop and turn: one buzz as long as the angle at 90 deg/s, plus 0.25 s to tell it from a veer
  CueLogic stand;
  const Cue turn90 = fresh(stand, standing(turn(-90)), 0.0);
  EXPECT_EQ(turn90.instruction, Instruction::TURN);
  EXPECT_EQ(turn90.pattern.on_10ms, 125);
  EXPECT_EQ(turn90.pattern.count, 1);
  EXPECT_GT(renderCue(turn90, 1.24)[RIGHT_SHOULDER], 0.f);
  EXPECT_EQ(renderCue(turn90, 1.26)[RIGHT_SHOULDER], 0.f);

  // UNSURE after a cue: three quick pulses on both waists, then silence; held (same id) after
  const Cue u = fresh(logic, status(NavStatus::NO_POSE), 2.0);
  EXPECT_EQ(u.mode, CueMode::UNSURE);
  EXPECT_EQ(u.instruction, Instruction::UNSURE);
  int pulses = 0;
  bool was = false;
  for (double t = 0.0; t < 2.0; t += 0.01)
  {
    const bool on = renderCue(u, t)[LEFT_WAIST] > 0.f && renderCue(u, t)[RIGHT_WAIST] > 0.f;
    EXPECT_EQ(renderCue(u, t)[LEFT_SHOULDER], 0.f);
    pulses += on && !was;
    was = on;
  }
  EXPECT_EQ(pulses, 3);
  EXPECT_EQ(fresh(logic, status(NavStatus::NO_POSE), 2.1).pattern.id, u.pattern.id);
  // and the walk-on tick ("go") at once when guidance resumes
  const Cue go = fresh(logic, base(), 2.2);
  EXPECT_EQ(go.instruction, Instruction::WALK_ON);
  EXPECT_NE(go.pattern.id, u.pattern.id);
}

// Over time: ticks every tick_period_s, a veer waits until carried out, a turn until the head is still.
TEST(CueLogic, SequencesOverTime)
{
  CueLogic logic;
  const uint8_t first = fresh(logic, base(), 0.0).pattern.id;
  for (double t = 0.1; t < 2.0 - 1e-6; t += 0.1)
    EXPECT_EQ(fresh(logic, base(), t).pattern.id, first) << t;  // the same tick, played once
  EXPECT_NE(fresh(logic, base(), 2.0).pattern.id, first);        // the next one

  // a veer left 30: held while the walk has not turned; a new decision once it turned half and steadied
  CueLogic v;
  const Cue veer = fresh(v, turn(30), 0.0);
  ASSERT_EQ(veer.instruction, Instruction::VEER);
  EXPECT_EQ(fresh(v, turn(30), 0.5).pattern.id, veer.pattern.id);
  EXPECT_NE(fresh(v, turn(30), 0.5).reason.find("veering"), std::string::npos);
  NavInput half = turn(30);
  half.walk_heading = half.head_yaw = 0.3 + 16 * kDeg;  // turned 16 deg: steady head
  half.steer_heading = 0.3 + 30 * kDeg;
  fresh(v, half, 1.0);
  const Cue after = fresh(v, half, 1.5);
  EXPECT_EQ(after.instruction, Instruction::VEER);  // 14 deg off still: the next, smaller veer
  EXPECT_EQ(after.level, 1);
  EXPECT_NE(after.pattern.id, veer.pattern.id);

  // a corner comes into view while veering: the rest is asked as soon as it can be felt as a new
  // pair (0.95 s after the first burst)
  CueLogic c;
  const Cue v1 = fresh(c, turn(15), 0.0);
  EXPECT_EQ(fresh(c, turn(55), 0.1).pattern.id, v1.pattern.id);
  const Cue v2 = fresh(c, turn(55), 0.95);
  EXPECT_NE(v2.pattern.id, v1.pattern.id);
  EXPECT_EQ(v2.level, 3);  // 55 - 15 still to come: 40 deg asked

  // a turn on the spot: held until its buzz ended and the head is still, then "go"
  CueLogic s;
  NavInput in = standing(turn(90));
  const Cue t0 = fresh(s, in, 0.0);
  ASSERT_EQ(t0.instruction, Instruction::TURN);
  EXPECT_EQ(fresh(s, in, 1.0).pattern.id, t0.pattern.id);
  in.head_yaw = in.walk_heading = in.steer_heading;  // turned
  EXPECT_EQ(fresh(s, in, 1.3).pattern.id, t0.pattern.id);  // the buzz ends at 1.25 s; + 0.3 s
  EXPECT_EQ(fresh(s, in, 1.5).pattern.id, t0.pattern.id);
  double go_at = -1.0;
  for (double t = 1.6; t < 3.0 && go_at < 0.0; t += 0.1)
    if (fresh(s, in, t).instruction == Instruction::WALK_ON)
      go_at = t;
  EXPECT_GT(go_at, 1.55);  // "go" once the head is still (turn rate under 10 deg/s)
  EXPECT_LT(go_at, 2.5);
}

// The side-step cue grows as the obstacle gets closer, up to full at the stop distance.
TEST(CueLogic, ProximityIntensityGrowsWhenCloser)
{
  CueLogic logic;
  float prev = 0.f;
  double t = 0.0;
  const double v = CueParams().walking_speed_mps;
  for (double d = 1.0 - 0.02; d > 0.5 + reach(v) + 0.05; d -= 0.04)
  {
    const Cue c = fresh(logic, close(d, 0.1, 2.0), t += 0.05);
    ASSERT_EQ(c.mode, CueMode::PROXIMITY) << d;
    EXPECT_GT(c.intensity[RIGHT_WAIST], prev) << d;
    EXPECT_NEAR(c.intensity[RIGHT_WAIST], proximityLevel(d), 1e-4) << d;
    EXPECT_EQ(c.pattern.on_10ms, 0) << "steady";
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
  expectUnsurePattern(c, "stale after guidance");
  EXPECT_NE(c.reason.find("stale"), std::string::npos);
  // After a stale period guidance starts afresh: "go" first.
  EXPECT_EQ(fresh(logic, turn(5), 11.0).instruction, Instruction::WALK_ON);
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
        EXPECT_EQ(v, 0.f) << what;  // a fresh logic: nothing to end, silence
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
              in.path_heading = in.steer_heading = in.heading + dev * kDeg;
              in.source_time = 100.0 - age;
              const Cue c = logic.update(in, 100.0);
              const std::string what = "status " + std::to_string(static_cast<int>(st)) + " ahead " +
                                       std::to_string(ahead) + " side " + std::to_string(side) + " age " +
                                       std::to_string(age) + ": " + modeName(c.mode) + " " + c.reason;
              const bool nothing_free = st == NavStatus::NO_PATH || st == NavStatus::NO_WAYPOINT;
              const double r = reach(CueParams().walking_speed_mps);
              const bool blocked = ahead < 0.5 + r || (ahead < 1.0 + r && side < 0.6);
              if (c.mode == CueMode::ALERT)
              {
                EXPECT_TRUE(nothing_free && age <= CueParams().max_input_age_s && blocked) << what;
                for (float v : c.intensity)
                  EXPECT_EQ(v, 1.f) << what;
                continue;
              }
              EXPECT_EQ(c.mode, CueMode::UNSURE) << what;
              EXPECT_FALSE(nothing_free && age <= CueParams().max_input_age_s && blocked) << what << " (should stop the wearer)";
              expectSilentOrUnsurePattern(c, what);
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
  expectUnsurePattern(c, "heartbeat after guidance");
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
// Default params: crossing_near_s 1, crossing_far_s 3, min intensity 0.4.
float crossingLevel(double t)
{
  return static_cast<float>(0.4 + 0.6 * std::min(1.0, std::max(0.0, (3.0 - t) / 2.0)));
}
}  // namespace

// One decision from a fresh logic: the crossing cue and its place among the others.
TEST(CueLogic, CrossingDecisionTable)
{
  using A = CrossingAdvice;
  const float f = 1.f;
  const std::vector<Row> rows = {
    { "person, step right in 1.8 s", crossing(base(), A::RIGHT, 1.8), CueMode::PROXIMITY, { 0, 0, 0, crossingLevel(1.8) },
      "person crossing, step right 1.8 s" },
    { "person, step left in 1.8 s", crossing(base(), A::LEFT, 1.8), CueMode::PROXIMITY, { 0, 0, crossingLevel(1.8), 0 },
      "person crossing, step left 1.8 s" },
    { "3 s away: weakest", crossing(base(), A::LEFT, 3.0), CueMode::PROXIMITY, { 0, 0, crossingLevel(3.0), 0 }, "3.0 s" },
    { "2 s away", crossing(base(), A::RIGHT, 2.0), CueMode::PROXIMITY, { 0, 0, 0, crossingLevel(2.0) }, "2.0 s" },
    { "0.9 s away: full", crossing(base(), A::LEFT, 0.9), CueMode::PROXIMITY, { 0, 0, f, 0 }, "0.9 s" },
    { "stop", crossing(base(), A::STOP, 0.8), CueMode::ALERT, { f, f, f, f }, "person crossing, stop 0.8 s" },
    { "no advice: as before", crossing(base(), A::NONE, 0.0), CueMode::IDLE, { kTick, kTick, 0, 0 }, "on course" },
    { "crossing beats a turn", crossing(turn(45), A::RIGHT, 1.8), CueMode::PROXIMITY, { 0, 0, 0, crossingLevel(1.8) },
      "person crossing" },
    { "crossing side beats the obstacle's side-step", crossing(close(0.8, 1.0, 1.5), A::LEFT, 1.8),
      CueMode::PROXIMITY, { 0, 0, crossingLevel(1.8), 0 }, "person crossing, step left" },
    { "crossing stop during an obstacle side-step", crossing(close(0.8, 1.5, 0.2), A::STOP, 1.2), CueMode::ALERT,
      { f, f, f, f }, "person crossing, stop 1.2 s" },
    { "obstacle inside the stop distance stays first", crossing(close(0.45, 2, 2), A::LEFT, 1.8), CueMode::ALERT,
      { f, f, f, f }, "obstacle 0.45 m ahead: stop" },
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
      const int k = steps[i].motor;
      const bool on = k == 4 || k == m || (k == 5 && m < 2) || (k == 6 && m >= 2);
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
                { 1.125, crossing(b, A::NONE, 0.0), M::IDLE, 5, "on course" } });  // held 0.5 s, advice gone 0.5 s: go
  runCrossing("the cue ends with the advice (after the hold)", p,
              { { 0.000, crossing(b, A::RIGHT, 2.8), M::PROXIMITY, RIGHT_WAIST, nullptr },
                { 0.125, crossing(b, A::RIGHT, 2.7), M::PROXIMITY, RIGHT_WAIST, nullptr },
                { 0.250, crossing(b, A::RIGHT, 2.5), M::PROXIMITY, RIGHT_WAIST, nullptr },
                { 0.500, crossing(b, A::RIGHT, 2.3), M::PROXIMITY, RIGHT_WAIST, nullptr },
                { 0.875, crossing(b, A::RIGHT, 1.9), M::PROXIMITY, RIGHT_WAIST, "1.9 s" },
                { 1.000, crossing(b, A::NONE, 0.0), M::PROXIMITY, RIGHT_WAIST, "1.8 s" },  // 0.125 s < release
                { 1.125, crossing(b, A::NONE, 0.0), M::IDLE, 5, nullptr },                 // 0.25 s: ended, go
                { 1.250, crossing(b, A::RIGHT, 1.5), M::PROXIMITY, RIGHT_WAIST, "1.5 s" } });  // a new warning at once
  runCrossing("guidance resumes after the crossing cue", p,
              { { 0.000, turn(45), M::GUIDANCE, LEFT_SHOULDER, "veer left" },
                { 0.125, crossing(turn(45), A::RIGHT, 2.0), M::PROXIMITY, RIGHT_WAIST, "person" },
                { 0.250, crossing(turn(15), A::RIGHT, 1.9), M::PROXIMITY, RIGHT_WAIST, "person" },
                { 0.750, turn(15), M::GUIDANCE, LEFT_SHOULDER, "veer left 15" } });
  runCrossing("losing the pose drops a held crossing cue", p,
              { { 0.000, crossing(b, A::LEFT, 2.0), M::PROXIMITY, LEFT_WAIST, nullptr },
                { 0.125, status(NavStatus::NO_POSE), M::UNSURE, 6, "no pose" },  // the UNSURE pattern
                { 0.250, b, M::IDLE, 5, "on course" } });
  runCrossing("no path drops a held crossing cue", p,
              { { 0.000, crossing(b, A::STOP, 0.9), M::ALERT, 4, nullptr },
                { 0.125, crossing(status(NavStatus::NO_PATH), A::STOP, 0.8), M::UNSURE, 6, "no path" },
                { 0.250, b, M::IDLE, 5, "on course" } });
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

// A veer is judged carried out when the head's turn rate shows it, not when the walk has turned by
// half of it: the walk's drift during the wearer's reaction ate into it, and the cue logic then
// waited the whole settle_timeout_s while the wearer drifted into a wall (corridor trials).
TEST(CueLogic, VeerDoneWhenSeenDespiteDrift)
{
  CueLogic v;
  const double h0 = 0.3;
  NavInput in = turn(20, h0);
  in.walking_speed = 1.2;
  const Cue veer = fresh(v, in, 0.0);
  ASSERT_EQ(veer.instruction, Instruction::VEER);
  ASSERT_EQ(veer.level, 1);  // 20 deg: level 1 (15 deg) is closest
  double t = 0.0;
  // the walk drifts 8 deg the wrong way during a 0.7 s reaction, then veers 15 deg in 0.25 s
  auto at = [&](double yaw_deg) {
    in.walk_heading = in.head_yaw = h0 + yaw_deg * kDeg;
    return fresh(v, in, t);
  };
  for (t = 1.0 / 15; t < 0.85; t += 1.0 / 15)
    EXPECT_EQ(at(-8.0 * t / 0.85).pattern.id, veer.pattern.id) << t;
  for (; t < 1.1; t += 1.0 / 15)
    EXPECT_EQ(at(-8.0 + 15.0 * (t - 0.85) / 0.25).pattern.id, veer.pattern.id) << t;  // seen here
  // turned by 7 deg from where it began (less than half of 15) but done: a new decision at once
  // once the head was steady for 0.3 s, long before settle_timeout_s (2.5 s)
  double next = -1.0;
  for (; t < 2.4 && next < 0.0; t += 1.0 / 15)
    if (at(7.0).pattern.id != veer.pattern.id)
      next = t;
  EXPECT_GT(next, 1.3);
  EXPECT_LT(next, 1.8);
}

// A veer carried out far beyond its amount (a weak burst read as medium) is done at once: the
// correction is asked while the wearer still turns, not after it steadied.
TEST(CueLogic, OvershotVeerIsDoneAtOnce)
{
  CueLogic v;
  NavInput in = turn(-12);
  in.walking_speed = 1.0;
  const Cue veer = fresh(v, in, 0.0);
  ASSERT_EQ(veer.instruction, Instruction::VEER);
  ASSERT_EQ(veer.level, 1);  // right 15
  double t = 1.0 / 15;
  for (; t < 0.75; t += 1.0 / 15)
    EXPECT_EQ(fresh(v, in, t).pattern.id, veer.pattern.id) << t;
  // the wearer turns right at 60 deg/s (read as a medium burst: 30 deg); past 1.3 x 15 + 5 =
  // 24.5 deg the next decision comes while it still turns
  Cue next = fresh(v, in, t);
  t += 1.0 / 15;
  double turned = 0.0;
  auto waiting = [](const Cue& c) { return c.reason.find("veering") != std::string::npos; };
  for (; t < 1.5 && waiting(next); t += 1.0 / 15)
  {
    turned = std::min(30.0, 60.0 * (t - 0.75));
    in.head_yaw = 0.3 - turned * kDeg;
    in.walk_heading = 0.3 - std::max(0.0, turned - 12.0) * kDeg;  // the chord lags
    next = fresh(v, in, t);
  }
  EXPECT_FALSE(waiting(next)) << next.reason;  // judged again (here: on course, walk on)
  EXPECT_GT(turned, 24.5);
  EXPECT_LT(turned, 30.0);  // before the turn has ended
}

// The walk's own drift is learnt and led: a veer is asked for the error expected when it is
// carried out.
TEST(CueLogic, DriftIsLearntAndLed)
{
  auto walk = [](CueLogic& logic, double drift_deg_per_m, double err_deg) {
    // 16 s straight at 1 m/s drifting, the steering point moving with the walk (no error), then
    // the steering point err_deg off
    NavInput in = base();
    in.walking_speed = 1.0;
    double t = 0.0, yaw = 0.3;
    for (; t < 16.0; t += 1.0 / 15)
    {
      yaw += drift_deg_per_m * kDeg * 1.0 / 15;
      in.walk_heading = in.head_yaw = yaw;
      in.steer_heading = yaw;
      fresh(logic, in, t);
    }
    in.steer_heading = yaw + err_deg * kDeg;
    return fresh(logic, in, t);
  };
  CueLogic straight, drifting_left, drifting_right;
  EXPECT_EQ(walk(straight, 0.0, 8.0).instruction, Instruction::WALK_ON);  // under veer_on_deg
  // drifting 5 deg/m to the right (away from a steering point 8 deg left): expected about
  // 8 + 5 x 1 m/s x (0.6 s reaction + 0.15 + 0.2 + drift_aim_s 1.0) = 17.75 deg -> veer left
  const Cue l = walk(drifting_right, -5.0, 8.0);
  EXPECT_EQ(l.instruction, Instruction::VEER);
  EXPECT_GT(l.intensity[LEFT_SHOULDER], 0.f);
  // (after 16 s of walking the drift is learnt to within 3 %: a 4 s time constant)
  const size_t at = l.reason.find(" expected");
  ASSERT_NE(at, std::string::npos) << l.reason;
  const double expected = std::stod(l.reason.substr(l.reason.rfind(' ', at - 1) + 1));
  EXPECT_NEAR(expected, 17.75, 0.8) << l.reason;
  // drifting 5 deg/m to the left (towards it): the drift closes it, no veer
  EXPECT_EQ(walk(drifting_left, 5.0, 8.0).instruction, Instruction::WALK_ON);
}

// The turning rate is learnt from the angle turned over the time it turned (the smoothed peak
// rate underestimated short turns: the next buzz came out too long, turn chains overshot).
TEST(CueLogic, TurnRateLearntFromTheAngleTurned)
{
  CueLogic s;
  NavInput in = standing(turn(90));
  const Cue t0 = fresh(s, in, 0.0);
  ASSERT_EQ(t0.pattern.on_10ms, 125);  // 90 deg at 90 deg/s + 0.25 s
  // the wearer turns 60 deg during the 1.0 s it turns (60 deg/s), head steady after
  Cue next = t0;
  for (double t = 1.0 / 15; t < 3.0 && next.pattern.id == t0.pattern.id; t += 1.0 / 15)
  {
    const double k = std::clamp((t - 0.5) / 1.0, 0.0, 1.0);
    in.head_yaw = in.walk_heading = 0.3 + 60.0 * kDeg * k;
    next = fresh(s, in, t);
  }
  // learnt 0.7 x 90 + 0.3 x 60 = 81 deg/s: the 30 deg still to turn take 30 / 81 + 0.25 = 0.62 s
  ASSERT_EQ(next.instruction, Instruction::TURN);
  EXPECT_EQ(next.pattern.on_10ms, 62);
}

// Doorways (the planner's passage_*): a walker whose straight walk passes the middle within the
// room (half the width less passage_body_m) walks on without veers; one that would miss is
// stopped by a turn buzz towards the middle; standing, it is turned until the middle lies within
// passage_align_deg, then told to go.
TEST(CueLogic, PassageStraightOnOrStopAndAlign)
{
  auto atDoor = [](double walk_speed, double dist, double middle_deg, double steer_deg) {
    NavInput in = turn(steer_deg);
    in.walking_speed = walk_speed;
    in.passage_distance = dist;
    in.passage_width = 1.05;  // as the planner reports 0.8 m of free cells (plus a cell): room 0.525 - 0.35 = 0.175 m
    in.passage_heading = in.walk_heading + middle_deg * kDeg;
    return in;
  };
  {
    // 1.5 m ahead at 1 m/s (stop distance 0.6 + 0.25 m: inside 0.9 + 0.85 + 0.3), passing
    // 1.5 sin 5 deg = 0.13 m off: straight on, although the steering point lies 20 deg off
    CueLogic c;
    const Cue k = fresh(c, atDoor(1.0, 1.5, 5.0, 20.0), 0.0);
    EXPECT_EQ(k.mode, CueMode::IDLE);
    EXPECT_EQ(k.instruction, Instruction::WALK_ON);
    // without the passage: a veer
    CueLogic o;
    EXPECT_EQ(fresh(o, turn(20.0), 0.0).instruction, Instruction::VEER);
  }
  {
    // 15 deg off: it would pass 0.39 m off the middle: stop, turn left 15 deg (15 / 90 + 0.25 s)
    CueLogic c;
    const Cue k = fresh(c, atDoor(1.0, 1.5, 15.0, 0.0), 0.0);
    ASSERT_EQ(k.instruction, Instruction::TURN);
    EXPECT_GT(k.intensity[LEFT_SHOULDER], 0.f);
    EXPECT_EQ(k.intensity[RIGHT_SHOULDER], 0.f);
    EXPECT_EQ(k.pattern.on_10ms, 42);
  }
  {
    // farther than the stop distance + passage_align_m + 0.3: ordinary steering (a veer)
    CueLogic c;
    EXPECT_EQ(fresh(c, atDoor(1.0, 2.5, 15.0, 20.0), 0.0).instruction, Instruction::VEER);
  }
  {
    // standing 1 m before it: 6 deg off -> turn right 6 deg; 3 deg off -> go
    CueLogic c;
    const Cue k = fresh(c, standing(atDoor(0.0, 1.0, -6.0, 0.0)), 0.0);
    ASSERT_EQ(k.instruction, Instruction::TURN);
    EXPECT_GT(k.intensity[RIGHT_SHOULDER], 0.f);
    EXPECT_EQ(k.pattern.on_10ms, 32);  // 6 / 90 + 0.25 s
    CueLogic g;
    EXPECT_EQ(fresh(g, standing(atDoor(0.0, 1.0, 3.0, 0.0)), 0.0).instruction, Instruction::WALK_ON);
    // told to go, the head's scanning past the limit during the reaction is no new turn
    EXPECT_EQ(fresh(g, standing(atDoor(0.0, 1.0, 6.0, 0.0)), 0.5).instruction, Instruction::WALK_ON);
  }
  {
    // in the passage (under passage_inside_m): ordinary steering again (a turn beyond it)
    CueLogic c;
    EXPECT_EQ(fresh(c, atDoor(1.0, 0.4, 2.0, 20.0), 0.0).instruction, Instruction::VEER);
    // switched off: ordinary steering everywhere
    CueParams p;
    p.passage_align_m = 0.0;
    CueLogic off(p);
    EXPECT_EQ(fresh(off, atDoor(1.0, 1.5, 5.0, 20.0), 0.0).instruction, Instruction::VEER);
  }
}

// Standing before a passage, the middle is faced within passage_align_deg (4), or within what
// passes the middle inside half the passage's room: a wide gap is not squared up to the degree.
TEST(CueLogic, StandingBeforeAWideGapNoTurnForWhatTheRoomTakes)
{
  auto before = [](double width, double middle_deg) {
    NavInput in = standing(turn(0.0));
    in.passage_distance = 1.0;
    in.passage_width = width;
    in.passage_heading = in.walk_heading + middle_deg * kDeg;
    return in;
  };
  // 1.45 m wide: room 0.725 - 0.35 = 0.375 m, half of it 1 m on: atan(0.1875) = 10.6 deg
  {
    CueLogic c;
    const Cue k = fresh(c, before(1.45, 8.0), 0.0);
    EXPECT_EQ(k.instruction, Instruction::WALK_ON) << k.reason;
    CueLogic t;
    const Cue k2 = fresh(t, before(1.45, 12.0), 0.0);
    ASSERT_EQ(k2.instruction, Instruction::TURN) << k2.reason;
    EXPECT_GT(k2.intensity[LEFT_SHOULDER], 0.f);
  }
  // an 0.80 m doorway: room 0.05 m, half of it 1 m on: 1.4 deg, so passage_align_deg (4) holds
  {
    CueLogic c;
    const Cue k = fresh(c, before(0.80, -6.0), 0.0);
    ASSERT_EQ(k.instruction, Instruction::TURN) << k.reason;
    EXPECT_GT(k.intensity[RIGHT_SHOULDER], 0.f);
    CueLogic g;
    EXPECT_EQ(fresh(g, before(0.80, 3.0), 0.0).instruction, Instruction::WALK_ON);
  }
}

// A stop-and-turn buzz barely longer than the 0.25 s that tells it from a veer's 0.15 s pulse
// is read as a veer (traced, issue 33: a walker 1.55 m before an 0.80 m doorway, its walk passing
// 0.08 m off the middle, was asked to stop and turn 1 deg with a 0.26 s buzz, carried it out as a
// 15 deg veer and walked into the jamb). A turn's buzz lasts at least 0.30 s.
TEST(CueLogic, SmallTurnBuzzStillReadsAsATurn)
{
  NavInput in = turn(0.0);
  in.walking_speed = 1.0;
  in.passage_distance = 1.55;
  in.passage_width = 0.8;  // room 0.4 - 0.35 = 0.05 m
  in.passage_heading = in.walk_heading + 3.0 * kDeg;  // passes 1.55 sin 3 deg = 0.08 m off
  CueLogic c;
  const Cue k = fresh(c, in, 0.0);
  ASSERT_EQ(k.instruction, Instruction::TURN) << k.reason;
  EXPECT_EQ(k.pattern.on_10ms, 30);  // 3 / 90 + 0.25 = 0.283 s asked: at least 0.30 s
  EXPECT_EQ(k.pattern.count, 1);
  // a large turn's buzz is its angle over the turning rate plus 0.25 s, as before
  CueLogic s;
  const Cue big = fresh(s, standing(turn(90.0)), 0.0);
  ASSERT_EQ(big.instruction, Instruction::TURN);
  EXPECT_EQ(big.pattern.on_10ms, 125);
}

// A side-step moves the body at 0.3 m/s (above walking_speed_mps) 90 deg off its facing: its
// chord is no facing. Traced (gen_home_3004 trial 0): a wearer facing 100 deg side-stepped left
// (chord -170 deg) 0.65 m before a doorway whose middle lay at 107 deg; judged on the chord it was
// asked to turn 83 deg right, and the body's facing (pulled to the chord) then said "facing the
// middle, go" with the body 66 deg off. Judged on the head, it is 7 deg off: a small turn left.
TEST(CueLogic, SideStepChordIsNoFacing)
{
  auto sideStep = []() {
    NavInput in = turn(7.0, 100.0 * kDeg);
    in.passage_distance = 0.65;
    in.passage_width = 0.80;
    in.passage_heading = 107.0 * kDeg;
    in.walking_speed = 0.3;
    in.walk_heading = -170.0 * kDeg;  // stepping left
    return in;
  };
  CueLogic c;
  Cue k;
  for (double t = 0.0; t < 0.5; t += 1.0 / 15.0)
    k = fresh(c, sideStep(), t);
  ASSERT_EQ(k.instruction, Instruction::TURN);
  EXPECT_GT(k.intensity[LEFT_SHOULDER], 0.f);  // towards the middle, 7 deg left of the head
  EXPECT_EQ(k.intensity[RIGHT_SHOULDER], 0.f);
  EXPECT_EQ(k.pattern.on_10ms, 33);             // 7 / 90 + 0.25 s, not 83 deg
  // the same chord along the head (a forward walk at 0.3 m/s 7 deg off the middle 0.65 m on: it
  // passes 0.08 m off it, within the room of a 1.05 m passage, 0.175 m): straight on
  CueLogic w;
  NavInput fw = sideStep();
  fw.walk_heading = 100.0 * kDeg;
  fw.passage_width = 1.05;
  EXPECT_EQ(fresh(w, fw, 0.0).instruction, Instruction::WALK_ON);
}

TEST(CueLogic, StandingFacingLeavesTheHeadScanOut)
{
  // A standing wearer whose body faces 0.3 rad, the steering point 10 deg to its left, 5 m free
  // ahead and 2 m to either side (stand_turn_deg 15 applies); the head scans +-8 deg over 7 s
  // (the simulated wearer's scan). Judged on the head, the error reaches 18 deg: a turn on the
  // spot chases the scan. Judged on the body's facing (the scan filtered out), it stays near
  // 10 deg: no turn, the tick says go.
  auto head = [](double t) { return 0.3 + 8.0 * kDeg * std::sin(2.0 * M_PI * t / 7.0); };
  auto run = [&](CueLogic& c, double t0, double t1, double body_turn_deg) {
    int turns = 0;
    for (double t = t0; t < t1; t += 1.0 / 15.0)
    {
      NavInput in = standing(turn(10.0));
      in.head_yaw = in.walk_heading = head(t) + body_turn_deg * kDeg;  // (the planner: the head's yaw while standing)
      turns += fresh(c, in, t).instruction == Instruction::TURN;
    }
    return turns;
  };
  CueLogic body;
  EXPECT_EQ(run(body, 0.0, 20.0, 0.0), 0);
  CueParams p;
  p.body_stand_tau_s = 0.0;  // the head's yaw itself (before)
  CueLogic head_only(p);
  EXPECT_GT(run(head_only, 0.0, 20.0, 0.0), 0);

  // The body turns 30 deg to the left on the spot (at 90 deg/s: the head turns with it): the
  // steering point now lies 20 deg to its right, a turn right of 20 / 90 + 0.25 s = 0.47 s.
  CueLogic c;
  run(c, 0.0, 7.0, 0.0);  // the scan at its start again (sin = 0)
  Cue k;
  for (double t = 7.0, b = 0.0; t < 7.5 && k.instruction != Instruction::TURN; t += 1.0 / 15.0)
  {
    b = std::min(30.0, b + 90.0 / 15.0);
    NavInput in = standing(turn(10.0));
    in.head_yaw = in.walk_heading = head(t) + b * kDeg;
    k = fresh(c, in, t);
  }
  ASSERT_EQ(k.instruction, Instruction::TURN);
  EXPECT_GT(k.intensity[RIGHT_SHOULDER], 0.f);
  EXPECT_NEAR(k.pattern.on_10ms, 47, 2);
}

// A vest with its own gyro (`body_yaw_rate`): the torso's turns without the head's scan. A
// standing wearer faces the steering point (0.3 rad, 5 m free ahead, 2 m to either side) while
// its head scans +-8 deg over 7 s; from t = 7 s its body turns slowly left, 6 deg/s for 5 s (a
// shuffle on the spot: with the scan's rate on top, under `body_turn_rate_deg`, so from the head
// alone it is the scan's kind of motion). With the gyro, the facing follows the body, and once it
// is about 15 deg off (`stand_turn_deg`, t = 9.5 s) a turn back to the right is asked. From the head
// alone the slow turn is filtered out as the scan (about 10 deg of the 30 by t = 12 s): no turn
// is asked while it lasts.
TEST(CueLogic, TheVestGyroCarriesASlowTurnTheHeadsFilterLeavesOut)
{
  auto body = [](double t) { return t < 7.0 ? 0.0 : std::min(30.0, 6.0 * (t - 7.0)) * kDeg; };
  auto head = [&](double t) { return 0.3 + body(t) + 8.0 * kDeg * std::sin(2.0 * M_PI * t / 7.0); };
  auto firstRightTurn = [&](bool gyro) {
    CueLogic c;
    double prev = 0.0;
    for (double t = 0.0; t < 12.0; t += 1.0 / 15.0)
    {
      NavInput in = standing(turn(0.0));
      in.head_yaw = in.walk_heading = head(t);  // (the planner: the head's yaw while standing)
      if (gyro)
        in.body_yaw_rate = t > 0.0 ? (body(t) - prev) / (1.0 / 15.0) : 0.0;
      prev = body(t);
      const Cue k = fresh(c, in, t);
      if (k.instruction == Instruction::TURN)
        return k.intensity[RIGHT_SHOULDER] > 0.f ? t : -t;
    }
    return 0.0;
  };
  const double with_gyro = firstRightTurn(true);
  EXPECT_GT(with_gyro, 9.2);
  EXPECT_LT(with_gyro, 9.8);
  EXPECT_EQ(firstRightTurn(false), 0.0);
}

// The vest gyro's bias (0.5 deg/s here; a MEMS gyro drifts by tenths of a deg/s after its
// power-up calibration) is learnt while the wearer stands still: a standing wearer facing 8 deg
// right of the steering point, its head scanning, is not turned in 40 s. Not learnt
// (`body_gyro_bias_tau_s` 0), the facing drifts 0.5 deg/s to the right and a turn is asked once
// it is 15 deg off, after about 14 s.
TEST(CueLogic, TheVestGyrosBiasIsLearntStandingStill)
{
  auto turns = [](double bias_tau_s) {
    CueParams p;
    p.body_gyro_bias_tau_s = bias_tau_s;
    CueLogic c(p);
    int n = 0;
    for (double t = 0.0; t < 40.0; t += 1.0 / 15.0)
    {
      NavInput in = standing(turn(8.0));
      in.head_yaw = in.walk_heading = 0.3 + 8.0 * kDeg * std::sin(2.0 * M_PI * t / 7.0);
      in.body_yaw_rate = -0.5 * kDeg;
      n += fresh(c, in, t).instruction == Instruction::TURN;
    }
    return n;
  };
  EXPECT_EQ(turns(3.0), 0);
  EXPECT_GT(turns(0.0), 0);
}

// Walking, what the walk chord keeps pulling out of the gyro's facing is its bias, and it is
// learnt: a wearer walking straight at 1 m/s for 30 s with a vest gyro 3 deg/s off (an
// uncalibrated MPU-6050's offset may be 20) stops on course and is asked no turn in the next 3 s.
// Not learnt (`body_gyro_bias_tau_s` 0), the facing was about bias x `body_gyro_tau_s` (15 deg)
// off at the stop and drifts on: a turn is asked.
TEST(CueLogic, WalkingTheVestGyrosBiasIsLearntFromTheWalkChord)
{
  auto turnsAskedAtTheStop = [](double bias_tau_s) {
    CueParams p;
    p.body_gyro_bias_tau_s = bias_tau_s;
    CueLogic c(p);
    NavInput in = turn(0.0);
    in.walking_speed = 1.0;
    in.body_yaw_rate = 3.0 * kDeg;
    int n = 0;
    for (double t = 0.0; t < 33.0; t += 1.0 / 15.0)
    {
      if (t >= 30.0)
        in.walking_speed = 0.0;
      n += t >= 30.0 && fresh(c, in, t).instruction == Instruction::TURN;
      if (t < 30.0)
        fresh(c, in, t);
    }
    return n;
  };
  EXPECT_EQ(turnsAskedAtTheStop(3.0), 0);
  EXPECT_GT(turnsAskedAtTheStop(0.0), 0);
}

// A veer's progress, with the vest's gyro, is the body's turn, not the walk chord's: a walker at
// 1 m/s is asked to veer left; 0.6 s after the burst its body turns 15 deg left at 60 deg/s, and
// the walk chord (0.4 s of positions) follows 0.2 s behind. In the first cycle after the body's
// turn ended, what is left to go is the amount asked less 15 deg with the gyro; judged on the
// chord, up to 12 deg of the turn (0.2 s at 60 deg/s) have not arrived yet.
TEST(CueLogic, WithTheVestGyroAVeersProgressIsTheBodysTurn)
{
  auto body = [](double t, double t0) { return std::clamp(60.0 * (t - t0), 0.0, 15.0) * kDeg; };
  auto toGo = [&](bool gyro, int& asked) {
    CueLogic c;
    double t0 = -1.0, prev = 0.0;
    for (double t = 0.0; t < 4.0; t += 1.0 / 15.0)
    {
      NavInput in = turn(35.0);
      in.walking_speed = 1.0;
      const double b = t0 < 0.0 ? 0.0 : body(t, t0);
      in.walk_heading = 0.3 + (t0 < 0.0 ? 0.0 : body(t - 0.2, t0));
      in.head_yaw = 0.3 + b + 3.0 * kDeg * std::sin(2.0 * M_PI * t / 7.0);
      in.steer_heading = in.path_heading = 0.3 + 35.0 * kDeg;  // the way on stays put
      if (gyro)
        in.body_yaw_rate = t > 0.0 ? (b - prev) * 15.0 : 0.0;
      prev = b;
      const Cue k = fresh(c, in, t);
      if (t0 < 0.0 && k.instruction == Instruction::VEER)
      {
        EXPECT_EQ(std::sscanf(k.reason.c_str(), "veer left %d deg", &asked), 1) << k.reason;
        t0 = t + 0.6;
      }
      if (t0 > 0.0 && t >= t0 + 0.25 - 1e-9)
      {
        int go = -1;
        const size_t at = k.reason.find("veering (");
        if (at == std::string::npos || std::sscanf(k.reason.c_str() + at, "veering (%d deg to go)", &go) != 1)
          ADD_FAILURE() << k.reason;
        return go;
      }
    }
    return -1;
  };
  int asked_gyro = 0, asked_chord = 0;
  const int gyro = toGo(true, asked_gyro), chord = toGo(false, asked_chord);
  ASSERT_GT(asked_gyro, 15);
  EXPECT_NEAR(gyro, asked_gyro - 15, 1);
  EXPECT_GE(chord, asked_chord - 15 + 6);
}

// The wearer's turning rate sets every later buzz's length, so it is learnt from the body's turn,
// not the head's: a standing wearer's head scans +-8 deg over 7 s, by up to several degrees while a
// turn is asked, carried out and judged. Traced in the held-out homes (trial seed 11), the rate
// learnt from the head wandered between 73 and 142 deg/s for wearers who all turn at 90, and a
// 168 deg turn asked at 113 deg/s came out 132 deg. Here a wearer (reaction 0.6 s) turns at 90
// deg/s while it feels a buzz, from 0.25 s into it (telling it from a veer's pulse), and the
// steering point moves 30 deg to alternate sides after each go: every buzz after the first few
// asks for its angle at 90 deg/s (+-6, the buzz's 10 ms steps included; learnt from the head,
// 82-104).
TEST(CueLogic, TurningRateLearntFromTheBodyNotTheScanningHead)
{
  constexpr double kReaction = 0.6, kRate = 90.0, kDt = 1.0 / 15.0;
  auto scan = [](double t) { return 8.0 * kDeg * std::sin(2.0 * M_PI * t / 7.0); };
  CueLogic c;
  double body = 0.3, target = body + 30.0 * kDeg, turn_from = -1.0, turn_to = -1.0;
  int side = 0, turns = 0, side_of_next = -1;
  bool turned_since_go = false;
  for (double t = 0.0; t < 120.0 && turns < 14; t += kDt)
  {
    // the body turns while it feels the buzz (felt a reaction late, told from a veer 0.25 s in)
    if (side != 0)
      body += side * kRate * kDeg * std::max(0.0, std::min(t, turn_to) - std::max(t - kDt, turn_from));
    NavInput in = standing(turn(0.0, body));
    in.head_yaw = in.walk_heading = body + scan(t);
    in.steer_heading = in.path_heading = target;
    const Cue k = fresh(c, in, t);
    if (k.instruction == Instruction::TURN && k.reason.find("stop, turn") != std::string::npos)
    {
      double asked = 0.0;
      char dir[8] = { 0 };
      ASSERT_EQ(std::sscanf(k.reason.c_str(), "stop, turn %7s %lf deg", dir, &asked), 2) << k.reason;
      const double buzz = 0.01 * k.pattern.on_10ms;
      side = std::string(dir) == "left" ? +1 : -1;
      turn_from = t + kReaction + 0.25;
      turn_to = t + kReaction + buzz;
      ++turns;
      turned_since_go = true;
      if (turns > 4 && asked > 15.0 && buzz < 2.5)
      {
        EXPECT_NEAR(asked / (buzz - 0.25), kRate, 6.0) << "turn " << turns << ": " << k.reason;
      }
    }
    if (k.instruction == Instruction::WALK_ON && turned_since_go && t > turn_to + kReaction)
    {
      // gone: the steering point moves 30 deg to the other side of the body
      turned_since_go = false;
      side = 0;
      target = body + side_of_next * 30.0 * kDeg;
      side_of_next = -side_of_next;
    }
  }
  EXPECT_GE(turns, 10);
}

TEST(CueLogic, ShortWalkStopTimedFromTheGo)
{
  // Standing, facing the steering point, 1.5 m free ahead: "go" at t = 0. The stop is asked
  // S = 0.1 + sqrt((1.5 - alert_m) / (a / 2 + a^2 / (2 stop_decel))) after it, a = 1.2 m/s^2,
  // stop_decel 2: 0.1 + sqrt(1 / 0.96) = 1.12062 s (the walk then ends alert_m short of the
  // obstacle whatever the wearer's reaction: it starts and stops a reaction late).
  auto at = [](double speed, double ahead) {
    NavInput in = standing(turn(0.0));
    in.walking_speed = speed;
    in.free_ahead = ahead;
    return in;
  };
  {
    CueLogic c;
    EXPECT_EQ(fresh(c, at(0.0, 1.5), 0.0).instruction, Instruction::WALK_ON);
    Cue k;
    double t = 1.0 / 15.0;
    for (; t < 1.1206; t += 1.0 / 15.0)
    {
      k = fresh(c, at(t > 0.6 ? 0.3 : 0.0, 1.5), t);
      EXPECT_NE(k.instruction, Instruction::STOP) << "t " << t;
    }
    k = fresh(c, at(0.3, 1.5), 1.1207);
    EXPECT_EQ(k.mode, CueMode::ALERT);
    EXPECT_EQ(k.instruction, Instruction::STOP);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(k.intensity[size_t(i)], 1.f);
    // held while it slows down, and for 0.5 s once it stands; then the tick again
    EXPECT_EQ(fresh(c, at(0.1, 1.3), 1.4).instruction, Instruction::STOP);
    EXPECT_EQ(fresh(c, at(0.0, 1.2), 1.6).instruction, Instruction::STOP);
    EXPECT_EQ(fresh(c, at(0.0, 1.2), 1.7).instruction, Instruction::WALK_ON);
  }
  {
    // 3 m free (over short_walk_m, 2.5): no timed stop
    CueLogic c;
    EXPECT_EQ(fresh(c, at(0.0, 3.0), 0.0).instruction, Instruction::WALK_ON);
    for (double t = 1.0 / 15.0; t < 3.0; t += 1.0 / 15.0)
      EXPECT_NE(fresh(c, at(t > 0.6 ? 0.5 : 0.0, 3.0), t).instruction, Instruction::STOP) << "t " << t;
  }
}

namespace
{
/// A walker for the cue logic, as the planner sees it: it acts on what the cue asks a reaction
/// time later (a walk-on tick, 0.1 s long, once it ended: speed up at `accel` to `pace`; all
/// four: slow down at `decel`),
/// walks straight towards an obstacle `wall` m ahead of where it starts, and its speed is the
/// chord of its positions over the last 0.4 s (the planner's `walk_window_s`).
struct GaitWalker
{
  GaitWalker(double reaction_s, double accel_mps2, double decel_mps2, double pace_mps, double wall_m)
    : reaction(reaction_s), accel(accel_mps2), decel(decel_mps2), pace(pace_mps), wall(wall_m)
  {
  }
  double reaction, accel, decel, pace, wall;
  double x = 0.0, v = 0.0;
  bool go = false;
  /// On its first stop, once slowed to half its pace, it walks on for this long (as a walk-on tick
  /// sent before the stop and felt after it would send it), then stops again (0: never).
  double resume_s = 0.0;
  double resume_until = -1.0;
  std::vector<std::pair<double, Instruction>> felt;  // (when it acts, what)
  std::vector<std::pair<double, double>> track;      // (t, x)
  NavInput input(double t) const
  {
    NavInput in = standing(turn(0.0));
    double x0 = 0.0;  // where it was 0.4 s ago (it stood at 0 before the track began)
    for (const auto& [tt, xx] : track)
      if (tt <= t - 0.4 + 1e-9)
        x0 = xx;
    in.walking_speed = (x - x0) / 0.4;
    in.free_ahead = wall - x;
    return in;
  }
  void step(double t, double dt, const Cue& c)
  {
    if (c.instruction == Instruction::WALK_ON)
      felt.emplace_back(t + 0.1 + reaction, c.instruction);  // a tick is understood when it ends
    else if (c.instruction == Instruction::STOP)
      felt.emplace_back(t + reaction, c.instruction);
    for (const auto& [when, ins] : felt)
      if (when <= t + 1e-9)
        go = ins == Instruction::WALK_ON;
    if (!go && resume_s > 0.0 && v > 0.0 && v <= 0.5 * pace)
    {
      resume_until = t + resume_s;
      resume_s = 0.0;
    }
    if (t < resume_until)
      go = true;
    v = go ? std::min(pace, v + accel * dt) : std::max(0.0, v - decel * dt);
    x += v * dt;
    track.emplace_back(t + dt, x);
  }
};

/// Runs the walker on the cue logic from `t0` for `seconds` (15 Hz); returns the free distance
/// ahead when the first all-four came (NaN: none), and the time it came.
std::pair<double, double> walk(CueLogic& c, GaitWalker& w, double t0, double seconds)
{
  std::pair<double, double> first{ std::nan(""), std::nan("") };
  const double dt = 1.0 / 15.0;
  for (double t = t0; t < t0 + seconds; t += dt)
  {
    const NavInput in = w.input(t);
    const Cue k = fresh(c, in, t);
    if (k.instruction == Instruction::STOP && std::isnan(first.first))
      first = { in.free_ahead, t };
    w.step(t, dt, k);
  }
  return first;
}
}  // namespace

// Issue 33: the cue logic learns how quickly this wearer starts and stops (gait initiation
// 0.5-1.2 m/s^2 in the population) instead of assuming one wearer. A wearer that starts at
// 0.5 m/s^2 and stops at 1 m/s^2 (reaction 0.8 s, pace 1 m/s): after its first stop on all
// four from its pace, the next stop comes v^2 / 2 (1/1 - 1/2) = 0.25 m earlier; a go with 1.5 m
// free then gets the timed stop computed with its own start and stop, 1.733 s after the go (the
// 1.12 s of an unknown wearer would stop it 0.6 m short).
TEST(CueLogic, LearnsTheWearersStartAndStop)
{
  CueLogic c;
  GaitWalker w{ 0.8, 0.5, 1.0, 1.0, 9.0 };
  // first walk: starts, reaches its pace, is stopped before the wall
  const auto first = walk(c, w, 0.0, 14.0);
  ASSERT_TRUE(std::isfinite(first.first));
  EXPECT_NEAR(w.v, 0.0, 1e-9);
  EXPECT_GT(w.wall - w.x, 0.15) << "stopped short of the wall";
  // second walk, from standing 9 m from the next wall: stopped 0.25 m earlier (its stop learnt)
  w.wall = w.x + 9.0;
  const auto second = walk(c, w, 14.0, 14.0);
  ASSERT_TRUE(std::isfinite(second.first));
  EXPECT_NEAR(second.first - first.first, 0.25, 0.08);
  EXPECT_GT(w.wall - w.x, 0.15);

  // a short walk (1.5 m free) after a go: the stop timed from its own start, 0.5 m/s^2, and its
  // own stop, 1 m/s^2: S = 0.1 + sqrt(1 / (0.25 + 0.125)) = 1.733 s after the go (1.12 s for a
  // wearer not yet seen, who is assumed to start at 1.2 and stop at 2 m/s^2)
  w.wall = w.x + 1.5;
  double go = std::nan(""), stop = std::nan("");
  const double dt = 1.0 / 15.0;
  for (double t = 28.0; t < 32.0 && std::isnan(stop); t += dt)
  {
    const Cue k = fresh(c, w.input(t), t);
    if (k.instruction == Instruction::WALK_ON && std::isnan(go) && k.pattern.id != 0 && w.v == 0.0)
      go = t;
    if (k.instruction == Instruction::STOP && std::isfinite(go))
      stop = t;
    w.step(t, dt, k);
  }
  ASSERT_TRUE(std::isfinite(go));
  ASSERT_TRUE(std::isfinite(stop));
  EXPECT_NEAR(stop - go, 1.733, 0.15);
}

// A stop whose fall is broken by a walk on (a tick sent before the stop, felt after it) is no
// sample of the wearer's stop: the wearer above, whose first stop halves its speed, walks on for
// 0.6 s and then stops, is stopped on its second walk where the same wearer with an unbroken first
// stop is (its stop, 1 m/s^2, learnt from the fall after the walk on). Before, the broken fall was read as a 0.3 m/s^2 stop
// (clamped to 0.5): the second stop came over 0.5 m earlier, and the predictive stop halted
// walkers on clear corridors every few metres (traced, gen_home_3012).
TEST(CueLogic, AStopBrokenByAWalkOnIsNoSampleOfTheWearersStop)
{
  // (alert_m 1.2 m: the walk on does not reach the wall, where a stop is no sample)
  CueParams p;
  p.alert_m = 1.2;
  CueLogic plain(p), broken(p);
  GaitWalker a{ 0.8, 0.5, 1.0, 1.0, 9.0 }, b{ 0.8, 0.5, 1.0, 1.0, 9.0 };
  b.resume_s = 0.6;
  walk(plain, a, 0.0, 14.0);
  walk(broken, b, 0.0, 14.0);
  ASSERT_EQ(b.resume_s, 0.0) << "the second walker walked on during its first stop";
  a.wall = a.x + 9.0;
  b.wall = b.x + 9.0;
  const auto second_a = walk(plain, a, 14.0, 14.0);
  const auto second_b = walk(broken, b, 14.0, 14.0);
  ASSERT_TRUE(std::isfinite(second_a.first));
  ASSERT_TRUE(std::isfinite(second_b.first));
  EXPECT_NEAR(second_b.first, second_a.first, 0.1);
  EXPECT_GT(b.wall - b.x, 0.15);
}

TEST(CueLogic, WrapAngle)
{
  const std::vector<std::pair<double, double>> table = { { 0, 0 },           { M_PI, M_PI },
                                                         { -M_PI, M_PI },    { 3 * M_PI, M_PI },
                                                         { 1.5 * M_PI, -0.5 * M_PI }, { -0.25, -0.25 } };
  for (const auto& r : table)
    EXPECT_NEAR(wrapAngle(r.first), r.second, 1e-12) << r.first;
}

namespace
{
/// A wall across x = 1.9 .. 2.1 m (one column of 0.2 m cells, centres at x = 2.0) with a doorway:
/// three free cells, centres at y = -0.2, 0, +0.2 (0.6 m of free cells: an 0.80 m doorway whose
/// jambs' faces lie inside the cells next to them; obstacle centres at y = +-0.4), open floor
/// elsewhere from x = -2.1 to 5.9 m.
std::shared_ptr<ObstacleGrid> doorwayGrid()
{
  auto g = std::make_shared<ObstacleGrid>();
  g->origin_x = -2.1;
  g->origin_y = -2.1;
  g->resolution = 0.2;
  g->width = g->height = 40;
  g->data.assign(size_t(40 * 40), 0);
  const int ix = 20;  // [1.9, 2.1)
  for (int iy = 0; iy < 40; ++iy)
    if (std::fabs(g->cellY(iy)) > 0.3)
      g->data[size_t(g->index(ix, iy))] = 100;
  return g;
}

/// A walker at (x, y) heading +x (yaw 0) at `v` m/s, the steering point `dev_deg` off, 5 m free
/// along the ray ahead and 2 m to either side (the rays of the planner see nothing of the jambs).
NavInput walkerAt(double x, double y, double v, double dev_deg = 0.0)
{
  NavInput in = turn(dev_deg, 0.0);
  in.x = x;
  in.y = y;
  in.walking_speed = v;
  return in;
}
}  // namespace

TEST(Sweep, NextCornerOfAPath)
{
  // an L: 3 m along x, then along y
  const std::vector<GroundPoint> ell{ { 0.0, 0.0 }, { 1.0, 0.0 }, { 2.0, 0.0 }, { 3.0, 0.0 }, { 3.0, 1.5 }, { 3.0, 3.0 } };
  PathCorner c = nextCorner(ell, 0.0, 0.1, 0.15, 8.0);
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.x, 3.0, 1e-9);
  EXPECT_NEAR(c.y, 0.0, 1e-9);
  EXPECT_NEAR(c.heading_out, M_PI / 2, 1e-9);
  EXPECT_NEAR(c.leg_out, 3.0, 1e-9);
  // seen from 1.2 m on: the same corner (the path from its nearest point on)
  c = nextCorner(ell, 1.2, 0.0, 0.15, 8.0);
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.x, 3.0, 1e-9);
  // cut off before the corner: none; past the corner: none (straight on)
  EXPECT_FALSE(nextCorner(ell, 0.0, 0.0, 0.15, 2.5).found);
  EXPECT_FALSE(nextCorner(ell, 3.0, 0.5, 0.15, 8.0).found);
  // rounded by a 0.42 m diagonal: one corner of 90 deg where the legs in and out meet, (3.3, 0)
  const std::vector<GroundPoint> cut{ { 0.0, 0.0 }, { 3.0, 0.0 }, { 3.3, 0.3 }, { 3.3, 3.0 } };
  c = nextCorner(cut, 0.0, 0.0, 0.15, 8.0);
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.x, 3.3, 1e-9);
  EXPECT_NEAR(c.y, 0.0, 1e-9);
  EXPECT_NEAR(c.heading_out, M_PI / 2, 1e-9);
  EXPECT_NEAR(c.leg_out, 2.7, 1e-9);
  // the same diagonal 0.71 m long is a corner of its own (45 deg)
  const std::vector<GroundPoint> bevel{ { 0.0, 0.0 }, { 3.0, 0.0 }, { 3.5, 0.5 }, { 3.5, 3.0 } };
  c = nextCorner(bevel, 0.0, 0.0, 0.15, 8.0);
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.x, 3.0, 1e-9);
  EXPECT_NEAR(c.heading_out, M_PI / 4, 1e-9);
}

namespace
{
/// Open floor from x, y = -2.1 to 7.9 m (0.2 m cells), with a wall (one column of cells, centres
/// at x = `wall_x`) across it when `wall_x` is finite.
std::shared_ptr<ObstacleGrid> openGrid(double wall_x = std::nan(""))
{
  auto g = std::make_shared<ObstacleGrid>();
  g->origin_x = g->origin_y = -2.1;
  g->resolution = 0.2;
  g->width = g->height = 50;
  g->data.assign(size_t(50 * 50), 0);
  for (int ix = 0; ix < 50 && std::isfinite(wall_x); ++ix)
    if (std::fabs(g->cellX(ix) - wall_x) < 0.1)
      for (int iy = 0; iy < 50; ++iy)
        g->data[size_t(g->index(ix, iy))] = 100;
  return g;
}

/// A walker along y = 0 at 1 m/s towards a left turn of the path at (4, 0) (then along +y), on
/// `grid`, from x = 0 for `seconds`: the cues and where it was at each.
std::vector<std::pair<double, Cue>> walkToCorner(std::shared_ptr<ObstacleGrid> grid, double seconds)
{
  CueParams p;
  p.corner_veer_deg = 20.0;  // (off by default)
  CueLogic c(p);
  std::vector<std::pair<double, Cue>> out;
  const double dt = 1.0 / 15.0;
  for (double t = 0.0; t < seconds; t += dt)
  {
    NavInput in = turn(0.0, 0.0);
    in.walking_speed = 1.0;
    in.x = t * 1.0;
    in.grid = grid;
    in.path = { { in.x, 0.0 }, { 4.0, 0.0 }, { 4.0, 4.0 } };
    out.emplace_back(in.x, fresh(c, in, t));
  }
  return out;
}
}  // namespace

// Issue 33, a corner taken walking: a walker nearing a left turn of 90 deg is asked to veer round
// it in stride, when the arc at its speed must begin a reaction and a pulse later. Its pace is
// learnt after a second of steady walking, 1 m/s: radius v / 60 deg/s = 0.955 m, so the arc
// begins 0.955 m before the corner; the reaction not yet learnt, 0.6 s, and the pulse, 0.15 s:
// 0.75 m of walk before it: the veer is asked at x = 4 - 0.955 - 0.75 = 2.295 m or up to 0.1 m
// (a cycle and a half) before, 45 deg (level 3) to the left, and the other 45 deg as a second
// pair 0.95 s later (felt apart). The walk on to it is neither steered nor stopped before.
TEST(CueLogic, ACornerIsVeeredRoundInStride)
{
  const auto cues = walkToCorner(openGrid(), 3.5);
  double first_x = std::nan(""), second_x = std::nan("");
  for (const auto& [x, c] : cues)
  {
    if (std::isnan(first_x) && c.instruction != Instruction::VEER)
    {
      ASSERT_EQ(c.instruction, Instruction::WALK_ON) << "x " << x << ": " << c.reason;
    }
    if (c.instruction == Instruction::VEER && std::isnan(first_x))
    {
      first_x = x;
      EXPECT_EQ(c.level, 3) << c.reason;
      EXPECT_GT(c.intensity[LEFT_SHOULDER], 0.f);
      EXPECT_NE(c.reason.find("a corner of 90 deg"), std::string::npos) << c.reason;
    }
    else if (c.instruction == Instruction::VEER && std::isfinite(first_x) && std::isnan(second_x) &&
             c.reason.find("round the corner") != std::string::npos)
    {
      second_x = x;
      EXPECT_EQ(c.level, 3) << c.reason;
    }
  }
  ASSERT_TRUE(std::isfinite(first_x));
  EXPECT_GT(first_x, 2.295 - 0.1 - 1e-6);
  EXPECT_LE(first_x, 2.295 + 1e-6);
  ASSERT_TRUE(std::isfinite(second_x));
  EXPECT_NEAR(second_x - first_x, 0.95, 0.07);
}

// ... and where the arc does not fit (a wall 0.2 m beyond the corner: the arc's end would bring
// the body's centre within 0.2 m of it), no corner veer: stopped before the wall as before.
TEST(CueLogic, ACornerWhoseArcDoesNotFitIsStoppedAtAsBefore)
{
  const auto cues = walkToCorner(openGrid(4.2), 3.5);
  bool stopped = false;
  for (const auto& [x, c] : cues)
  {
    EXPECT_EQ(c.reason.find("corner"), std::string::npos) << "x " << x << ": " << c.reason;
    stopped = stopped || c.instruction == Instruction::STOP;
    if (stopped)
      break;
  }
  EXPECT_TRUE(stopped);
}

TEST(Sweep, ClearanceIsToTheObstacleCellsCentres)
{
  const auto g = doorwayGrid();
  EXPECT_NEAR(obstacleClearance(*g, 2.0, 0.0, 1.0), 0.4, 1e-9);   // the middle of the doorway
  EXPECT_NEAR(obstacleClearance(*g, 1.0, 0.4, 2.0), 1.0, 1e-9);   // 1 m before the jamb's centre
  EXPECT_NEAR(obstacleClearance(*g, -1.0, 0.0, 0.5), 0.5, 1e-9);  // nothing within reach
  EXPECT_NEAR(sideFree(*g, 2.0, 0.0, 0.0, +1, 1.0), 0.30, 0.021);  // the jamb's cell begins 0.3 m left
  EXPECT_NEAR(sideFree(*g, 2.0, 0.0, 0.0, -1, 1.0), 0.30, 0.021);
  EXPECT_NEAR(sideFree(*g, 0.0, 0.0, 0.0, +1, 1.0), 1.0, 1e-9);
}

TEST(Sweep, DoorwayJambClippedOffTheMiddleOnly)
{
  // A body of radius 0.24 m walking straight at 1 m/s (no stop, no turn): through the middle it
  // keeps 0.4 m from the jambs' centres; 0.2 m off the middle its disc meets the left jamb's
  // centre (2.0, 0.4) where (2.0 - x)^2 + 0.2^2 = 0.24^2: x = 1.867 m (within a 5 cm step).
  const auto g = doorwayGrid();
  WalkModel m;
  m.v0 = m.pace = 1.0;
  m.accel = 0.0;
  m.horizon_s = 4.0;
  const SweepResult mid = sweepWalk(*g, 0.0, 0.0, 0.0, m, 0.24);
  EXPECT_FALSE(mid.hit);
  EXPECT_NEAR(mid.min_clear, 0.4, 1e-6);
  const SweepResult off = sweepWalk(*g, 0.0, 0.2, 0.0, m, 0.24);
  ASSERT_TRUE(off.hit);
  EXPECT_NEAR(off.hit_along, 1.867, 0.05);
  EXPECT_NEAR(off.end_x, 1.867, 0.05);
  // the same walk stopped in time: the stop begins after 0.5 s and lasts v^2 / 2d = 0.25 m
  m.decel = 2.0;
  m.stop_at_s = 0.5;
  const SweepResult stopped = sweepWalk(*g, 0.5, 0.2, 0.0, m, 0.24);
  EXPECT_FALSE(stopped.hit);
  EXPECT_NEAR(stopped.walked, 0.75, 0.06);
  // ... and stopped too late: from 1.3 m (its 0.75 m end past 1.867 m) it meets the jamb
  EXPECT_TRUE(sweepWalk(*g, 1.3, 0.2, 0.0, m, 0.24).hit);
  EXPECT_FALSE(sweepWalk(*g, 1.0, 0.2, 0.0, m, 0.24).hit);  // (its end 1.75 m)
  // a veer of 30 deg to the right, begun after 1 s at 60 deg/s from the middle, carries the body
  // into the right jamb (2.0, -0.4) just past the jamb line
  WalkModel v = m;
  v.stop_at_s = 1e9;
  v.turn_start_s = 1.0;
  v.turn = -30.0 * kDeg;
  v.turn_rate = 60.0 * kDeg;
  const SweepResult veer = sweepWalk(*g, 0.0, 0.0, 0.0, v, 0.24);
  ASSERT_TRUE(veer.hit);
  EXPECT_GT(veer.hit_along, 1.3);
  EXPECT_LT(veer.hit_along, 2.1);
  EXPECT_NEAR(veer.end_yaw, -30.0 * kDeg, 1e-6);
  // a body already closer to a jamb than its radius (squeezing past it) is not hit where it
  // stands, only when the walk takes it 3 cm closer still
  WalkModel still;
  still.horizon_s = 1.0;
  EXPECT_FALSE(sweepWalk(*g, 2.0, 0.2, 0.0, still, 0.24).hit);
}

namespace
{
/// A shelf along y = 0.6 (a row of obstacle cells, centres at y = 0.6, from x = -2 to 5.8 m),
/// open floor elsewhere from -2.1 to 5.9 m.
std::shared_ptr<ObstacleGrid> shelfGrid()
{
  auto g = std::make_shared<ObstacleGrid>();
  g->origin_x = g->origin_y = -2.1;
  g->resolution = 0.2;
  g->width = g->height = 40;
  g->data.assign(size_t(40 * 40), 0);
  for (int ix = 0; ix < 40; ++ix)
    g->data[size_t(g->index(ix, 13))] = 100;  // cellY(13) = 0.6
  return g;
}
}  // namespace

TEST(Sweep, SpreadAsksForMoreRoomFurtherOnButNotMoreThanTheBodyHasNow)
{
  // The shelf; a body of radius 0.24 m at (0, 0) walking at 1 m/s for 4 s (no stop, no turn).
  const auto g = shelfGrid();
  ASSERT_NEAR(g->cellY(13), 0.6, 1e-9);
  WalkModel m;
  m.v0 = m.pace = 1.0;
  m.accel = 0.0;
  m.horizon_s = 4.0;
  // along the shelf: clear with the radius alone and with a spread (it never asks for more than
  // the 0.6 m the body has now less 3 cm)
  EXPECT_FALSE(sweepWalk(*g, 0.0, 0.0, 0.0, m, 0.24).hit);
  WalkModel spread = m;
  spread.spread_per_m = 0.1;
  EXPECT_FALSE(sweepWalk(*g, 0.0, 0.0, 0.0, spread, 0.24).hit);
  // 3 deg towards it: the clearance 0.6 - 0.0523 s meets the radius only after 6.9 m (beyond the
  // 4 m walked), but meets 0.24 + 0.1 s at s = 0.36 / 0.1523 = 2.36 m
  const double yaw = 3.0 * kDeg;
  EXPECT_FALSE(sweepWalk(*g, 0.0, 0.0, yaw, m, 0.24).hit);
  const SweepResult r = sweepWalk(*g, 0.0, 0.0, yaw, spread, 0.24);
  ASSERT_TRUE(r.hit);
  EXPECT_NEAR(r.hit_along, 2.36, 0.1);  // (the cells' centres lie every 0.2 m along the shelf)
  // 3 deg away from it: clear
  EXPECT_FALSE(sweepWalk(*g, 0.0, 0.0, -yaw, spread, 0.24).hit);
}

// The cue logic's sweep carries the spread (sweep_spread_m): a walker at 1 m/s converging on a
// shelf at 6 deg, 0.6 m beside it, on course (the rays see nothing ahead or beside). With the
// radius alone its committed walk (an unlearnt wearer: 1.2 s to react, a stop at 1 m/s^2) ends
// clear of the shelf; with the default spread the walk's end needs more room than it keeps: stop.
TEST(CueLogic, PredictiveStopAsksForMoreRoomFurtherAlongTheWalk)
{
  NavInput in = turn(0.0, 6.0 * kDeg);
  in.walking_speed = 1.0;
  in.grid = shelfGrid();
  CueLogic spread;
  const Cue k = fresh(spread, in, 0.0);
  EXPECT_EQ(k.instruction, Instruction::STOP) << k.reason;
  EXPECT_NE(k.reason.find("sweep the body"), std::string::npos) << k.reason;
  CueParams p;
  p.sweep_spread_m = 0.0;
  CueLogic radius_only(p);
  const Cue w = fresh(radius_only, in, 0.0);
  EXPECT_EQ(w.instruction, Instruction::WALK_ON) << w.reason;
}

// A body turning now goes on turning until it feels a stop: a walker at 1 m/s, 1.2 m from a shelf,
// whose head turns towards it at 50 deg/s (a veer carried out beyond its amount) is stopped while
// it still faces along the shelf; the same facing with a steady head walks on (its straight walk
// and stop keep clear of the shelf).
TEST(CueLogic, PredictiveStopCountsTheTurnUnderWay)
{
  const double dt = 1.0 / 15;
  CueLogic turning;
  NavInput in = walkerAt(0.0, -0.6, 1.0);
  in.grid = shelfGrid();
  Cue c = fresh(turning, in, 0.0);
  ASSERT_EQ(c.instruction, Instruction::WALK_ON) << c.reason;
  double t = dt, head_deg = 0.0;
  for (; t < 0.5 && c.instruction != Instruction::STOP; t += dt)
  {
    head_deg = 50.0 * t;
    in.x = t;
    in.head_yaw = in.heading = head_deg * kDeg;
    c = fresh(turning, in, t);
  }
  EXPECT_EQ(c.instruction, Instruction::STOP) << c.reason;
  EXPECT_NE(c.reason.find("sweep the body"), std::string::npos) << c.reason;
  EXPECT_LE(head_deg, 10.0);  // (without the turn under way: at 17 deg, where a steady walk meets the shelf too)

  CueLogic steady;
  NavInput still = walkerAt(0.0, -0.6, 1.0);
  still.grid = shelfGrid();
  for (double u = 0.0; u < 0.5; u += dt)
  {
    still.x = u;
    still.head_yaw = still.heading = still.walk_heading = head_deg * kDeg;
    const Cue k = fresh(steady, still, u);
    EXPECT_EQ(k.reason.find("sweep the body"), std::string::npos) << u << " " << k.reason;
  }
}

TEST(CueLogic, PredictiveStopSeesTheJambBesideTheBody)
{
  // A walker at 1 m/s, 0.2 m off a doorway's middle 1.5 m before the jamb line: the planner's ray
  // ahead passes through the free cell (5 m free), so the rays give no stop; the body's disc,
  // swept along the walk with the stop a wearer of unknown reaction (1.2 s) and stop (1 m/s^2)
  // would make, meets the jamb: stop now. Through the middle it walks on; without the planner's
  // grid the cue logic judges on the rays as before.
  const auto g = doorwayGrid();
  CueLogic with;
  NavInput off = walkerAt(0.5, 0.2, 1.0);
  off.grid = g;
  const Cue k = fresh(with, off, 0.0);
  EXPECT_EQ(k.instruction, Instruction::STOP);
  EXPECT_EQ(k.mode, CueMode::ALERT);
  EXPECT_NE(k.reason.find("sweep the body"), std::string::npos) << k.reason;
  // held until it stands (its slowing walk sweeps clear again)
  NavInput slower = off;
  slower.walking_speed = 0.5;
  slower.x = 0.9;
  EXPECT_EQ(fresh(with, slower, 0.3).instruction, Instruction::STOP);
  // ... the same pattern, no tick in between, even where the guidance would send it on (its walk,
  // back on the middle's line, sweeps clear): before, the guidance's tick replaced the stop after
  // one cycle; then, standing, the guidance goes on
  NavInput clear = slower;
  clear.y = 0.0;
  const Cue held = fresh(with, clear, 0.4);
  EXPECT_EQ(held.instruction, Instruction::STOP) << held.reason;
  EXPECT_EQ(held.pattern.id, k.pattern.id);
  clear.walking_speed = 0.0;
  EXPECT_EQ(fresh(with, clear, 1.0).instruction, Instruction::WALK_ON);

  CueLogic mid;
  NavInput through = walkerAt(0.5, 0.0, 1.0);
  through.grid = g;
  EXPECT_EQ(fresh(mid, through, 0.0).instruction, Instruction::WALK_ON);

  CueLogic rays;
  EXPECT_EQ(fresh(rays, walkerAt(0.5, 0.2, 1.0), 0.0).instruction, Instruction::WALK_ON);

  CueParams p;
  p.sweep_radius_m = 0.0;  // the sweep off
  CueLogic off_param(p);
  EXPECT_EQ(fresh(off_param, off, 0.0).instruction, Instruction::WALK_ON);
}

TEST(CueLogic, NoVeerInADoorwayWhileWalkingOnSweepsClear)
{
  // In the doorway (x = 1.95, its middle), the steering point 20 deg to the left: on the rays
  // alone a veer (the traced case: a veer carried out a reaction later, just past the jambs, into
  // the wall beyond); with the grid, walking on sweeps clear (open floor beyond): straight on.
  const auto g = doorwayGrid();
  CueLogic rays;
  EXPECT_EQ(fresh(rays, walkerAt(1.95, 0.0, 1.0, 20.0), 0.0).instruction, Instruction::VEER);
  CueLogic with;
  NavInput in = walkerAt(1.95, 0.0, 1.0, 20.0);
  in.grid = g;
  const Cue k = fresh(with, in, 0.0);
  EXPECT_EQ(k.instruction, Instruction::WALK_ON) << k.reason;
  EXPECT_NE(k.reason.find("in a doorway"), std::string::npos) << k.reason;
  // out in the open (2 m past the doorway) the veer is asked as before
  CueLogic open;
  NavInput beyond = walkerAt(3.0, 0.0, 1.0, 20.0);
  beyond.grid = g;
  EXPECT_EQ(fresh(open, beyond, 0.0).instruction, Instruction::VEER);
  // a wall 1.2 m beyond the doorway (a home's hall): walking on would meet it, the veer is asked
  auto hall = std::make_shared<ObstacleGrid>(*g);
  for (int iy = 0; iy < hall->height; ++iy)
    hall->data[size_t(hall->index(26, iy))] = 100;  // cells [3.1, 3.3)
  CueLogic h;
  NavInput near_wall = walkerAt(1.95, 0.0, 1.0, 20.0);
  near_wall.grid = hall;
  EXPECT_NE(fresh(h, near_wall, 0.0).reason.find("in a doorway"), 0u);
  EXPECT_EQ(fresh(h, near_wall, 0.0).reason.find("in a doorway"), std::string::npos);
}

namespace
{
/// The doorway of doorwayGrid() (middle (2, 0), axis +x) as the planner reports it to a wearer at
/// (x, y): along the path `dist` m, its middle, its axis and its width (0.8 m: 0.6 m of free cells
/// plus a cell).
NavInput atDoorway(NavInput in, double dist)
{
  in.grid = doorwayGrid();
  in.passage_distance = dist;
  in.passage_width = 0.8;
  in.passage_x = 2.0;
  in.passage_y = 0.0;
  in.passage_axis = 0.0;
  in.passage_heading = std::atan2(0.0 - in.y, 2.0 - in.x);
  return in;
}

/// A standing wearer at (x, y) whose body and head face `yaw_deg`, the steering point `steer_deg`.
NavInput standingAt(double x, double y, double yaw_deg, double steer_deg)
{
  NavInput in = standing(base());
  in.x = x;
  in.y = y;
  in.head_yaw = in.walk_heading = in.heading = yaw_deg * kDeg;
  in.steer_heading = in.path_heading = steer_deg * kDeg;
  return in;
}
}  // namespace

// A wearer standing 0.8 m before an 0.80 m doorway but 1.0 m to the side of its axis (51 deg off
// it, seen from the middle): faced to the middle from there it would cross the jamb line on the
// slant, where the jambs close in on the body. It is turned towards the point passage_stage_m
// (0.6 m) before the middle on the axis (79 deg right, not the middle's 51), sent there, and
// stopped by a stop timed from the go. Without the axis (an older planner) it faces the middle.
TEST(CueLogic, StandingOffADoorwaysAxisWalksToTheAxisFirst)
{
  CueLogic c;
  const Cue k = fresh(c, atDoorway(standingAt(1.2, 1.0, 0.0, -51.0), 1.5), 0.0);
  ASSERT_EQ(k.instruction, Instruction::TURN) << k.reason;
  EXPECT_GT(k.intensity[RIGHT_SHOULDER], 0.f);
  EXPECT_NE(k.reason.find("to its axis first"), std::string::npos) << k.reason;
  const double stage_deg = std::atan2(-1.0, 0.2) / kDeg;  // -78.7
  EXPECT_EQ(k.pattern.on_10ms, int(std::lround(100.0 * (-stage_deg / 90.0 + 0.25))));

  // facing the stage point: go, then a stop timed from the go, no turn on the way (the sweep's
  // spread off: for a wearer whose reaction and stop are not learnt yet, 1.2 s and 1 m/s^2, the
  // walk it predicts runs 2 m on past the stage point, and 0.1 m/m of spread then meets the wall
  // beside the doorway: the predictive stop would come at once, before the timed one)
  CueParams no_spread;
  no_spread.sweep_spread_m = 0.0;
  CueLogic g(no_spread);
  NavInput in = atDoorway(standingAt(1.2, 1.0, stage_deg, -51.0), 1.5);
  const Cue go = fresh(g, in, 0.0);
  ASSERT_EQ(go.instruction, Instruction::WALK_ON) << go.reason;
  EXPECT_NE(go.reason.find("to its axis"), std::string::npos) << go.reason;
  double stop_at = -1.0;
  for (double t = 1.0 / 15.0; t < 4.0 && stop_at < 0.0; t += 1.0 / 15.0)
  {
    NavInput w = in;
    w.walking_speed = 0.6;  // walking towards it (the position is not what is judged)
    const Cue q = fresh(g, w, t);
    EXPECT_NE(q.instruction, Instruction::TURN) << t << " " << q.reason;
    if (q.instruction == Instruction::STOP)
      stop_at = t;
  }
  // 1.02 m: a^-1 (0.5 + a / (2 d)) s^2 = 1.02 at the unlearnt start (1.2) and stop: about 1 s
  EXPECT_GT(stop_at, 0.5);
  EXPECT_LT(stop_at, 2.0);

  CueLogic old;
  NavInput no_axis = atDoorway(standingAt(1.2, 1.0, 0.0, -51.0), 1.5);
  no_axis.passage_axis = std::numeric_limits<double>::quiet_NaN();
  const Cue o = fresh(old, no_axis, 0.0);
  ASSERT_EQ(o.instruction, Instruction::TURN);
  EXPECT_EQ(o.pattern.on_10ms, int(std::lround(100.0 * (std::atan2(1.0, 0.8) / kDeg / 90.0 + 0.25))));
}

// A walker going along a hall past the doorway's side (x = 1.4, heading -y at 1 m/s), the doorway
// to its left: its walk crosses the doorway's axis 0.6 m before the middle. It walks on (no turn
// short of it), then a stop lands it on the axis: the stop is asked when the crossing lies about
// its stop's reach ahead.
TEST(CueLogic, WalkerOnTheSlantStopsOnTheDoorwaysAxis)
{
  CueLogic c;
  double stop_y = -1.0;
  for (int i = 0; i < 60 && stop_y < 0.0; ++i)
  {
    NavInput in = base();
    in.x = 1.4;
    in.y = 3.0 - i * (1.0 / 15.0);
    in.walking_speed = 1.0;
    in.head_yaw = in.walk_heading = in.heading = -90.0 * kDeg;
    in.steer_heading = in.path_heading = std::atan2(-in.y, 0.6);
    in = atDoorway(in, in.y + 0.6);
    const Cue q = fresh(c, in, i / 15.0);
    ASSERT_NE(q.instruction, Instruction::TURN) << in.y << " " << q.reason;
    if (q.instruction == Instruction::STOP)
    {
      stop_y = in.y;
      EXPECT_NE(q.reason.find("doorway's axis"), std::string::npos) << q.reason;
    }
  }
  // a stop from 1 m/s lands after its reach (reaction 1.2 s unlearnt: about 1.2 + 0.5 m)
  EXPECT_GT(stop_y, 0.8);
  EXPECT_LT(stop_y, 2.5);
}

// Standing in the doorway's middle with the way turning left just beyond it: turned on the spot
// there, the body would leave on the slant past a jamb; it steps out along the axis first (a go
// with a timed stop). Walking through, the stop before that turn is asked at once (it lands
// past passage_clear_m). With the way straight on, ordinary steering; without the axis, a turn.
TEST(CueLogic, InADoorwayTheBodyLeavesOnItsAxisBeforeATurn)
{
  CueLogic c;
  const Cue k = fresh(c, atDoorway(standingAt(2.0, 0.0, 0.0, 90.0), 0.05), 0.0);
  EXPECT_EQ(k.instruction, Instruction::WALK_ON) << k.reason;
  EXPECT_NE(k.reason.find("out of it"), std::string::npos) << k.reason;

  CueLogic w;
  NavInput walk = atDoorway(walkerAt(1.8, 0.0, 1.0, 90.0), 0.2);
  const Cue s = fresh(w, walk, 0.0);
  EXPECT_EQ(s.instruction, Instruction::STOP) << s.reason;
  EXPECT_NE(s.reason.find("clear of its jambs"), std::string::npos) << s.reason;

  CueLogic straight;
  EXPECT_EQ(fresh(straight, atDoorway(walkerAt(1.8, 0.0, 1.0, 0.0), 0.2), 0.0).instruction, Instruction::WALK_ON);

  CueLogic old;
  NavInput no_axis = atDoorway(standingAt(2.0, 0.0, 0.0, 90.0), 0.05);
  no_axis.passage_axis = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(fresh(old, no_axis, 0.0).instruction, Instruction::TURN);

  // standing in it 0.2 m left of the middle (room 0.4 - 0.35 = 0.05 m, plus 5 cm): against the
  // jamb every step along the axis scrapes it; a short side-step right (0.35 s), then a wait
  // until it was carried out, then the next judgement
  CueLogic side;
  const Cue r = fresh(side, atDoorway(standingAt(2.0, 0.2, 0.0, 90.0), 0.05), 0.0);
  ASSERT_EQ(r.instruction, Instruction::SIDESTEP) << r.reason;
  EXPECT_GT(r.intensity[RIGHT_WAIST], 0.f);
  EXPECT_EQ(r.intensity[LEFT_WAIST], 0.f);
  EXPECT_EQ(r.pattern.on_10ms, 35);
  const Cue held = fresh(side, atDoorway(standingAt(2.0, 0.2, 0.0, 90.0), 0.05), 0.5);
  EXPECT_EQ(held.pattern.id, r.pattern.id);  // the same pattern: not played again
  // facing the other way (the way on is back out, -x), the middle lies to its left
  CueLogic back;
  const Cue b = fresh(back, atDoorway(standingAt(2.0, 0.2, 180.0, 90.0), 0.05), 0.0);
  ASSERT_EQ(b.instruction, Instruction::SIDESTEP) << b.reason;
  EXPECT_GT(b.intensity[LEFT_WAIST], 0.f);
}

// An aisle 1.0 m wide between shelves (obstacle cells beyond 0.5 m either side, all along it) that
// the planner reports as a passage just ahead of the walker, the way on straight along it. The
// walk has veered 15-25 deg left: told "straight on through it" (the doorway routine's walk, within
// 40 deg of the axis) the wearer drifted into the shelf (traced: no cue until the ray ahead met
// it). Ordinary steering asks a veer right; the sweep judges that veer's walk (not a straight one)
// and, with this wearer's reaction not yet learnt (1.2 s assumed), stops it before the shelf.
TEST(CueLogic, InAnAisleAVeeredWalkIsSteeredBack)
{
  auto g = std::make_shared<ObstacleGrid>(*doorwayGrid());
  std::fill(g->data.begin(), g->data.end(), 0);
  for (int iy = 0; iy < g->height; ++iy)
    for (int ix = 0; ix < g->width; ++ix)
      if (std::fabs(g->cellY(iy)) > 0.5)
        g->data[size_t(g->index(ix, iy))] = 100;
  for (const double v : { 0.5, 1.0 })
    for (const double dev : { 15.0, 25.0 })
    {
      NavInput in = atDoorway(walkerAt(1.0, 0.0, v), 0.2);
      in.grid = g;
      in.passage_width = 1.0;
      in.passage_x = 1.2;
      in.passage_heading = 0.0;
      in.head_yaw = in.walk_heading = in.heading = dev * kDeg;  // veered left; the way on is +x
      in.steer_heading = in.path_heading = 0.0;
      CueLogic c;
      const Cue k = fresh(c, in, 0.0);
      EXPECT_EQ(k.reason.find("straight on"), std::string::npos) << k.reason;
      if (k.instruction == Instruction::VEER)
      {
        EXPECT_GT(k.intensity[RIGHT_SHOULDER], 0.f) << k.reason;
        continue;
      }
      ASSERT_EQ(k.instruction, Instruction::STOP) << k.reason;
      int turn_deg = 0;  // the committed walk the sweep stopped carries the veer right
      const size_t at = k.reason.find("turn ");
      ASSERT_NE(at, std::string::npos) << k.reason;
      ASSERT_EQ(std::sscanf(k.reason.c_str() + at, "turn %d deg", &turn_deg), 1) << k.reason;
      EXPECT_LT(turn_deg, 0) << k.reason;
    }
}

// A wearer standing 0.85 m before a jamb on the slant (the approach to a narrow doorway), no room
// to step aside, the way on 17 deg to the right and blocked within a metre along it: before, "no
// room left or right: stop" held it there for good. Nothing lies inside its stop distance, so the
// guidance turns it; walking at 0.6 m/s the same spot lies inside its stop distance: stop.
TEST(CueLogic, StandingBoxedInIsTurnedNotHeld)
{
  NavInput in = standing(turn(-17.0));
  in.free_ahead = 0.85;
  in.free_left = in.free_right = 0.55;
  in.free_steer = 0.7;
  CueLogic c;
  const Cue k = fresh(c, in, 0.0);
  ASSERT_EQ(k.instruction, Instruction::TURN) << k.reason;
  EXPECT_GT(k.intensity[RIGHT_SHOULDER], 0.f);
  in.walking_speed = 0.6;
  CueLogic w;
  const Cue s = fresh(w, in, 0.0);
  EXPECT_EQ(s.mode, CueMode::ALERT) << s.reason;
  EXPECT_EQ(s.instruction, Instruction::STOP);
}

// A wearer standing 12 deg off the steering point (within stand_turn_deg: told to go before) with
// a shelf's corner beside the line of its walk: walking along its facing, a reaction late, the
// body's disc meets the corner 0.8 m on, before any stop can act (traced, gen_shop_4001 trial 0,
// t 57.1: 15 deg off, the corner 0.15 m beside the walk's line). It is turned to face the steering
// point, whose way sweeps clear. The same wearer without the shelf, or facing the steering point,
// is told to go.
TEST(CueLogic, StandingBesideAnEdgeIsTurnedBeforeTheGo)
{
  auto shelf = std::make_shared<ObstacleGrid>(*doorwayGrid());
  std::fill(shelf->data.begin(), shelf->data.end(), 0);
  for (int iy = 0; iy < shelf->height; ++iy)
    for (int ix = 0; ix < shelf->width; ++ix)
      if (shelf->cellX(ix) > 0.5 && shelf->cellX(ix) < 1.5 && shelf->cellY(iy) > 0.3 && shelf->cellY(iy) < 0.9)
        shelf->data[size_t(shelf->index(ix, iy))] = 100;
  auto open = std::make_shared<ObstacleGrid>(*shelf);
  std::fill(open->data.begin(), open->data.end(), 0);
  NavInput in = standingAt(0.0, 0.0, 12.0, 0.0);
  in.grid = shelf;
  CueLogic c;
  const Cue k = fresh(c, in, 0.0);
  ASSERT_EQ(k.instruction, Instruction::TURN) << k.reason;
  EXPECT_GT(k.intensity[RIGHT_SHOULDER], 0.f) << k.reason;
  EXPECT_NE(k.reason.find("edge"), std::string::npos) << k.reason;
  in.grid = open;
  CueLogic o;
  EXPECT_EQ(fresh(o, in, 0.0).instruction, Instruction::WALK_ON);
  NavInput facing = standingAt(0.0, 0.0, 12.0, 12.0);
  facing.grid = shelf;
  CueLogic f;
  EXPECT_EQ(fresh(f, facing, 0.0).instruction, Instruction::WALK_ON);
  CueParams off;
  off.go_clear_m = 0.0;
  CueLogic before(off);
  in.grid = shelf;
  EXPECT_EQ(fresh(before, in, 0.0).instruction, Instruction::WALK_ON);
}

// A wearer standing on course 0.2 m beside a shelf on its left (1 m free on its right): its walk
// off along the shelf, bent by its veering and a reaction-late correction, meets the shelf within
// a metre or two. It side-steps right first (a short waist buzz), is left to carry it out (the
// buzz and a reaction), and once 0.45 m clear is told to go. With go_side_m 0 it goes at once.
TEST(CueLogic, StandingAgainstAnEdgeStepsAwayBeforeTheGo)
{
  NavInput in = standing(turn(0.0));
  in.free_left = 0.2;
  in.free_right = 1.0;
  CueLogic c;
  const Cue k = fresh(c, in, 0.0);
  ASSERT_EQ(k.instruction, Instruction::SIDESTEP) << k.reason;
  EXPECT_GT(k.intensity[RIGHT_WAIST], 0.f) << k.reason;
  EXPECT_EQ(k.intensity[LEFT_WAIST], 0.f) << k.reason;
  in.free_left = 0.45;
  in.free_right = 0.75;
  EXPECT_EQ(fresh(c, in, 0.5).instruction, Instruction::SIDESTEP);  // still carrying it out
  EXPECT_EQ(fresh(c, in, 2.0).instruction, Instruction::WALK_ON);
  CueParams off;
  off.go_side_m = 0.0;
  CueLogic before(off);
  in.free_left = 0.2;
  in.free_right = 1.0;
  EXPECT_EQ(fresh(before, in, 0.0).instruction, Instruction::WALK_ON);
}

// A standing wearer turned 90 deg onto open floor is told to walk on 0.2 s after the turn's buzz
// ended (felt a reaction later, as its turn ends), not left standing while the turn is judged
// (a reaction and 0.3 s after the buzz). The same turn towards a wall 0.6 m along the new way,
// towards floor nobody has seen 0.6 m on (unknown cells: the camera has not looked that way), and
// every turn with turn_go_clear_m 0, waits to be judged. The wearer (reaction 0.6 s) turns at
// 90 deg/s from when the buzz has been felt and told from a veer until it has felt its end.
TEST(CueLogic, TurnOntoAClearWayIsFollowedByTheGoAtOnce)
{
  auto open = std::make_shared<ObstacleGrid>(*doorwayGrid());
  std::fill(open->data.begin(), open->data.end(), 0);
  auto walled = std::make_shared<ObstacleGrid>(*open);
  auto unseen = std::make_shared<ObstacleGrid>(*open);
  for (int iy = 0; iy < walled->height; ++iy)
    for (int ix = 0; ix < walled->width; ++ix)
      if (walled->cellY(iy) > 0.5 && walled->cellY(iy) < 0.7)
      {
        walled->data[size_t(walled->index(ix, iy))] = 100;
        unseen->data[size_t(unseen->index(ix, iy))] = -1;
      }
  struct Outcome
  {
    double buzz_end = 0.0, go_at = -1.0;
    bool turn_again = false;
    bool walk_held = true;  // from the go until the turn is judged: the walk-on held, no "turning"
    std::string first_reason;
  };
  auto run = [](const std::shared_ptr<ObstacleGrid>& g, const CueParams& p) {
    Outcome o;
    CueLogic c(p);
    NavInput in = standingAt(0.0, 0.0, 0.0, 90.0);
    in.grid = g;
    const Cue t0 = fresh(c, in, 0.0);
    EXPECT_EQ(t0.instruction, Instruction::TURN) << t0.reason;
    o.first_reason = t0.reason;
    o.buzz_end = 0.01 * t0.pattern.on_10ms;
    for (double t = 1.0 / 15; t < 5.0; t += 1.0 / 15)
    {
      const double yaw = std::clamp((t - 0.85) * 90.0, 0.0, (o.buzz_end + 0.6 - 0.85) * 90.0);
      in.head_yaw = in.walk_heading = in.heading = yaw * kDeg;
      const Cue k = fresh(c, in, t);
      if (k.instruction == Instruction::TURN && k.pattern.id != t0.pattern.id)
        o.turn_again = true;
      if (o.go_at >= 0.0 && t < o.buzz_end + 0.6 + 0.3 - 0.05 &&
          (k.mode != CueMode::IDLE || k.instruction != Instruction::WALK_ON))
        o.walk_held = false;
      if (k.instruction == Instruction::WALK_ON && o.go_at < 0.0)
        o.go_at = t;
    }
    return o;
  };
  const double judged = 0.6 + 0.3;  // the default reaction (alert_reaction_s) and 0.3 s
  const Outcome clear = run(open, CueParams());
  EXPECT_NE(clear.first_reason.find("then walk on"), std::string::npos) << clear.first_reason;
  EXPECT_FALSE(clear.turn_again);
  EXPECT_TRUE(clear.walk_held);
  EXPECT_GE(clear.go_at, clear.buzz_end + 0.2 - 1e-9);
  EXPECT_LT(clear.go_at, clear.buzz_end + 0.2 + 0.07);
  const Outcome wall = run(walled, CueParams());
  EXPECT_EQ(wall.first_reason.find("then walk on"), std::string::npos) << wall.first_reason;
  EXPECT_GE(wall.go_at, wall.buzz_end + judged - 1e-9);
  const Outcome unknown = run(unseen, CueParams());
  EXPECT_EQ(unknown.first_reason.find("then walk on"), std::string::npos) << unknown.first_reason;
  EXPECT_TRUE(unknown.go_at < 0.0 || unknown.go_at >= unknown.buzz_end + judged - 1e-9) << unknown.go_at;
  CueParams off;
  off.turn_go_clear_m = 0.0;
  const Outcome judged_first = run(open, off);
  EXPECT_GE(judged_first.go_at, judged_first.buzz_end + judged - 1e-9);
  EXPECT_FALSE(judged_first.turn_again);
}

// Issue 34: lost at a plain wall (vision corridor trial: the VO untrusted, the wearer standing nose
// to a bare wall, UNSURE for 27 s until the timeout). After lost_turn_after_s of NO_POSE on fresh
// images the vest asks a turn on the spot (a stop-and-turn buzz, open loop: a lost pose has no
// heading), then waits lost_turn_wait_s after each buzz for another, at most lost_turns_max. A
// stop-and-turn shortly before the loss is undone first; stale input never turns anyone.
TEST(CueLogic, LostAtABlankViewTheWearerIsTurnedToLookElsewhere)
{
  const CueParams p;
  struct Turn
  {
    double at, buzz;
    int side;  // + left shoulder
    uint8_t id;
  };
  auto lostFor = [&](CueLogic& c, double t0, double t1, bool fresh_input) {
    std::vector<Turn> turns;
    NavInput lost = status(NavStatus::NO_POSE);
    lost.message = "the visual odometry cannot trust its pose";
    for (double t = t0; t < t1; t += 1.0 / 15)
    {
      if (!fresh_input)
        lost.source_time = t - 1.0;  // the camera is dead: stale states
      const Cue k = fresh(c, lost, t);
      const bool playing = !turns.empty() && t < turns.back().at + turns.back().buzz - 1e-6;
      if (k.instruction == Instruction::TURN && (turns.empty() || turns.back().id != k.pattern.id))
      {
        EXPECT_EQ(k.mode, CueMode::GUIDANCE);
        EXPECT_EQ(k.level, 3);
        EXPECT_EQ(k.pattern.count, 1);
        EXPECT_EQ(k.intensity[LEFT_WAIST] + k.intensity[RIGHT_WAIST], 0.f);
        turns.push_back({ t, 0.01 * k.pattern.on_10ms, k.intensity[LEFT_SHOULDER] > 0.f ? 1 : -1, k.pattern.id });
      }
      else if (playing)
      {
        EXPECT_EQ(k.pattern.id, turns.back().id) << "the buzz is held while it plays, at " << t;
      }
      else
      {
        EXPECT_EQ(k.mode, CueMode::UNSURE) << k.reason;
      }
    }
    return turns;
  };
  {
    CueLogic c;
    const std::vector<Turn> turns = lostFor(c, 0.0, 30.0, true);
    ASSERT_EQ(turns.size(), size_t(p.lost_turns_max));
    EXPECT_NEAR(turns[0].at, p.lost_turn_after_s, 0.07);
    EXPECT_EQ(turns[0].side, 1);
    EXPECT_NEAR(turns[0].buzz, std::min(2.5, 180.0 / 90.0 + 0.25), 0.011);  // 90 deg/s before any turn is learnt
    EXPECT_NEAR(turns[1].at, turns[0].at + turns[0].buzz + p.lost_turn_wait_s, 0.07);
    EXPECT_NEAR(turns[1].buzz, 90.0 / 90.0 + 0.25, 0.011);
    EXPECT_EQ(turns[1].side, 1);
  }
  {
    // The pose back (OK) and lost again: a new loss, its turns counted afresh.
    CueLogic c;
    lostFor(c, 0.0, 4.0, true);
    fresh(c, standing(base()), 4.1);
    const std::vector<Turn> again = lostFor(c, 4.2, 8.0, true);
    ASSERT_EQ(again.size(), 1u);
    EXPECT_NEAR(again[0].at, 4.2 + p.lost_turn_after_s, 0.07);
  }
  {
    // The pose back and the map being rebuilt (NO_MAP), then SLAM not yet placing the goal (NO_POSE):
    // the same loss, its next turn lost_turn_wait_s after the first buzz, not a fresh 180.
    CueLogic c;
    const std::vector<Turn> first = lostFor(c, 0.0, 4.5, true);
    ASSERT_EQ(first.size(), 1u);
    for (double t = 4.5; t < 5.0; t += 1.0 / 15)
      EXPECT_EQ(fresh(c, status(NavStatus::NO_MAP), t).mode, CueMode::UNSURE);
    const std::vector<Turn> next = lostFor(c, 5.0, 14.0, true);
    ASSERT_EQ(next.size(), 1u);
    EXPECT_NEAR(next[0].at, first[0].at + first[0].buzz + p.lost_turn_wait_s, 0.07);
    EXPECT_NEAR(next[0].buzz, 90.0 / 90.0 + 0.25, 0.011);
  }
  {
    // Stale input (no camera): never a turn.
    CueLogic c;
    EXPECT_TRUE(lostFor(c, 0.0, 20.0, false).empty());
  }
  {
    CueParams off;
    off.lost_turn_after_s = 0.0;
    CueLogic c(off);
    EXPECT_TRUE(lostFor(c, 0.0, 20.0, true).empty());
  }
  {
    // A standing wearer turned left 75 deg (towards the wall), then lost: turned back right first.
    CueLogic c;
    NavInput in = standingAt(0.0, 0.0, -20.0, 55.0);
    const Cue t0 = fresh(c, in, 0.0);
    ASSERT_EQ(t0.instruction, Instruction::TURN) << t0.reason;
    for (double t = 1.0 / 15; t < 3.0; t += 1.0 / 15)
    {
      in.head_yaw = in.walk_heading = in.heading = std::clamp(-20.0 + (t - 0.6) * 90.0, -20.0, 55.0) * kDeg;
      fresh(c, in, t);
    }
    const std::vector<Turn> turns = lostFor(c, 3.0, 8.0, true);
    ASSERT_EQ(turns.size(), 1u);
    EXPECT_EQ(turns[0].side, -1);
    EXPECT_NEAR(turns[0].buzz, 75.0 / 90.0 + 0.25, 0.15);
  }
}

// Issue 33: a corner overtakes a veer being carried out. The walker is asked a slight veer (15 deg)
// for a steering point 20 deg off; the way on then swings to 55 deg while the wearer has not begun
// to turn. The next burst asks for the rest beyond the first (40: level 3, 45 deg) and adds to it
// (60 deg to go in all), and it comes only once it can be felt as a new pair, 0.95 s after the
// first: asked on every cycle, the bursts ran together into one long buzz on the shoulder, which
// the wearer took for a stop-and-turn (traced, plaza trial 0 of seed 11, t 11.9-12.3). The chain
// waits its settle time from its last burst.
TEST(CueLogic, AVeerOvertakenByACornerAddsABurstFeltAsANewPair)
{
  const CueParams p;
  CueLogic c;
  NavInput in = turn(20.0);
  in.walking_speed = 1.0;
  const Cue first = fresh(c, in, 0.0);
  ASSERT_EQ(first.instruction, Instruction::VEER) << first.reason;
  ASSERT_EQ(first.level, 1);
  in.steer_heading = in.path_heading = in.walk_heading + 55.0 * kDeg;
  std::vector<std::pair<double, Cue>> bursts;
  uint8_t id = first.pattern.id;
  double t = 1.0 / 15;
  for (; t < 4.0; t += 1.0 / 15)
  {
    const Cue k = fresh(c, in, t);
    ASSERT_EQ(k.mode, CueMode::GUIDANCE) << t << ": " << k.reason;
    ASSERT_NE(k.instruction, Instruction::TURN) << t << ": " << k.reason;
    if (k.pattern.id != id)
    {
      bursts.emplace_back(t, k);
      id = k.pattern.id;
    }
  }
  ASSERT_GE(bursts.size(), 1u);
  EXPECT_GE(bursts[0].first, 0.95 - 1e-9);
  EXPECT_LT(bursts[0].first, 0.95 + 1.0 / 15 + 1e-9);
  EXPECT_EQ(bursts[0].second.instruction, Instruction::VEER) << bursts[0].second.reason;
  EXPECT_EQ(bursts[0].second.level, 3) << bursts[0].second.reason;
  EXPECT_GT(bursts[0].second.intensity[LEFT_SHOULDER], 0.f);
  // the wearer never turned: the chain holds for settle_timeout_s after its last burst, no longer
  ASSERT_EQ(bursts.size(), 2u) << bursts[1].second.reason;
  EXPECT_NEAR(bursts[1].first, bursts[0].first + p.settle_timeout_s, 1.0 / 15 + 1e-9);
  // held in between, with all the chain asked still to go
  CueLogic h;
  NavInput again = turn(20.0);
  again.walking_speed = 1.0;
  fresh(h, again, 0.0);
  again.steer_heading = again.path_heading = again.walk_heading + 55.0 * kDeg;
  for (t = 1.0 / 15; t < 1.5; t += 1.0 / 15)
    fresh(h, again, t);
  const Cue held = fresh(h, again, t);
  EXPECT_NE(held.reason.find("veering (60 deg to go)"), std::string::npos) << held.reason;
}

// Issue 33: the body's facing is watched during the obstacle cues too. A standing wearer stopped
// by an obstacle turns 13 deg left in 0.25 s (a body turn: 52 deg/s) while the stop is held for
// 0.9 s; the way then clears. Seen only by the guidance, the turn came out as 13 deg over 0.93 s,
// slower than body_turn_rate_deg (the head's own scan), and the facing stayed 11 deg off, for good
// if the stops went on (traced, plaza trial 13 of seed 11: facing 179 deg, the body 160). It is
// known to face 13 deg left of the steering point, in a tight spot: it is turned back right.
TEST(CueLogic, TheFacingFollowsATurnMadeDuringAStop)
{
  NavInput in = standing(turn(0.0));
  in.free_left = in.free_right = 0.5;
  CueLogic c;
  ASSERT_EQ(fresh(c, in, 0.0).instruction, Instruction::WALK_ON);
  NavInput stopped = in;
  stopped.free_ahead = 0.3;
  stopped.free_left = stopped.free_right = 0.2;
  double t = 1.0 / 15;
  for (; t < 0.9; t += 1.0 / 15)
  {
    stopped.head_yaw = in.head_yaw + std::clamp((t - 0.3) / 0.25, 0.0, 1.0) * 13.0 * kDeg;
    const Cue k = fresh(c, stopped, t);
    ASSERT_EQ(k.mode, CueMode::ALERT) << t << ": " << k.reason;
  }
  in.head_yaw = stopped.head_yaw;
  const Cue k = fresh(c, in, t);
  EXPECT_EQ(k.instruction, Instruction::TURN) << k.reason;
  EXPECT_GT(k.intensity[RIGHT_SHOULDER], 0.f) << k.reason;
}

// Issue 33: a standing wearer boxed in (0.15 m before an obstacle, 0.05 m free to either side) with
// the way on 60 deg to its left is turned towards it on the spot, which sweeps a round body into
// nothing; the stop alone held it there for good (traced, plaza trial 13 of seed 11: 150 s on
// "obstacle ahead: stop" before a planter). Facing the way on (within stand_turn_deg), or
// walking, it is stopped.
TEST(CueLogic, BoxedInAndStandingIsTurnedTowardsTheWayOn)
{
  NavInput in = standing(turn(60.0));
  in.free_ahead = 0.15;
  in.free_left = in.free_right = 0.05;
  CueLogic c;
  const Cue k = fresh(c, in, 0.0);
  EXPECT_EQ(k.mode, CueMode::GUIDANCE) << k.reason;
  ASSERT_EQ(k.instruction, Instruction::TURN) << k.reason;
  EXPECT_GT(k.intensity[LEFT_SHOULDER], 0.f) << k.reason;
  NavInput ahead = in;
  ahead.steer_heading = ahead.path_heading = ahead.head_yaw + 10.0 * kDeg;
  CueLogic a;
  const Cue s = fresh(a, ahead, 0.0);
  EXPECT_EQ(s.mode, CueMode::ALERT) << s.reason;
  EXPECT_EQ(s.instruction, Instruction::STOP) << s.reason;
  NavInput walking = in;
  walking.walking_speed = 1.0;
  CueLogic w;
  EXPECT_EQ(fresh(w, walking, 0.0).mode, CueMode::ALERT);
}

// A wearer standing 0.8 m before a wall, the way on 70 deg to its right but the steering ray
// meeting a jamb (free along it 0.7 m: no "steering away"), each side-step opening the other side's
// room: it stepped left and right there for 40 s (traced, gen_home_3015 trial 4 of seed 11). After
// four side-steps within 20 s, both ways, with the waypoint no nearer, it is turned towards the way
// on instead; a wearer whose side-steps bring it nearer keeps stepping.
TEST(CueLogic, SideStepsLeftAndRightWithoutProgressGiveWayToATurn)
{
  for (bool progress : { false, true })
  {
    NavInput in = standing(turn(-70.0));
    in.free_ahead = 0.8;
    in.free_steer = 0.7;
    CueLogic c;
    int steps = 0, turns = 0;
    double t = 0.0;
    for (int k = 0; k < 6; ++k)
    {
      // the room left and right changes over after each step (the other side now freer)
      in.free_left = k % 2 == 0 ? 1.0 : 0.6;
      in.free_right = k % 2 == 0 ? 0.6 : 1.0;
      if (progress) in.waypoint_distance = 3.0 - 0.3 * k;
      Cue q;
      for (int i = 0; i < 20; ++i, t += 0.1)  // two seconds on this side
        q = fresh(c, in, t);
      steps += q.instruction == Instruction::SIDESTEP;
      turns += q.instruction == Instruction::TURN;
      if (q.instruction == Instruction::TURN)
      {
        EXPECT_GT(q.intensity[RIGHT_SHOULDER], 0.f) << q.reason;
      }
    }
    if (progress)
    {
      EXPECT_EQ(steps, 6);
      EXPECT_EQ(turns, 0);
    }
    else
    {
      EXPECT_EQ(steps, 4);  // the fifth is a turn
      EXPECT_GE(turns, 1);
    }
  }
}

TEST(CueLogic, AGoTimedToStopShortIsNotStoppedByItsOwnWalk)
{
  // A slow wearer (reaction 1.5 s) standing 1.55 m before an obstacle, no room to either side,
  // the path's next waypoint 1.08 m on: the go gets a stop timed to land short of the obstacle
  // (shortWalk). Counting the go as a walk on, its own reach (1.09 m) alerted on the next cycle,
  // the stop left a standing wearer, the go came back: stop and go in turn on every cycle, and
  // the wearer stood there for good (vision trial gen_lobby_2101 trial 1 of seed 21, traced).
  CueParams p;
  p.alert_reaction_s = 1.5;
  for (double ahead : { 1.2, 1.4, 1.55, 1.7, 1.9 })
  {
    CueLogic c(p);
    NavInput in = standing(turn(0.0));
    in.free_ahead = ahead;
    in.free_left = 0.25;
    in.free_right = 0.15;
    in.waypoint_distance = 1.08;
    std::vector<Instruction> seen;
    for (double t = 0.0; t < 1.4; t += 1.0 / 15.0)  // it has not reacted yet: still standing
      seen.push_back(fresh(c, in, t).instruction);
    int changes = 0;
    for (size_t i = 1; i < seen.size(); ++i)
      changes += seen[i] != seen[i - 1];
    EXPECT_EQ(seen.front(), Instruction::WALK_ON) << ahead << " m free";
    EXPECT_LE(changes, 1) << ahead << " m free: the cue changed " << changes << " times in 1.4 s";
  }
}

// With the vest's gyro a turn on the spot is judged as soon as the torso has stopped: a standing
// wearer is asked to turn 40 deg right; a reaction (0.6 s) after the buzz began its body turns at
// 90 deg/s, and stops a reaction after the buzz ended. The next cue is judged within 0.25 s of that
// stop (the raw rate quiet for 0.15 s, two frames); from the head's smoothed rate alone (no vest
// gyro) 0.35 s or more later. A fast sample while the buzz still plays (the vest's first samples,
// its bias not yet learnt; a piece of an earlier turn) does not end the wait: the turn is to come.
TEST(CueLogic, WithTheVestGyroATurnIsJudgedOnceTheTorsoStops)
{
  constexpr double kDt = 1.0 / 15.0;
  auto judgedAfterStop = [&](bool gyro, bool early_spike) {
    CueLogic c;
    double yaw = 0.3, asked_at = -1.0, buzz_s = 0.0, stop_at = -1.0;
    for (double t = 0.0; t < 6.0; t += kDt)
    {
      const double prev = yaw;
      if (asked_at >= 0.0 && t >= asked_at + 0.6 && t < asked_at + buzz_s + 0.6)
        yaw -= 90.0 * kDeg * kDt;
      if (asked_at >= 0.0 && stop_at < 0.0 && t >= asked_at + buzz_s + 0.6)
        stop_at = t;
      NavInput in = standing(turn(0.0, yaw));
      in.steer_heading = in.path_heading = 0.3 - 40.0 * kDeg;
      if (gyro)
        in.body_yaw_rate = (yaw - prev) / kDt;
      if (gyro && early_spike && asked_at >= 0.0 && t < asked_at + 0.2)
        in.body_yaw_rate = -20.0 * kDeg;
      const Cue k = fresh(c, in, t);
      if (asked_at < 0.0 && k.instruction == Instruction::TURN)
      {
        asked_at = t;
        buzz_s = 0.01 * k.pattern.on_10ms;
        continue;
      }
      if (asked_at >= 0.0 && k.reason.rfind("turning (", 0) != 0)
        return stop_at < 0.0 ? -1.0 : t - stop_at;  // < 0: judged before the torso stopped
    }
    return 99.0;
  };
  const double with_gyro = judgedAfterStop(true, false);
  EXPECT_GE(with_gyro, 0.0);
  EXPECT_LE(with_gyro, 0.25);
  EXPECT_GE(judgedAfterStop(false, false), 0.35);
  EXPECT_GE(judgedAfterStop(true, true), 0.0);
}
