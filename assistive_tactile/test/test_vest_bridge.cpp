// The bridge core on a pseudo-terminal with the simulated vest (the firmware's code on the other
// side). Real file descriptors and bytes; the clocks are simulated, so nothing depends on timing.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "assistive_tactile/sim_vest.h"
#include "assistive_tactile/vest_bridge.h"

using namespace assistive_tactile;

namespace
{
using Duty = std::array<uint8_t, 4>;

struct Rig
{
  std::string link = "/tmp/assistive_tactile_test_" + std::to_string(getpid()) + "_" +
                     ::testing::UnitTest::GetInstance()->current_test_info()->name();
  SimVest vest;
  std::unique_ptr<VestBridge> bridge;
  double t = 100.0;  // seconds, bridge clock

  explicit Rig(BridgeParams p = BridgeParams())
  {
    std::string err;
    EXPECT_TRUE(vest.open(link, ms(), &err)) << err;
    p.port = link;
    bridge.reset(new VestBridge(p));
    bridge->spinOnce(t);
    EXPECT_TRUE(bridge->stats().open) << bridge->stats().last_error;
    pump();
  }
  uint32_t ms() const { return static_cast<uint32_t>(t * 1000.0); }
  /// Let the vest take what the bridge wrote (waits for bytes only when some are expected).
  void pump(int wait_ms = 50)
  {
    vest.poll(wait_ms, ms());
    while (vest.poll(0, ms()) > 0)
    {
    }
  }
  void advance(double dt)
  {
    t += dt;
    bridge->spinOnce(t);
  }
};

Duty duty(const SimVest& v)
{
  return v.duty();
}

}  // namespace

TEST(VestBridge, ToDuty)
{
  EXPECT_EQ(VestBridge::toDuty(0.f), 0);
  EXPECT_EQ(VestBridge::toDuty(-1.f), 0);
  EXPECT_EQ(VestBridge::toDuty(std::nanf("")), 0);
  EXPECT_EQ(VestBridge::toDuty(1e-6f), 1);  // a cue that is on is never silently off
  EXPECT_EQ(VestBridge::toDuty(0.5f), 128);
  EXPECT_EQ(VestBridge::toDuty(1.f), 255);
  EXPECT_EQ(VestBridge::toDuty(7.f), 255);
}

TEST(VestBridge, RightMotorsForACueSequence)
{
  Rig rig;
  struct Row
  {
    std::array<float, 4> cue;
    Duty expect;
  };
  const std::vector<Row> rows = {
    { { 0.5f, 0, 0, 0 }, { 128, 0, 0, 0 } },      // turn left
    { { 0, 1.f, 0, 0 }, { 0, 255, 0, 0 } },       // turn right
    { { 0, 0, 0.25f, 0 }, { 0, 0, 64, 0 } },      // step left
    { { 0, 0, 0, 0.75f }, { 0, 0, 0, 191 } },     // step right
    { { 1.f, 1.f, 1.f, 1.f }, { 255, 255, 255, 255 } },  // alert
    { { 0, 0, 0, 0 }, { 0, 0, 0, 0 } },           // walk straight
  };
  uint64_t statuses = rig.bridge->stats().status_packets;
  for (const Row& r : rows)
  {
    rig.t += 0.05;
    ASSERT_TRUE(rig.bridge->setCue(r.cue, rig.t));
    rig.pump();
    EXPECT_EQ(duty(rig.vest), r.expect);
    rig.bridge->waitForInput(200);
    rig.bridge->spinOnce(rig.t);  // read the vest's STATUS
    EXPECT_GT(rig.bridge->stats().status_packets, statuses);
    statuses = rig.bridge->stats().status_packets;
    EXPECT_EQ(rig.bridge->stats().last_status.seq, rig.bridge->stats().seq);
    for (int i = 0; i < 4; ++i)
      EXPECT_EQ(rig.bridge->stats().last_status.intensity[i], r.expect[i]);
    EXPECT_TRUE(rig.bridge->linkUp(rig.t));
  }
  EXPECT_EQ(rig.bridge->stats().garbage_bytes, 0u);
  // What the wearer felt: right waist stayed on from "step right" into the alert.
  EXPECT_EQ(rig.vest.onsets(), (std::array<uint32_t, 4>{ { 2, 2, 2, 1 } }));
  const auto on = rig.vest.onSeconds(rig.ms());
  EXPECT_NEAR(on[0], 0.10, 1e-3);  // 50 ms turn left + 50 ms alert (simulated clock)
  EXPECT_NEAR(on[3], 0.10, 1e-3);  // step right straight into the alert
}

TEST(VestBridge, ResendsAtFixedRate)
{
  BridgeParams p;
  p.resend_hz = 20.0;
  p.stale_s = 10.0;
  p.max_source_age_s = 10.0;
  Rig rig(p);
  rig.bridge->setCue({ { 0.f, 0.6f, 0.f, 0.f } }, rig.t);
  const uint64_t sent0 = rig.bridge->stats().packets_sent;
  for (int i = 0; i < 100; ++i)  // 1 s in 10 ms housekeeping steps
  {
    rig.advance(0.01);
    rig.pump(0);
  }
  EXPECT_NEAR(static_cast<double>(rig.bridge->stats().packets_sent - sent0), 20.0, 1.0);
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 153, 0, 0 } }));
}

TEST(VestBridge, AllOffWithinStaleTimeWhenCuesStop)
{
  BridgeParams p;
  p.stale_s = 0.3;
  Rig rig(p);
  const double lead = rig.bridge->offLeadS();
  EXPECT_EQ(VEST_PACKET_SIZE, 21u);
  EXPECT_NEAR(lead, 21 * 10.0 / 57600 + 0.010, 1e-9);  // 21 bytes on the wire + wake-up margin
  const double t0 = rig.t;
  rig.bridge->setCue({ { 1.f, 0.f, 0.f, 0.f } }, t0);
  rig.pump();
  ASSERT_EQ(duty(rig.vest), (Duty{ { 255, 0, 0, 0 } }));
  EXPECT_NEAR(rig.bridge->cueExpiry(), t0 + 0.3 - lead, 1e-9);
  double off_at = -1.0;
  for (int i = 1; i <= 600 && off_at < 0.0; ++i)  // 1 ms steps
  {
    rig.advance(0.001);
    rig.pump(0);
    if (duty(rig.vest) == Duty{ { 0, 0, 0, 0 } })
      off_at = rig.t - t0;
    else
      EXPECT_TRUE(rig.bridge->stats().cue_stale == false) << rig.t - t0;
  }
  ASSERT_GT(off_at, 0.0);
  EXPECT_LE(off_at, 0.3 - lead + 0.001 + 1e-9);  // the first step at the expiry
  EXPECT_GT(off_at, 0.3 - lead - 1e-9);          // not before
  EXPECT_TRUE(rig.bridge->stats().cue_stale);
  EXPECT_EQ(rig.bridge->sentDuty(), (Duty{ { 0, 0, 0, 0 } }));
  // A new cue brings it back at once.
  rig.bridge->setCue({ { 0.f, 0.f, 1.f, 0.f } }, rig.t);
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 255, 0 } }));
}

