// The audio cleanup: framing (10 ms, nothing lost), off is a pass-through, speexdsp suppresses
// steady noise. Synthetic input, fixed seed.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "assistive_voice/audio_cleaner.h"

using namespace assistive_voice;

namespace
{
double rms(const std::vector<int16_t>& v, size_t from)
{
  double s = 0;
  for (size_t i = from; i < v.size(); ++i)
    s += double(v[i]) * v[i];
  return std::sqrt(s / double(v.size() - from));
}

/// 3 s of white noise (RMS 1000) cleaned in 20 ms chunks, as the nodelet feeds it.
std::vector<int16_t> cleanNoise(AudioCleaner& c)
{
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1000);
  std::vector<int16_t> in(48000), out;
  for (auto& x : in)
    x = static_cast<int16_t>(std::lround(g(rng)));
  for (size_t i = 0; i < in.size(); i += 320)
  {
    const std::vector<int16_t> o = c.process(in.data() + i, 320);
    out.insert(out.end(), o.begin(), o.end());
  }
  return out;
}
}  // namespace

TEST(AudioCleaner, OffPassesSamplesUnchanged)
{
  AudioCleaner c("off");
  const std::vector<int16_t> in = {1, -2, 3, 32767, -32768};
  EXPECT_EQ(c.process(in.data(), in.size()), in);
  EXPECT_THROW(AudioCleaner("loud"), std::invalid_argument);
  EXPECT_THROW(AudioCleaner("webrtc"), std::invalid_argument);  // measured, not kept
}

TEST(AudioCleaner, WholeTenMillisecondFramesNothingLost)
{
  AudioCleaner c("speex");
  const std::vector<int16_t> in(250, 100);
  EXPECT_EQ(c.process(in.data(), 250).size(), 160u);  // one frame, 90 samples wait
  EXPECT_EQ(c.process(in.data(), 70).size(), 160u);   // 90 + 70: the second frame
  EXPECT_EQ(c.process(in.data(), 159).size(), 0u);
  c.clearBuffer();
  EXPECT_EQ(c.process(in.data(), 1).size(), 0u);
}

TEST(AudioCleaner, SteadyNoiseIsSuppressed)
{
  AudioCleaner c("speex");
  const std::vector<int16_t> out = cleanNoise(c);
  ASSERT_EQ(out.size(), 48000u);
  // after 1 s of adaptation the noise is at least 6 dB down (AGC included)
  EXPECT_LT(rms(out, 16000), 500.0);
}
