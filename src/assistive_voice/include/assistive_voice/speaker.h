#pragma once
// Spoken replies with espeak-ng's library (Debian libespeak-ng-dev). espeak-ng is one engine per
// process: open it once, in one of two ways. ROS-free.
//   Speaker::openPlayback(): replies play on the default sound output (espeak-ng's own audio
//     output) asynchronously; stop() cuts a reply short (an ALERT).
//   Speaker::openSynthesis(): replies are synthesised into samples (to a WAV file, the benchmark).
#include <cstdint>
#include <string>
#include <vector>

#include "assistive_voice/audio.h"

namespace assistive_voice
{
class Speaker
{
public:
  /// Opens espeak-ng for playback. False when it cannot (no data, no sound output).
  static bool openPlayback(std::string* err = nullptr);
  /// Opens espeak-ng for synthesis into memory.
  static bool openSynthesis(std::string* err = nullptr);
  /// The engine's sample rate (22050 Hz for espeak-ng's voices).
  static int sampleRate();

  /// Sets the voice ("en-us", "en-gb+f3") and speaking rate (words per minute).
  static bool setVoice(const std::string& voice, int rate_wpm);
  /// Playback: starts speaking (returns at once). Synthesis: no effect, returns false.
  static bool say(const std::string& text);
  /// Synthesis: the reply's samples at sampleRate(). Playback: empty.
  static Audio synth(const std::string& text);
  /// Stops speech now (playback).
  static void stop();
  /// True while playback is speaking.
  static bool speaking();
};
}  // namespace assistive_voice
