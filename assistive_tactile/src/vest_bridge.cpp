#include "assistive_tactile/vest_bridge.h"

#include <poll.h>

#include <algorithm>
#include <cmath>

namespace assistive_tactile
{
VestBridge::VestBridge(const BridgeParams& p) : params_(p)
{
  vest_parser_init(&parser_);
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
  send(now);  // tell the vest the current state right away
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
    {
      stats_.open = false;
      stats_.losses++;
      stats_.last_error = err;
      next_open_time_ = now + params_.reopen_s;
      return false;
    }
    stats_.bytes_written += static_cast<uint64_t>(n);
    pending_.erase(pending_.begin(), pending_.begin() + n);
    if (!pending_.empty())
    {
      stats_.packets_skipped++;
      return false;
    }
  }
  const std::array<uint8_t, VEST_NUM_MOTORS> duty =
      stats_.cue_stale ? std::array<uint8_t, VEST_NUM_MOTORS>{ { 0, 0, 0, 0 } } : duty_;
  vest_packet_t p{};
  p.type = VEST_TYPE_COMMAND;
  p.seq = static_cast<uint8_t>(stats_.seq + 1);
  for (unsigned i = 0; i < VEST_NUM_MOTORS; ++i)
  {
    p.intensity[i] = duty[i];
    if (duty[i] > 0)
      p.motors = static_cast<uint8_t>(p.motors | (1u << i));
  }
  uint8_t buf[VEST_PACKET_SIZE];
  vest_encode(&p, buf);
  const ssize_t n = port_.write(buf, sizeof(buf), &err);
  if (n < 0)
  {
    stats_.open = false;
    stats_.losses++;
    stats_.last_error = err;
    next_open_time_ = now + params_.reopen_s;
    return false;
  }
  stats_.bytes_written += static_cast<uint64_t>(n);
  if (n == 0)
  {
    stats_.packets_skipped++;  // nothing taken: the next re-send carries the state
    return false;
  }
  stats_.seq = p.seq;
  stats_.packets_sent++;
  sent_duty_ = duty;
  if (static_cast<size_t>(n) < sizeof(buf))
    pending_.assign(buf + n, buf + sizeof(buf));
  return true;
}

bool VestBridge::setCue(const std::array<float, VEST_NUM_MOTORS>& intensity, double now)
{
  for (unsigned i = 0; i < VEST_NUM_MOTORS; ++i)
    duty_[i] = toDuty(intensity[i]);
  last_cue_time_ = now;
  stats_.cue_stale = false;
  if (shut_down_)
    return false;
  return send(now);
}

void VestBridge::readReplies()
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
    const uint16_t skipped0 = parser_.skipped, rejected0 = parser_.rejected;
    for (ssize_t i = 0; i < n; ++i)
    {
      vest_packet_t p;
      if (vest_parser_feed(&parser_, buf[i], &p) && p.type == VEST_TYPE_STATUS)
      {
        stats_.status_packets++;
        stats_.last_status = p;
      }
    }
    stats_.garbage_bytes += static_cast<uint16_t>(parser_.skipped - skipped0);
    stats_.rejected_packets += static_cast<uint16_t>(parser_.rejected - rejected0);
  }
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
    stats_.open = false;
    stats_.losses++;
    stats_.last_error = err;
    next_open_time_ = now + params_.reopen_s;
    return;
  }
  const uint64_t before = stats_.status_packets;
  readReplies();
  if (stats_.status_packets != before)
    stats_.last_status_time = now;
  if (!port_.isOpen())
  {
    next_open_time_ = now + params_.reopen_s;
    return;
  }
  const bool stale = (now - last_cue_time_) > params_.stale_s;
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

}  // namespace assistive_tactile

namespace assistive_tactile
{
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
}  // namespace assistive_tactile
