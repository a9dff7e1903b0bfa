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
};

class VoiceController
{
public:
  explicit VoiceController(double unsure_warn_s = 2.0) : unsure_warn_s_(unsure_warn_s) {}

  /// A command (voice, script or button) at time t.
  Effects onCommand(const Command& c, double t);
  /// A button press (sensor_msgs/Joy value: 1 short, 2 long) through the action table.
  Effects onButton(int button, int press, double t) { return onCommand(Command{buttonAction(button, press), ""}, t); }
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
  double unsure_warn_s_;
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
