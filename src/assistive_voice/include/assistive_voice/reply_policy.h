#pragma once
// When a spoken reply may start: priorities, a rate limit, no repeats, and never over an alert
// (the vest keeps priority over speech). ROS-free; times in seconds on any one clock.
#include <optional>
#include <string>

namespace assistive_voice
{
enum class Priority
{
  INFO = 0,     ///< answers: "where am I", "what is ahead"
  CONFIRM = 1,  ///< confirmations of the wearer's actions: "place two saved"
  WARNING = 2,  ///< the system's state: "I am not sure of the way"
};

struct Reply
{
  std::string text;
  Priority priority = Priority::INFO;
  double stamp = 0.0;  ///< when it was offered
};

struct ReplyPolicyConfig
{
  bool enabled = true;            ///< false: nothing is ever spoken
  double min_interval_s = 2.0;    ///< between the starts of two replies
  double repeat_s = 10.0;         ///< the same text not again within this (after it started)
  double max_age_s = 5.0;         ///< a waiting reply older than this is dropped
  bool silence_on_alert = true;   ///< an ALERT stops speech and holds replies
  double alert_hold_s = 1.5;      ///< ... until this long after the last ALERT
};

/// One waiting slot: a new reply replaces the waiting one unless that one has a higher priority
/// (then the new one is dropped). next() hands out the waiting reply when it may start.
class ReplyPolicy
{
public:
  explicit ReplyPolicy(const ReplyPolicyConfig& c = ReplyPolicyConfig()) : c_(c) {}

  /// Offers a reply at time t. False when it is dropped at once (switched off, a higher-priority
  /// reply is waiting, or the same text started less than repeat_s ago).
  bool offer(const std::string& text, Priority p, double t);
  /// An ALERT cue at time t. True when speech must stop now (silence_on_alert).
  bool alert(double t);
  /// True while replies are held by an alert.
  bool silenced(double t) const;
  /// The reply to start at time t, if one may; it counts as started at t.
  std::optional<Reply> next(double t);
  bool waiting() const { return pending_.has_value(); }
  int dropped() const { return dropped_; }

private:
  ReplyPolicyConfig c_;
  std::optional<Reply> pending_;
  double last_start_ = -1e18;
  double last_alert_ = -1e18;
  std::string last_text_;
  int dropped_ = 0;
};
}  // namespace assistive_voice
