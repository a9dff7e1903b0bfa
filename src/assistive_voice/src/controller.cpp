#include "assistive_voice/controller.h"

#include <cmath>
#include <sstream>

namespace assistive_voice
{
namespace
{
Reply reply(const std::string& text, Priority p, double t)
{
  return Reply{text, p, t};
}
/// "the door", but "place two" (SLAM's own names take no article).
std::string theName(const std::string& name)
{
  const std::string s = spokenName(name);
  return s.rfind("place ", 0) == 0 ? s : "the " + s;
}
}  // namespace

std::string speakable(const std::string& reason)
{
  std::istringstream in(reason);
  std::string w, out;
  while (in >> w)
  {
    if (w == "m")
      w = "metres";
    else if (w == "deg")
      w = "degrees";
    out += (out.empty() ? "" : " ") + w;
  }
  return out;
}

Effects VoiceController::onCommand(const Command& c, double t)
{
  Effects e;
  e.command = c;
  switch (c.action)
  {
    case Action::SAVE_PLACE:
      e.tag = c.name;
      break;
    case Action::GUIDE_BACK:
      e.guide = c.name;
      break;
    case Action::TOGGLE_PAUSE:
      return onCommand(Command{paused_ ? Action::RESUME : Action::PAUSE, ""}, t);
    case Action::PAUSE:
      paused_ = true;
      e.pause = true;
      e.reply = reply("cues paused", Priority::CONFIRM, t);
      break;
    case Action::RESUME:
      paused_ = false;
      e.pause = false;
      e.reply = reply("cues resumed", Priority::CONFIRM, t);
      break;
    case Action::WHERE_AM_I:
      e.reply = reply(whereAmI(), Priority::INFO, t);
      break;
    case Action::WHAT_IS_AHEAD:
      e.reply = reply(whatIsAhead(), Priority::INFO, t);
      break;
    case Action::YES:
    case Action::NO:  // an answer with no question open
    case Action::NONE:
      break;
  }
  return e;
}

Effects VoiceController::onVoiceCommand(const Command& c, double t)
{
  if (pending_ && c.action == Action::YES)
  {
    const Command confirmed = *pending_;
    pending_.reset();
    return onCommand(confirmed, t);
  }
  if (pending_ && c.action == Action::NO)
    return cancel("cancelled", t);
  pending_.reset();  // another command replaces the question
  if (c.action != Action::GUIDE_BACK || confirm_s_ <= 0)
    return onCommand(c, t);
  pending_ = c;
  pending_since_ = t;
  Effects e;
  const std::string what =
      c.name.empty() ? "take me back to the last place" : "take me back to " + theName(c.name);
  e.reply = reply(what + "? say yes or press a button", Priority::CONFIRM, t);
  e.listen = true;
  return e;
}

Effects VoiceController::onButton(int button, int press, double t)
{
  if (pending_ && press != PRESS_NONE)
    return onVoiceCommand(Command{Action::YES, ""}, t);
  return onCommand(Command{buttonAction(button, press), ""}, t);
}

Effects VoiceController::onTime(double t)
{
  if (pending_ && t - pending_since_ >= confirm_s_)
    return cancel("cancelled", t);
  return Effects();
}

Effects VoiceController::cancel(const std::string& why, double t)
{
  pending_.reset();
  Effects e;
  e.reply = reply(why, Priority::CONFIRM, t);
  return e;
}

Effects VoiceController::onRejected(double t)
{
  Effects e;
  e.reply = reply("say again", Priority::CONFIRM, t);
  e.listen = pending_.has_value();  // the question stays open: listen for the answer again
  return e;
}

Effects VoiceController::onTagResult(bool ok, const std::string& name, const std::optional<Pose2>& where, double t)
{
  Effects e;
  if (!ok)
  {
    e.reply = reply("I cannot save this place yet", Priority::CONFIRM, t);
    return e;
  }
  last_saved_ = name;
  if (where)
    places_[name] = *where;
  e.reply = reply(spokenName(name) + " saved", Priority::CONFIRM, t);
  return e;
}

Effects VoiceController::onGuideResult(bool ok, const std::string& requested, double t)
{
  Effects e;
  const std::string name = requested.empty() ? last_saved_ : requested;
  if (!ok)
    e.reply = reply(name.empty() && places_.empty() ? "no place is saved" : "I cannot guide you back", Priority::CONFIRM, t);
  else
    e.reply = reply(name.empty() ? "guiding back" : "guiding back to " + theName(name), Priority::CONFIRM, t);
  return e;
}

Effects VoiceController::onCue(int mode, const std::string& reason, double t)
{
  Effects e;
  last_mode_ = mode;
  last_reason_ = reason;
  if (mode != CUE_UNSURE)
  {
    unsure_since_ = -1;
    unsure_warned_ = false;
    return e;
  }
  if (unsure_since_ < 0)
    unsure_since_ = t;
  if (!unsure_warned_ && unsure_warn_s_ > 0 && t - unsure_since_ >= unsure_warn_s_)
  {
    unsure_warned_ = true;
    e.reply = reply("I am not sure of the way", Priority::WARNING, t);
  }
  return e;
}

std::string VoiceController::whereAmI() const
{
  if (!pose_)
    return "I do not know where I am";
  if (places_.empty())
    return "no place is saved";
  const std::pair<const std::string, Pose2>* best = nullptr;
  double best_d = 1e18;
  for (const auto& p : places_)
  {
    const double d = std::hypot(p.second.x - pose_->x, p.second.y - pose_->y);
    if (d < best_d)
    {
      best_d = d;
      best = &p;
    }
  }
  const std::string name = theName(best->first);
  const int metres = static_cast<int>(std::lround(best_d));
  if (metres < 1)
    return "you are at " + name;
  double b = std::atan2(best->second.y - pose_->y, best->second.x - pose_->x) - pose_->yaw;
  b = std::atan2(std::sin(b), std::cos(b));
  const double deg = b * 180.0 / M_PI;
  const char* side = std::abs(deg) <= 45 ? "ahead" : std::abs(deg) >= 135 ? "behind you" : deg > 0 ? "to your left" : "to your right";
  return name + " is " + numberWords(metres) + (metres == 1 ? " metre " : " metres ") + side;
}

std::string VoiceController::whatIsAhead() const
{
  switch (last_mode_)
  {
    case CUE_IDLE: return "the way ahead is clear";
    case CUE_GUIDANCE: return last_reason_.empty() ? "turn as the vest says" : speakable(last_reason_);
    case CUE_PROXIMITY: return last_reason_.empty() ? "an obstacle is close" : speakable(last_reason_);
    case CUE_ALERT: return "stop";
    case CUE_UNSURE: return "I am not sure of the way";
    default: return "I have no cues yet";
  }
}
}  // namespace assistive_voice
