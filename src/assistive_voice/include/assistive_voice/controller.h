#pragma once
// The wearer's controls as one state machine: buttons and voice commands become actions (service
// requests, the cue pause) and spoken replies; service results and cues become replies. ROS-free:
// the nodelet performs the effects (calls the services, publishes, speaks through ReplyPolicy).
#include <map>
#include <optional>
#include <string>

#include "assistive_voice/commands.h"
#include "assistive_voice/reply_policy.h"

namespace assistive_voice
{
/// assistive_msgs/TactileCue modes (kept in step with the message).
constexpr int CUE_IDLE = 0;
constexpr int CUE_GUIDANCE = 1;
constexpr int CUE_PROXIMITY = 2;
constexpr int CUE_ALERT = 3;
constexpr int CUE_UNSURE = 4;

/// The wearer's head on the ground plane of `map` (x, y in m; yaw in rad, 0 = +x, counter-clockwise).
struct Pose2
{
  double x = 0, y = 0, yaw = 0;
};

/// What the nodelet must do after an event. Unset members: nothing to do.
struct Effects
{
  Command command;                     ///< the command acted on (NONE: none)
  std::optional<std::string> tag;      ///< call slam/tag_place with this name ("" = SLAM's place<N>)
  std::optional<std::string> guide;    ///< call slam/guide_to_place with this name ("" = the last tagged)
  std::optional<bool> pause;           ///< publish the cue pause (true = paused)
  std::optional<Reply> reply;          ///< offer to the ReplyPolicy
  bool listen = false;                 ///< open a listening window for a yes / no answer
};

class VoiceController
{
public:
  /// confirm_s: how long a consequential voice command waits for its confirmation (0: none).
  explicit VoiceController(double unsure_warn_s = 2.0, double confirm_s = 6.0)
    : unsure_warn_s_(unsure_warn_s), confirm_s_(confirm_s)
  {
  }

  /// A command acted on at once at time t (button, script, typed text).
  Effects onCommand(const Command& c, double t);
  /// A recognised voice command. A consequential one (guide back) is not acted on yet: the reply
  /// names what was understood and asks for a yes or a button press within confirm_s. While a
  /// question is open: yes confirms, no cancels, another command replaces the question.
  Effects onVoiceCommand(const Command& c, double t);
  /// A button press (sensor_msgs/Joy value: 1 short, 2 long) through the action table; while a
  /// question is open any press confirms instead.
  Effects onButton(int button, int press, double t);
  /// Time passing: an unanswered question is cancelled after confirm_s (silence cancels).
  Effects onTime(double t);
  /// True while a consequential command waits for its confirmation.
  bool awaitingConfirmation() const { return pending_.has_value(); }
  /// A command heard without enough confidence (Recognition::rejected): nothing is done but the
  /// wearer is asked to say it again.
  Effects onRejected(double t);
  /// slam/tag_place answered: `name` as stored, `where` the head's pose when known.
  Effects onTagResult(bool ok, const std::string& name, const std::optional<Pose2>& where, double t);
  /// slam/guide_to_place answered for the requested name ("" = the last tagged).
  Effects onGuideResult(bool ok, const std::string& requested, double t);
  /// A cue of the cue logic (mode, reason); UNSURE for unsure_warn_s gives one warning per episode.
  Effects onCue(int mode, const std::string& reason, double t);
  /// The wearer's current pose (nullopt: not localised).
  void setPose(const std::optional<Pose2>& p) { pose_ = p; }

  bool paused() const { return paused_; }
  const std::map<std::string, Pose2>& places() const { return places_; }

  /// "where am I": the nearest saved place, how far and to which side.
  std::string whereAmI() const;
  /// "what is ahead": the last cue in words.
  std::string whatIsAhead() const;

private:
  Effects cancel(const std::string& why, double t);

  double unsure_warn_s_;
  double confirm_s_;
  std::optional<Command> pending_;  ///< waits for yes / a button press
  double pending_since_ = 0;
  bool paused_ = false;
  std::optional<Pose2> pose_;
  std::map<std::string, Pose2> places_;
  std::string last_saved_;
  int last_mode_ = -1;
  std::string last_reason_;
  double unsure_since_ = -1;
  bool unsure_warned_ = false;
};

/// A cue reason made speakable: "m" -> "metres", "deg" -> "degrees".
std::string speakable(const std::string& reason);
}  // namespace assistive_voice
