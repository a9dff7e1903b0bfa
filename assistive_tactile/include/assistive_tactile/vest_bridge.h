#pragma once

#include <array>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
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
  bool cue_stale = true;           ///< no valid cue (expired or none): sending all-off
  std::string last_error;          ///< why the port is closed / last failure
  uint64_t opens = 0;              ///< successful opens (1 + reconnections)
  uint64_t losses = 0;             ///< times an open port was lost
  uint64_t packets_sent = 0;
  uint64_t bytes_written = 0;
  uint64_t packets_skipped = 0;    ///< not written because the driver buffer was full
  uint64_t status_packets = 0;     ///< valid STATUS packets from the vest
  uint64_t garbage_bytes = 0;      ///< bytes from the vest in rejected frames
  uint64_t rejected_packets = 0;   ///< frames from the vest with a bad COBS / CRC / length / field
  uint64_t version_mismatches = 0; ///< CRC-valid frames of a protocol version we do not speak
  uint8_t vest_version = 0;        ///< VERSION of the vest's last CRC-valid frame (0 = none seen)
  /// VERSION the COMMANDs go out in: ours, or 4 for a version-4 vest (the same bytes; it has no
  /// IMU), which a STATUS of version 4 tells. Back to ours when the vest answers the version-5
  /// probe (every 2 s while driving a version-4 vest) or the port is reopened.
  uint8_t command_version = VEST_PROTOCOL_VERSION;
  uint64_t probes_sent = 0;        ///< version-5 copies sent to a vest driven in version 4
  /// The vest answered in an older version (2 or 3: no pulse patterns): refused. COMMANDs stay
  /// all-off in our version (it drives nothing on them; its watchdog ends what an earlier bridge
  /// left on): the wearer feels silence = stop. Cleared when a STATUS of ours arrives (the vest
  /// was reflashed on a link that stayed open) or the port is reopened.
  bool vest_refused = false;
  uint64_t cues_refused = 0;       ///< motor-driving cues not driven because the vest is refused
  /// Count-limited patterns whose motors the bridge switched off (at their end + stale_s, or
  /// after a reopen of the port): a vest that starts the pattern late never replays an old burst.
  uint64_t patterns_ended = 0;
  /// The highest duty per motor the vest reported (STATUS) since the last takeStatusPeak():
  /// what the wearer felt lately, pulses included (the last STATUS may fall into a gap).
  std::array<uint8_t, VEST_NUM_MOTORS> status_peak{ { 0, 0, 0, 0 } };
  // Forward ranger (RANGE packets).
  uint64_t ranges = 0;             ///< RANGE packets received
  uint64_t ranges_published = 0;   ///< readings handed on (echo within the limits, or no echo)
  uint64_t ranges_out_of_limits = 0;  ///< echoes outside [sonar_min_range, sonar_max_range]: dropped
  uint64_t ranges_sensor_missing = 0; ///< the vest reports the sensor missing / not answering
  uint64_t ranges_lost = 0;        ///< gaps in the RANGE sequence numbers
  double last_range_time = -1e300; ///< last RANGE packet (any status)
  double last_range_ok_time = -1e300;  ///< last published reading
  uint8_t last_range_status = VEST_RANGE_NO_ECHO;
  // Buttons (BUTTONS packets).
  uint64_t buttons_packets = 0;
  uint64_t button_presses = 0;     ///< short + long presses reported
  uint64_t button_resyncs = 0;     ///< counters that jumped (vest reset): taken as the new base
  // The vest's IMU (IMU packets, protocol version 5).
  uint64_t imu_packets = 0;        ///< IMU packets received
  uint64_t imu_lost = 0;           ///< gaps in the IMU sequence numbers
  uint64_t imu_sensor_missing = 0; ///< IMU packets saying the sensor could not be read
  uint64_t imu_clock_resets = 0;   ///< the vest's clock taken afresh (a stall or jump of over 0.25 s)
  double last_imu_time = -1e300;   ///< last IMU packet (any status)
  uint8_t last_imu_status = VEST_IMU_OK;
  uint64_t cues_accepted = 0;      ///< cues that passed the stamp checks
  uint64_t cues_rejected = 0;      ///< cues ignored by the stamp checks (never drove a motor)
  std::string last_rejection;      ///< why the last one was ignored
  double last_status_time = -1e300;
  vest_packet_t last_status{};     ///< what the vest reported its motors do
  uint8_t seq = 0;                 ///< SEQ of the last COMMAND sent
};

