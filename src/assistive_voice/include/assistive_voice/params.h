#pragma once
// The voice nodelet's parameters: ONE table (assistive_common/param_table.h). The README table
// and config/default.yaml are checked against it (test_params).
#include <string>

#include <assistive_common/param_table.h>

namespace assistive_voice
{
// clang-format off
// X(type, field, ROS name, default, lo, hi, unit, text)
#define ASSISTIVE_VOICE_PARAMS(X) \
  /* Listening */ \
  X(std::string, listen_mode, "listen_mode", "push_to_talk", {}, {}, "", "default push_to_talk: keyword mode hears a command right 0.37 of the time on voice_benchmark's test set (false commands held to 1 per 10 min by the wake rejection); `keyword`: always listening, a command follows the keyphrase (in one breath or after a pause); `push_to_talk`: a long B press opens a listening window (long B is then no longer where-am-I: say it); `off`: buttons and command_text only") \
  X(std::string, keyphrase, "keyphrase", "hello navigator", {}, {}, "", "the keyphrase (words of pocketsphinx's dictionary; longer = fewer false commands)") \
  X(double, max_utterance_s, "max_utterance_s", 4.0, 1.0, 30.0, "s", "longer speech is no command (other talk forced onto the grammar)") \
  X(double, listen_window_s, "listen_window_s", 4.0, 0.5, 30.0, "s", "after the keyword or the push-to-talk press, a command must end within this") \
  X(double, stable_s, "stable_s", 0.3, 0.05, 2.0, "s", "a complete command whose hypothesis has not changed for this long is acted on (before the end-of-speech detector)") \
  X(int, vad_postspeech_frames, "vad_postspeech_frames", 30, 5, 200, "10 ms", "silence that ends an utterance (pocketsphinx -vad_postspeech)") \
  X(std::string, hmm, "hmm", "/usr/share/pocketsphinx/model/en-us/en-us", {}, {}, "", "acoustic model (Debian pocketsphinx-en-us)") \
  X(std::string, dict, "dict", "/usr/share/pocketsphinx/model/en-us/cmudict-en-us.dict", {}, {}, "", "pronunciation dictionary") \
  X(std::string, audio_cleanup, "audio_cleanup", "off", {}, {}, "", "noise suppression and automatic gain before recognition: `off` or `speex` (speexdsp's preprocessor; it did not improve voice_benchmark on either set, WebRTC's did worse and is gone)") \
  X(std::string, decoder_args, "decoder_args", "", {}, {}, "", "more pocketsphinx arguments for both decoders, `-name value ...` (e.g. `-beam 1e-60`)") \
  /* Rejection (issue 38): the grammar's score against a phone loop's, per 10 ms frame */ \
  X(std::string, phone_lm, "phone_lm", "/usr/share/pocketsphinx/model/en-us/en-us-phone.lm.bin", {}, {}, "", "the phone loop's model (Debian pocketsphinx-en-us): the open alternative a command is scored against; empty: no rejection, every decoded command is acted on") \
  X(double, min_confidence, "min_confidence", 7.5, -1000.0, 1000.0, "score/frame", "a command (push-to-talk, or after the keyphrase alone) scoring below this against the phone loop is not acted on: the wearer hears say again (7.5: no wrong action on voice_benchmark's development set)") \
  X(double, min_confidence_wake, "min_confidence_wake", 12.0, -1000.0, 1000.0, "score/frame", "keyword mode: a keyphrase (with or without its command) scoring below this against the phone loop is ignored, other talk gets no answer (12: no false command in 10 min of the development set's unrelated speech)") \
  /* Audio input */ \
  X(std::string, audio_input, "audio_input", "", {}, {}, "", "empty: no audio (buttons, command_text and script only); `mic`: mic_command's output; a .wav file (16 kHz mono int16 or resampled) or a text file listing .wav files, played at wall-clock rate") \
  X(std::string, mic_command, "mic_command", "sox -q -d -t raw -r 16000 -c 1 -b 16 -e signed-integer -", {}, {}, "", "command whose stdout is raw 16 kHz mono int16 from the default microphone (sox through ALSA/PulseAudio)") \
  X(double, audio_gap_s, "audio_gap_s", 2.0, 0.0, 60.0, "s", "silence fed before and between the files of a WAV list") \
  /* Scripted commands (replay, tests) */ \
  X(std::string, script, "script", "", {}, {}, "", "timed commands `T text; T text; ...`, T in s of ROS time after the first non-zero ROS time the nodelet sees (a replay: the bag start)") \
  /* Replies */ \
  X(bool, speech, "speech", true, {}, {}, "", "speak replies (false: only the `reply` topic)") \
  X(std::string, speech_output, "speech_output", "default", {}, {}, "", "`default`: the default sound output (espeak-ng playback); a directory: each reply written as reply_NNN.wav there") \
  X(std::string, voice, "voice", "en-us", {}, {}, "", "espeak-ng voice") \
  X(int, speech_rate_wpm, "speech_rate_wpm", 175, 80, 450, "words/min", "espeak-ng speaking rate") \
  X(double, min_interval_s, "min_interval_s", 2.0, 0.0, 60.0, "s", "a reply starts at the earliest this long after the previous one started") \
  X(double, repeat_s, "repeat_s", 10.0, 0.0, 600.0, "s", "the same text is not spoken again within this") \
  X(double, max_age_s, "max_age_s", 5.0, 0.1, 60.0, "s", "a reply still waiting after this is dropped") \
  X(bool, silence_on_alert, "silence_on_alert", true, {}, {}, "", "an ALERT cue stops speech and holds replies until alert_hold_s after the last ALERT") \
  X(double, alert_hold_s, "alert_hold_s", 1.5, 0.0, 30.0, "s", "quiet time after the last ALERT cue") \
  X(std::string, map_frame, "map_frame", "map", {}, {}, "", "frame of the saved places (SLAM's map)") \
  X(std::string, head_frame, "head_frame", "camera_link", {}, {}, "", "the wearer's head (x forward): where am I is answered from map_frame -> head_frame") \
  X(double, confirm_s, "confirm_s", 6.0, 0.0, 30.0, "s", "a consequential voice command (take me back) waits this long for yes or a button press; no or silence cancels it (0: acted on at once)") \
  X(double, unsure_warn_s, "unsure_warn_s", 2.0, 0.0, 60.0, "s", "UNSURE cues for this long give a spoken warning (0: never)")
// clang-format on

struct VoiceParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_VOICE_PARAMS)
};
}  // namespace assistive_voice
