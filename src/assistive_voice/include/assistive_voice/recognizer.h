#pragma once
// Offline recognition of the command grammar with Debian bookworm's pocketsphinx
// (0.8+5prealpha: the sphinxbase cmd_ln_t API; pocketsphinx 5.0's ps_config_t API is not what
// bookworm ships). Two JSGF searches: `wake` (the keyphrase followed by a command) and `command`
// (a command alone, commands.h). Modes:
//   keyword      : `wake` runs all the time on utterances cut by pocketsphinx's voice activity
//                  detector; an utterance that is the keyphrase and a command is a command.
//                  (pocketsphinx's own keyphrase search, `kws`, detected nothing in bookworm's
//                  build on espeak-ng speech at any threshold, so the keyphrase is part of the
//                  grammar.)
//   push_to_talk : nothing is decoded until listen() (a button) opens a window of `command`.
// An utterance is decided when its hypothesis is a complete command that no word can extend
// (e.g. "where am i", "save place door", not "save place") unchanged for stable_s, at the end of
// speech, or after listen_window_s; an utterance longer than max_utterance_s is no command.
// Rejection: a second decoder runs a phone loop (pocketsphinx's allphone search, the open
// alternative: any speech) on the same audio; the confidence of a decision is the grammar path's
// score minus the phone loop's, per frame of the utterance. Below min_confidence
// (min_confidence_wake for the keyphrase search) the utterance is rejected: "say again" in a
// command window, silence when spotting the keyphrase. ROS-free.
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "assistive_voice/params.h"

struct ps_decoder_s;
struct cmd_ln_s;

namespace assistive_voice
{
struct RecognizerConfig
{
  std::string mode = "keyword";  ///< keyword | push_to_talk
  std::string keyphrase = "hello navigator";
  double listen_window_s = 4.0;
  double stable_s = 0.3;
  int vad_postspeech_frames = 30;
  std::string hmm = "/usr/share/pocketsphinx/model/en-us/en-us";
  std::string dict = "/usr/share/pocketsphinx/model/en-us/cmudict-en-us.dict";
  std::string decoder_args;  ///< more pocketsphinx arguments, "-name value ..." (both decoders)
  double max_utterance_s = 4.0;  ///< longer speech is no command (sentences forced onto the grammar)
  /// The phone loop's language model; empty: no rejection (every decision is acted on).
  std::string phone_lm = "/usr/share/pocketsphinx/model/en-us/en-us-phone.lm.bin";
  double min_confidence = -1e9;       ///< command windows (push-to-talk, after the keyphrase)
  double min_confidence_wake = -1e9;  ///< keyphrase + command utterances (keyword mode)
};

struct Recognition
{
  std::string text;        ///< the grammar sentence ("" when the window closed with nothing)
  int64_t decided_at = 0;  ///< samples fed (since construction) when it was decided
  bool keyword = false;    ///< true: the keyphrase was heard (reported just before its command)
  /// Grammar minus phone loop path score per 10 ms frame (pocketsphinx's log scale); NaN without
  /// a phone loop.
  double confidence = std::numeric_limits<double>::quiet_NaN();
  /// true: a command was decoded but its confidence is below the threshold: nothing is done and
  /// the wearer hears "say again"; `text` keeps what was decoded (logs, the benchmark).
  bool rejected = false;
};

/// The recognizer's part of the nodelet's parameters (mode = listen_mode).
RecognizerConfig recognizerConfig(const VoiceParams& p);

class Recognizer
{
public:
  /// Loads the model (about 0.5 s); throws std::runtime_error when pocketsphinx cannot start.
  explicit Recognizer(const RecognizerConfig& c);
  ~Recognizer();
  Recognizer(const Recognizer&) = delete;
  Recognizer& operator=(const Recognizer&) = delete;

  /// Opens a command window now (push-to-talk; in keyword mode as if the keyphrase was heard);
  /// `answer`: a window for the answer to a confirmation question (yes | no) instead.
  void listen(bool answer = false);
  /// True while a command window is open.
  bool listening() const { return state_ == State::COMMAND; }
  /// Feeds 16 kHz mono samples; returns what was decided while they were decoded (keyphrase
  /// detections and command windows closing, in order).
  std::vector<Recognition> feed(const int16_t* s, size_t n);
  /// Closes any window and restarts the idle state (between unrelated clips).
  void reset();
  int64_t samplesFed() const { return fed_; }

private:
  enum class State { IDLE, SPOTTING, COMMAND };
  void startSpotting();
  void startCommand(const char* search = "command");
  void feedSlice(const int16_t* s, size_t n, std::vector<Recognition>* out);
  void finish(bool timeout, std::vector<Recognition>* out);
  void startUtt(const char* search);
  void endUtt();
  /// Ends the utterance: the grammar's final hypothesis and its confidence against the phone loop.
  std::string endWithConfidence(double* confidence);
  std::string command(const std::string& hyp) const;  ///< the command sentence in a hypothesis, or ""

  RecognizerConfig c_;
  cmd_ln_s* config_ = nullptr;
  ps_decoder_s* ps_ = nullptr;
  cmd_ln_s* loop_config_ = nullptr;
  ps_decoder_s* loop_ = nullptr;  ///< the phone loop (nullptr: no rejection)
  State state_ = State::IDLE;
  int64_t fed_ = 0;
  std::string keyphrase_;  ///< normalised
  int64_t window_start_ = 0;
  int64_t speech_start_ = -1;
  bool speech_seen_ = false;
  std::string hyp_;
  int64_t hyp_since_ = 0;
};
}  // namespace assistive_voice