/// How old a cue is by its own stamps, in seconds of ROS time (simulated time in bag replay),
/// measured by the caller when the cue arrives.
struct CueAge
{
  /// now - header.stamp (the cue logic's decision time); +inf when the cue has no stamp.
  double stamp_age_s = 0.0;
  /// now - source_stamp (the camera image behind the cue); NaN when unknown (zero stamp).
  double source_age_s = 0.0;
};

/// Verdict of VestBridge::checkCue.
enum class CueCheck : uint8_t
{
  FRESH = 0,       ///< obeyed
  STALE,           ///< header.stamp older than stale_s (minus the time the all-off needs)
  SOURCE_STALE,    ///< drives a motor and its camera image is older than max_source_age_s
  SOURCE_UNKNOWN,  ///< drives a motor and has no source_stamp
  FUTURE           ///< a stamp more than stale_s ahead of our clock (clock skew): cannot judge
};
const char* cueCheckName(CueCheck c);

/// A ranger reading for `sonar/front`: range in m, +inf for no echo within the sensor's range.
struct RangeEvent
{
  double time = 0.0;   ///< monotonic seconds when it arrived
  double range_m = 0.0;
};

/// Verdict on a RANGE packet.
enum class RangeVerdict : uint8_t
{
  ECHO = 0,        ///< published (range_m)
  NO_ECHO,         ///< published as +inf
  OUT_OF_LIMITS,   ///< dropped
  SENSOR_MISSING,  ///< dropped; diagnostics ERROR
};
/// RANGE -> verdict (+ the range in m for ECHO / NO_ECHO).
RangeVerdict checkRange(const vest_range_t& r, const BridgeParams& p, double* range_m);

/// What the buttons did since the previous BUTTONS packet (sensor_msgs/Joy on `buttons`).
struct ButtonEvent
{
  double time = 0.0;
  uint8_t held = 0;  ///< bit 0 = A down, bit 1 = B down
  int short_a = 0, long_a = 0, short_b = 0, long_b = 0;  ///< presses
};

/// One IMU window (IMU packet), in SI units, on the bridge's clock (steadyNow seconds).
struct ImuEvent
{
  /// When the window ended: the vest's clock (its T_MS), mapped onto ours by the earliest
  /// arrival (serial and USB delays only ever make a packet later), so the windows' lengths
  /// are the vest's, not the link's jitter.
  double time = 0.0;
  bool ok = false;                         ///< false: SENSOR_MISSING (rate and accel 0)
  std::array<double, 3> rate{ { 0, 0, 0 } };   ///< mean angular rate over the window, rad/s, sensor axes
  std::array<double, 3> accel{ { 0, 0, 0 } };  ///< mean specific force, m/s^2
};

/// Maps the vest's 16-bit millisecond clock (IMU T_MS) onto the bridge's: the offset is the
/// smallest (arrival - vest time) seen, let rise by `drift_per_s` (a ceramic resonator's 0.5 %
/// and more) so a slow vest clock is followed; a jump of more than `reset_s` (a stalled link, a
/// restarted vest) takes the clock afresh.
class VestClock
{
public:
  explicit VestClock(double drift_per_s = 0.01, double reset_s = 0.25) : drift_(drift_per_s), reset_s_(reset_s) {}
  /// The time (our clock) of a vest stamp t_ms that arrived at `arrival`. Never goes back.
  double map(uint16_t t_ms, double arrival);
  void reset() { have_ = false; }
  uint64_t resets() const { return resets_; }

private:
  double drift_, reset_s_;
  bool have_ = false;
  uint16_t last_ms_ = 0;
  double vest_s_ = 0.0;      ///< the vest's clock, unwrapped, s
  double offset_ = 0.0;      ///< ours - the vest's
  double last_arrival_ = 0.0, last_out_ = 0.0;
  uint64_t resets_ = 0;
};

