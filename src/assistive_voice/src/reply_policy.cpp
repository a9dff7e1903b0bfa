#include "assistive_voice/reply_policy.h"

namespace assistive_voice
{
bool ReplyPolicy::offer(const std::string& text, Priority p, double t)
{
  if (!c_.enabled || text.empty())
  {
    ++dropped_;
    return false;
  }
  if (text == last_text_ && t - last_start_ < c_.repeat_s)
  {
    ++dropped_;
    return false;
  }
  if (pending_ && pending_->priority > p && t - pending_->stamp <= c_.max_age_s)
  {
    ++dropped_;
    return false;
  }
  if (pending_)
    ++dropped_;  // the waiting one is replaced
  pending_ = Reply{text, p, t};
  return true;
}

bool ReplyPolicy::alert(double t)
{
  last_alert_ = t;
  return c_.silence_on_alert;
}

bool ReplyPolicy::silenced(double t) const
{
  return c_.silence_on_alert && t - last_alert_ < c_.alert_hold_s;
}

std::optional<Reply> ReplyPolicy::next(double t)
{
  if (!pending_)
    return std::nullopt;
  if (t - pending_->stamp > c_.max_age_s)
  {
    pending_.reset();
    ++dropped_;
    return std::nullopt;
  }
  if (silenced(t) || t - last_start_ < c_.min_interval_s)
    return std::nullopt;
  Reply r = *pending_;
  pending_.reset();
  last_start_ = t;
  last_text_ = r.text;
  return r;
}
}  // namespace assistive_voice
