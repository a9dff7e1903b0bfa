#pragma once
// The wearer's commands: the spoken grammar (JSGF, for pocketsphinx's grammar search), the parser
// from recognised text to a command, and the action table that maps vest button presses onto the
// same actions. ROS-free.
#include <string>
#include <vector>

namespace assistive_voice
{
/// What the wearer asked for. Buttons and voice commands end in the same actions.
enum class Action
{
  NONE,           ///< nothing (text outside the grammar, an unmapped press)
  SAVE_PLACE,     ///< tag the current place (slam/tag_place), optional name
  GUIDE_BACK,     ///< guide back to a place (slam/guide_to_place), empty name: the last saved
  TOGGLE_PAUSE,   ///< pause the cues if running, resume them if paused (short B)
  PAUSE,          ///< pause the cues
  RESUME,         ///< resume the cues
  WHERE_AM_I,     ///< the nearest saved place, its distance and side
  WHAT_IS_AHEAD,  ///< what the cue logic sees ahead (its last cue's reason)
  YES,            ///< the answer to a confirmation question (confirmGrammar())
  NO,             ///< the answer to a confirmation question: cancel
};

/// A command: an action and, for SAVE_PLACE / GUIDE_BACK, an optional place name.
struct Command
{
  Action action = Action::NONE;
  std::string name;
  bool operator==(const Command& o) const { return action == o.action && name == o.name; }
};

/// The action's name for logs and topics ("save_place", "guide_back", ...).
const char* actionName(Action a);

/// The place names the grammar knows (a name may be more than one word: "bus stop").
const std::vector<std::string>& defaultPlaceNames();

/// The command grammar as a JSGF string (grammar `vest`, public rule `command`):
///   save place [<name>] | take me back [to [the] <name>] | pause | resume | where am i | what is ahead
std::string commandGrammar(const std::vector<std::string>& names = defaultPlaceNames());

/// The answer to a confirmation question as a JSGF string (grammar `confirm`): yes | no. A search
/// of its own: "no" in the command grammar would swallow noise and short words.
std::string confirmGrammar();

/// Lower-cases, drops punctuation and pocketsphinx's alternates ("the(2)") and fillers
/// ("<sil>", "[noise]"), and collapses spaces.
std::string normalizeText(const std::string& text);

/// The command a recognised sentence asks for; Action::NONE when it is not a sentence of the
/// grammar. A name after "save place" / "take me back to [the]" is taken as it is (scripted text may
/// name any place); an unparsable tail makes the sentence NONE.
Command parseCommand(const std::string& text);

/// Button indices of the vest's sensor_msgs/Joy (`buttons[0]` = A, `buttons[1]` = B) and press
/// values (1 = short, 2 = long, on the message of the press; 0 = no press).
constexpr int BUTTON_A = 0;
constexpr int BUTTON_B = 1;
constexpr int PRESS_NONE = 0;
constexpr int PRESS_SHORT = 1;
constexpr int PRESS_LONG = 2;

/// The action table: short A = save place, long A = guide back to the last saved place,
/// short B = pause / resume cues, long B = where am I; anything else NONE.
Action buttonAction(int button, int press);

/// A place name as spoken: "place2" -> "place two", "bus_stop" -> "bus stop".
std::string spokenName(const std::string& name);
/// 0..99 in words ("two", "twenty one"); other numbers as digits.
std::string numberWords(int n);
}  // namespace assistive_voice
