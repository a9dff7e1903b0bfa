#pragma once
// Audio cleanup before recognition (issue 38): noise suppression and automatic gain from a Debian
// library, on 10 ms frames, in the device's audio thread and in voice_benchmark alike.
//   off   : samples pass unchanged (the default: no cleanup improved recognition, see README)
//   speex : speexdsp's preprocessor (libspeexdsp: spectral noise suppression, AGC)
// WebRTC's audio processing (libwebrtc-audio-processing 0.3, high-pass, noise suppression, adaptive
// digital gain) was measured too and did worse than speex on both sets: not kept. Voice activity
// detection stays pocketsphinx's (it cuts the utterances). ROS-free.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace assistive_voice
{
class AudioCleaner
{
public:
  /// `kind`: off | speex; throws std::invalid_argument for another kind or when the
  /// library cannot start. 16 kHz mono.
  explicit AudioCleaner(const std::string& kind);
  ~AudioCleaner();
  AudioCleaner(const AudioCleaner&) = delete;
  AudioCleaner& operator=(const AudioCleaner&) = delete;

  /// Cleans `n` samples. Output is delayed by less than one 10 ms frame: the samples of the
  /// frames completed so far (fewer than n, or more, as frames complete).
  std::vector<int16_t> process(const int16_t* s, size_t n);
  /// Forgets the buffered partial frame (between unrelated clips); the adaptive state stays.
  void clearBuffer() { pending_.clear(); }
  const std::string& kind() const { return kind_; }

private:
  struct Impl;
  std::string kind_;
  std::unique_ptr<Impl> impl_;
  std::vector<int16_t> pending_;  ///< a partial frame
};
}  // namespace assistive_voice
