#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "assistive_tactile/params.h"
#include "assistive_tactile/serial_port.h"
#include "assistive_tactile/vest_protocol.h"

namespace assistive_tactile
{
/// Counters and state of the serial link, for diagnostics and tests.
struct LinkStats
{
  bool open = false;
  bool cue_stale = true;           ///< no cue for stale_s: sending all-off
  std::string last_error;          ///< why the port is closed / last failure
  uint64_t opens = 0;              ///< successful opens (1 + reconnections)
  uint64_t losses = 0;             ///< times an open port was lost
  uint64_t packets_sent = 0;
  uint64_t bytes_written = 0;
  uint64_t packets_skipped = 0;    ///< not written because the driver buffer was full
  uint64_t status_packets = 0;     ///< valid STATUS packets from the vest
  uint64_t garbage_bytes = 0;      ///< bytes from the vest outside valid packets
  uint64_t rejected_packets = 0;   ///< SYNC-started candidates with a bad CRC / field
  double last_status_time = -1e300;
  vest_packet_t last_status{};     ///< what the vest reported its motors do
  uint8_t seq = 0;                 ///< SEQ of the last COMMAND sent
};

/**
 * The vest bridge's core (no ROS): owns the serial port, turns cue intensities into COMMAND
 * packets (vest_protocol.h), sends each new cue at once and re-sends the state at resend_hz,
 * sends all-off when cues are stale or on shutdown, reopens a lost port every reopen_s, and
 * reads STATUS packets back (ignoring garbage). Times are seconds on a monotonic clock.
 * Not thread-safe: call from one thread.
 */
class VestBridge
{
public:
  explicit VestBridge(const BridgeParams& p = BridgeParams());
  ~VestBridge();
  VestBridge(const VestBridge&) = delete;
  VestBridge& operator=(const VestBridge&) = delete;

  const BridgeParams& params() const { return params_; }

  /// A new cue (intensities 0..1, TactileCue motor order). Written to the port immediately.
  /// Returns true when the packet reached the driver.
  bool setCue(const std::array<float, VEST_NUM_MOTORS>& intensity, double now);

  /// Housekeeping: (re)open, read the vest's replies, stale check, periodic re-send.
  void spinOnce(double now);

  /// Blocks up to timeout_ms until the vest sent something (tests, benchmark); false if not.
  bool waitForInput(int timeout_ms) const;

  /// Sends all-off (best effort) and closes the port. Called by the destructor.
  void shutdown();

  /// True when the port is open and the vest answered within link_timeout_s.
  bool linkUp(double now) const;
  const LinkStats& stats() const { return stats_; }
  /// Duties of the last COMMAND sent (all-off while stale).
  const std::array<uint8_t, VEST_NUM_MOTORS>& sentDuty() const { return sent_duty_; }

  /// Float intensity (0..1) -> PWM duty; any positive intensity gives at least 1.
  static uint8_t toDuty(float intensity);

private:
  bool send(double now);
  void tryOpen(double now);
  void readReplies();

  BridgeParams params_;
  SerialPort port_;
  LinkStats stats_;
  vest_parser_t parser_{};
  std::array<uint8_t, VEST_NUM_MOTORS> duty_{ { 0, 0, 0, 0 } };       ///< from the last cue
  std::array<uint8_t, VEST_NUM_MOTORS> sent_duty_{ { 0, 0, 0, 0 } };  ///< in the last packet
  std::vector<uint8_t> pending_;  ///< unwritten tail of the last packet
  double last_cue_time_ = -1e300;
  double last_send_time_ = -1e300;
  double next_open_time_ = -1e300;
  bool shut_down_ = false;
};

}  // namespace assistive_tactile