// The stamp rules, one verdict per row (stale_s 0.3, max_source_age_s 0.5, lead 5 ms).
TEST(VestBridge, CueCheckTable)
{
  const BridgeParams p;
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  const Duty on{ { 0, 200, 0, 0 } }, off{ { 0, 0, 0, 0 } };
  struct Row
  {
    Duty duty;
    double stamp_age, source_age;
    CueCheck want;
  };
  const std::vector<Row> rows = {
    { on, 0.0, 0.05, CueCheck::FRESH },           { on, 0.29, 0.3, CueCheck::FRESH },
    { on, 0.296, 0.3, CueCheck::STALE },          // can no longer be felt before its all-off
    { on, 0.31, 0.3, CueCheck::STALE },           { on, 1.42, 1.5, CueCheck::STALE },  // the 1.4 s stall
    { on, 10.0, 10.1, CueCheck::STALE },          { on, inf, 0.1, CueCheck::STALE },   // unstamped
    { on, nan, 0.1, CueCheck::STALE },            { on, 0.05, 0.49, CueCheck::FRESH },
    { on, 0.05, 0.6, CueCheck::SOURCE_STALE },    { on, 0.05, nan, CueCheck::SOURCE_UNKNOWN },
    { on, -0.1, 0.0, CueCheck::FRESH },           // small clock offset: age taken as 0
    { on, -0.5, 0.0, CueCheck::FUTURE },          { on, 0.0, -0.5, CueCheck::FUTURE },
    { off, 0.05, nan, CueCheck::FRESH },          // all-off needs no source
    { off, 0.05, 5.0, CueCheck::FRESH },          { off, 0.5, 0.5, CueCheck::STALE },
  };
  for (const Row& r : rows)
  {
    CueAge a;
    a.stamp_age_s = r.stamp_age;
    a.source_age_s = r.source_age;
    EXPECT_EQ(cueCheckName(VestBridge::checkCue(r.duty, a, p, 0.005)), std::string(cueCheckName(r.want)))
        << "stamp age " << r.stamp_age << " source age " << r.source_age;
  }
  // An UNSURE cue (its opening pattern on both waist motors) says "cannot tell, stop" and guides
  // nothing: it is often decided because the camera image is old or missing, so it needs only a
  // fresh header.stamp, like an all-off.
  const Duty unsure{ { 0, 0, 255, 255 } };
  const std::vector<Row> unsure_rows = {
    { unsure, 0.05, nan, CueCheck::FRESH },   { unsure, 0.05, 5.0, CueCheck::FRESH },
    { unsure, 0.05, 0.1, CueCheck::FRESH },   { unsure, 0.31, 0.3, CueCheck::STALE },
    { unsure, inf, nan, CueCheck::STALE },    { unsure, -0.5, 0.0, CueCheck::FUTURE },
  };
  for (const Row& r : unsure_rows)
  {
    CueAge a;
    a.stamp_age_s = r.stamp_age;
    a.source_age_s = r.source_age;
    EXPECT_EQ(cueCheckName(VestBridge::checkCue(r.duty, a, p, 0.005, true)), std::string(cueCheckName(r.want)))
        << "unsure: stamp age " << r.stamp_age << " source age " << r.source_age;
  }
}

// An old-stamped cue is ignored (never drives); a fresh one is obeyed; all-off at
// header.stamp + stale_s (not arrival + stale_s); the source age shortens it further.
TEST(VestBridge, JudgesCuesByTheirStamps)
{
  BridgeParams p;
  p.stale_s = 0.3;
  p.max_source_age_s = 0.5;
  Rig rig(p);
  const double lead = rig.bridge->offLeadS();
  auto age = [](double stamp_age, double source_age) {
    CueAge a;
    a.stamp_age_s = stamp_age;
    a.source_age_s = source_age;
    return a;
  };
  // The bridge stalled 1.42 s: the cue it finds in its queue is old. Ignored, motors stay off.
  EXPECT_FALSE(rig.bridge->setCue({ { 0.f, 1.f, 0.f, 0.f } }, rig.t, age(1.42, 1.5)));
  EXPECT_EQ(rig.bridge->stats().cues_rejected, 1u);
  EXPECT_NE(rig.bridge->stats().last_rejection.find("stale"), std::string::npos);
  for (int i = 0; i < 30; ++i)
  {
    rig.advance(0.01);
    rig.pump(0);
    ASSERT_EQ(duty(rig.vest), (Duty{ { 0, 0, 0, 0 } })) << i;
  }
  // Stamped 10 s ago, or without a source stamp: ignored too.
  EXPECT_FALSE(rig.bridge->setCue({ { 0.f, 1.f, 0.f, 0.f } }, rig.t, age(10.0, 10.05)));
  EXPECT_FALSE(rig.bridge->setCue({ { 0.f, 1.f, 0.f, 0.f } }, rig.t, age(0.01, std::nan(""))));
  rig.pump(0);
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 0, 0 } }));
  EXPECT_EQ(rig.bridge->stats().cues_rejected, 3u);

  // Fresh (decided 0.1 s ago from an image 0.15 s old): obeyed at once, off 0.2 s later.
  double t0 = rig.t;
  ASSERT_TRUE(rig.bridge->setCue({ { 0.f, 1.f, 0.f, 0.f } }, t0, age(0.1, 0.15)));
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 255, 0, 0 } }));
  EXPECT_NEAR(rig.bridge->cueExpiry(), t0 + 0.2 - lead, 1e-9);
  // A stale cue in between changes nothing: the valid one keeps driving until its expiry.
  EXPECT_FALSE(rig.bridge->setCue({ { 1.f, 1.f, 1.f, 1.f } }, t0, age(0.4, 0.45)));
  double off_at = -1.0;
  for (int i = 1; i <= 400 && off_at < 0.0; ++i)
  {
    rig.advance(0.001);
    rig.pump(0);
    const Duty d = duty(rig.vest);
    if (d == Duty{ { 0, 0, 0, 0 } })
      off_at = rig.t - t0;
    else
      ASSERT_EQ(d, (Duty{ { 0, 255, 0, 0 } })) << rig.t - t0;
  }
  EXPECT_GT(off_at, 0.2 - lead - 1e-9);
  EXPECT_LE(off_at, 0.2 - lead + 0.001 + 1e-9);  // 0.3 s after its stamp, not after arrival

  // The camera image behind it is 0.45 s old: it drives only until the image is 0.5 s old.
  t0 = rig.t;
  ASSERT_TRUE(rig.bridge->setCue({ { 0.f, 0.f, 0.7f, 0.f } }, t0, age(0.0, 0.45)));
  EXPECT_NEAR(rig.bridge->cueExpiry(), t0 + 0.05 - lead, 1e-9);
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 179, 0 } }));
  rig.advance(0.05 - lead);
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 0, 0 } }));
  EXPECT_TRUE(rig.bridge->stats().cue_stale);
  EXPECT_EQ(rig.bridge->stats().cues_accepted, 2u);
}

// The housekeeping thread sends the all-off at the expiry itself (real clock).
TEST(VestBridge, RunnerSendsAllOffAtTheExpiry)
{
  const std::string link = "/tmp/assistive_tactile_test_runner_" + std::to_string(getpid());
  SimVest vest;
  std::string err;
  const double t_base = steadyNow();
  auto ms = [&] { return static_cast<uint32_t>((steadyNow() - t_base) * 1000.0); };
  ASSERT_TRUE(vest.open(link, ms(), &err)) << err;
  BridgeParams p;
  p.port = link;
  VestBridgeRunner runner(p);
  for (int i = 0; i < 100 && !runner.locked([](VestBridge& b) { return b.stats().open; }); ++i)
    vest.poll(10, ms());
  CueAge a;
  a.stamp_age_s = 0.02;  // published 20 ms ago
  a.source_age_s = 0.1;
  const double stamp = steadyNow() - a.stamp_age_s;
  ASSERT_EQ(runner.setCue({ { 1.f, 0.f, 0.f, 0.f } }, a), CueCheck::FRESH);
  double on_at = -1.0, off_at = -1.0;
  while (steadyNow() - stamp < 1.0 && off_at < 0.0)
  {
    vest.poll(2, ms());
    if (on_at < 0.0 && vest.duty()[0] > 0)
      on_at = steadyNow() - stamp;
    if (on_at >= 0.0 && vest.duty()[0] == 0)
      off_at = steadyNow() - stamp;
  }
  ASSERT_GE(on_at, 0.0);
  ASSERT_GT(off_at, 0.0);
  EXPECT_GT(off_at, 0.25);
  EXPECT_LE(off_at, 0.3 + 0.02) << "all-off " << off_at * 1000.0 << " ms after the cue's stamp";
  runner.stop();
}

