#include "assistive_tactile/vest_bridge.h"

#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace assistive_tactile
{
namespace
{
// Wake-up jitter of the housekeeping thread plus the write() call: the all-off is sent this much
// (plus the packet's wire time) before a cue expires, so it has landed by the expiry.
constexpr double kWakeMarginS = 0.010;

std::atomic<bool> g_signalled{ false };
}  // namespace

std::string describeDuty(const uint8_t* d)
{
  char buf[96];
  std::snprintf(buf, sizeof(buf), "L-sh %3u  R-sh %3u  L-w %3u  R-w %3u", d[0], d[1], d[2], d[3]);
  return buf;
}

std::string describePattern(const vest_pattern_t& p)
{
  if (p.on_10ms == 0)
    return "steady";
  char buf[96];
  if (p.count == 0)
    std::snprintf(buf, sizeof(buf), "#%u %u ms on %u ms off, repeating", p.id, 10u * p.on_10ms, 10u * p.off_10ms);
  else
    std::snprintf(buf, sizeof(buf), "#%u %u ms on %u ms off x%u", p.id, 10u * p.on_10ms, 10u * p.off_10ms, p.count);
  return buf;
}

const char* cueCheckName(CueCheck c)
{
  switch (c)
  {
    case CueCheck::FRESH:
      return "fresh";
    case CueCheck::STALE:
      return "stale (header.stamp older than stale_s)";
    case CueCheck::SOURCE_STALE:
      return "camera image behind it older than max_source_age_s";
    case CueCheck::SOURCE_UNKNOWN:
      return "drives a motor without a source_stamp";
    case CueCheck::FUTURE:
      return "stamped in the future (clock skew)";
  }
  return "?";
}

RangeVerdict checkRange(const vest_range_t& r, const BridgeParams& p, double* range_m)
{
  if (r.status == VEST_RANGE_SENSOR_MISSING)
    return RangeVerdict::SENSOR_MISSING;
  if (r.status == VEST_RANGE_NO_ECHO)
  {
    *range_m = std::numeric_limits<double>::infinity();  // REP 117: nothing within max_range
    return RangeVerdict::NO_ECHO;
  }
  const double m = r.range_mm / 1000.0;
  if (!(m >= p.sonar_min_range && m <= p.sonar_max_range))
    return RangeVerdict::OUT_OF_LIMITS;
  *range_m = m;
  return RangeVerdict::ECHO;
}

double steadyNow()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

VestBridge::VestBridge(const BridgeParams& p) : params_(p)
{
  vest_parser_init(&parser_);
  port_.enableFailSafe(true);
}

VestBridge::~VestBridge()
{
  shutdown();
}

uint8_t VestBridge::toDuty(float intensity)
{
  if (!(intensity > 0.f))  // also NaN
    return 0;
  const float v = std::min(1.f, intensity) * 255.f;
  return static_cast<uint8_t>(std::max(1.f, std::round(v)));
}

double VestBridge::wireS() const
{
  return VEST_PACKET_SIZE * 10.0 / std::max(1, params_.baud);  // 8N1: 10 bits per byte
}

double VestBridge::offLeadS() const
{
  return wireS() + kWakeMarginS;
}

uint16_t VestBridge::ttlMs(double now) const
{
  const bool off = stats_.cue_stale || g_signalled.load() ||
                   std::all_of(duty_.begin(), duty_.end(), [](uint8_t d) { return d == 0; });
  if (off)
    return 0xFFFF;  // nothing to end: the vest's watchdog rules
  // The vest counts from receipt (one wire time after the write) and switches off one tick
  // (1 ms) after the TTL: floor, minus that tick.
  const double left_ms = (cue_deadline_ - wireS() - now) * 1000.0 - 1.0;
  if (!(left_ms > 0.0))
    return 0;
  return static_cast<uint16_t>(std::min(65535.0, std::floor(left_ms)));
}

CueCheck VestBridge::checkCue(const std::array<uint8_t, VEST_NUM_MOTORS>& duty, const CueAge& age,
                              const BridgeParams& p, double lead_s, bool unsure)
{
  // Negated comparisons: NaN / +inf (unstamped) fail them.
  if (!(age.stamp_age_s >= -p.stale_s))
    return age.stamp_age_s < 0.0 ? CueCheck::FUTURE : CueCheck::STALE;
  if (!(age.stamp_age_s < p.stale_s - lead_s))
    return CueCheck::STALE;  // would have to be switched off before it could be felt
  const bool drives = std::any_of(duty.begin(), duty.end(), [](uint8_t d) { return d > 0; });
  if (!drives || unsure)
    return CueCheck::FRESH;  // all-off or "cannot tell": nothing is guided on it, whatever the source
  if (std::isnan(age.source_age_s))
    return CueCheck::SOURCE_UNKNOWN;
  if (age.source_age_s < -p.stale_s)
    return CueCheck::FUTURE;
  if (!(age.source_age_s < p.max_source_age_s - lead_s))
    return CueCheck::SOURCE_STALE;
  return CueCheck::FRESH;
}

void VestBridge::tryOpen(double now)
{
  next_open_time_ = now + params_.reopen_s;
  std::string err;
  if (!port_.open(params_.port, params_.baud, &err))
  {
    stats_.last_error = err;
    return;
  }
  stats_.open = true;
  stats_.opens++;
  stats_.last_error.clear();
  pending_.clear();
  vest_parser_init(&parser_);
  stats_.vest_refused = false;  // a new port may hold a new vest
  stats_.vest_version = 0;
  stats_.command_version = VEST_PROTOCOL_VERSION;
  range_seq_ = imu_seq_ = SeqGap{};
  have_buttons_ = false;
  vest_clock_.reset();
  last_probe_time_ = -1e300;
  last_old_sent_ = -1e300;
  send(now);  // tell the vest the current state right away
}

bool VestBridge::linkLost(const std::string& err, double now)
{
  // the port is closed and reopened after reopen_s; the vest's own watchdog stops the motors
  stats_.open = false;
  stats_.losses++;
  stats_.last_error = err;
  next_open_time_ = now + params_.reopen_s;
  return false;
}

bool VestBridge::send(double now)
{
  if (!port_.isOpen())
    return false;
  last_send_time_ = now;
  std::string err;
  if (!pending_.empty())
  {
    const ssize_t n = port_.write(pending_.data(), pending_.size(), &err);
    if (n < 0)
      return linkLost(err, now);
    stats_.bytes_written += static_cast<uint64_t>(n);
    pending_.erase(pending_.begin(), pending_.begin() + n);
    if (!pending_.empty())
    {
      stats_.packets_skipped++;
      return false;
    }
  }
  // A count-limited pattern is over: written on an earlier port session (the vest there may have
  // played part of it; the one here would start it from 0), or by our clock, with stale_s to
  // spare for a vest that got it late. The same pattern then goes on with zero duties, so a vest
  // that starts it only now (a reopened port, a restarted vest) does not replay an old burst,
  // and one that plays it keeps its phase (the same pattern) and is silent anyway.
  const uint32_t len_ms = vest_pattern_length_ms(&pattern_);
  const bool ended = len_ms != VEST_NEVER && ((pattern_session_ != 0 && pattern_session_ != stats_.opens) ||
                                              now - pattern_since_ > len_ms / 1000.0 + params_.stale_s);
  if (ended && !pattern_ended_ && !stats_.cue_stale)
  {
    pattern_ended_ = true;
    stats_.patterns_ended++;
  }
  const bool off = stats_.cue_stale || g_signalled.load() || stats_.vest_refused || ended;
  const std::array<uint8_t, VEST_NUM_MOTORS> duty = off ? std::array<uint8_t, VEST_NUM_MOTORS>{ { 0, 0, 0, 0 } } : duty_;
  vest_packet_t p{};
  p.type = VEST_TYPE_COMMAND;
  p.seq = static_cast<uint8_t>(stats_.seq + 1);
  // The pattern also with zero duties (stale, refused, ended): the vest keeps its phase, so the
  // same pattern coming back continues rather than replaying from its start.
  p.pattern = pattern_;
  p.ttl_ms = off ? static_cast<uint16_t>(0xFFFF) : ttlMs(now);  // all-off: nothing to end
  for (unsigned i = 0; i < VEST_NUM_MOTORS; ++i)
  {
    p.intensity[i] = duty[i];
    if (duty[i] > 0)
      p.motors = static_cast<uint8_t>(p.motors | (1u << i));
  }
  // Ours, or version 4 for a version-4 vest (the same bytes); a version-2 / 3 vest drives nothing
  // on either (refused). Driving a version-4 vest, the same state also goes out in ours every
  // kProbeS: a vest reflashed on a link that stayed open applies it (the same pattern continues)
  // and answers in ours; a version-4 one answers it and applies nothing.
  constexpr double kProbeS = 2.0;
  uint8_t buf[2 * VEST_PACKET_SIZE];
  size_t len = vest_encode_version(&p, stats_.command_version, buf);
  if (stats_.command_version < VEST_PROTOCOL_VERSION)
    last_old_sent_ = now;
  if (stats_.command_version < VEST_PROTOCOL_VERSION && now - last_probe_time_ >= kProbeS)
  {
    last_probe_time_ = now;
    p.seq = static_cast<uint8_t>(p.seq + 1);
    len += vest_encode_version(&p, static_cast<uint8_t>(VEST_PROTOCOL_VERSION), buf + len);
    stats_.probes_sent++;
  }
  const ssize_t n = port_.write(buf, len, &err);
  if (n < 0)
    return linkLost(err, now);
  stats_.bytes_written += static_cast<uint64_t>(n);
  if (n == 0)
  {
    stats_.packets_skipped++;  // nothing taken: the next re-send carries the state
    return false;
  }
  stats_.seq = p.seq;
  stats_.packets_sent++;
  sent_duty_ = duty;
  if (pattern_session_ == 0)
    pattern_session_ = stats_.opens;  // this port's vest has the pattern now
  if (static_cast<size_t>(n) < len)
    pending_.assign(buf + n, buf + len);
  return true;
}

bool VestBridge::setCue(const VestCue& cue, double now, const CueAge& age)
{
  std::array<uint8_t, VEST_NUM_MOTORS> duty;
  for (unsigned i = 0; i < VEST_NUM_MOTORS; ++i)
    duty[i] = toDuty(cue.intensity[i]);
  const double lead = offLeadS();
  const CueCheck check = checkCue(duty, age, params_, lead, cue.unsure);
  if (check != CueCheck::FRESH)
  {
    // Ignored: it never drives a motor; the previous valid cue keeps its own expiry.
    stats_.cues_rejected++;
    stats_.last_rejection = cueCheckName(check);
    return false;
  }
  stats_.cues_accepted++;
  duty_ = duty;
  vest_pattern_t pat = cue.pattern;
  if (pat.on_10ms == 0)
    pat.off_10ms = pat.count = 0;  // steady: no timing (as it goes on the wire)
  if (!vest_pattern_equal(&pat, &pattern_))
  {
    pattern_ = pat;
    pattern_since_ = now;
    pattern_ended_ = false;
    pattern_session_ = 0;
  }
  if (stats_.vest_refused && std::any_of(duty.begin(), duty.end(), [](uint8_t d) { return d > 0; }))
    stats_.cues_refused++;
  double valid_s = params_.stale_s - std::max(0.0, age.stamp_age_s);
  if (!cue.unsure && std::any_of(duty.begin(), duty.end(), [](uint8_t d) { return d > 0; }))
    valid_s = std::min(valid_s, params_.max_source_age_s - std::max(0.0, age.source_age_s));
  cue_deadline_ = now + valid_s;
  cue_expiry_ = cue_deadline_ - lead;
  stats_.cue_stale = false;
  if (shut_down_ || g_signalled.load())
    return false;
  return send(now);
}

double VestBridge::cueExpiry() const
{
  return stats_.cue_stale ? std::numeric_limits<double>::infinity() : cue_expiry_;
}

void VestBridge::readReplies(double now)
{
  uint8_t buf[256];
  std::string err;
  for (int guard = 0; guard < 64 && port_.isOpen(); ++guard)
  {
    const ssize_t n = port_.read(buf, sizeof(buf), &err);
    if (n < 0)
    {
      stats_.open = false;
      stats_.losses++;
      stats_.last_error = err;
      return;
    }
    if (n == 0)
      return;
    const uint16_t skipped0 = parser_.skipped, rejected0 = parser_.rejected,
                   mismatch0 = parser_.version_mismatch;
    for (ssize_t i = 0; i < n; ++i)
    {
      vest_message_t m;
      if (!vest_parser_feed_message(&parser_, buf[i], &m))
        continue;
      stats_.vest_version = m.version;
      if (m.type == VEST_TYPE_STATUS)
      {
        stats_.status_packets++;
        stats_.last_status = m.packet;
        for (unsigned k = 0; k < VEST_NUM_MOTORS; ++k)
          stats_.status_peak[k] = std::max(stats_.status_peak[k], m.packet.intensity[k]);
        onStatusVersion(m.version, now);
      }
      else if (m.type == VEST_TYPE_RANGE)
        onRange(m.range, now);
      else if (m.type == VEST_TYPE_IMU)
        onImu(m.imu, now);
      else if (m.type == VEST_TYPE_BUTTONS)
        onButtons(m.buttons, now);
    }
    stats_.garbage_bytes += static_cast<uint16_t>(parser_.skipped - skipped0);
    stats_.rejected_packets += static_cast<uint16_t>(parser_.rejected - rejected0);
    if (parser_.version_mismatch != mismatch0)
    {
      stats_.version_mismatches += static_cast<uint16_t>(parser_.version_mismatch - mismatch0);
      stats_.vest_version = parser_.peer_version;
    }
  }
}

void VestBridge::onStatusVersion(uint8_t version, double now)
{
  // We send version 5 or 4: a STATUS in 2 / 3 is an old vest's version reply (it cannot play
  // patterns): refused from now on. One in ours (reflashed on a link that stayed open, or the
  // probe's answer): driven in ours. One in 4 answers a COMMAND in ours from a version-4 vest
  // (driven in 4, no IMU), but a vest of ours answers each COMMAND in its version too: while
  // version-4 COMMANDs may still be on the wire (kInFlightS since the last), a STATUS in 4 says
  // nothing (it once undid the probe's answer that came just before it).
  constexpr double kInFlightS = 0.5;
  stats_.vest_refused = version < VEST_PATTERN_VERSION;
  if (stats_.vest_refused)
    return;
  if (version >= VEST_PROTOCOL_VERSION)
    stats_.command_version = VEST_PROTOCOL_VERSION;
  else if (now - last_old_sent_ > kInFlightS)
    stats_.command_version = version;
}

double VestClock::map(uint16_t t_ms, double arrival)
{
  const double da = arrival - last_arrival_;
  vest_s_ += have_ ? static_cast<uint16_t>(t_ms - last_ms_) / 1000.0 : 0.0;
  last_ms_ = t_ms;
  last_arrival_ = arrival;
  const double off = arrival - vest_s_;
  // Afresh: the first packet; a gap the 16-bit clock may have wrapped in; a vest clock ahead of
  // ours (a restarted vest); or packets late by seconds (no link holds them that long).
  constexpr double kWrapGuardS = 30.0, kLateS = 2.0;
  if (!have_ || da > kWrapGuardS || off < offset_ - reset_s_ || off > offset_ + kLateS)
  {
    resets_ += have_ ? 1 : 0;
    have_ = true;
    offset_ = off;
  }
  else
    offset_ = std::min(offset_ + drift_ * std::max(0.0, da), off);
  double out = vest_s_ + offset_;
  if (out <= last_out_)
    out = last_out_ + 1e-6;  // (a reset may step back: the time never does)
  last_out_ = out;
  return out;
}

void VestBridge::onImu(const vest_imu_t& u, double now)
{
  stats_.imu_packets++;
  stats_.imu_lost += imu_seq_.lostBefore(u.seq);
  stats_.last_imu_time = now;
  stats_.last_imu_status = u.status;
  ImuEvent e;
  e.time = vest_clock_.map(u.t_ms, now);
  stats_.imu_clock_resets = vest_clock_.resets();
  e.ok = u.status == VEST_IMU_OK;
  if (!e.ok)
    stats_.imu_sensor_missing++;
  for (unsigned i = 0; e.ok && i < 3; ++i)
  {
    e.rate[i] = u.gyro[i] * 1e-3;   // mrad/s
    e.accel[i] = u.accel[i] * 1e-3; // mm/s^2
  }
  if (imu_.size() < 512)
    imu_.push_back(e);
}

void VestBridge::takeImu(std::vector<ImuEvent>& out)
{
  out.swap(imu_);
  imu_.clear();
}

bool VestBridge::imuSilent(double now) const
{
  return vestHasImu() && linkUp(now) && now - stats_.last_imu_time > params_.imu_timeout_s;
}

void VestBridge::onRange(const vest_range_t& r, double now)
{
  stats_.ranges++;
  stats_.ranges_lost += range_seq_.lostBefore(r.seq);
  stats_.last_range_time = now;
  stats_.last_range_status = r.status;
  double m = 0.0;
  switch (checkRange(r, params_, &m))
  {
    case RangeVerdict::ECHO:
    case RangeVerdict::NO_ECHO:
      stats_.ranges_published++;
      stats_.last_range_ok_time = now;
      if (ranges_.size() < 256)
        ranges_.push_back({ now, m });
      break;
    case RangeVerdict::OUT_OF_LIMITS:
      stats_.ranges_out_of_limits++;
      break;
    case RangeVerdict::SENSOR_MISSING:
      stats_.ranges_sensor_missing++;
      break;
  }
}

void VestBridge::onButtons(const vest_buttons_t& b, double now)
{
  stats_.buttons_packets++;
  ButtonEvent e;
  e.time = now;
  e.held = b.held;
  if (have_buttons_)
  {
    e.short_a = static_cast<uint8_t>(b.short_a - last_buttons_.short_a);
    e.long_a = static_cast<uint8_t>(b.long_a - last_buttons_.long_a);
    e.short_b = static_cast<uint8_t>(b.short_b - last_buttons_.short_b);
    e.long_b = static_cast<uint8_t>(b.long_b - last_buttons_.long_b);
    // A few presses may hide in lost packets; a larger jump is a vest that restarted its
    // counters: taken as the new base, nothing invented.
    constexpr int kMaxPresses = 8;
    if (e.short_a > kMaxPresses || e.long_a > kMaxPresses || e.short_b > kMaxPresses || e.long_b > kMaxPresses)
    {
      stats_.button_resyncs++;
      e.short_a = e.long_a = e.short_b = e.long_b = 0;
    }
  }
  // The first packet after (re)opening is the base: presses before it are not known to be new.
  const bool changed = !have_buttons_ || e.held != last_buttons_.held || e.short_a || e.long_a || e.short_b || e.long_b;
  have_buttons_ = true;
  last_buttons_ = b;
  stats_.button_presses += static_cast<uint64_t>(e.short_a + e.long_a + e.short_b + e.long_b);
  if (changed && buttons_.size() < 256)
    buttons_.push_back(e);
}

std::array<uint8_t, VEST_NUM_MOTORS> VestBridge::takeStatusPeak()
{
  const std::array<uint8_t, VEST_NUM_MOTORS> p = stats_.status_peak;
  stats_.status_peak.fill(0);
  return p;
}

void VestBridge::takeRanges(std::vector<RangeEvent>& out)
{
  out.swap(ranges_);
  ranges_.clear();
}

void VestBridge::takeButtons(std::vector<ButtonEvent>& out)
{
  out.swap(buttons_);
  buttons_.clear();
}

bool VestBridge::rangerSilent(double now) const
{
  return vestHasSensors() && linkUp(now) && now - stats_.last_range_time > params_.sonar_timeout_s;
}

void VestBridge::spinOnce(double now)
{
  if (shut_down_)
    return;
  if (!port_.isOpen())
  {
    stats_.open = false;
    if (now >= next_open_time_)
      tryOpen(now);
    if (!port_.isOpen())
      return;
  }
  std::string err;
  if (!port_.checkAlive(&err))
  {
    linkLost(err, now);
    return;
  }
  const uint64_t before = stats_.status_packets;
  readReplies(now);
  if (stats_.status_packets != before)
    stats_.last_status_time = now;
  if (!port_.isOpen())
  {
    next_open_time_ = now + params_.reopen_s;
    return;
  }
  const bool stale = now >= cue_expiry_ || g_signalled.load();
  const bool became_stale = stale && !stats_.cue_stale;
  stats_.cue_stale = stale;
  if (became_stale || now - last_send_time_ >= 1.0 / params_.resend_hz)
    send(now);
}

void VestBridge::shutdown()
{
  if (shut_down_)
    return;
  shut_down_ = true;
  if (port_.isOpen())
  {
    stats_.cue_stale = true;
    pending_.clear();
    send(last_send_time_);
  }
  port_.close();
  stats_.open = false;
}

bool VestBridge::linkUp(double now) const
{
  return port_.isOpen() && (now - stats_.last_status_time) <= params_.link_timeout_s;
}

bool VestBridge::waitForInput(int timeout_ms) const
{
  if (!port_.isOpen())
    return false;
  struct pollfd p;
  p.fd = port_.fd();
  p.events = POLLIN;
  p.revents = 0;
  return ::poll(&p, 1, timeout_ms) > 0 && (p.revents & POLLIN);
}

// ---- VestBridgeRunner ----

VestBridgeRunner::VestBridgeRunner(const BridgeParams& p, double period_s, Hook after_spin)
  : bridge_(new VestBridge(p)), period_s_(std::max(1e-3, period_s)), hook_(std::move(after_spin))
{
  thread_ = std::thread(&VestBridgeRunner::loop, this);
  sched_error_ = setRealtimePriority(thread_.native_handle(), p.realtime_priority);
}

VestBridgeRunner::~VestBridgeRunner()
{
  stop();
}

CueCheck VestBridgeRunner::setCue(const VestCue& cue, const CueAge& age)
{
  CueCheck verdict;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::array<uint8_t, VEST_NUM_MOTORS> duty;
    for (unsigned i = 0; i < VEST_NUM_MOTORS; ++i)
      duty[i] = VestBridge::toDuty(cue.intensity[i]);
    verdict = VestBridge::checkCue(duty, age, bridge_->params(), bridge_->offLeadS(), cue.unsure);
    bridge_->setCue(cue, steadyNow(), age);
  }
  wake_.notify_one();  // the expiry may have moved
  return verdict;
}

