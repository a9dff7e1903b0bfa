// tactile_benchmark: cue-to-serial latency on this machine (no roscore, no hardware).
//   rosrun assistive_tactile tactile_benchmark [--cues N] [--period-ms P]
// A simulated vest (the firmware's code) listens on a pseudo-terminal in a second thread; the
// bridge core writes to it. For every cue it measures
//   latency      : TactileCue message in -> conversion -> packet encoded -> write() returned
//                  (the bytes are in the serial driver) -- the SPEC's latency_ms_* figures;
//   state->bytes : NavigationState in -> cue logic -> TactileCue -> ... -> write() returned;
//   vest decode  : TactileCue in -> the vest's parser accepted the packet (other thread).
// The radio / UART time on a real link comes on top (9 bytes at 57600 baud = 1.56 ms, computed).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "assistive_tactile/conversions.h"
#include "assistive_tactile/cue_logic.h"
#include "assistive_tactile/sim_vest.h"
#include "assistive_tactile/vest_bridge.h"

using namespace assistive_tactile;
using Clock = std::chrono::steady_clock;

namespace
{
double secs(Clock::time_point t)
{
  return std::chrono::duration<double>(t.time_since_epoch()).count();
}

double pct(std::vector<double> v, double p)
{
  if (v.empty())
    return -1.0;
  std::sort(v.begin(), v.end());
  const double idx = p / 100.0 * static_cast<double>(v.size() - 1);
  const size_t lo = static_cast<size_t>(idx);
  const size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (v[hi] - v[lo]) * (idx - static_cast<double>(lo));
}

std::string num(double v, int prec = 4)
{
  if (v < 0.0)
    return "null";
  char b[64];
  std::snprintf(b, sizeof(b), "%.*f", prec, v);
  return b;
}
}  // namespace