TEST(VestBridge, FirmwareWatchdogWhenBridgeFallsSilent)
{
  BridgeParams p;
  p.stale_s = 10.0;  // a TTL beyond the watchdog: the watchdog is what ends it
  p.max_source_age_s = 10.0;
  Rig rig(p);
  rig.bridge->setCue({ { 1.f, 1.f, 0.f, 0.f } }, rig.t);
  rig.pump();
  ASSERT_EQ(duty(rig.vest), (Duty{ { 255, 255, 0, 0 } }));
  const uint32_t last = rig.ms();
  rig.vest.tick(last + 500);
  EXPECT_EQ(duty(rig.vest), (Duty{ { 255, 255, 0, 0 } }));
  rig.vest.tick(last + 501);  // e.g. the PC hung with the port open: the vest stops by itself
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 0, 0 } }));
}

// The bridge stalls right after sending a cue (the 1.4 s stall of the fault injection): the vest
// ends the cue at its deadline by itself, from the COMMAND's TTL.
TEST(VestBridge, VestEndsTheCueItselfWhenTheBridgeStalls)
{
  Rig rig;
  const double t0 = rig.t;
  CueAge a;
  a.stamp_age_s = 0.1;
  a.source_age_s = 0.15;  // deadline: t0 + 0.2 s
  ASSERT_TRUE(rig.bridge->setCue({ { 0.f, 1.f, 0.f, 0.f } }, t0, a));
  rig.pump();
  ASSERT_EQ(duty(rig.vest), (Duty{ { 0, 255, 0, 0 } }));
  const uint32_t ms0 = rig.ms();
  const uint16_t ttl = rig.vest.firmware().hold_ms;
  EXPECT_EQ(ttl, static_cast<uint16_t>(std::floor((0.2 - rig.bridge->wireS()) * 1000.0 - 1.0)));
  // No more spinOnce: the bridge is frozen. The vest's own clock runs on.
  rig.vest.tick(ms0 + ttl);
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 255, 0, 0 } }));
  rig.vest.tick(ms0 + ttl + 1);
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 0, 0 } }));
  EXPECT_LE(ttl + 1, 200);  // off by the cue's deadline, receipt counted from the write
  EXPECT_EQ(rig.vest.firmware().expiries, 1);
  EXPECT_EQ(rig.vest.firmware().timeouts, 0);
}

TEST(VestBridge, AllOffOnShutdown)
{
  Rig rig;
  rig.bridge->setCue({ { 0.f, 0.f, 0.5f, 0.5f } }, rig.t);
  rig.pump();
  ASSERT_EQ(duty(rig.vest), (Duty{ { 0, 0, 128, 128 } }));
  rig.bridge.reset();  // destructor = shutdown
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 0, 0 } }));
}

TEST(VestBridge, RecoversWhenThePortDisappearsAndComesBack)
{
  BridgeParams p;
  p.reopen_s = 1.0;
  p.stale_s = 100.0;
  p.max_source_age_s = 100.0;
  Rig rig(p);
  rig.bridge->setCue({ { 0.f, 1.f, 0.f, 0.f } }, rig.t);
  rig.pump();
  ASSERT_EQ(duty(rig.vest), (Duty{ { 0, 255, 0, 0 } }));

  rig.vest.close();  // USB unplugged: the device node vanishes
  rig.advance(0.01);
  EXPECT_FALSE(rig.bridge->stats().open);
  EXPECT_EQ(rig.bridge->stats().losses, 1u);
  EXPECT_FALSE(rig.bridge->stats().last_error.empty());
  EXPECT_FALSE(rig.bridge->setCue({ { 0.f, 0.f, 0.f, 1.f } }, rig.t));  // no crash, reported
  for (int i = 0; i < 150; ++i)  // 1.5 s with the port missing: retries fail quietly
    rig.advance(0.01);
  EXPECT_FALSE(rig.bridge->stats().open);
  EXPECT_NE(rig.bridge->stats().last_error.find("No such file"), std::string::npos)
      << rig.bridge->stats().last_error;

  std::string err;
  ASSERT_TRUE(rig.vest.open(rig.link, rig.ms(), &err)) << err;  // plugged back in
  for (int i = 0; i < 110 && !rig.bridge->stats().open; ++i)
    rig.advance(0.01);
  ASSERT_TRUE(rig.bridge->stats().open) << rig.bridge->stats().last_error;
  EXPECT_EQ(rig.bridge->stats().opens, 2u);
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 0, 255 } }));  // the latest cue, sent on reopen
  ASSERT_TRUE(rig.bridge->waitForInput(200));
  rig.bridge->spinOnce(rig.t);
  EXPECT_TRUE(rig.bridge->linkUp(rig.t));
}

TEST(VestBridge, SecondOpenerOfThePortFails)
{
  Rig rig;
  BridgeParams p;
  p.port = rig.link;
  VestBridge second(p);
  second.spinOnce(rig.t);
  EXPECT_FALSE(second.stats().open);
  EXPECT_NE(second.stats().last_error.find("in use by another process"), std::string::npos)
      << second.stats().last_error;
  // The first one is not disturbed; once it lets go, the port is free again.
  rig.bridge->setCue({ { 0.f, 0.f, 1.f, 0.f } }, rig.t);
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 255, 0 } }));
  rig.bridge.reset();
  second.spinOnce(rig.t + 10.0);
  EXPECT_TRUE(second.stats().open) << second.stats().last_error;
}

TEST(VestBridge, OtherProtocolVersionFromTheVestIsReported)
{
  Rig rig;
  // A STATUS of a protocol version we do not speak (valid CRC): not a STATUS for us, counted with
  // its version. (Version 3 became ours with RANGE / BUTTONS: the future one is 4.)
  const uint8_t raw[8] = { VEST_PROTOCOL_VERSION + 1, VEST_TYPE_STATUS, 1, 0, 0, 0, 0, 0 };
  uint8_t frame[VEST_PACKET_SIZE];
  const uint8_t len = vest_frame(raw, 8, frame);
  rig.bridge->waitForInput(200);  // the STATUS answering the bridge's first packet
  rig.advance(0.0);
  const uint64_t st = rig.bridge->stats().status_packets;
  ASSERT_TRUE(rig.vest.inject(frame, len));
  ASSERT_TRUE(rig.bridge->waitForInput(200));
  rig.advance(0.0);
  EXPECT_EQ(rig.bridge->stats().version_mismatches, 1u);
  EXPECT_EQ(rig.bridge->stats().vest_version, VEST_PROTOCOL_VERSION + 1);
  EXPECT_EQ(rig.bridge->stats().status_packets, st);
}

// ---- Protocol version 3: an old vest, the ranger, the buttons. ----
namespace
{
/// Runs bridge and vest side by side for `seconds` in 10 ms steps (both clocks simulated).
void run(Rig& rig, double seconds)
{
  for (double e = 0.0; e < seconds - 1e-9; e += 0.01)
  {
    rig.t += 0.01;
    rig.vest.poll(1, rig.ms());
    rig.bridge->waitForInput(1);
    rig.bridge->spinOnce(rig.t);
  }
}

/// The bridge alone for `seconds` (10 ms steps): the vest is not polled, so it sends nothing
/// (a silent sensor while the link stays up)
void runVestSilent(Rig& rig, double seconds)
{
  for (double e = 0.0; e < seconds - 1e-9; e += 0.01)
  {
    rig.t += 0.01;
    rig.bridge->spinOnce(rig.t);
  }
}
}  // namespace