void VestBridgeRunner::stop()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_ && !thread_.joinable())
      return;
    stop_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable())
    thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  bridge_->shutdown();  // all motors off before the port closes
}

std::string setRealtimePriority(std::thread::native_handle_type thread, int priority)
{
  if (priority <= 0)
    return std::string();
  struct sched_param sp;
  std::memset(&sp, 0, sizeof(sp));
  sp.sched_priority = std::min(priority, sched_get_priority_max(SCHED_FIFO));
  const int err = pthread_setschedparam(thread, SCHED_FIFO, &sp);
  return err == 0 ? std::string() : std::string("SCHED_FIFO ") + std::to_string(sp.sched_priority) + ": " + std::strerror(err);
}

void VestBridgeRunner::loop()
{
  using Clock = std::chrono::steady_clock;
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_)
  {
    const double now = steadyNow();
    bridge_->spinOnce(now);
    if (hook_)
      hook_(*bridge_, now);
    double wake = now + period_s_;
    const double expiry = bridge_->cueExpiry();
    if (expiry > now && expiry < wake)
      wake = expiry;  // the all-off goes out at the expiry, not up to a period later
    wake_.wait_until(lock, Clock::time_point(std::chrono::duration_cast<Clock::duration>(
                               std::chrono::duration<double>(wake))));
  }
}

