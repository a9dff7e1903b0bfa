// The bridge core on a pseudo-terminal with the simulated vest (the firmware's code on the other
// side). Real file descriptors and bytes; the clocks are simulated, so nothing depends on timing.
#include <gtest/gtest.h>

#include <unistd.h>

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
  const double t0 = rig.t;
  rig.bridge->setCue({ { 1.f, 0.f, 0.f, 0.f } }, t0);
  rig.pump();
  ASSERT_EQ(duty(rig.vest), (Duty{ { 255, 0, 0, 0 } }));
  double off_at = -1.0;
  for (int i = 1; i <= 60 && off_at < 0.0; ++i)  // 10 ms steps, like the nodelet's timer
  {
    rig.advance(0.01);
    rig.pump(0);
    rig.vest.poll(20, rig.ms());
    if (duty(rig.vest) == Duty{ { 0, 0, 0, 0 } })
      off_at = rig.t - t0;
    else
      EXPECT_TRUE(rig.bridge->stats().cue_stale == false) << rig.t - t0;
  }
  ASSERT_GT(off_at, 0.0);
  EXPECT_LE(off_at, 0.3 + 0.01 + 1e-9);  // the first housekeeping step after stale_s
  EXPECT_GT(off_at, 0.3 - 1e-9);         // not before
  EXPECT_TRUE(rig.bridge->stats().cue_stale);
  EXPECT_EQ(rig.bridge->sentDuty(), (Duty{ { 0, 0, 0, 0 } }));
  // A new cue brings it back at once.
  rig.bridge->setCue({ { 0.f, 0.f, 1.f, 0.f } }, rig.t);
  rig.pump();
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 255, 0 } }));
}

TEST(VestBridge, FirmwareWatchdogWhenBridgeFallsSilent)
{
  Rig rig;
  rig.bridge->setCue({ { 1.f, 1.f, 0.f, 0.f } }, rig.t);
  rig.pump();
  ASSERT_EQ(duty(rig.vest), (Duty{ { 255, 255, 0, 0 } }));
  const uint32_t last = rig.ms();
  rig.vest.tick(last + 500);
  EXPECT_EQ(duty(rig.vest), (Duty{ { 255, 255, 0, 0 } }));
  rig.vest.tick(last + 501);  // e.g. the PC hung with the port open: the vest stops by itself
  EXPECT_EQ(duty(rig.vest), (Duty{ { 0, 0, 0, 0 } }));
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
    junk[i] = static_cast<uint8_t>(i % 11 == 0 ? VEST_SYNC : byte(rng));
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
