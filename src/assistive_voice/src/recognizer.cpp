#include "assistive_voice/recognizer.h"

#include <pocketsphinx.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "assistive_voice/audio.h"
#include "assistive_voice/commands.h"

namespace assistive_voice
{
namespace
{
constexpr size_t SLICE = 320;  // 20 ms: the decision granularity

/// A command no word can extend: acted on as soon as its hypothesis is stable.
bool closed(const Command& c)
{
  return c.action != Action::NONE && !((c.action == Action::SAVE_PLACE || c.action == Action::GUIDE_BACK) && c.name.empty());
}
}  // namespace

Recognizer::Recognizer(const RecognizerConfig& c) : c_(c), keyphrase_(normalizeText(c.keyphrase))
{
  const std::string postspeech = std::to_string(c_.vad_postspeech_frames);
  config_ = cmd_ln_init(nullptr, ps_args(), TRUE, "-hmm", c_.hmm.c_str(), "-dict", c_.dict.c_str(), "-logfn", "/dev/null",
                        "-vad_postspeech", postspeech.c_str(), nullptr);
  if (!config_)
    throw std::runtime_error("pocketsphinx: bad configuration (hmm " + c_.hmm + ", dict " + c_.dict + ")");
  ps_ = ps_init(config_);
  if (!ps_)
    throw std::runtime_error("pocketsphinx: cannot load the model " + c_.hmm);
  const std::string grammar = commandGrammar();
  if (ps_set_jsgf_string(ps_, "command", grammar.c_str()) < 0)
    throw std::runtime_error("pocketsphinx: the command grammar does not load (words missing from the dictionary?)");
  if (c_.mode == "keyword")
  {
    if (keyphrase_.empty())
      throw std::runtime_error("keyword mode needs a keyphrase");
    std::string wake = grammar;
    wake.replace(wake.find("public <command>"), 6, "");  // one public rule: <wake>
    wake += "public <wake> = " + keyphrase_ + " <command>;\n";
    if (ps_set_jsgf_string(ps_, "wake", wake.c_str()) < 0)
      throw std::runtime_error("pocketsphinx: keyphrase '" + c_.keyphrase + "' does not load (words missing from the dictionary?)");
  }
  else if (c_.mode != "push_to_talk")
    throw std::runtime_error("recognizer mode must be keyword or push_to_talk, not '" + c_.mode + "'");
  reset();
}

Recognizer::~Recognizer()
{
  if (ps_)
    ps_free(ps_);
  if (config_)
    cmd_ln_free_r(config_);
}

void Recognizer::reset()
{
  if (state_ != State::IDLE)
    ps_end_utt(ps_);
  state_ = State::IDLE;
  if (c_.mode == "keyword")
    startSpotting();
}

void Recognizer::startSpotting()
{
  ps_set_search(ps_, "wake");
  ps_start_utt(ps_);
  state_ = State::SPOTTING;
  window_start_ = fed_;
  speech_start_ = -1;
  hyp_.clear();
  hyp_since_ = fed_;
}

void Recognizer::startCommand()
{
  if (state_ != State::IDLE)
    ps_end_utt(ps_);
  ps_set_search(ps_, "command");
  ps_start_utt(ps_);
  state_ = State::COMMAND;
  window_start_ = fed_;
  speech_start_ = -1;
  hyp_.clear();
  hyp_since_ = fed_;
}

void Recognizer::listen()
{
  startCommand();
}

std::vector<Recognition> Recognizer::feed(const int16_t* s, size_t n)
{
  std::vector<Recognition> out;
  for (size_t i = 0; i < n; i += SLICE)
    feedSlice(s + i, std::min(SLICE, n - i), &out);
  return out;
}

std::string Recognizer::command(const std::string& hyp) const
{
  std::string s = normalizeText(hyp);
  if (state_ == State::SPOTTING)
  {
    if (s.compare(0, keyphrase_.size(), keyphrase_) != 0 || s.size() <= keyphrase_.size() + 1)
      return "";
    s = s.substr(keyphrase_.size() + 1);
  }
  return parseCommand(s).action == Action::NONE ? "" : s;
}

void Recognizer::feedSlice(const int16_t* s, size_t n, std::vector<Recognition>* out)
{
  fed_ += static_cast<int64_t>(n);
  if (state_ == State::IDLE)
    return;  // push-to-talk, no window: nothing is decoded
  ps_process_raw(ps_, s, n, FALSE, FALSE);
  const bool in_speech = ps_get_in_speech(ps_);
  if (in_speech && speech_start_ < 0)
    speech_start_ = fed_;
  int32 score = 0;
  const char* h = ps_get_hyp(ps_, &score);
  const std::string hyp = h ? h : "";
  if (hyp != hyp_)
  {
    hyp_ = hyp;
    hyp_since_ = fed_;
  }
  const std::string cmd = command(hyp_);
  const bool stable = !cmd.empty() && closed(parseCommand(cmd)) &&
                      (fed_ - hyp_since_) >= static_cast<int64_t>(c_.stable_s * RECOGNIZER_RATE);
  const bool ended = speech_start_ >= 0 && !in_speech;
  const bool too_long = speech_start_ >= 0 && fed_ - speech_start_ > static_cast<int64_t>(c_.max_utterance_s * RECOGNIZER_RATE);
  const bool timeout = state_ == State::COMMAND && (fed_ - window_start_) >= static_cast<int64_t>(c_.listen_window_s * RECOGNIZER_RATE);
  if (too_long)
    finish(true, out);
  else if (stable || ended || timeout)
    finish(false, out);
  else if (state_ == State::SPOTTING && speech_start_ < 0 && fed_ - window_start_ > 10 * RECOGNIZER_RATE)
  {
    ps_end_utt(ps_);  // silence or steady noise only: restart to bound the utterance
    startSpotting();
  }
}

void Recognizer::finish(bool reject, std::vector<Recognition>* out)
{
  const State was = state_;
  ps_end_utt(ps_);
  int32 score = 0;
  const char* h = ps_get_hyp(ps_, &score);
  const std::string text = reject ? "" : command(h ? h : "");
  if (was == State::SPOTTING)
  {
    if (!text.empty())
    {
      out->push_back(Recognition{keyphrase_, fed_, true});
      out->push_back(Recognition{text, fed_, false});
      startSpotting();
    }
    else if (!reject && normalizeText(h ? h : hyp_).rfind(keyphrase_, 0) == 0)
    {
      // the keyphrase alone (the wearer paused after it): the command follows in a window
      out->push_back(Recognition{keyphrase_, fed_, true});
      state_ = State::IDLE;
      startCommand();
    }
    else
      startSpotting();
    return;
  }
  out->push_back(Recognition{text, fed_, false});
  state_ = State::IDLE;
  if (c_.mode == "keyword")
    startSpotting();
}
}  // namespace assistive_voice
