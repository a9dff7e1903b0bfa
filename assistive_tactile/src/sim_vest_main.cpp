// sim_vest: the simulated tactile vest on a pseudo-terminal (no ROS needed).
//   sim_vest [--link PATH] [--quiet] [--no-status] [--duration S]
// Prints the pty path, points PATH (default /tmp/assistive_vest) at it, and logs every change of
// the four motor outputs, as the firmware (vest_protocol.h) would drive them.
#include <signal.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "assistive_tactile/sim_vest.h"

namespace
{
volatile sig_atomic_t g_stop = 0;
void onSignal(int)
{
  g_stop = 1;
}
}  // namespace

int main(int argc, char** argv)
{
  std::string link = "/tmp/assistive_vest";
  bool quiet = false, status = true;
  double duration = -1.0;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--link" && i + 1 < argc)
      link = argv[++i];
    else if (a == "--quiet")
      quiet = true;
    else if (a == "--no-status")
      status = false;
    else if (a == "--duration" && i + 1 < argc)
      duration = std::atof(argv[++i]);
    else if (a == "-h" || a == "--help")
    {
      std::printf("usage: sim_vest [--link PATH] [--quiet] [--no-status] [--duration S]\n");
      return 0;
    }
    else if (a.rfind("__", 0) == 0 || a.rfind("_", 0) == 0)
      continue;  // roslaunch's __name:= / __log:= arguments
    else
    {
      std::fprintf(stderr, "sim_vest: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  signal(SIGINT, onSignal);
  signal(SIGTERM, onSignal);
  signal(SIGPIPE, SIG_IGN);

  const auto t0 = std::chrono::steady_clock::now();
  auto nowMs = [&]() {
    return static_cast<uint32_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count());
  };
  assistive_tactile::SimVest vest;
  vest.reply_status = status;
  std::string err;
  if (!vest.open(link, nowMs(), &err))
  {
    std::fprintf(stderr, "sim_vest: %s\n", err.c_str());
    return 1;
  }
  std::printf("sim_vest: pty %s, link %s\n", vest.slavePath().c_str(), link.c_str());
  std::fflush(stdout);
  uint64_t changes = 0;
  vest.on_change = [&](uint32_t t, const std::string& line) {
    ++changes;
    if (!quiet)
    {
      std::printf("[%9.3f s] %s\n", t / 1000.0, line.c_str());
      std::fflush(stdout);
    }
  };
  while (!g_stop)
  {
    vest.poll(20, nowMs());
    if (duration > 0.0 && nowMs() / 1000.0 > duration)
      break;
  }
  const vest_firmware_t& fw = vest.firmware();
  std::printf("sim_vest: %llu commands, %llu output changes, %u bad packets, %u stray bytes, %u watchdog trips, "
              "%u cues expired (TTL)\n",
              static_cast<unsigned long long>(vest.commands()), static_cast<unsigned long long>(changes),
              fw.parser.rejected, fw.parser.skipped, fw.timeouts, fw.expiries);
  if (fw.parser.version_mismatch)
    std::printf("sim_vest: %u packets of protocol version %u ignored (this vest speaks version %u)\n",
                fw.parser.version_mismatch, fw.parser.peer_version, VEST_PROTOCOL_VERSION);
  const auto on = vest.onSeconds(nowMs());
  const auto n = vest.onsets();
  static const char* names[4] = { "left shoulder (turn left)", "right shoulder (turn right)",
                                  "left waist (step left)", "right waist (step right)" };
  for (int i = 0; i < 4; ++i)
    std::printf("sim_vest: %-28s %5u cues, %8.1f s on\n", names[i], n[i], on[i]);
  std::fflush(stdout);
  vest.close();
  return 0;
}