// ---- SIGINT / SIGTERM fail-safe ----

namespace
{
std::mutex g_signal_mutex;
int g_signal_users = 0;
struct sigaction g_old_int, g_old_term;

void onFatalSignal(int sig, siginfo_t* info, void* ctx)
{
  const int saved_errno = errno;
  g_signalled = true;
  writeFailSafeBytes();  // all motors off now, whatever the other threads are doing
  const struct sigaction& old = sig == SIGINT ? g_old_int : g_old_term;
  if (old.sa_flags & SA_SIGINFO)
  {
    if (old.sa_sigaction)
      old.sa_sigaction(sig, info, ctx);
  }
  else if (old.sa_handler == SIG_DFL)
  {
    // Default action (terminate) once this handler returns and the signal is unblocked.
    signal(sig, SIG_DFL);
    raise(sig);
  }
  else if (old.sa_handler != SIG_IGN)
    old.sa_handler(sig);  // e.g. roscpp's SIGINT handler: graceful shutdown
  errno = saved_errno;
}
}  // namespace

void installAllOffSignalHandlers()
{
  std::lock_guard<std::mutex> lock(g_signal_mutex);
  if (g_signal_users++ > 0)
    return;
  vest_packet_t off{};
  off.type = VEST_TYPE_COMMAND;
  off.ttl_ms = 0xFFFF;  // all-off: nothing to expire
  // In our version and in version 2 (every vest since version 2 obeys that one; an all-off
  // never hurts, even on a vest this bridge refused).
  uint8_t buf[VEST_PACKET_SIZE + VEST_PACKET_SIZE_V3];
  vest_encode(&off, buf);  // its leading delimiter ends any packet the signal interrupted
  const uint8_t n2 = vest_encode_version(&off, static_cast<uint8_t>(VEST_PROTOCOL_MIN_VERSION), buf + VEST_PACKET_SIZE);
  setFailSafeBytes(buf, VEST_PACKET_SIZE + n2);
  struct sigaction sa;
  std::memset(&sa, 0, sizeof(sa));
  sa.sa_sigaction = &onFatalSignal;
  sa.sa_flags = SA_SIGINFO | SA_RESTART;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &g_old_int);
  sigaction(SIGTERM, &sa, &g_old_term);
}

void removeAllOffSignalHandlers()
{
  std::lock_guard<std::mutex> lock(g_signal_mutex);
  if (g_signal_users == 0 || --g_signal_users > 0)
    return;
  // Restore only if nobody replaced ours in the meantime.
  struct sigaction cur;
  if (sigaction(SIGINT, nullptr, &cur) == 0 && (cur.sa_flags & SA_SIGINFO) && cur.sa_sigaction == &onFatalSignal)
    sigaction(SIGINT, &g_old_int, nullptr);
  if (sigaction(SIGTERM, nullptr, &cur) == 0 && (cur.sa_flags & SA_SIGINFO) && cur.sa_sigaction == &onFatalSignal)
    sigaction(SIGTERM, &g_old_term, nullptr);
}

bool allOffSignalReceived()
{
  return g_signalled.load();
}

}  // namespace assistive_tactile