/// "L-sh 200  R-sh   0  L-w   0  R-w   0": motor duties as the diagnostics and the simulated vest write them.
std::string describeDuty(const uint8_t* duty);
/// "steady" / "#7 150 ms on 150 ms off x2" / "#9 100 ms on 100 ms off, repeating".
std::string describePattern(const vest_pattern_t& p);

/// One cue as the bridge drives it (from assistive_msgs/TactileCue).
struct VestCue
{
  VestCue() {}  // not an aggregate: a braced intensity array means the steady setCue overloads
  /// 0..1 per motor (TactileCue motor order): the drive while the pattern is on.
  std::array<float, VEST_NUM_MOTORS> intensity{ { 0.f, 0.f, 0.f, 0.f } };
  /// How the vest pulses them (protocol version 4); the same pattern re-sent continues its
  /// phase on the vest, another starts it. Default: steady.
  vest_pattern_t pattern{ 0, 0, 0, 0 };
  /// An UNSURE cue (TactileCue mode UNSURE): it says "cannot tell, stop" and guides nothing, so
  /// it needs no source_stamp (it is often decided *because* the camera image is old or
  /// missing), only a fresh header.stamp, like an all-off.
  bool unsure = false;
};

/**
 * The vest bridge's core (no ROS): owns the serial port (opened exclusively), turns cue
 * intensities into COMMAND packets (vest_protocol.h), sends each new cue at once and re-sends
 * the state at resend_hz, reopens a lost port every reopen_s, and reads STATUS packets back
 * (ignoring garbage).
 *
 * A cue is judged by its stamps, not by when it arrived (a queue or a stalled process can
 * deliver it late): it is obeyed only while header.stamp + stale_s and, if it drives a motor,
 * source_stamp + max_source_age_s are in the future, and all motors go off when the last valid
 * cue expires (early by the packet's wire time plus a wake-up margin, so the all-off has landed
 * by then). Each COMMAND also carries the time left (TTL), so the vest ends the cue by itself
 * when this side is late or stalled. Each COMMAND carries the cue's pulse pattern; the vest
 * times the pulses (re-sent with the same pattern, it continues the phase). A count-limited
 * pattern drives only on the port it was first written to and until its last pulse's end +
 * stale_s after this bridge first got it, then the same pattern goes out with zero duties: a
 * vest that starts it late (a reopened port, a restarted vest) never replays an old burst. A vest that answers in an older protocol
 * version (2 / 3: no patterns) is refused: all-off, LinkStats::vest_refused; a version-4 vest is driven in version 4 (LinkStats::command_version) and has no IMU. All-off also on shutdown and, with installAllOffSignalHandlers(), on SIGINT/SIGTERM.
 * `now` arguments are seconds on a monotonic clock. Not thread-safe: call from one thread (or
 * use VestBridgeRunner).
 */
class VestBridge
{
public:
  explicit VestBridge(const BridgeParams& p = BridgeParams());
  ~VestBridge();
  VestBridge(const VestBridge&) = delete;
  VestBridge& operator=(const VestBridge&) = delete;

  const BridgeParams& params() const { return params_; }

  /// A new cue of the given age. When checkCue passes it is written to the port immediately
  /// and returns true when the packet reached the driver; a rejected cue changes nothing
  /// (counted in stats) and returns false.
  bool setCue(const VestCue& cue, double now, const CueAge& age);
  /// A steady cue (intensities 0..1, TactileCue motor order).
  bool setCue(const std::array<float, VEST_NUM_MOTORS>& intensity, double now, const CueAge& age)
  {
    VestCue c;
    c.intensity = intensity;
    return setCue(c, now, age);
  }
  /// A steady cue stamped now with a fresh source (tests, benchmark).
  bool setCue(const std::array<float, VEST_NUM_MOTORS>& intensity, double now)
  {
    return setCue(intensity, now, CueAge());
  }

