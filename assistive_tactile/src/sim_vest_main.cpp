// sim_vest: the simulated tactile vest on a pseudo-terminal (no ROS needed).
//   sim_vest [--link PATH] [--quiet] [--no-status] [--duration S] [--range M|none|missing]
//            [--imu-yaw DEG_S|missing] [--v2|--v3|--v4]
// Prints the pty path, points PATH (default /tmp/assistive_vest) at it, and logs every change of
// the four motor outputs, as the firmware (vest_protocol.h) would drive them, pulses included
// (timed on this process's clock, like the firmware's millis()).
// The forward ranger measures the range it is given (--range, or a line `range M`, `range none`
// (no echo), `range missing` (sensor unplugged) on stdin); `press a`, `press b`, `press a long`
// on stdin press the wearer's buttons. The IMU (protocol version 5) reads an upright vest
// turning at the yaw rate it is given (--imu-yaw, or a line `imu DEG_S` / `imu missing` on stdin;
// default 0). --v2 / --v3 play an old vest of that protocol version (no pulse patterns: the
// bridge refuses it); --v4 one with pulse patterns and no IMU (the bridge drives it in version 4).
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
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

struct Options
{
  std::string link = "/tmp/assistive_vest";
  bool quiet = false, status = true;
  double duration = -1.0;
  std::string range = "none";
  std::string imu = "0";
  int old_version = 0;
};

/// Reads the command line into `o`; returns the exit code when the program is to stop (help or an
/// unknown argument), else -1.
int parseOptions(int argc, char** argv, Options& o)
{
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--link" && i + 1 < argc)
      o.link = argv[++i];
    else if (a == "--quiet")
      o.quiet = true;
    else if (a == "--no-status")
      o.status = false;
    else if (a == "--duration" && i + 1 < argc)
      o.duration = std::atof(argv[++i]);
    else if (a == "--range" && i + 1 < argc)
      o.range = argv[++i];
    else if (a == "--v2")
      o.old_version = 2;
    else if (a == "--v3")
      o.old_version = 3;
    else if (a == "--v4")
      o.old_version = 4;
    else if (a == "--imu-yaw" && i + 1 < argc)
      o.imu = argv[++i];
    else if (a == "-h" || a == "--help")
    {
      std::printf("usage: sim_vest [--link PATH] [--quiet] [--no-status] [--duration S] [--range M|none|missing]\n"
                  "                [--imu-yaw DEG_S|missing] [--v2|--v3|--v4]\n"
                  "  stdin: `range M|none|missing`, `press a|b [long]`, `imu DEG_S|missing`\n");
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
  return -1;
}

/// The ranger's reading: a range in m, `none` (no echo) or `missing` (sensor unplugged).
void setRange(assistive_tactile::SimVest& vest, const std::string& what)
{
  vest.setSensorMissing(what == "missing");
  vest.setRange(what == "none" || what == "missing" ? std::numeric_limits<double>::infinity() : std::atof(what.c_str()));
}

/// The IMU's reading: an upright vest turning at DEG_S (+ = left), or `missing` (unplugged).
void setImu(assistive_tactile::SimVest& vest, const std::string& what)
{
  vest.setImuMissing(what == "missing");
  const double rate = what == "missing" ? 0.0 : std::atof(what.c_str()) * M_PI / 180.0;
  vest.setImu({ { 0.0, 0.0, rate } }, { { 0.0, 0.0, 9.80665 } });
}

/// Carries out the complete command lines waiting on stdin (non-blocking): range / press;
/// `pending` keeps a line not yet complete.
void readCommands(assistive_tactile::SimVest& vest, std::string& pending, uint32_t now_ms)
{
  struct pollfd in;
  in.fd = 0;
  in.events = POLLIN;
  in.revents = 0;
  if (::poll(&in, 1, 0) <= 0 || !(in.revents & POLLIN))
    return;
  char buf[256];
  const ssize_t n = ::read(0, buf, sizeof(buf));
  if (n > 0)
    pending.append(buf, static_cast<size_t>(n));
  size_t nl;
  while ((nl = pending.find('\n')) != std::string::npos)
  {
    std::istringstream cmd(pending.substr(0, nl));
    pending.erase(0, nl + 1);
    std::string verb, arg, kind;
    cmd >> verb >> arg >> kind;
    if (verb == "range")
      setRange(vest, arg);
    else if (verb == "imu")
      setImu(vest, arg);
    else if (verb == "press" && (arg == "a" || arg == "b"))
      vest.press(arg == "a" ? VEST_BUTTON_A : VEST_BUTTON_B, kind == "long" ? 1500u : 150u, now_ms);
    else if (!verb.empty())
      std::fprintf(stderr, "sim_vest: unknown command '%s' (range M|none|missing, press a|b [long], imu DEG_S|missing)\n", verb.c_str());
  }
}

void printSummary(const assistive_tactile::SimVest& vest, uint64_t changes, int old_version, uint32_t now_ms)
{
  const vest_firmware_t& fw = vest.firmware();
  std::printf("sim_vest: %llu commands, %llu output changes, %u bad packets, %u stray bytes, %u watchdog trips, "
              "%u cues expired (TTL)\n",
              static_cast<unsigned long long>(vest.commands()), static_cast<unsigned long long>(changes),
              fw.parser.rejected, fw.parser.skipped, fw.timeouts, fw.expiries);
  if (fw.parser.version_mismatch)
    std::printf("sim_vest: %u packets of a protocol version it does not speak ignored (this vest speaks version %u)\n",
                fw.parser.version_mismatch, old_version ? static_cast<unsigned>(old_version) : VEST_PROTOCOL_VERSION);
  std::printf("sim_vest: sent %llu RANGE, %llu BUTTONS, %llu IMU packets\n",
              static_cast<unsigned long long>(vest.rangePackets()), static_cast<unsigned long long>(vest.buttonPackets()),
              static_cast<unsigned long long>(vest.imuPackets()));
  const auto on = vest.onSeconds(now_ms);
  const auto n = vest.onsets();
  static const char* names[4] = { "left shoulder (veer / turn left)", "right shoulder (veer / turn right)",
                                  "left waist (step left)", "right waist (step right)" };
  for (int i = 0; i < 4; ++i)
    std::printf("sim_vest: %-34s %5u pulses, %8.1f s on\n", names[i], n[i], on[i]);
  std::fflush(stdout);
}
}  // namespace

