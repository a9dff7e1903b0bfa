// rostest: tactile/cue -> vest_bridge nodelet -> pty -> simulated vest (in this process).
#include <gtest/gtest.h>

#include <assistive_msgs/TactileCue.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <nodelet/NodeletUnload.h>
#include <ros/ros.h>
#include <sensor_msgs/Joy.h>
#include <sensor_msgs/Range.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <functional>
#include <map>

#include "assistive_tactile/sim_vest.h"
#include "assistive_tactile/vest_bridge.h"

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
  bool publishing = false;
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
        m.source_stamp = m.header.stamp - ros::Duration(0.05);  // the camera image behind it
        m.mode = assistive_msgs::TactileCue::GUIDANCE;
        for (int i = 0; i < 4; ++i)
          m.intensity[i] = cue[i];
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
}  // namespace

TEST(VestBridgeNodelet, CuesStaleOffUnplugReplugGarbage)
{
  Harness h;
  std::string link;
  ASSERT_TRUE(ros::NodeHandle("~").getParam("link", link));
  std::string err;
  ASSERT_TRUE(h.vest.open(link, nowMs(), &err)) << err;

  // The bridge (re)opens the port and talks to the vest.
  ASSERT_TRUE(h.runUntil([] { return g_level >= 0 && g_diag["link up"] == "True"; }, 30.0)) << g_message;

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

  // Unplug: the nodelet reports it and keeps running.
  h.vest.close();
  ASSERT_TRUE(h.runUntil([] { return g_level == diagnostic_msgs::DiagnosticStatus::ERROR; }, 10.0)) << g_message;
  EXPECT_NE(g_message.find("port closed"), std::string::npos) << g_message;

  // Plug back in: reopened, cues flow again.
  ASSERT_TRUE(h.vest.open(link, nowMs(), &err)) << err;
  h.cue = { { 0, 0, 0.5f, 0 } };
  h.publishing = true;
  ASSERT_TRUE(h.runUntil([&] { return h.vest.duty() == Duty{ { 0, 0, 128, 0 } }; }, 20.0));
  EXPECT_TRUE(h.runUntil([] { return g_diag["opens"] == "2" && g_diag["losses"] == "1"; }, 10.0))
      << g_diag["opens"] << " " << g_diag["losses"];

  // Garbage from the device: counted, ignored, link stays up.
  std::vector<uint8_t> junk(2000);
  for (size_t i = 0; i < junk.size(); ++i)
    junk[i] = static_cast<uint8_t>(i % 13 == 0 ? VEST_DELIMITER : (i * 37u + 11u) & 0xFF);
  ASSERT_TRUE(h.vest.inject(junk.data(), junk.size()));
  EXPECT_TRUE(h.runUntil([] { return !g_diag["garbage bytes"].empty() && g_diag["garbage bytes"] != "0"; }, 10.0));
  h.cue = { { 0, 1.f, 0, 0 } };
  EXPECT_TRUE(h.runUntil([&] { return h.vest.duty() == Duty{ { 0, 255, 0, 0 } }; }, 10.0));
  EXPECT_TRUE(h.runUntil([] { return g_diag["link up"] == "True" && g_level == 0; }, 10.0)) << g_message;

  // The ranger and the buttons (protocol version 3): /sonar/front and /vest/buttons.
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
  h.vest.close();
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_vest_bridge_nodelet");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
