// rostest: tactile/cue -> vest_bridge nodelet -> pty -> simulated vest (in this process).
#include <gtest/gtest.h>

#include <assistive_msgs/TactileCue.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <nodelet/NodeletUnload.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/Joy.h>
#include <sensor_msgs/Range.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <functional>
#include <map>
#include <vector>

#include "assistive_tactile/sim_vest.h"
#include "assistive_tactile/vest_bridge.h"

// One executable with test_tactile_nodelets.cpp, which holds main() (issue 31: CMakeLists.txt); this
// file's names in a namespace of their own, apart from that file's.
namespace vest_bridge_test
{

using assistive_tactile::describeDuty;
using assistive_tactile::SimVest;
using Duty = std::array<uint8_t, 4>;

namespace
{
std::map<std::string, std::string> g_diag;
int g_level = -1;
std::string g_message;

void diagCb(const diagnostic_msgs::DiagnosticArray::ConstPtr& m)
{
  for (const auto& s : m->status)
    if (s.name.find("vest link") != std::string::npos)
    {
      g_level = s.level;
      g_message = s.message;
      for (const auto& kv : s.values)
        g_diag[kv.key] = kv.value;
    }
}

uint32_t nowMs()
{
  static const auto t0 = std::chrono::steady_clock::now();
  return static_cast<uint32_t>(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count());
}

struct Harness
{
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<assistive_msgs::TactileCue>("/tactile/cue", 1);
  ros::Subscriber sub = nh.subscribe("/diagnostics", 50, diagCb);
  SimVest vest;
  std::array<float, 4> cue{ { 0, 0, 0, 0 } };
  uint8_t mode = assistive_msgs::TactileCue::GUIDANCE;
  // the pulse pattern (TactileCue fields; default steady)
  uint8_t pattern_id = 0, pulse_count = 0;
  uint16_t pulse_on_ms = 0, pulse_off_ms = 0;
  bool publishing = false;
  bool no_source = false;  ///< publish a zero source_stamp (unknown camera time)
  double stamp_age = 0.0;  ///< publish cues stamped this long ago