int main(int argc, char** argv)
{
  int cues = 2000;
  double period_ms = 2.0;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--cues" && i + 1 < argc)
      cues = std::max(10, std::atoi(argv[++i]));
    else if (a == "--period-ms" && i + 1 < argc)
      period_ms = std::max(0.0, std::atof(argv[++i]));
    else
    {
      std::fprintf(stderr, "usage: tactile_benchmark [--cues N] [--period-ms P]\n");
      return 2;
    }
  }

  const std::string link = "/tmp/assistive_tactile_bench_" + std::to_string(getpid());
  SimVest vest;
  std::string err;
  const Clock::time_point t0 = Clock::now();
  auto ms = [&]() {
    return static_cast<uint32_t>(std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count());
  };
  if (!vest.open(link, ms(), &err))
  {
    std::fprintf(stderr, "tactile_benchmark: cannot open a pseudo-terminal: %s\n", err.c_str());
    std::printf("{\"latency_ms_median\": null, \"latency_ms_p99\": null}\n");
    return 1;
  }
  // Vest thread: record when each SEQ was accepted.
  std::vector<double> accepted_at(256, -1.0);
  std::mutex mu;
  std::atomic<bool> stop{ false };
  uint8_t last_seen_seq = 0;
  std::atomic<uint64_t> seen{ 0 };
  std::thread vest_thread([&]() {
    while (!stop)
    {
      if (vest.poll(5, ms()) > 0)
      {
        const double now = secs(Clock::now());
        std::lock_guard<std::mutex> lock(mu);
        last_seen_seq = vest.firmware().last_seq;
        accepted_at[last_seen_seq] = now;
        ++seen;
      }
    }
  });

  BridgeParams bp;
  bp.port = link;
  VestBridge bridge(bp);
  bridge.spinOnce(secs(Clock::now()));
  if (!bridge.stats().open)
  {
    stop = true;
    vest_thread.join();
    std::fprintf(stderr, "tactile_benchmark: bridge cannot open %s: %s\n", link.c_str(),
                 bridge.stats().last_error.c_str());
    std::printf("{\"latency_ms_median\": null, \"latency_ms_p99\": null}\n");
    return 1;
  }

  CueLogic logic;
  std::vector<double> lat_ms, chain_ms, decode_ms;
  lat_ms.reserve(cues);
  uint64_t missing = 0;
  for (int i = 0; i < cues; ++i)
  {
    // A planner state that alternates left turn / right turn / side-step / on course.
    assistive_msgs::NavigationState st;
    st.status = assistive_msgs::NavigationState::OK;
    st.source_stamp = ros::Time(1000.0 + i * 0.05);
    st.heading = 0.0f;
    st.path_heading = static_cast<float>((i % 4 == 0) ? 0.8 : (i % 4 == 1) ? -0.6 : 0.0);
    st.waypoint_distance = 3.0f;
    st.free_distance_ahead = (i % 4 == 2) ? 0.8f : 4.0f;
    st.free_distance_left = 1.5f;
    st.free_distance_right = 0.2f;

    const Clock::time_point a = Clock::now();
    const Cue decided = logic.update(fromMsg(st), secs(a));
    const assistive_msgs::TactileCue msg = toMsg(decided, ros::Time(secs(a)), st.source_stamp, "torso");
    const Clock::time_point b = Clock::now();  // cue in (as the bridge receives it)
    const Cue cue = fromMsg(msg);
    const bool ok = bridge.setCue(cue.intensity, secs(b));
    const Clock::time_point c = Clock::now();  // bytes written
    if (ok)
    {
      lat_ms.push_back(std::chrono::duration<double, std::milli>(c - b).count());
      chain_ms.push_back(std::chrono::duration<double, std::milli>(c - a).count());
      const uint8_t seq = bridge.stats().seq;
      const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(200);
      double got = -1.0;
      while (Clock::now() < deadline)
      {
        {
          std::lock_guard<std::mutex> lock(mu);
          if (accepted_at[seq] >= secs(b))
          {
            got = accepted_at[seq];
            break;
          }
        }
        std::this_thread::yield();
      }
      if (got >= 0.0)
        decode_ms.push_back((got - secs(b)) * 1000.0);
      else
        ++missing;
    }
    else
      ++missing;
    bridge.spinOnce(secs(Clock::now()));  // read the vest's replies
    if (period_ms > 0.0)
      std::this_thread::sleep_for(std::chrono::microseconds(static_cast<int>(period_ms * 1000.0)));
    if ((i + 1) % 500 == 0)
      std::fprintf(stderr, "tactile_benchmark: %d / %d cues\n", i + 1, cues);
  }
  bridge.shutdown();
  stop = true;
  vest_thread.join();
  vest.close();

  const double med = pct(lat_ms, 50), p99 = pct(lat_ms, 99), mx = pct(lat_ms, 100);
  const double cmed = pct(chain_ms, 50), cp99 = pct(chain_ms, 99);
  const double dmed = pct(decode_ms, 50), dp99 = pct(decode_ms, 99);
  std::printf("tactile_benchmark: %d cues, bridge core -> simulated vest on a pseudo-terminal\n", cues);
  std::printf("%-44s %10s %10s %10s\n", "stage", "median ms", "p99 ms", "max ms");
  std::printf("%-44s %10.4f %10.4f %10.4f\n", "cue in -> bytes written (latency)", med, p99, mx);
  std::printf("%-44s %10.4f %10.4f %10.4f\n", "state in -> cue logic -> bytes written", cmed, cp99,
              pct(chain_ms, 100));
  std::printf("%-44s %10.4f %10.4f %10.4f\n", "cue in -> packet accepted by the vest code", dmed, dp99,
              pct(decode_ms, 100));
  std::printf("packets sent %llu, STATUS replies %llu, cues without a vest decode %llu\n",
              static_cast<unsigned long long>(bridge.stats().packets_sent),
              static_cast<unsigned long long>(bridge.stats().status_packets),
              static_cast<unsigned long long>(missing));
  std::printf("(not measured: UART/radio time; 9 bytes at %d baud take %.2f ms on the wire)\n", bp.baud,
              9.0 * 10.0 / bp.baud * 1000.0);
  std::printf("{\"latency_ms_median\": %s, \"latency_ms_p99\": %s, \"latency_ms_max\": %s, "
              "\"state_to_bytes_ms_median\": %s, \"state_to_bytes_ms_p99\": %s, "
              "\"vest_decode_ms_median\": %s, \"vest_decode_ms_p99\": %s, \"cues\": %d, "
              "\"cues_not_decoded\": %llu}\n",
              num(med).c_str(), num(p99).c_str(), num(mx).c_str(), num(cmed).c_str(), num(cp99).c_str(),
              num(dmed).c_str(), num(dp99).c_str(), cues, static_cast<unsigned long long>(missing));
  return 0;
}
