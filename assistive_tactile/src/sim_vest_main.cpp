// sim_vest: the simulated tactile vest on a pseudo-terminal (no ROS needed).
//   sim_vest [--link PATH] [--quiet] [--no-status] [--duration S] [--range M|none|missing] [--v2|--v3]
// Prints the pty path, points PATH (default /tmp/assistive_vest) at it, and logs every change of
// the four motor outputs, as the firmware (vest_protocol.h) would drive them, pulses included
// (timed on this process's clock, like the firmware's millis()).
// The forward ranger measures the range it is given (--range, or a line `range M`, `range none`
// (no echo), `range missing` (sensor unplugged) on stdin); `press a`, `press b`, `press a long`
// on stdin press the wearer's buttons. --v2 / --v3 play an old vest of that protocol version (no
// pulse patterns: a version-4 bridge refuses it).
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
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
  std::string range_arg = "none";
  int old_version = 0;
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
    else if (a == "--range" && i + 1 < argc)
      range_arg = argv[++i];
    else if (a == "--v2")
      old_version = 2;
    else if (a == "--v3")
      old_version = 3;
    else if (a == "-h" || a == "--help")
    {
      std::printf("usage: sim_vest [--link PATH] [--quiet] [--no-status] [--duration S] [--range M|none|missing] [--v2|--v3]\n"
                  "  stdin: `range M|none|missing`, `press a|b [long]`\n");
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
  vest.old_version = old_version;
  vest.clock = nowMs;  // pulses timed on this process's clock
  auto setRange = [&](const std::string& what) {
    vest.setSensorMissing(what == "missing");
    vest.setRange(what == "none" || what == "missing" ? std::numeric_limits<double>::infinity() : std::atof(what.c_str()));
  };
  setRange(range_arg);
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
  std::string line;
  while (!g_stop)
  {
    // Commands on stdin (non-blocking): range / press.
    struct pollfd in;
    in.fd = 0;
    in.events = POLLIN;
    in.revents = 0;
    if (::poll(&in, 1, 0) > 0 && (in.revents & POLLIN))
    {
      char buf[256];
      const ssize_t n = ::read(0, buf, sizeof(buf));
      if (n > 0)
        line.append(buf, static_cast<size_t>(n));
      size_t nl;
      while ((nl = line.find('\n')) != std::string::npos)
      {
        std::istringstream cmd(line.substr(0, nl));
        line.erase(0, nl + 1);
        std::string verb, arg, kind;
        cmd >> verb >> arg >> kind;
        if (verb == "range")
          setRange(arg);
        else if (verb == "press" && (arg == "a" || arg == "b"))
          vest.press(arg == "a" ? VEST_BUTTON_A : VEST_BUTTON_B, kind == "long" ? 1500u : 150u, nowMs());
        else if (!verb.empty())
          std::fprintf(stderr, "sim_vest: unknown command '%s' (range M|none|missing, press a|b [long])\n", verb.c_str());
      }
    }
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
    std::printf("sim_vest: %u packets of a protocol version it does not speak ignored (this vest speaks version %u)\n",
                fw.parser.version_mismatch, old_version ? static_cast<unsigned>(old_version) : VEST_PROTOCOL_VERSION);
  const auto on = vest.onSeconds(nowMs());
  const auto n = vest.onsets();
  static const char* names[4] = { "left shoulder (veer / turn left)", "right shoulder (veer / turn right)",
                                  "left waist (step left)", "right waist (step right)" };
  for (int i = 0; i < 4; ++i)
    std::printf("sim_vest: %-34s %5u pulses, %8.1f s on\n", names[i], n[i], on[i]);
  std::fflush(stdout);
  vest.close();
  return 0;
}
