#include "assistive_tactile/sim_vest.h"
#include "assistive_tactile/vest_bridge.h"  // describeDuty

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace assistive_tactile
{
SimVest::~SimVest()
{
  close();
}

bool SimVest::open(const std::string& link, uint32_t now_ms, std::string* error)
{
  close();
  auto fail = [&](const char* what) {
    if (error)
      *error = std::string(what) + ": " + std::strerror(errno);
    close();
    return false;
  };
  master_ = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (master_ < 0)
    return fail("posix_openpt");
  if (grantpt(master_) != 0 || unlockpt(master_) != 0)
    return fail("grantpt/unlockpt");
  char name[128];
  if (ptsname_r(master_, name, sizeof(name)) != 0)
    return fail("ptsname_r");
  slave_path_ = name;
  slave_hold_ = ::open(name, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (slave_hold_ < 0)
    return fail("open slave");
  struct termios tio;
  if (tcgetattr(slave_hold_, &tio) == 0)
  {
    cfmakeraw(&tio);  // no echo, no line editing before any client configures it
    tcsetattr(slave_hold_, TCSANOW, &tio);
  }
  if (!link.empty())
  {
    const std::string tmp = link + ".tmp";
    ::unlink(tmp.c_str());
    if (::symlink(name, tmp.c_str()) != 0 || ::rename(tmp.c_str(), link.c_str()) != 0)
      return fail("symlink");
    link_ = link;
  }
  vest_firmware_init(&fw_, now_ms);
  reported_.fill(0);
  return true;
}

void SimVest::close()
{
  if (!link_.empty())
    ::unlink(link_.c_str());
  link_.clear();
  if (slave_hold_ >= 0)
    ::close(slave_hold_);
  if (master_ >= 0)
    ::close(master_);
  slave_hold_ = master_ = -1;
}

std::array<uint8_t, VEST_NUM_MOTORS> SimVest::duty() const
{
  return { { fw_.duty[0], fw_.duty[1], fw_.duty[2], fw_.duty[3] } };
}

std::array<double, VEST_NUM_MOTORS> SimVest::onSeconds(uint32_t now_ms) const
{
  std::array<double, VEST_NUM_MOTORS> out = on_s_;
  for (unsigned i = 0; i < VEST_NUM_MOTORS; ++i)
    if (reported_[i] > 0)
      out[i] += static_cast<uint32_t>(now_ms - on_since_ms_[i]) / 1000.0;
  return out;
}

void SimVest::reportIfChanged(uint32_t now_ms, const char* why)
{
  bool changed = false;
  for (unsigned i = 0; i < VEST_NUM_MOTORS; ++i)
    changed = changed || reported_[i] != fw_.duty[i];
  if (!changed)
    return;
  for (unsigned i = 0; i < VEST_NUM_MOTORS; ++i)
  {
    if (reported_[i] == 0 && fw_.duty[i] > 0)
    {
      onsets_[i]++;
      on_since_ms_[i] = now_ms;
    }
    else if (reported_[i] > 0 && fw_.duty[i] == 0)
      on_s_[i] += static_cast<uint32_t>(now_ms - on_since_ms_[i]) / 1000.0;
    reported_[i] = fw_.duty[i];
  }
  if (on_change)
    on_change(now_ms, describeDuty(fw_.duty) + "  (" + why + ")");
}

bool SimVest::inject(const uint8_t* data, size_t len)
{
  if (master_ < 0)
    return false;
  return ::write(master_, data, len) == static_cast<ssize_t>(len);
}

void SimVest::press(unsigned button, uint32_t hold_ms, uint32_t now_ms)
{
  if (button >= VEST_NUM_BUTTONS)
    return;
  down_from_[button] = now_ms;
  down_until_[button] = now_ms + hold_ms;
}

void SimVest::sense(uint32_t now_ms)
{
  // An old firmware sends sensors only to a bridge of version 3 up to its own that it obeyed (the
  // peer version may still be ours from before old_version was set).
  if (master_ < 0 || old_version == 2 || (old_version != 0 && (fw_.peer_version < 3 || fw_.peer_version > old_version)))
    return;
  if (old_version == 0)
    senseImu(now_ms);
  if (static_cast<uint32_t>(now_ms - last_ping_ms_) >= VEST_PING_PERIOD_MS || !pinged_)
  {
    pinged_ = true;
    last_ping_ms_ = now_ms;
    // The echo line as the sensor drives it: never high without a sensor; high for the round
    // trip of an echo; high for about 38 ms (then low) when nothing came back.
    const bool echo = std::isfinite(range_m_) && range_m_ >= 0.0;
    const uint32_t width_us =
        echo ? static_cast<uint32_t>(std::min(1e6, std::lround(range_m_ * 2e6 / 343.0) * 1.0)) : 38000u;
    uint16_t mm = 0;
    const uint8_t ping = vest_classify_ping(sensor_missing_ ? 0 : 1, 1, width_us, &mm);
    vest_range_t r;
    if (vest_firmware_range(&fw_, ping, mm, &r))
    {
      uint8_t out[VEST_RANGE_PACKET_SIZE];
      vest_encode_range_version(&r, vest_firmware_sensor_version(&fw_), out);  // the bridge's version
      if (::write(master_, out, sizeof(out)) == static_cast<ssize_t>(sizeof(out)))
        ++range_packets_;
    }
  }
  uint8_t down[VEST_NUM_BUTTONS];
  for (unsigned i = 0; i < VEST_NUM_BUTTONS; ++i)
    down[i] = static_cast<uint32_t>(now_ms - down_from_[i]) < static_cast<uint32_t>(down_until_[i] - down_from_[i]);
  vest_buttons_t b;
  if (vest_firmware_buttons(&fw_, down[0], down[1], now_ms, &b))
  {
    uint8_t out[VEST_BUTTONS_PACKET_SIZE];
    vest_encode_buttons_version(&b, vest_firmware_sensor_version(&fw_), out);
    if (::write(master_, out, sizeof(out)) == static_cast<ssize_t>(sizeof(out)))
      ++button_packets_;
  }
}

void SimVest::senseImu(uint32_t now_ms)
{
  // The sketch reads the sensor every VEST_IMU_SAMPLE_MS; here the readings missed since the last
  // wake are taken now, each at its own time (at most a second of them: a long sleep is a gap).
  if (!imu_started_ || static_cast<uint32_t>(now_ms - last_imu_sample_ms_) > 1000u)
  {
    imu_started_ = true;
    last_imu_sample_ms_ = now_ms;
    return;
  }
  int16_t gyro[3], accel[3];
  for (unsigned i = 0; i < 3; ++i)
  {
    gyro[i] = vest_sat16(std::lround(imu_rate_[i] * 1e3));
    accel[i] = vest_sat16(std::lround(imu_accel_[i] * 1e3));
  }
  while (static_cast<uint32_t>(now_ms - last_imu_sample_ms_) >= VEST_IMU_SAMPLE_MS)
  {
    last_imu_sample_ms_ += VEST_IMU_SAMPLE_MS;
    vest_imu_t u;
    if (!vest_firmware_imu(&fw_, imu_missing_ ? 0 : 1, gyro, accel, last_imu_sample_ms_, &u))
      continue;
    uint8_t out[VEST_IMU_PACKET_SIZE];
    vest_encode_imu_version(&u, vest_firmware_sensor_version(&fw_), out);
    if (::write(master_, out, sizeof(out)) == static_cast<ssize_t>(sizeof(out)))
      ++imu_packets_;
  }
}

void SimVest::tick(uint32_t now_ms)
{
  if (clock)
    now_ms = clock();
  sense(now_ms);
  const int r = vest_firmware_tick(&fw_, now_ms);
  if (r == VEST_TICK_WATCHDOG)
    reportIfChanged(now_ms, "watchdog: no valid packet for 500 ms");
  else if (r == VEST_TICK_EXPIRED)
    reportIfChanged(now_ms, "cue expired (TTL)");
  else if (r == VEST_TICK_PULSE)
    reportIfChanged(now_ms, fw_.duty[0] | fw_.duty[1] | fw_.duty[2] | fw_.duty[3] ? "pulse" : "gap");
}

void SimVest::feedOld(uint8_t byte, uint32_t now_ms, int* applied)
{
  // The firmware of version old_version: obeys COMMANDs up to its version (steady), answers a
  // CRC-valid frame of a newer version with a STATUS of its own version and applies nothing.
  vest_message_t m;
  vest_packet_t status;
  const uint8_t v = static_cast<uint8_t>(old_version);
  const uint16_t mism = fw_.parser.version_mismatch;
  const bool ok = vest_parser_feed_message(&fw_.parser, byte, &m);
  if (!ok && fw_.parser.version_mismatch == mism)
    return;  // nothing complete, or garbage
  uint8_t reply = v;
  if (ok && m.version <= v && m.type == VEST_TYPE_COMMAND)
  {
    // Applied as that version's firmware did (no pattern bytes: steady), through today's code.
    uint8_t frame[VEST_PACKET_SIZE];
    const uint8_t n = vest_encode_version(&m.packet, m.version, frame);
    vest_firmware_t tmp = fw_;
    for (uint8_t i = 0; i < n; ++i)
      vest_firmware_feed(&tmp, frame[i], now_ms, &status);
    fw_ = tmp;
    ++*applied;
    ++commands_;
    reportIfChanged(now_ms, "old-version command");
    reply = m.version;
  }
  else if (ok && m.version > v)
    fw_.parser.version_mismatch++;  // what the old firmware counted: a version it does not speak
  else if (ok || fw_.parser.version_mismatch == mism)
    return;  // STATUS / RANGE / BUTTONS of a version it knows: ignored
  vest_firmware_status(&fw_, &status);
  if (reply_status)
  {
    uint8_t out[VEST_PACKET_SIZE];
    const uint8_t n = vest_encode_version(&status, reply, out);
    if (::write(master_, out, n) < 0)
    {
      // the bridge is not reading; the vest does not care
    }
  }
}

int SimVest::poll(int timeout_ms, uint32_t now_ms)
{
  int applied = 0;
  if (clock)
  {
    // Wake for the next pulse edge / TTL / watchdog too: the firmware ticks every loop.
    now_ms = clock();
    uint32_t due = vest_firmware_next_change_ms(&fw_, now_ms);
    // ... and for the IMU's next window while a version-5 bridge listens (packets at 50 Hz)
    if (old_version == 0 && fw_.peer_version >= VEST_IMU_VERSION)
    {
      const uint32_t since = static_cast<uint32_t>(now_ms - fw_.imu.window_start_ms);
      due = std::min(due, since >= VEST_IMU_PERIOD_MS ? 0u : VEST_IMU_PERIOD_MS - since);
    }
    if (timeout_ms < 0 || (due != VEST_NEVER && due < static_cast<uint32_t>(timeout_ms)))
      timeout_ms = due == VEST_NEVER ? timeout_ms : static_cast<int>(due);
  }
  if (master_ >= 0)
  {
    struct pollfd p;
    p.fd = master_;
    p.events = POLLIN;
    p.revents = 0;
    if (::poll(&p, 1, timeout_ms) > 0 && (p.revents & POLLIN))
    {
      if (clock)
        now_ms = clock();  // receipt time
      uint8_t buf[512];
      const ssize_t n = ::read(master_, buf, sizeof(buf));
      for (ssize_t i = 0; i < n; ++i)
      {
        if (old_version != 0)
        {
          feedOld(buf[i], now_ms, &applied);
          continue;
        }
        vest_packet_t status;
        const int r = vest_firmware_feed(&fw_, buf[i], now_ms, &status);
        if (r != VEST_FEED_NONE)
        {
          if (r == VEST_FEED_APPLIED)
          {
            ++applied;
            ++commands_;
            const std::string why = "seq " + std::to_string(status.seq) + ", " + describePattern(fw_.pattern);
            reportIfChanged(now_ms, why.c_str());
          }
          if (reply_status)
          {
            uint8_t out[VEST_PACKET_SIZE];
            const uint8_t len = vest_encode_version(&status, fw_.reply_version, out);  // the COMMAND's version
            if (::write(master_, out, len) < 0)
            {
              // the bridge is not reading; the vest does not care (like the real one)
            }
          }
        }
      }
    }
  }
  else if (timeout_ms > 0)
  {
    ::usleep(static_cast<useconds_t>(timeout_ms) * 1000u);
  }
  tick(now_ms);
  return applied;
}

}  // namespace assistive_tactile