// An old vest (protocol version 2 or 3: no pulse patterns) is refused: the bridge sends it only
// version-4 COMMANDs, which it never applies (it answers each with a STATUS of its own version),
// so its motors stay off whatever the cues say: the wearer feels silence = stop. Reflashed on a
// link that stayed open, it is driven again.
TEST(VestBridge, OldVestIsRefusedMotorsStayOff)
{
  for (const int old : { 3, 2 })
  {
    Rig rig;
    rig.vest.old_version = old;  // from now on the vest answers as that version's firmware did
    const uint64_t applied0 = rig.vest.commands();
    VestCue veer;
    veer.intensity = { { 0.7f, 0.f, 0.f, 0.f } };
    veer.pattern = vest_pattern_t{ 5, 15, 15, 2 };
    ASSERT_TRUE(rig.bridge->setCue(veer, rig.t, CueAge()));
    bool ever_on = false;
    for (int i = 0; i < 100; ++i)  // 1 s of cues at 10 Hz
    {
      if (i % 10 == 0)
      {
        VestCue steady;
        steady.intensity = { { 1.f, 1.f, 1.f, 1.f } };
        rig.bridge->setCue(i % 20 ? steady : veer, rig.t, CueAge());
      }
      run(rig, 0.01);
      ever_on = ever_on || duty(rig.vest) != Duty{ { 0, 0, 0, 0 } };
    }
    EXPECT_FALSE(ever_on) << "version " << old;
    EXPECT_EQ(rig.vest.commands(), applied0) << "version " << old;  // not one COMMAND applied
    EXPECT_EQ(rig.bridge->stats().vest_version, old);
    EXPECT_TRUE(rig.bridge->stats().vest_refused);
    EXPECT_GE(rig.bridge->stats().cues_refused, 9u);
    EXPECT_EQ(rig.bridge->sentDuty(), (Duty{ { 0, 0, 0, 0 } }));
    EXPECT_TRUE(rig.bridge->linkUp(rig.t));  // its replies prove the link (the diagnostics name it)
    EXPECT_EQ(rig.bridge->stats().version_mismatches, 0u);
    EXPECT_EQ(rig.bridge->stats().ranges, 0u);  // an old vest sends sensors to an old bridge only
    EXPECT_GT(rig.vest.firmware().parser.version_mismatch, 0);  // what the old vest saw: version 4

    // Reflashed (the port stayed open, e.g. a radio link): the next STATUS is version 4.
    rig.vest.old_version = 0;
    rig.bridge->setCue({ { 0.f, 0.f, 1.f, 0.f } }, rig.t);
    run(rig, 0.1);
    rig.bridge->setCue({ { 0.f, 0.f, 1.f, 0.f } }, rig.t);
    run(rig, 0.02);
    EXPECT_FALSE(rig.bridge->stats().vest_refused);
    EXPECT_EQ(rig.bridge->stats().vest_version, VEST_PROTOCOL_VERSION);
    EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 255, 0 } }));
  }
}

// ---- Protocol version 4: the cue's pulse pattern, timed by the vest. ----
namespace
{
const vest_pattern_t kVeer{ 5, 15, 15, 2 };  // veer burst: 150 ms on, 150 ms off, x2

VestCue veerCue(vest_pattern_t pattern = kVeer, float level = 0.7f)
{
  VestCue c;
  c.intensity = { { level, 0.f, 0.f, 0.f } };
  c.pattern = pattern;
  return c;
}

bool veerOn(long t_ms)
{
  return (t_ms >= 0 && t_ms < 150) || (t_ms >= 300 && t_ms < 450);
}

/// Bridge and vest side by side in 1 ms steps (simulated clocks); the cue logic's heartbeat
/// (`cue` every 100 ms, fresh stamps) until `cues_until_s`; returns the left shoulder's duty
/// per ms.
std::vector<uint8_t> runMs(Rig& rig, int ms, const VestCue& cue, int cues_until_ms)
{
  std::vector<uint8_t> out;
  for (int k = 0; k < ms; ++k)
  {
    if (k % 100 == 0 && k < cues_until_ms)
      rig.bridge->setCue(cue, rig.t, CueAge());
    rig.pump(0);
    out.push_back(duty(rig.vest)[0]);
    rig.advance(0.001);
  }
  return out;
}
}  // namespace

// The veer burst from the cue to the motors: on at 0-149 and 300-449 ms, off at 150-299 and from
// 450 ms, while the bridge re-sends it at 20 Hz and the cue logic repeats it at 10 Hz (same
// pattern: continued, never restarted). Then a new id restarts it.
TEST(VestBridge, PatternEndToEndDutyOverTime)
{
  Rig rig;
  const uint16_t starts0 = rig.vest.firmware().pattern_starts;  // the all-off on open: steady
  const std::vector<uint8_t> d = runMs(rig, 1500, veerCue(), 1500);
  for (int t = 0; t < 1500; ++t)
    ASSERT_EQ(d[static_cast<size_t>(t)], veerOn(t) ? 179 : 0) << "t = " << t << " ms";
  EXPECT_EQ(rig.vest.firmware().pattern_starts, starts0 + 1);
  EXPECT_EQ(rig.vest.onsets()[0], 2u);  // two pulses felt
  EXPECT_NEAR(rig.vest.onSeconds(rig.ms())[0], 0.300, 1e-9);
  EXPECT_GE(rig.bridge->stats().packets_sent, 30u);  // 20 Hz re-sends + the cues
  EXPECT_EQ(rig.bridge->stats().cues_accepted, 15u);
  // The vest reports the pattern it plays; its peak shows what was felt.
  rig.bridge->waitForInput(100);
  rig.advance(0.0);
  EXPECT_EQ(rig.bridge->stats().last_status.pattern.id, 5);
  EXPECT_EQ(rig.bridge->stats().last_status.intensity[0], 0);  // now: the burst is over
  EXPECT_EQ(rig.bridge->takeStatusPeak()[0], 179);
  EXPECT_EQ(rig.bridge->takeStatusPeak()[0], 0);

  // A new id (the next burst, level 3): starts again at once.
  const std::vector<uint8_t> e = runMs(rig, 700, veerCue(vest_pattern_t{ 6, 15, 15, 2 }, 1.f), 700);
  for (int t = 0; t < 700; ++t)
    ASSERT_EQ(e[static_cast<size_t>(t)], veerOn(t) ? 255 : 0) << "second burst, t = " << t << " ms";
  EXPECT_EQ(rig.vest.firmware().pattern_starts, starts0 + 2);
  EXPECT_EQ(rig.vest.onsets()[0], 4u);
}