  /// Runs vest + ROS at ~20 Hz cue rate until pred() or timeout.
  bool runUntil(const std::function<bool()>& pred, double timeout)
  {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    ros::WallTime next;
    while (ros::ok() && ros::WallTime::now() < end)
    {
      if (publishing && ros::WallTime::now() >= next)
      {
        assistive_msgs::TactileCue m;
        m.header.stamp = ros::Time::now() - ros::Duration(stamp_age);
        if (!no_source)
          m.source_stamp = m.header.stamp - ros::Duration(0.05);  // the camera image behind it
        m.mode = mode;
        for (int i = 0; i < 4; ++i)
          m.intensity[i] = cue[i];
        m.pattern_id = pattern_id;
        m.pulse_on_ms = pulse_on_ms;
        m.pulse_off_ms = pulse_off_ms;
        m.pulse_count = pulse_count;
        pub.publish(m);
        next = ros::WallTime::now() + ros::WallDuration(0.05);
      }
      vest.poll(5, nowMs());
      ros::spinOnce();
      if (pred())
        return true;
    }
    return pred();
  }
};

/// Records the on/off edges (vest clock) of the motors `on` looks at.
void recordEdges(Harness& h, std::vector<std::pair<uint32_t, bool>>& edges, std::function<bool(const Duty&)> on)
{
  edges.clear();
  h.vest.on_change = [&h, &edges, on](uint32_t t, const std::string&) {
    const bool now_on = on(h.vest.duty());
    if (edges.empty() ? now_on : edges.back().second != now_on)
      edges.emplace_back(t, now_on);
  };
}

// The steps of the test, in order (each starts where the one before left the bridge and the vest).

void cueSequence(Harness& h)
{
  // Cue sequence -> the right motors.
  h.publishing = true;
  const std::vector<std::pair<std::array<float, 4>, Duty>> seq = {
    { { { 1.f, 0, 0, 0 } }, { { 255, 0, 0, 0 } } },
    { { { 0, 0.5f, 0, 0 } }, { { 0, 128, 0, 0 } } },
    { { { 0, 0, 0, 0.25f } }, { { 0, 0, 0, 64 } } },
    { { { 1.f, 1.f, 1.f, 1.f } }, { { 255, 255, 255, 255 } } },
  };
  for (const auto& s : seq)
  {
    h.cue = s.first;
    const Duty want = s.second;
    ASSERT_TRUE(h.runUntil([&] { return h.vest.duty() == want; }, 10.0)) << describeDuty(want.data());
  }
}

void staleCuesOff(Harness& h)
{
  // Cues stop: the bridge itself sends all-off (the vest's own watchdog does not have to).
  const uint16_t trips = h.vest.firmware().timeouts;
  h.publishing = false;
  ASSERT_TRUE(h.runUntil([&] { return h.vest.duty() == Duty{ { 0, 0, 0, 0 } }; }, 10.0));
  EXPECT_EQ(h.vest.firmware().timeouts, trips);
  EXPECT_TRUE(h.runUntil([] { return g_diag["cue stale"] == "True"; }, 10.0));

  // Cues stamped 1 s ago (a stalled or replayed stream): ignored, the vest stays quiet.
  h.stamp_age = 1.0;
  h.publishing = true;
  EXPECT_FALSE(h.runUntil([&] { return h.vest.duty() != Duty{ { 0, 0, 0, 0 } }; }, 1.5));
  EXPECT_TRUE(h.runUntil([] { return !g_diag["cues ignored (old stamps)"].empty() &&
                                     g_diag["cues ignored (old stamps)"] != "0"; }, 10.0));
  EXPECT_NE(g_diag["last ignored because"].find("stale"), std::string::npos) << g_diag["last ignored because"];
  h.publishing = false;
  h.stamp_age = 0.0;
}

void unplugReplug(Harness& h, const std::string& link)
{
  // Unplug: the nodelet reports it and keeps running.
  h.vest.close();
  ASSERT_TRUE(h.runUntil([] { return g_level == diagnostic_msgs::DiagnosticStatus::ERROR; }, 10.0)) << g_message;
  EXPECT_NE(g_message.find("port closed"), std::string::npos) << g_message;

  // Plug back in: reopened, cues flow again.
  std::string err;
  ASSERT_TRUE(h.vest.open(link, nowMs(), &err)) << err;
  h.cue = { { 0, 0, 0.5f, 0 } };
  h.publishing = true;
  ASSERT_TRUE(h.runUntil([&] { return h.vest.duty() == Duty{ { 0, 0, 128, 0 } }; }, 20.0));
  EXPECT_TRUE(h.runUntil([] { return g_diag["opens"] == "2" && g_diag["losses"] == "1"; }, 10.0))
      << g_diag["opens"] << " " << g_diag["losses"];
}

void garbageIgnored(Harness& h)
{
  // Garbage from the device: counted, ignored, link stays up.
  std::vector<uint8_t> junk(2000);
  for (size_t i = 0; i < junk.size(); ++i)
    junk[i] = static_cast<uint8_t>(i % 13 == 0 ? VEST_DELIMITER : (i * 37u + 11u) & 0xFF);
  ASSERT_TRUE(h.vest.inject(junk.data(), junk.size()));
  EXPECT_TRUE(h.runUntil([] { return !g_diag["garbage bytes"].empty() && g_diag["garbage bytes"] != "0"; }, 10.0));
  h.cue = { { 0, 1.f, 0, 0 } };
  EXPECT_TRUE(h.runUntil([&] { return h.vest.duty() == Duty{ { 0, 255, 0, 0 } }; }, 10.0));
  EXPECT_TRUE(h.runUntil([] { return g_diag["link up"] == "True" && g_level == 0; }, 10.0)) << g_message;
}

void pulsePatterns(Harness& h)
{
  // Protocol version 4: the cue's pulse pattern, timed by the vest. A veer burst (150 ms on,
  // 150 ms off, x2) repeated at 20 Hz with the same id: two pulses of 150 ms, 150 ms apart, on
  // the vest's clock, then nothing; "vest drove since last report" shows it on diagnostics.
  h.publishing = false;
  ASSERT_TRUE(h.runUntil([&] { return h.vest.duty() == Duty{ { 0, 0, 0, 0 } }; }, 10.0));
  std::vector<std::pair<uint32_t, bool>> edges;  // vest clock, left shoulder on
  recordEdges(h, edges, [](const Duty& d) { return d[0] > 0; });
  h.cue = { { 0.7f, 0, 0, 0 } };
  h.pattern_id = 41;
  h.pulse_on_ms = 150;
  h.pulse_off_ms = 150;
  h.pulse_count = 2;
  h.publishing = true;
  h.runUntil([] { return false; }, 1.2);
  ASSERT_EQ(edges.size(), 4u) << "on/off edges of the left shoulder";
  EXPECT_TRUE(edges[0].second);
  EXPECT_NEAR(static_cast<double>(edges[1].first - edges[0].first), 150.0, 20.0);  // pulse
  EXPECT_NEAR(static_cast<double>(edges[2].first - edges[1].first), 150.0, 20.0);  // gap
  EXPECT_NEAR(static_cast<double>(edges[3].first - edges[2].first), 150.0, 20.0);  // pulse
  EXPECT_EQ(h.vest.firmware().pattern.id, 41);
  EXPECT_EQ(h.vest.duty(), (Duty{ { 0, 0, 0, 0 } }));  // the burst is over, cues still coming
  EXPECT_TRUE(h.runUntil([] { return g_diag["vest pattern"] == "#41 150 ms on 150 ms off x2"; }, 5.0))
      << g_diag["vest pattern"];
  // UNSURE without a camera time (it is often decided because there is none): its opening
  // pattern (three 100 ms pulses on both waist motors) is still felt.
  recordEdges(h, edges, [](const Duty& d) { return d[2] > 0 && d[3] > 0; });
  h.mode = assistive_msgs::TactileCue::UNSURE;
  h.no_source = true;
  h.cue = { { 0, 0, 1.f, 1.f } };
  h.pattern_id = 42;
  h.pulse_on_ms = 100;
  h.pulse_off_ms = 100;
  h.pulse_count = 3;
  h.runUntil([] { return false; }, 1.2);
  EXPECT_EQ(edges.size(), 6u) << "three pulses on both waist motors";
  EXPECT_TRUE(h.runUntil([] { return g_diag["vest pattern"] == "#42 100 ms on 100 ms off x3"; }, 5.0))
      << g_diag["vest pattern"];
  h.vest.on_change = nullptr;
  h.mode = assistive_msgs::TactileCue::GUIDANCE;
  h.no_source = false;
  h.pattern_id = 0;
  h.pulse_on_ms = h.pulse_off_ms = 0;
  h.pulse_count = 0;
}

void oldVestRefused(Harness& h)
{
  // An old vest (protocol version 3, no patterns): refused. Its motors stay off while cues come,
  // ERROR names its version; reflashed (the port stays open), it is driven again.
  h.vest.old_version = 3;
  h.cue = { { 0, 0, 1.f, 0 } };
  h.publishing = true;
  EXPECT_FALSE(h.runUntil([&] { return h.vest.duty() != Duty{ { 0, 0, 0, 0 } }; }, 1.0));
  EXPECT_TRUE(h.runUntil([] { return g_level == diagnostic_msgs::DiagnosticStatus::ERROR &&
                                     g_message.find("old vest firmware (protocol version 3") != std::string::npos; },
                         10.0)) << g_message;
  EXPECT_EQ(g_diag["vest refused (old firmware)"], "True");
  EXPECT_EQ(h.vest.duty(), (Duty{ { 0, 0, 0, 0 } }));
  h.vest.old_version = 0;
  EXPECT_TRUE(h.runUntil([&] { return h.vest.duty() == Duty{ { 0, 0, 255, 0 } }; }, 10.0));
  EXPECT_TRUE(h.runUntil([] { return g_diag["vest refused (old firmware)"] == "False"; }, 10.0));
}

void rangerAndButtons(Harness& h)
{
  // The ranger and the buttons (protocol version 3 on): /sonar/front and /vest/buttons.
  sensor_msgs::Range range;
  int short_a = 0;
  ros::Subscriber rs = h.nh.subscribe<sensor_msgs::Range>("/sonar/front", 20, [&](const sensor_msgs::Range::ConstPtr& m) { range = *m; });
  ros::Subscriber bs = h.nh.subscribe<sensor_msgs::Joy>("/vest/buttons", 20, [&](const sensor_msgs::Joy::ConstPtr& m) {
    if (m->buttons.size() == 6)
      short_a += m->buttons[0];
  });
  h.vest.setRange(1.5);
  EXPECT_TRUE(h.runUntil([&] { return std::abs(range.range - 1.5f) < 0.002f; }, 10.0)) << range.range;
  EXPECT_EQ(range.header.frame_id, "sonar_front");
  EXPECT_EQ(range.radiation_type, sensor_msgs::Range::ULTRASOUND);
  EXPECT_NEAR(range.max_range, 4.0, 1e-6);
  h.vest.setRange(std::numeric_limits<double>::infinity());
  EXPECT_TRUE(h.runUntil([&] { return std::isinf(range.range); }, 10.0)) << range.range;
  h.vest.press(VEST_BUTTON_A, 150, nowMs());
  EXPECT_TRUE(h.runUntil([&] { return short_a == 1; }, 10.0));
  h.vest.setSensorMissing(true);
  EXPECT_TRUE(h.runUntil([] { return g_level == diagnostic_msgs::DiagnosticStatus::ERROR &&
                                     g_message.find("ranger missing") != std::string::npos; }, 10.0)) << g_message;
  h.vest.setSensorMissing(false);
  EXPECT_TRUE(h.runUntil([] { return g_level == 0; }, 10.0)) << g_message;
}

void imuAndVersionFourVest(Harness& h)
{
  // The vest's IMU (protocol version 5) on /vest/imu: the window means in SI units, 50 Hz on the
  // vest's clock, no orientation; unplugged -> WARN. A version-4 vest (no IMU) is driven in
  // version 4 with a WARN; reflashed, back to version 5.
  std::vector<sensor_msgs::Imu> got;
  ros::Subscriber is = h.nh.subscribe<sensor_msgs::Imu>("/vest/imu", 200, [&](const sensor_msgs::Imu::ConstPtr& m) {
    if (m->angular_velocity.z > 0.25)
      got.push_back(*m);
  });
  h.vest.setImu({ { 0.0, 0.0, 0.5 } }, { { 0.0, 0.0, 9.80665 } });
  ASSERT_TRUE(h.runUntil([&] { return got.size() >= 50; }, 10.0)) << got.size();
  EXPECT_EQ(got.back().header.frame_id, "vest_imu");
  EXPECT_DOUBLE_EQ(got.back().angular_velocity.z, 0.5);
  EXPECT_DOUBLE_EQ(got.back().linear_acceleration.z, 9.807);
  EXPECT_EQ(got.back().orientation_covariance[0], -1.0);
  const double span = (got.back().header.stamp - got.front().header.stamp).toSec();
  EXPECT_NEAR(span / (got.size() - 1), 0.020, 0.003);  // the vest's 20 ms windows
  for (size_t i = 1; i < got.size(); ++i)
    EXPECT_GT(got[i].header.stamp, got[i - 1].header.stamp);
  h.vest.setImuMissing(true);
  EXPECT_TRUE(h.runUntil([] { return g_level == diagnostic_msgs::DiagnosticStatus::WARN &&
                                     g_message.find("IMU missing") != std::string::npos; }, 10.0)) << g_message;
  h.vest.setImuMissing(false);
  EXPECT_TRUE(h.runUntil([] { return g_level == 0; }, 10.0)) << g_message;

  h.vest.old_version = 4;
  h.cue = { { 0, 1.f, 0, 0 } };
  EXPECT_TRUE(h.runUntil([&] { return h.vest.duty() == Duty{ { 0, 255, 0, 0 } }; }, 10.0));
  EXPECT_TRUE(h.runUntil([] { return g_level == diagnostic_msgs::DiagnosticStatus::WARN &&
                                     g_message.find("protocol version 4: driven, no IMU") != std::string::npos; },
                         10.0)) << g_message;
  EXPECT_EQ(g_diag["commands sent in version"], "4");
  h.vest.old_version = 0;
  EXPECT_TRUE(h.runUntil([] { return g_diag["commands sent in version"] == "5" && g_level == 0; }, 10.0))
      << g_message << "; version probes sent " << g_diag["version probes sent"];
  EXPECT_EQ(h.vest.duty(), (Duty{ { 0, 255, 0, 0 } }));
}

void unloadSwitchesOff(Harness& h)
{
  // Unloading the nodelet from its manager switches the motors off (before the vest's watchdog).
  const uint16_t trips2 = h.vest.firmware().timeouts;
  ros::ServiceClient unload = h.nh.serviceClient<nodelet::NodeletUnload>("/bridge_manager/unload_nodelet");
  ASSERT_TRUE(unload.waitForExistence(ros::Duration(10.0)));
  h.publishing = false;
  nodelet::NodeletUnload srv;
  srv.request.name = "/vest_bridge";
  const ros::WallTime t_unload = ros::WallTime::now();
  ASSERT_TRUE(unload.call(srv));
  EXPECT_TRUE(srv.response.success);
  ASSERT_TRUE(h.runUntil([&] { return h.vest.duty() == Duty{ { 0, 0, 0, 0 } }; }, 2.0));
  EXPECT_EQ(h.vest.firmware().timeouts, trips2) << "the vest's watchdog, not the bridge, switched off after "
                                                << (ros::WallTime::now() - t_unload).toSec() << " s";
}
}  // namespace

// One scenario against one loaded nodelet: each step relies on the state the one before left.
TEST(VestBridgeNodelet, CuesStaleOffUnplugReplugGarbage)
{
  Harness h;
  std::string link;
  ASSERT_TRUE(ros::NodeHandle("~").getParam("link", link));
  std::string err;
  h.vest.clock = nowMs;  // the vest times the pulses on its own clock
  ASSERT_TRUE(h.vest.open(link, nowMs(), &err)) << err;

  // The bridge (re)opens the port and talks to the vest.
  ASSERT_TRUE(h.runUntil([] { return g_level >= 0 && g_diag["link up"] == "True"; }, 30.0)) << g_message;
  ASSERT_NO_FATAL_FAILURE(cueSequence(h));
  ASSERT_NO_FATAL_FAILURE(staleCuesOff(h));
  ASSERT_NO_FATAL_FAILURE(unplugReplug(h, link));
  ASSERT_NO_FATAL_FAILURE(garbageIgnored(h));
  ASSERT_NO_FATAL_FAILURE(pulsePatterns(h));
  ASSERT_NO_FATAL_FAILURE(oldVestRefused(h));
  ASSERT_NO_FATAL_FAILURE(rangerAndButtons(h));
  ASSERT_NO_FATAL_FAILURE(imuAndVersionFourVest(h));
  ASSERT_NO_FATAL_FAILURE(unloadSwitchesOff(h));
  h.vest.close();
}
}  // namespace vest_bridge_test