int main(int argc, char** argv)
{
  Options o;
  if (const int rc = parseOptions(argc, argv, o); rc >= 0)
    return rc;
  signal(SIGINT, onSignal);
  signal(SIGTERM, onSignal);
  signal(SIGPIPE, SIG_IGN);

  const auto t0 = std::chrono::steady_clock::now();
  auto nowMs = [&]() {
    return static_cast<uint32_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count());
  };
  assistive_tactile::SimVest vest;
  vest.reply_status = o.status;
  vest.old_version = o.old_version;
  vest.clock = nowMs;  // pulses timed on this process's clock
  setRange(vest, o.range);
  setImu(vest, o.imu);
  std::string err;
  if (!vest.open(o.link, nowMs(), &err))
  {
    std::fprintf(stderr, "sim_vest: %s\n", err.c_str());
    return 1;
  }
  std::printf("sim_vest: pty %s, link %s\n", vest.slavePath().c_str(), o.link.c_str());
  std::fflush(stdout);
  uint64_t changes = 0;
  vest.on_change = [&](uint32_t t, const std::string& line) {
    ++changes;
    if (!o.quiet)
    {
      std::printf("[%9.3f s] %s\n", t / 1000.0, line.c_str());
      std::fflush(stdout);
    }
  };
  std::string pending;
  while (!g_stop)
  {
    readCommands(vest, pending, nowMs());
    vest.poll(20, nowMs());
    if (o.duration > 0.0 && nowMs() / 1000.0 > o.duration)
      break;
  }
  printSummary(vest, changes, o.old_version, nowMs());
  vest.close();
  return 0;
}