// USB / radio jitter and lost packets do not change what the wearer feels: the COMMANDs reach
// the vest late and in bursts (bytes held back for up to 120 ms, cues 0-60 ms apart), the pulses
// still start and end on the vest's clock, exactly.
TEST(VestBridge, PatternUnchangedByLinkJitter)
{
  Rig rig;
  std::mt19937 rng(3);
  const uint16_t starts0 = rig.vest.firmware().pattern_starts;
  rig.bridge->setCue(veerCue(), rig.t, CueAge());
  rig.pump(0);  // the first COMMAND arrives: the pattern starts here
  const uint32_t start = rig.ms();
  std::vector<uint8_t> felt;
  int held = 0;
  for (int k = 0; k < 1000; ++k)
  {
    if (rng() % 40 == 0)
      rig.bridge->setCue(veerCue(), rig.t, CueAge());  // heartbeats at random moments
    if (held == 0 && rng() % 25 == 0)
      held = 20 + static_cast<int>(rng() % 100);  // the link stalls: bytes pile up
    if (held > 0)
    {
      --held;
      rig.vest.tick(rig.ms());  // the vest's loop runs on; nothing arrives
    }
    else
      rig.pump(0);
    felt.push_back(duty(rig.vest)[0]);
    rig.advance(0.001);
  }
  for (size_t t = 0; t < felt.size(); ++t)
    ASSERT_EQ(felt[t], veerOn(static_cast<long>(t)) ? 179 : 0) << "t = " << t << " ms after the start at " << start;
  EXPECT_EQ(rig.vest.firmware().pattern_starts, starts0 + 1);
  EXPECT_EQ(rig.vest.firmware().expiries + rig.vest.firmware().timeouts, 0);
}

// The cue stream pauses past stale_s (the bridge sends all-off) and comes back with the same
// pattern: the all-off carried the pattern, so the vest continues it (the second pulse) rather
// than replaying the burst from its start.
TEST(VestBridge, AllOffKeepsThePatternNoReplay)
{
  BridgeParams p;
  p.stale_s = 0.25;
  Rig rig(p);
  const uint16_t starts0 = rig.vest.firmware().pattern_starts;
  std::vector<uint8_t> d = runMs(rig, 260, veerCue(), 1);  // one cue, then none
  for (int t = 0; t < 260; ++t)
  {
    const bool on = veerOn(t) && t < 250 - 14;  // all-off lands 14 ms early (wire time + margin)
    if (t < 230)
    {
      ASSERT_EQ(d[static_cast<size_t>(t)], on ? 179 : 0) << t;
    }
  }
  EXPECT_TRUE(rig.bridge->stats().cue_stale);
  const std::vector<uint8_t> e = runMs(rig, 400, veerCue(), 400);  // back at 260 ms: same pattern
  for (int t = 0; t < 400; ++t)
    ASSERT_EQ(e[static_cast<size_t>(t)], veerOn(260 + t) ? 179 : 0) << "t = " << 260 + t << " ms";
  EXPECT_EQ(rig.vest.firmware().pattern_starts, starts0 + 1);
  EXPECT_EQ(rig.vest.onsets()[0], 2u);
}

// UNSURE begins with its own pattern (three 100 ms pulses on both waist motors). It is often
// decided because the camera image is old or missing; the bridge still plays it (it guides
// nothing), for as long as its header.stamp is fresh, then the vest is silent (= stop).
TEST(VestBridge, UnsureOpeningPatternPlayedWithoutCameraTime)
{
  Rig rig;
  VestCue unsure;
  unsure.intensity = { { 0.f, 0.f, 1.f, 1.f } };
  unsure.pattern = vest_pattern_t{ 9, 10, 10, 3 };
  unsure.unsure = true;
  for (const double source_age : { std::nan(""), 2.0 })
  {
    CueAge a;
    a.stamp_age_s = 0.0;
    a.source_age_s = source_age;
    unsure.pattern.id = static_cast<uint8_t>(unsure.pattern.id + 1);
    std::vector<uint8_t> felt;
    for (int k = 0; k < 800; ++k)
    {
      if (k % 100 == 0)
      {
        ASSERT_TRUE(rig.bridge->setCue(unsure, rig.t, a)) << rig.bridge->stats().last_rejection;
      }
      rig.pump(0);
      felt.push_back(duty(rig.vest)[2] > 0 && duty(rig.vest)[3] > 0 ? 1 : duty(rig.vest)[2] | duty(rig.vest)[3]);
      rig.advance(0.001);
    }
    for (int t = 0; t < 800; ++t)
      ASSERT_EQ(felt[static_cast<size_t>(t)], (t < 500 && t % 200 < 100) ? 1 : 0) << "source age " << source_age << ", t = " << t;
    EXPECT_FALSE(rig.bridge->stats().cue_stale);
  }
  // The same without the UNSURE mark (a guiding cue) and no camera time: ignored.
  unsure.unsure = false;
  CueAge a;
  a.source_age_s = std::nan("");
  EXPECT_FALSE(rig.bridge->setCue(unsure, rig.t, a));
}

// A vest that gets a burst only late (the port was reopened, the vest restarted) while the cue
// logic still repeats it: the bridge sends it with zero duties once it is over by the bridge's
// clock (+ stale_s), so nothing old is replayed.
TEST(VestBridge, ReopenedVestDoesNotReplayAnOldBurst)
{
  BridgeParams p;
  p.reopen_s = 0.2;
  Rig rig(p);
  std::vector<uint8_t> d = runMs(rig, 100, veerCue(), 100);  // the first pulse starts
  EXPECT_EQ(d[50], 179);
  rig.vest.close();  // unplugged in the first pulse
  runMs(rig, 10, veerCue(), 10);
  EXPECT_FALSE(rig.bridge->stats().open);
  std::string err;
  ASSERT_TRUE(rig.vest.open(rig.link, rig.ms(), &err)) << err;  // a fresh vest: no pattern yet
  // The cue logic still repeats the same burst (it waits for the wearer to carry it out).
  const std::vector<uint8_t> e = runMs(rig, 1500, veerCue(), 1500);
  ASSERT_TRUE(rig.bridge->stats().open);
  EXPECT_EQ(rig.bridge->stats().opens, 2u);
  for (size_t t = 0; t < e.size(); ++t)
    ASSERT_EQ(e[t], 0) << "replayed at " << t << " ms after the re-plug";
  EXPECT_EQ(rig.vest.firmware().pattern_starts, 1);  // the fresh vest got only that pattern...
  EXPECT_EQ(rig.vest.firmware().pattern.id, 5);      // ...with zero duties
  EXPECT_EQ(rig.bridge->stats().patterns_ended, 1u);
  // A new burst is felt at once.
  const std::vector<uint8_t> f = runMs(rig, 500, veerCue(vest_pattern_t{ 6, 15, 15, 2 }), 500);
  for (int t = 0; t < 500; ++t)
    ASSERT_EQ(f[static_cast<size_t>(t)], veerOn(t) ? 179 : 0) << t;
}

