#pragma once
// Audio helpers: 16-bit PCM WAV read/write and linear resampling. ROS-free.
#include <cstdint>
#include <string>
#include <vector>

namespace assistive_voice
{
constexpr int RECOGNIZER_RATE = 16000;  ///< pocketsphinx's en-us model: 16 kHz mono

struct Audio
{
  int rate = RECOGNIZER_RATE;
  std::vector<int16_t> samples;  ///< mono
};

/// Reads a PCM 16-bit WAV (channels averaged to mono). False (and *err) when it cannot.
bool readWav(const std::string& path, Audio* out, std::string* err = nullptr);
/// Writes mono PCM 16-bit.
bool writeWav(const std::string& path, const Audio& a);
/// Linear-interpolation resampling to `rate`.
Audio resample(const Audio& a, int rate);
/// The WAV files a path names: itself (*.wav) or the lines of a list file (relative to the list's
/// folder; blank lines and # comments skipped).
std::vector<std::string> wavList(const std::string& path);
}  // namespace assistive_voice
