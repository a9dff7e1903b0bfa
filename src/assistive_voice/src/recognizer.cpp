#include "assistive_voice/recognizer.h"

#include <pocketsphinx.h>

#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <algorithm>
#include <stdexcept>

#include "assistive_voice/audio.h"
#include "assistive_voice/commands.h"

namespace assistive_voice
{
namespace
{
constexpr size_t SLICE = 320;  // 20 ms: the decision granularity

/// pocketsphinx's configuration: the model, the detector's hangover, then `extra` ("-name value").
cmd_ln_t* decoderConfig(const RecognizerConfig& c, const std::string& extra)
{
  std::vector<std::string> args = {"recognizer", "-hmm", c.hmm, "-dict", c.dict, "-logfn",
                                   "/dev/null", "-vad_postspeech",
                                   std::to_string(c.vad_postspeech_frames)};
  std::istringstream in(extra);
  for (std::string w; in >> w;)
    args.push_back(w);
  std::vector<char*> argv;
  for (std::string& a : args)
    argv.push_back(a.data());
  return cmd_ln_parse_r(nullptr, ps_args(), static_cast<int32>(argv.size()), argv.data(), TRUE);
}

/// A command no word can extend: acted on as soon as its hypothesis is stable.
bool closed(const Command& c)
{
  return c.action != Action::NONE && !((c.action == Action::SAVE_PLACE || c.action == Action::GUIDE_BACK) && c.name.empty());
}
}  // namespace

RecognizerConfig recognizerConfig(const VoiceParams& p)
{
  RecognizerConfig c;
  c.mode = p.listen_mode;
  c.keyphrase = p.keyphrase;
  c.max_utterance_s = p.max_utterance_s;
  c.listen_window_s = p.listen_window_s;
  c.stable_s = p.stable_s;
  c.vad_postspeech_frames = p.vad_postspeech_frames;
  c.hmm = p.hmm;
  c.dict = p.dict;
  c.decoder_args = p.decoder_args;
  c.phone_lm = p.phone_lm;
  c.min_confidence = p.min_confidence;
  c.min_confidence_wake = p.min_confidence_wake;
  return c;
}

Recognizer::Recognizer(const RecognizerConfig& c) : c_(c), keyphrase_(normalizeText(c.keyphrase))
{
  config_ = decoderConfig(c_, c_.decoder_args);
  if (!config_)
    throw std::runtime_error("pocketsphinx: bad configuration (hmm " + c_.hmm + ", dict " +
                             c_.dict + ", decoder_args '" + c_.decoder_args + "')");
  ps_ = ps_init(config_);
  if (!ps_)
    throw std::runtime_error("pocketsphinx: cannot load the model " + c_.hmm);
  const std::string grammar = commandGrammar();
  if (ps_set_jsgf_string(ps_, "command", grammar.c_str()) < 0)
    throw std::runtime_error("pocketsphinx: the command grammar does not load (words missing from the dictionary?)");
  if (ps_set_jsgf_string(ps_, "confirm", confirmGrammar().c_str()) < 0)
    throw std::runtime_error("pocketsphinx: the yes / no grammar does not load");
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
  if (!c_.phone_lm.empty())
  {
    // Same front end (and voice activity detector) as the grammar decoder: same frames.
    // Context-independent phones: the context-dependent loop cost 20 times the grammar's CPU.
    loop_config_ = decoderConfig(c_, c_.decoder_args + " -allphone_ci yes");
    loop_ = loop_config_ ? ps_init(loop_config_) : nullptr;
    if (!loop_ || ps_set_allphone_file(loop_, "loop", c_.phone_lm.c_str()) < 0 ||
        ps_set_search(loop_, "loop") < 0)
      throw std::runtime_error("pocketsphinx: the phone loop does not load (phone_lm " +
                               c_.phone_lm + ")");
  }
  reset();
}

Recognizer::~Recognizer()
{
  if (ps_)
    ps_free(ps_);
  if (config_)
    cmd_ln_free_r(config_);
  if (loop_)
    ps_free(loop_);
  if (loop_config_)
    cmd_ln_free_r(loop_config_);
}

void Recognizer::startUtt(const char* search)
{
  ps_set_search(ps_, search);
  ps_start_utt(ps_);
  if (loop_)
    ps_start_utt(loop_);
}

void Recognizer::endUtt()
{
  ps_end_utt(ps_);
  if (loop_)
    ps_end_utt(loop_);
}

std::string Recognizer::endWithConfidence(double* confidence)
{
  endUtt();
  int32 score = 0;
  const char* h = ps_get_hyp(ps_, &score);
  *confidence = std::numeric_limits<double>::quiet_NaN();
  if (loop_ && h)
  {
    // Whole paths (acoustic and language scores, silence included): on the development set this
    // separated right from wrong better than the acoustic scores of the words' frames alone.
    int32 loop_score = 0;
    ps_get_hyp(loop_, &loop_score);
    *confidence = (double(score) - double(loop_score)) / std::max(1, ps_get_n_frames(ps_));
  }
  return h ? h : "";
}

void Recognizer::reset()
{
  if (state_ != State::IDLE)
    endUtt();
  state_ = State::IDLE;
  if (c_.mode == "keyword")
    startSpotting();
}

void Recognizer::startSpotting()
{
  startUtt("wake");
  state_ = State::SPOTTING;
  window_start_ = fed_;
  speech_start_ = -1;
  hyp_.clear();
  hyp_since_ = fed_;
}

void Recognizer::startCommand(const char* search)
{
  if (state_ != State::IDLE)
    endUtt();
  startUtt(search);
  state_ = State::COMMAND;
  window_start_ = fed_;
  speech_start_ = -1;
  hyp_.clear();
  hyp_since_ = fed_;
}

void Recognizer::listen(bool answer)
{
  startCommand(answer ? "confirm" : "command");
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
  if (loop_)
    ps_process_raw(loop_, s, n, FALSE, FALSE);
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
    endUtt();  // silence or steady noise only: restart to bound the utterance
    startSpotting();
  }
}

void Recognizer::finish(bool reject, std::vector<Recognition>* out)
{
  const State was = state_;
  double conf = 0;
  const std::string h = endWithConfidence(&conf);
  const std::string text = reject ? "" : command(h);
  const double threshold = was == State::SPOTTING ? c_.min_confidence_wake : c_.min_confidence;
  // NaN (no phone loop) never rejects
  const bool low = conf < threshold;
  if (was == State::SPOTTING)
  {
    if (low)
      startSpotting();  // not the keyphrase: other talk stays unanswered
    else if (!text.empty())
    {
      out->push_back(Recognition{keyphrase_, fed_, true, conf, false});
      out->push_back(Recognition{text, fed_, false, conf, false});
      startSpotting();
    }
    else if (!reject && normalizeText(h.empty() ? hyp_ : h).rfind(keyphrase_, 0) == 0)
    {
      // the keyphrase alone (the wearer paused after it): the command follows in a window
      out->push_back(Recognition{keyphrase_, fed_, true, conf, false});
      state_ = State::IDLE;
      startCommand();
    }
    else
      startSpotting();
    return;
  }
  out->push_back(Recognition{text, fed_, false, conf, !text.empty() && low});
  state_ = State::IDLE;
  if (c_.mode == "keyword")
    startSpotting();
}
}  // namespace assistive_voice