// The same on the real clock with the housekeeping thread (VestBridgeRunner) and the simulated
// vest on its own millisecond clock: the motor's on-time measured by the vest shows two pulses
// of 150 ms, 150 ms apart, while the cue is repeated at 10 Hz.
TEST(VestBridge, RunnerPulsesOnTheRealClock)
{
  const std::string link = "/tmp/assistive_tactile_test_pulses_" + std::to_string(getpid());
  SimVest vest;
  std::string err;
  const double t_base = steadyNow();
  vest.clock = [t_base] { return static_cast<uint32_t>((steadyNow() - t_base) * 1000.0); };
  ASSERT_TRUE(vest.open(link, vest.clock(), &err)) << err;
  std::vector<std::pair<uint32_t, bool>> edges;  // vest clock, on
  vest.on_change = [&](uint32_t t, const std::string&) { edges.emplace_back(t, vest.duty()[0] > 0); };
  BridgeParams p;
  p.port = link;
  VestBridgeRunner runner(p);
  for (int i = 0; i < 100 && !runner.locked([](VestBridge& b) { return b.stats().open; }); ++i)
    vest.poll(10, 0);
  CueAge fresh;
  fresh.source_age_s = 0.05;
  double next = steadyNow();
  const double end = steadyNow() + 1.0;
  double last_poll = steadyNow(), max_poll_gap_ms = 0.0;
  while (steadyNow() < end)
  {
    if (steadyNow() >= next)
    {
      ASSERT_EQ(runner.setCue(veerCue(), fresh), CueCheck::FRESH);
      next += 0.1;
    }
    vest.poll(5, 0);
    max_poll_gap_ms = std::max(max_poll_gap_ms, (steadyNow() - last_poll) * 1000.0);
    last_poll = steadyNow();
  }
  runner.stop();
  std::vector<std::pair<uint32_t, bool>> on_edges;
  for (const auto& e : edges)
    if (on_edges.empty() || on_edges.back().second != e.second)
      on_edges.push_back(e);
  // on, off, on, off (then the all-off of stop() changes nothing)
  ASSERT_GE(on_edges.size(), 4u);
  ASSERT_TRUE(on_edges[0].second);
  const long p1 = static_cast<long>(on_edges[1].first - on_edges[0].first);
  const long gap = static_cast<long>(on_edges[2].first - on_edges[1].first);
  const long p2 = static_cast<long>(on_edges[3].first - on_edges[2].first);
  // Exact on the vest's clock but for the simulated vest's own wake-up: an edge is seen at the
  // first poll after it, so each duration is off by at most the longest gap between polls (a
  // loaded machine gave 75 ms once; a pattern restarted by the re-sends would never turn off).
  const double tol = 10.0 + max_poll_gap_ms;
  EXPECT_NEAR(p1, 150, tol);
  EXPECT_NEAR(gap, 150, tol);
  EXPECT_NEAR(p2, 150, tol);
  EXPECT_NEAR(static_cast<double>(on_edges[3].first - on_edges[0].first), 450, tol);
  EXPECT_EQ(on_edges.size(), 4u);
  EXPECT_LE(vest.firmware().pattern_starts, 2);  // the all-off on open (steady), the burst
}

// ---- Protocol version 5: the vest's IMU; a version-4 vest. ----
// A version-4 vest (pulse patterns, no IMU) is driven in version 4: it answers the first
// version-5 COMMAND with a version-4 STATUS, and from then on the same bytes go out as version 4,
// which it obeys (pulses and all). It sends RANGE / BUTTONS, no IMU. Every 2 s the state also goes
// out once in version 5 (the vest answers it and applies nothing); reflashed on a link that stayed
// open, the vest answers that probe in version 5 and is driven in it, IMU and all.
TEST(VestBridge, VersionFourVestDrivenInVersionFourWithoutImu)
{
  Rig rig;
  rig.vest.old_version = 4;
  run(rig, 0.1);  // its version-4 reply to the bridge's version-5 COMMAND
  EXPECT_EQ(rig.bridge->stats().command_version, 4);
  EXPECT_FALSE(rig.bridge->stats().vest_refused);
  const uint64_t applied0 = rig.vest.commands();
  const uint32_t start_ms = rig.ms();
  rig.bridge->setCue(veerCue(), rig.t, CueAge());
  std::vector<std::pair<uint32_t, uint8_t>> left;  // (ms since the cue, duty)
  for (int i = 0; i < 300; ++i)  // 3 s, the cue logic's heartbeat at 10 Hz
  {
    if (i % 10 == 0)
      rig.bridge->setCue(veerCue(), rig.t, CueAge());
    run(rig, 0.01);
    left.emplace_back(rig.ms() - start_ms, duty(rig.vest)[0]);
  }
  // The veer burst as the vest times it: on at 0-149 and 300-449 ms, then off, never replayed.
  int on_ms = 0;
  for (const auto& l : left)
  {
    if (l.first >= 20 && l.first < 140)
    {
      EXPECT_EQ(l.second, VestBridge::toDuty(0.7f)) << l.first;
    }
    on_ms += l.second > 0 ? 10 : 0;
    if (l.first >= 470)
    {
      EXPECT_EQ(l.second, 0) << l.first;
    }
  }
  EXPECT_NEAR(on_ms, 300, 20);
  EXPECT_GT(rig.vest.commands(), applied0 + 50);  // 20 Hz for 3 s, in version 4
  const LinkStats& s = rig.bridge->stats();
  EXPECT_EQ(s.command_version, 4);
  EXPECT_EQ(s.vest_version, 4);
  EXPECT_FALSE(s.vest_refused);
  EXPECT_GE(s.probes_sent, 1u);
  EXPECT_LE(s.probes_sent, 2u);  // one per 2 s
  EXPECT_GE(rig.vest.firmware().parser.version_mismatch, 1);  // what it saw of them
  EXPECT_GT(s.ranges, 0u);
  EXPECT_EQ(s.imu_packets, 0u);
  EXPECT_FALSE(rig.bridge->vestHasImu());
  EXPECT_FALSE(rig.bridge->imuSilent(rig.t));  // no IMU to miss

  // Reflashed: within a probe's period it answers in version 5 and sends its IMU.
  rig.vest.old_version = 0;
  run(rig, 2.1);
  EXPECT_EQ(rig.bridge->stats().command_version, VEST_PROTOCOL_VERSION);
  EXPECT_EQ(rig.bridge->stats().vest_version, VEST_PROTOCOL_VERSION);
  const uint64_t probes = rig.bridge->stats().probes_sent;
  run(rig, 1.0);
  EXPECT_GT(rig.bridge->stats().imu_packets, 40u);
  EXPECT_EQ(rig.bridge->stats().probes_sent, probes);  // none while it speaks ours
}

// A vest of ours answers each COMMAND in the COMMAND's version: the probe's answer (in ours) can
// arrive before the answer to a version-4 COMMAND the bridge sent after the probe. That older
// answer must not put the bridge back to version 4 (it did, in the rostest, now and then).
TEST(VestBridge, ProbeAnswerNotUndoneByAnswersStillOnTheWire)
{
  Rig rig;
  rig.vest.old_version = 4;
  run(rig, 0.1);
  ASSERT_EQ(rig.bridge->stats().command_version, 4);
  rig.bridge->setCue(veerCue(), rig.t, CueAge());
  run(rig, 0.5);
  rig.vest.old_version = 0;  // reflashed
  const uint64_t probes = rig.bridge->stats().probes_sent;
  for (int i = 0; i < 300 && rig.bridge->stats().probes_sent == probes; ++i)
    rig.advance(0.01);  // the bridge alone: the vest reads nothing yet
  ASSERT_EQ(rig.bridge->stats().probes_sent, probes + 1);
  rig.advance(0.06);  // one more version-4 COMMAND after the probe
  rig.pump();         // the vest answers: ..., 4, 5 (the probe), 4
  rig.bridge->waitForInput(50);
  rig.advance(0.01);
  EXPECT_EQ(rig.bridge->stats().command_version, VEST_PROTOCOL_VERSION);
  run(rig, 1.0);
  EXPECT_EQ(rig.bridge->stats().command_version, VEST_PROTOCOL_VERSION);
  EXPECT_EQ(rig.bridge->stats().probes_sent, probes + 1);
  EXPECT_GT(rig.bridge->stats().imu_packets, 40u);
  // a vest flashed back to version 4 on the open link: driven in 4 again (its answers to ours)
  rig.vest.old_version = 4;
  run(rig, 0.2);
  EXPECT_EQ(rig.bridge->stats().command_version, 4);
}

