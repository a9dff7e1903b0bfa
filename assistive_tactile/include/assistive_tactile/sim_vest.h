#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>

#include "assistive_tactile/vest_protocol.h"

namespace assistive_tactile
{
/**
 * The simulated vest: the firmware's side of vest_protocol.h (the very vest_firmware_* code the
 * sketch runs) on a pseudo-terminal. The bridge opens the pty's slave (or the symlink to it)
 * like a USB serial port. close() makes the port disappear (the bridge sees a hang-up), open()
 * brings a new one back under the same link.
 */
class SimVest
{
public:
  SimVest() = default;
  ~SimVest();
  SimVest(const SimVest&) = delete;
  SimVest& operator=(const SimVest&) = delete;

  /// Opens a new pty (posix_openpt); when `link` is not empty, (re)points that symlink at it.
  bool open(const std::string& link, uint32_t now_ms, std::string* error);
  /// Closes the pty and removes the link: the port disappears.
  void close();
  bool isOpen() const { return master_ >= 0; }
  const std::string& slavePath() const { return slave_path_; }

  /// Waits up to timeout_ms for bytes, feeds them to the firmware, answers valid COMMANDs with a
  /// STATUS, runs the pattern's pulses, TTL and watchdog. Returns the number of COMMANDs applied.
  /// With a `clock`, it waits at most until the next pulse edge and takes the time from the
  /// clock after waiting (now_ms is ignored), so the pulses are timed like the firmware's.
  int poll(int timeout_ms, uint32_t now_ms);
  /// Pulses, TTL and watchdog only (no bytes).
  void tick(uint32_t now_ms);
  /// The vest's own millisecond clock (real-time use: sim_vest, the benchmark, rostests). Empty
  /// (tests on a simulated clock): the now_ms arguments are the time.
  std::function<uint32_t()> clock;

  /// The forward ranger's world: the distance the next pings measure (m; +inf or NaN = nothing
  /// within range: no echo). Pings run every VEST_PING_PERIOD_MS through the firmware's own
  /// classification and median; RANGE packets go out once the bridge spoke version 3.
  void setRange(double range_m) { range_m_ = range_m; }
  /// Unplugs (true) / plugs the ranger: its echo line never rises -> "sensor missing".
  void setSensorMissing(bool missing) { sensor_missing_ = missing; }
  /// Holds button (VEST_BUTTON_A / _B) down from now_ms for hold_ms (a long press:
  /// >= VEST_LONG_PRESS_MS), through the firmware's debouncer.
  void press(unsigned button, uint32_t hold_ms, uint32_t now_ms);
  /// The IMU's world: what the next readings measure (rad/s and m/s^2, the sensor's axes;
  /// default still and upright: no rate, +9.81 m/s^2 up). Read every VEST_IMU_SAMPLE_MS of the
  /// vest's clock through the firmware's own windows; IMU packets go out once the bridge spoke
  /// version 5.
  void setImu(const std::array<double, 3>& rate, const std::array<double, 3>& accel)
  {
    imu_rate_ = rate;
    imu_accel_ = accel;
  }
  /// Unplugs (true) / plugs the IMU: its reads fail -> SENSOR_MISSING packets.
  void setImuMissing(bool missing) { imu_missing_ = missing; }
  /// Pretends to be the firmware of an older protocol version (2, 3 or 4; 0 = this version):
  /// COMMANDs of that version or older are obeyed (2 / 3: steady, no patterns), frames of a
  /// newer version are answered with a STATUS of that version and never applied (what the old
  /// firmware did). A version-3 / 4 vest sends RANGE / BUTTONS to a bridge of version 3 up to its
  /// own only, a version-2 one never; none sends IMU. (Tests: the bridge must refuse a version-2
  /// / 3 vest and drive a version-4 one in version 4.)
  int old_version = 0;
  uint64_t rangePackets() const { return range_packets_; }
  uint64_t buttonPackets() const { return button_packets_; }
  uint64_t imuPackets() const { return imu_packets_; }

  /// Writes raw bytes towards the bridge (tests: garbage from the device).
  bool inject(const uint8_t* data, size_t len);

  const vest_firmware_t& firmware() const { return fw_; }
  std::array<uint8_t, VEST_NUM_MOTORS> duty() const;
  uint64_t commands() const { return commands_; }
  /// Per motor: times it switched on (pulses felt; a steady cue is one) and total on-time up to now_ms.
  std::array<uint32_t, VEST_NUM_MOTORS> onsets() const { return onsets_; }
  std::array<double, VEST_NUM_MOTORS> onSeconds(uint32_t now_ms) const;

  /// Called with a one-line description whenever the motor outputs change.
  std::function<void(uint32_t now_ms, const std::string& line)> on_change;
  bool reply_status = true;

private:
  void reportIfChanged(uint32_t now_ms, const char* why);
  void feedOld(uint8_t byte, uint32_t now_ms, int* applied);  ///< old_version's firmware
  void sense(uint32_t now_ms);  ///< ranger pings, buttons and the IMU
  void senseImu(uint32_t now_ms);

  double range_m_ = std::numeric_limits<double>::infinity();
  bool sensor_missing_ = false;
  bool pinged_ = false;
  uint32_t last_ping_ms_ = 0;
  std::array<uint32_t, VEST_NUM_BUTTONS> down_from_{ { 0, 0 } }, down_until_{ { 0, 0 } };
  uint64_t range_packets_ = 0, button_packets_ = 0, imu_packets_ = 0;
  std::array<double, 3> imu_rate_{ { 0.0, 0.0, 0.0 } }, imu_accel_{ { 0.0, 0.0, 9.80665 } };
  bool imu_missing_ = false;
  bool imu_started_ = false;
  uint32_t last_imu_sample_ms_ = 0;

  int master_ = -1;
  int slave_hold_ = -1;  ///< keeps the slave side open so reads never see EIO between clients
  std::string slave_path_, link_;
  vest_firmware_t fw_{};
  std::array<uint8_t, VEST_NUM_MOTORS> reported_{ { 0, 0, 0, 0 } };
  uint64_t commands_ = 0;
  std::array<uint32_t, VEST_NUM_MOTORS> onsets_{ { 0, 0, 0, 0 } };
  std::array<double, VEST_NUM_MOTORS> on_s_{ { 0, 0, 0, 0 } };
  std::array<uint32_t, VEST_NUM_MOTORS> on_since_ms_{ { 0, 0, 0, 0 } };
};

}  // namespace assistive_tactile