  /// The stamp rules (see the class comment); `lead_s` = offLeadS(); `unsure`: VestCue::unsure.
  static CueCheck checkCue(const std::array<uint8_t, VEST_NUM_MOTORS>& duty, const CueAge& age,
                           const BridgeParams& p, double lead_s, bool unsure = false);
  /// How much before a cue's expiry the all-off is sent: one packet's wire time + wake-up margin.
  double offLeadS() const;
  /// One packet's time on the wire at the configured baud rate.
  double wireS() const;
  /// TTL_MS for a COMMAND written at `now` (what is left of the cue, less the wire time).
  uint16_t ttlMs(double now) const;

  /// Housekeeping: (re)open, read the vest's replies, expiry check, periodic re-send.
  void spinOnce(double now);

  /// When the current cue expires (monotonic seconds; +inf when none is active).
  double cueExpiry() const;

  /// Blocks up to timeout_ms until the vest sent something (tests, benchmark); false if not.
  bool waitForInput(int timeout_ms) const;

  /// Sends all-off (best effort) and closes the port. Called by the destructor.
  void shutdown();

  /// True when the port is open and the vest answered within link_timeout_s.
  bool linkUp(double now) const;
  const LinkStats& stats() const { return stats_; }
  /// Duties of the last COMMAND sent (all-off while stale, refused or the pattern has ended).
  const std::array<uint8_t, VEST_NUM_MOTORS>& sentDuty() const { return sent_duty_; }
  /// Pattern of the last COMMAND sent.
  const vest_pattern_t& sentPattern() const { return pattern_; }
  /// stats().status_peak, then zeroes it.
  std::array<uint8_t, VEST_NUM_MOTORS> takeStatusPeak();

  /// Float intensity (0..1) -> PWM duty; any positive intensity gives at least 1.
  static uint8_t toDuty(float intensity);

  /// Ranger readings / button changes since the last call (moved out; at most 256 kept each).
  void takeRanges(std::vector<RangeEvent>& out);
  void takeButtons(std::vector<ButtonEvent>& out);
  /// IMU windows since the last call (moved out; at most 512 kept).
  void takeImu(std::vector<ImuEvent>& out);
  /// The vest speaks a version with the ranger and buttons (it answered in version 3).
  bool vestHasSensors() const { return stats_.vest_version >= 3; }
  /// True when the vest speaks version 3, the link is up and no RANGE came for sonar_timeout_s.
  bool rangerSilent(double now) const;
  /// The vest speaks version 5 (it answered in it): it has an IMU.
  bool vestHasImu() const { return stats_.vest_version >= VEST_IMU_VERSION; }
  /// True when the vest speaks version 5, the link is up and no IMU packet came for imu_timeout_s.
  bool imuSilent(double now) const;

private:
  void onRange(const vest_range_t& r, double now);
  void onButtons(const vest_buttons_t& b, double now);
  void onImu(const vest_imu_t& u, double now);
  void onStatusVersion(uint8_t version, double now);
  bool send(double now);
  bool linkLost(const std::string& err, double now);  ///< counts a lost link, schedules the reopen; false
  void tryOpen(double now);
  void readReplies(double now);
  void closePort();

