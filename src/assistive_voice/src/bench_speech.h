#pragma once
// voice_benchmark's speech and noise (never on the device): the development set's voices
// (espeak-ng, the engine the grammar and the thresholds were chosen on), the test set's voices
// (flite and festival, Debian's other engines, synthesised at run time: nothing is downloaded),
// and generated street, cafe and indoor noise. Deterministic: fixed voices, rates and seeds.
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace assistive_voice
{
namespace bench
{
/// A voice of the test set: an engine (`flite` or `festival`) and one of its packaged voices.
struct TestVoice
{
  std::string engine;
  std::string voice;
  std::string label() const { return engine + ":" + voice; }
};

/// flite's four 16 kHz voices and festival's three packaged English voices (Debian packages flite,
/// festival, festvox-kallpc16k, festvox-kdlpc16k, festvox-us-slt-hts).
const std::vector<TestVoice>& testVoices();
/// Duration stretches of the test set (slow, fast): 1.2 = 20 % slower than the voice's default.
const std::vector<double>& testStretches();

/// espeak-ng speech at 16 kHz (Speaker::openSynthesis() first), silence trimmed.
std::vector<float> speakDev(const std::string& text, const std::string& voice, int rate_wpm);
/// flite / festival speech at 16 kHz, silence trimmed, peak normalised to 12000; empty when the
/// engine cannot run (prints why once).
std::vector<float> speakTest(const std::string& text, const TestVoice& v, double stretch);

double rms(const std::vector<float>& v, size_t a, size_t b);
/// Street: brown rumble, engine hum with a slow swell, passing cars (noise swells), rare horns.
std::vector<float> streetNoise(size_t n, std::mt19937& rng);
/// Cafe: babble of four talkers from `babble` (reversed: speech-shaped without words, as the
/// development set has it; forward: words, as a real cafe), clatter, hiss.
std::vector<float> cafeNoise(size_t n, std::mt19937& rng,
                             const std::vector<std::vector<float>>& babble, bool reversed);
/// Indoor: ventilation (low-passed noise), a fridge's mains hum, a distant television (speech
/// from `tv`, muffled and echoing), footsteps and a door now and then.
std::vector<float> indoorNoise(size_t n, std::mt19937& rng,
                               const std::vector<std::vector<float>>& tv);
/// speech + noise scaled to `snr_db` (speech RMS over the speech spans, noise RMS over the clip).
std::vector<int16_t> mix(const std::vector<float>& clean,
                         const std::vector<std::pair<size_t, size_t>>& spans,
                         const std::vector<float>& noise, double snr_db);
}  // namespace bench
}  // namespace assistive_voice