// The IMU's windows: every 20 ms of the vest's clock, the mean rate and specific force in SI
// units, on the bridge's clock at the vest's spacing; a missing sensor is reported and measures
// nothing; a silent IMU is told.
TEST(VestBridge, ImuWindowsOnTheVestClock)
{
  Rig rig;
  rig.vest.setImu({ { 0.0, -0.25, 0.5 } }, { { 0.3, 0.0, 9.80665 } });
  run(rig, 0.2);
  std::vector<ImuEvent> got;
  rig.bridge->takeImu(got);
  const double t0 = rig.t;
  run(rig, 2.0);
  rig.bridge->takeImu(got);
  ASSERT_GE(got.size(), 99u);
  ASSERT_LE(got.size(), 101u);
  EXPECT_TRUE(rig.bridge->vestHasImu());
  double turn = 0.0;
  for (size_t i = 0; i < got.size(); ++i)
  {
    EXPECT_TRUE(got[i].ok);
    EXPECT_DOUBLE_EQ(got[i].rate[2], 0.5);
    EXPECT_DOUBLE_EQ(got[i].rate[1], -0.25);
    EXPECT_DOUBLE_EQ(got[i].accel[0], 0.3);
    EXPECT_DOUBLE_EQ(got[i].accel[2], 9.807);
    EXPECT_LE(got[i].time, rig.t);
    if (i > 0)
    {
      EXPECT_NEAR(got[i].time - got[i - 1].time, 0.020, 0.001) << i;
      turn += got[i].rate[2] * (got[i].time - got[i - 1].time);
    }
  }
  EXPECT_NEAR(got.back().time - got.front().time, 2.0, 0.03);
  EXPECT_NEAR(turn, 0.5 * (got.back().time - got.front().time), 1e-3);
  EXPECT_GT(got.front().time, t0 - 0.03);
  EXPECT_EQ(rig.bridge->stats().imu_lost, 0u);
  EXPECT_EQ(rig.bridge->stats().imu_sensor_missing, 0u);
  EXPECT_FALSE(rig.bridge->imuSilent(rig.t));
  // Unplugged: SENSOR_MISSING windows, no measurement.
  rig.vest.setImuMissing(true);
  run(rig, 0.2);
  rig.bridge->takeImu(got);
  ASSERT_FALSE(got.empty());
  EXPECT_FALSE(got.back().ok);
  EXPECT_EQ(got.back().rate[2], 0.0);
  EXPECT_GT(rig.bridge->stats().imu_sensor_missing, 0u);
  EXPECT_EQ(rig.bridge->stats().last_imu_status, VEST_IMU_SENSOR_MISSING);
  // Silent (no IMU packet for imu_timeout_s while the link is up): told.
  rig.vest.setImuMissing(false);
  run(rig, 0.1);
  runVestSilent(rig, 0.6);
  EXPECT_TRUE(rig.bridge->linkUp(rig.t));
  EXPECT_TRUE(rig.bridge->imuSilent(rig.t));
}

// The vest's 16-bit millisecond clock onto ours: through the link's jitter (2-12 ms of delay),
// the windows keep the vest's spacing and sit at the smallest delay; a vest clock 0.5 % slow
// (a ceramic resonator) is followed; the 65.536 s wrap is seamless; a restarted vest is taken
// afresh.
TEST(VestClock, JitterDriftWrapAndRestart)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> delay(0.002, 0.012);
  for (const double rate : { 1.0, 0.995, 1.005 })
  {
    VestClock c;
    double worst_gap = 0.0, worst_lag = 0.0, prev = -1.0;
    const double start = 1000.0;
    for (int k = 0; k < 20000; ++k)  // 400 s: six wraps of the 16-bit clock
    {
      const double truth = start + 0.02 * k;
      const uint16_t t_ms = static_cast<uint16_t>(static_cast<uint64_t>(std::llround(60000.0 + 20.0 * k * rate)) & 0xFFFF);
      const double got = c.map(t_ms, truth + delay(rng));
      if (k > 50)
      {
        worst_gap = std::max(worst_gap, std::abs((got - prev) - 0.02 * rate));
        worst_lag = std::max(worst_lag, std::abs(got - (truth + 0.002)));
      }
      prev = got;
    }
    // a window's length: the vest's, within 8 ms (the least-delay estimate steps down by the leak
    // it gathered since the last fast packet; the turn, a sum over windows, keeps only the ends')
    EXPECT_LT(worst_gap, 0.008) << rate;
    EXPECT_LT(worst_lag, 0.010) << rate;  // on our clock within 10 ms of the truth + the least delay
    EXPECT_EQ(c.resets(), 0u) << rate;
  }
  VestClock c;
  EXPECT_DOUBLE_EQ(c.map(100, 50.0), 50.0);
  EXPECT_NEAR(c.map(120, 50.025), 50.02, 5e-4);  // 5 ms late: the vest's spacing (+ the leak)
  const double before = c.map(140, 50.041);
  EXPECT_NEAR(before, 50.04, 5e-4);
  // A restarted vest: its clock starts again near 0 (far ahead modulo 2^16): afresh.
  const double after = c.map(3, 50.061);
  EXPECT_EQ(c.resets(), 1u);
  EXPECT_DOUBLE_EQ(after, 50.061);
}

TEST(VestBridge, RangerReadingsPublishedBadOnesRejected)
{
  Rig rig;
  std::vector<RangeEvent> got;
  rig.vest.setRange(1.5);
  run(rig, 0.5);
  rig.bridge->takeRanges(got);
  ASSERT_GE(got.size(), 5u);
  for (const RangeEvent& e : got) EXPECT_NEAR(e.range_m, 1.5, 0.0011);
  EXPECT_TRUE(rig.bridge->vestHasSensors());
  EXPECT_FALSE(rig.bridge->rangerSilent(rig.t));
  // Nothing within range: +inf (REP 117), not a distance.
  rig.vest.setRange(std::numeric_limits<double>::infinity());
  run(rig, 0.3);
  rig.bridge->takeRanges(got);
  ASSERT_FALSE(got.empty());
  EXPECT_TRUE(std::isinf(got.back().range_m));
  // Out of the sensor's limits (0.2 - 4 m): dropped, counted.
  const uint64_t ool = rig.bridge->stats().ranges_out_of_limits;
  rig.vest.setRange(0.1);
  run(rig, 0.3);
  rig.bridge->takeRanges(got);
  for (const RangeEvent& e : got) EXPECT_FALSE(e.range_m < 0.2) << e.range_m;
  EXPECT_GT(rig.bridge->stats().ranges_out_of_limits, ool);
  // Sensor unplugged: reported, nothing published.
  rig.vest.setRange(1.0);
  rig.vest.setSensorMissing(true);
  run(rig, 0.3);
  rig.bridge->takeRanges(got);
  run(rig, 0.3);
  rig.bridge->takeRanges(got);
  EXPECT_TRUE(got.empty());
  EXPECT_GT(rig.bridge->stats().ranges_sensor_missing, 0u);
  EXPECT_EQ(rig.bridge->stats().last_range_status, VEST_RANGE_SENSOR_MISSING);
  // A RANGE with a bad checksum: rejected, not published.
  rig.vest.setSensorMissing(false);
  run(rig, 0.3);
  rig.bridge->takeRanges(got);
  const vest_range_t r{ 99, VEST_RANGE_OK, 2500, 3 };
  uint8_t frame[VEST_RANGE_PACKET_SIZE];
  vest_encode_range(&r, frame);
  frame[6] ^= 0x10;
  const uint64_t rejected = rig.bridge->stats().rejected_packets;
  ASSERT_TRUE(rig.vest.inject(frame, sizeof(frame)));
  ASSERT_TRUE(rig.bridge->waitForInput(200));
  rig.bridge->spinOnce(rig.t);
  rig.bridge->takeRanges(got);
  EXPECT_EQ(rig.bridge->stats().rejected_packets, rejected + 1);
  for (const RangeEvent& e : got) EXPECT_NEAR(e.range_m, 1.0, 0.0011);
  // A silent ranger (no RANGE for sonar_timeout_s while the link is up): reported.
  runVestSilent(rig, 0.7);
  EXPECT_TRUE(rig.bridge->linkUp(rig.t));
  EXPECT_TRUE(rig.bridge->rangerSilent(rig.t));
}