  BridgeParams params_;
  SerialPort port_;
  LinkStats stats_;
  vest_parser_t parser_{};
  std::vector<RangeEvent> ranges_;
  std::vector<ButtonEvent> buttons_;
  std::vector<ImuEvent> imu_;
  VestClock vest_clock_;
  /// One stream's 8-bit sequence numbers (RANGE, IMU): the packets lost before each.
  struct SeqGap
  {
    bool have = false;
    uint8_t last = 0;
    /// the packets missing between the last number and `seq` (wrapping); 0 for the first
    unsigned lostBefore(uint8_t seq)
    {
      const unsigned lost = have ? static_cast<uint8_t>(seq - last - 1) : 0u;
      have = true;
      last = seq;
      return lost;
    }
  };
  SeqGap range_seq_, imu_seq_;
  bool have_buttons_ = false;
  double last_probe_time_ = -1e300;
  double last_old_sent_ = -1e300;  ///< when a COMMAND last went out in an older version than ours
  vest_buttons_t last_buttons_{};
  std::array<uint8_t, VEST_NUM_MOTORS> duty_{ { 0, 0, 0, 0 } };       ///< from the last valid cue
  vest_pattern_t pattern_{ 0, 0, 0, 0 };  ///< its pattern (kept, with zero duties, when it ends)
  double pattern_since_ = -1e300;         ///< when this pattern was first accepted (our clock)
  bool pattern_ended_ = false;            ///< counted in patterns_ended
  uint64_t pattern_session_ = 0;          ///< stats_.opens when it was first written (0: not yet)
  std::array<uint8_t, VEST_NUM_MOTORS> sent_duty_{ { 0, 0, 0, 0 } };  ///< in the last packet
  std::vector<uint8_t> pending_;  ///< unwritten tail of the last packet
  double cue_deadline_ = -std::numeric_limits<double>::infinity();  ///< all-off must have landed
  double cue_expiry_ = -std::numeric_limits<double>::infinity();    ///< deadline - offLeadS()
  double last_send_time_ = -1e300;
  double next_open_time_ = -1e300;
  bool shut_down_ = false;
};

/// Seconds on std::chrono::steady_clock (the bridge's monotonic clock).
double steadyNow();

/**
 * Runs a VestBridge's housekeeping in its own thread: every period_s and exactly at the current
 * cue's expiry, so the all-off is on time even when the ROS callback queue (shared with the
 * other nodelets of a manager) is busy; on SCHED_FIFO (realtime_priority) when allowed, so an
 * overloaded CPU does not delay it either (it sleeps between steps: never hogs a core). `after_spin` runs in that thread after each
 * housekeeping step, with the bridge locked (diagnostics, logging). stop() / the destructor send
 * all-off and close the port.
 */
class VestBridgeRunner
{
public:
  using Hook = std::function<void(VestBridge&, double now)>;
  explicit VestBridgeRunner(const BridgeParams& p, double period_s = 0.01, Hook after_spin = Hook());
  ~VestBridgeRunner();
  VestBridgeRunner(const VestBridgeRunner&) = delete;
  VestBridgeRunner& operator=(const VestBridgeRunner&) = delete;

  /// VestBridge::setCue at steadyNow(); wakes the thread for the new expiry. Returns the verdict.
  CueCheck setCue(const VestCue& cue, const CueAge& age);
  CueCheck setCue(const std::array<float, VEST_NUM_MOTORS>& intensity, const CueAge& age)
  {
    VestCue c;
    c.intensity = intensity;
    return setCue(c, age);
  }
  /// Runs f(bridge) with the bridge locked.
  template <typename F>
  auto locked(F&& f)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return f(*bridge_);
  }
  /// All-off, close, join (idempotent).
  void stop();
  /// Empty when the thread runs with params().realtime_priority (or 0 was asked), else why not.
  const std::string& schedulingError() const { return sched_error_; }

private:
  void loop();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::unique_ptr<VestBridge> bridge_;
  double period_s_;
  Hook hook_;
  bool stop_ = false;
  std::string sched_error_;
  std::thread thread_;
};

/// Puts `thread` on SCHED_FIFO at `priority` (0: leaves it alone). Empty on success, else why
/// not (e.g. no CAP_SYS_NICE / rtprio limit): the thread then keeps normal scheduling.
std::string setRealtimePriority(std::thread::native_handle_type thread, int priority);

/**
 * Fail-safe for SIGINT and SIGTERM: the handler writes an all-off packet (async-signal-safe
 * write()) to every port a VestBridge has open in this process, makes every bridge send only
 * all-off from then on, and then does what the previous disposition did (roscpp's SIGINT
 * handler: graceful shutdown; default SIGTERM: the process ends). Reference-counted; remove
 * restores the previous handlers when the last user goes.
 */
void installAllOffSignalHandlers();
void removeAllOffSignalHandlers();
/// True once SIGINT/SIGTERM arrived while the handlers were installed.
bool allOffSignalReceived();

}  // namespace assistive_tactile