TEST(VestBridge, ButtonPressesReportedOnce)
{
  Rig rig;
  std::vector<ButtonEvent> got;
  run(rig, 0.2);
  rig.vest.press(VEST_BUTTON_A, 150, rig.ms());
  run(rig, 0.5);
  rig.vest.press(VEST_BUTTON_B, 1500, rig.ms());
  run(rig, 2.5);  // includes heartbeats: they report nothing new
  rig.bridge->takeButtons(got);
  int short_a = 0, long_a = 0, short_b = 0, long_b = 0, b_held = 0;
  for (const ButtonEvent& e : got)
  {
    short_a += e.short_a;
    long_a += e.long_a;
    short_b += e.short_b;
    long_b += e.long_b;
    b_held += (e.held & 2) ? 1 : 0;
  }
  EXPECT_EQ(short_a, 1);
  EXPECT_EQ(long_a, 0);
  EXPECT_EQ(short_b, 0);
  EXPECT_EQ(long_b, 1);
  EXPECT_GE(b_held, 1);
  EXPECT_EQ(rig.bridge->stats().button_presses, 2u);
  EXPECT_EQ(got.back().held, 0);
}

namespace
{
int g_chained = 0;
void chainedHandler(int)
{
  g_chained = 1;
}

/// Forks a process that drives the vest through a bridge with the fail-safe handlers installed
/// (after `old` as the previous handler), sends it `sig`, and returns how it ended; *off_ms =
/// time from the signal to all motors off at the vest (-1 if never).
int signalChild(Rig& rig, int sig, void (*old)(int), double* off_ms)
{
  rig.bridge.reset();  // the child opens the port (exclusive)
  rig.pump();
  int ready[2];
  EXPECT_EQ(pipe(ready), 0);
  const pid_t pid = fork();
  if (pid == 0)
  {
    if (old)
      signal(sig, old);
    BridgeParams p;
    p.port = rig.link;
    p.stale_s = 100.0;
    p.max_source_age_s = 100.0;
    VestBridge b(p);
    b.spinOnce(1.0);
    installAllOffSignalHandlers();
    b.setCue({ { 1.f, 1.f, 1.f, 1.f } }, 1.0);
    if (::write(ready[1], "x", 1) != 1)
      _exit(3);
    for (int i = 0; i < 500 && !g_chained; ++i)
    {
      b.spinOnce(1.0 + i * 0.01);  // keeps re-sending the cue until the signal
      ::usleep(10000);
    }
    b.spinOnce(100.0);
    _exit(g_chained && allOffSignalReceived() ? 7 : 4);
  }
  char c;
  EXPECT_EQ(::read(ready[0], &c, 1), 1);
  ::close(ready[0]);
  ::close(ready[1]);
  for (int i = 0; i < 100 && rig.vest.duty() != Duty{ { 255, 255, 255, 255 } }; ++i)
    rig.vest.poll(10, rig.ms());
  EXPECT_EQ(rig.vest.duty(), (Duty{ { 255, 255, 255, 255 } }));
  const double t0 = steadyNow();
  ::kill(pid, sig);
  *off_ms = -1.0;
  while (steadyNow() - t0 < 0.4)  // well under the firmware watchdog's 0.5 s
  {
    rig.vest.poll(5, rig.ms());
    if (rig.vest.duty() == Duty{ { 0, 0, 0, 0 } })
    {
      *off_ms = (steadyNow() - t0) * 1000.0;
      break;
    }
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}
}  // namespace

TEST(VestBridge, AllOffOnSigterm)
{
  Rig rig;
  double off_ms = -1.0;
  const int status = signalChild(rig, SIGTERM, nullptr, &off_ms);
  EXPECT_GE(off_ms, 0.0) << "no all-off after SIGTERM";
  EXPECT_LT(off_ms, 100.0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;  // still terminates
  EXPECT_EQ(rig.vest.firmware().timeouts, 0);  // the bridge, not the watchdog
}

TEST(VestBridge, AllOffOnSigint)
{
  Rig rig;
  double off_ms = -1.0;
  const int status = signalChild(rig, SIGINT, nullptr, &off_ms);
  EXPECT_GE(off_ms, 0.0) << "no all-off after SIGINT";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << status;
}

TEST(VestBridge, AllOffOnSigintThenThePreviousHandlerRuns)
{
  // Like roscpp's SIGINT handler (graceful shutdown): it still runs, and the bridge sends only
  // all-off from then on although the process goes on.
  Rig rig;
  double off_ms = -1.0;
  const int status = signalChild(rig, SIGINT, &chainedHandler, &off_ms);
  EXPECT_GE(off_ms, 0.0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 7) << status;
  EXPECT_EQ(rig.vest.duty(), (Duty{ { 0, 0, 0, 0 } }));
}

TEST(VestBridge, MissingOrWrongPortIsReportedNotFatal)
{
  for (const std::string& port : { std::string("/tmp/assistive_tactile_no_such_port"), std::string("/dev/null") })
  {
    BridgeParams p;
    p.port = port;
    VestBridge b(p);
    for (int i = 0; i < 5; ++i)
    {
      b.spinOnce(i * 1.0);
      EXPECT_FALSE(b.setCue({ { 1.f, 0.f, 0.f, 0.f } }, i * 1.0));
    }
    EXPECT_FALSE(b.stats().open);
    EXPECT_FALSE(b.stats().last_error.empty()) << port;
    EXPECT_FALSE(b.linkUp(5.0));
  }
}

TEST(VestBridge, GarbageFromTheDeviceIsIgnored)
{
  Rig rig;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<uint8_t> junk(3000);
  for (size_t i = 0; i < junk.size(); ++i)
    junk[i] = static_cast<uint8_t>(i % 11 == 0 ? VEST_DELIMITER : byte(rng));
  ASSERT_TRUE(rig.vest.inject(junk.data(), junk.size()));
  for (int i = 0; i < 20; ++i)
  {
    rig.bridge->waitForInput(20);
    rig.advance(0.01);
  }
  EXPECT_TRUE(rig.bridge->stats().open);
  EXPECT_GT(rig.bridge->stats().garbage_bytes + rig.bridge->stats().rejected_packets, 100u);
  // The link still works both ways.
  const uint64_t st = rig.bridge->stats().status_packets;
  rig.bridge->setCue({ { 0.f, 0.f, 1.f, 0.f } }, rig.t);
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 255, 0 } }));
  ASSERT_TRUE(rig.bridge->waitForInput(200));
  rig.advance(0.0);
  EXPECT_GT(rig.bridge->stats().status_packets, st);
  EXPECT_EQ(rig.bridge->stats().last_status.intensity[2], 255);
}

TEST(VestBridge, DeviceNotReadingDoesNotBlock)
{
  BridgeParams p;
  p.stale_s = 1e6;
  Rig rig(p);
  // The vest stops reading: the pty buffer fills, writes must not block or fail the link.
  for (int i = 0; i < 30000; ++i)
    rig.bridge->setCue({ { (i % 2) ? 1.f : 0.5f, 0.f, 0.f, 0.f } }, rig.t += 0.001);
  EXPECT_TRUE(rig.bridge->stats().open);
  EXPECT_GT(rig.bridge->stats().packets_skipped, 0u);
  // Reading again: the backlog drains and the latest cue wins.
  while (rig.vest.poll(20, rig.ms()) > 0)
  {
  }
  rig.bridge->setCue({ { 0.f, 0.f, 0.f, 0.2f } }, rig.t += 0.001);
  rig.bridge->spinOnce(rig.t);
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 0, 51 } }));
}
