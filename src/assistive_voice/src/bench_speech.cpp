#include "bench_speech.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "assistive_voice/audio.h"
#include "assistive_voice/speaker.h"

namespace assistive_voice
{
namespace bench
{
namespace
{
constexpr int FS = RECOGNIZER_RATE;

/// Silence trimmed: from the first to the last sample above 2 % of the peak.
std::vector<float> trimmed(const std::vector<int16_t>& s)
{
  int peak = 1;
  for (int16_t x : s)
    peak = std::max(peak, std::abs(int(x)));
  size_t b = 0, e = s.size();
  while (b < e && std::abs(int(s[b])) < peak / 50)
    ++b;
  while (e > b && std::abs(int(s[e - 1])) < peak / 50)
    --e;
  return std::vector<float>(s.begin() + b, s.begin() + e);
}

/// Runs a shell command and returns its stdout.
std::string capture(const std::string& cmd)
{
  std::string out;
  FILE* f = popen(cmd.c_str(), "r");
  if (!f)
    return out;
  char buf[65536];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, f)) > 0)
    out.append(buf, n);
  pclose(f);
  return out;
}

/// 16-bit mono samples of a RIFF stream written to a pipe (its size fields may be 0) or of raw.
Audio parseStream(const std::string& bytes, int raw_rate)
{
  Audio a;
  a.rate = raw_rate;
  size_t at = 0;
  if (bytes.size() >= 44 && bytes.compare(0, 4, "RIFF") == 0)
  {
    uint32_t rate = 0;
    std::memcpy(&rate, bytes.data() + 24, 4);
    a.rate = static_cast<int>(rate);
    const size_t d = bytes.find("data", 12);
    at = d == std::string::npos ? bytes.size() : d + 8;
  }
  a.samples.resize((bytes.size() - at) / 2);
  std::memcpy(a.samples.data(), bytes.data() + at, a.samples.size() * 2);
  return a;
}

std::string quoted(const std::string& text)
{
  std::string q = "'";
  for (char c : text)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void lowpass(std::vector<float>& v, double fc)
{
  const double a = std::exp(-2 * M_PI * fc / FS);
  double y = 0;
  for (float& x : v)
    x = static_cast<float>(y = (1 - a) * x + a * y);
}

size_t secs(double s)
{
  return static_cast<size_t>(s * FS);
}
}  // namespace

const std::vector<TestVoice>& testVoices()
{
  static const std::vector<TestVoice> v = {{"flite", "kal16"},
                                           {"flite", "awb"},
                                           {"flite", "rms"},
                                           {"flite", "slt"},
                                           {"festival", "kal_diphone"},
                                           {"festival", "ked_diphone"},
                                           {"festival", "cmu_us_slt_arctic_hts"}};
  return v;
}

const std::vector<double>& testStretches()
{
  static const std::vector<double> s = {1.2, 0.85};
  return s;
}

std::vector<float> speakDev(const std::string& text, const std::string& voice, int rate_wpm)
{
  Speaker::setVoice(voice, rate_wpm);
  return trimmed(resample(Speaker::synth(text), FS).samples);
}

std::vector<float> speakTest(const std::string& text, const TestVoice& v, double stretch)
{
  char s[32];
  std::string cmd;
  if (v.engine == "flite")
  {
    std::snprintf(s, sizeof s, "%.3f", stretch);
    cmd = "flite -voice " + v.voice + " --setf duration_stretch=" + s + " -t " + quoted(text) +
          " -o /dev/stdout 2>/dev/null";
  }
  else
  {
    // diphone voices take Duration_Stretch; the HTS voice its engine's speed (-r, 1/stretch)
    const bool hts = v.voice.find("hts") != std::string::npos;
    std::snprintf(s, sizeof s, "%.3f", hts ? 1.0 / stretch : stretch);
    const std::string rate =
        hts ? "(set! hts_engine_params (append hts_engine_params (list (list \"-r\" " +
                  std::string(s) + "))))"
            : "(Parameter.set (quote Duration_Stretch) " + std::string(s) + ")";
    cmd = "echo " + quoted(text) + " | text2wave -F 16000 -otype raw -o /dev/stdout -eval " +
          quoted("(voice_" + v.voice + ")") + " -eval " + quoted(rate) + " 2>/dev/null";
  }
  const Audio a = resample(parseStream(capture(cmd), 16000), FS);
  if (a.samples.size() < 1600)
  {
    static bool told = false;
    if (!told)
      std::cerr << "voice_benchmark: no speech from `" << cmd << "`\n";
    told = true;
    return {};
  }
  std::vector<float> out = trimmed(a.samples);
  float peak = 1;
  for (float x : out)
    peak = std::max(peak, std::abs(x));
  for (float& x : out)
    x *= 12000.0f / peak;
  return out;
}

double rms(const std::vector<float>& v, size_t a, size_t b)
{
  double s = 0;
  for (size_t i = a; i < b; ++i)
    s += double(v[i]) * v[i];
  return b > a ? std::sqrt(s / (b - a)) : 0.0;
}

std::vector<float> streetNoise(size_t n, std::mt19937& rng)
{
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<float> v(n), hiss(n);
  double brown = 0;
  for (size_t i = 0; i < n; ++i)
  {
    brown = 0.998 * brown + 0.05 * g(rng);
    hiss[i] = static_cast<float>(g(rng));
    const double t = double(i) / FS;
    const double hum = (0.6 + 0.4 * std::sin(2 * M_PI * 0.13 * t)) *
                       (std::sin(2 * M_PI * 70 * t) + 0.5 * std::sin(2 * M_PI * 140 * t));
    v[i] = static_cast<float>(brown + 0.3 * hum);
  }
  lowpass(hiss, 1500);
  // cars: a swell of hiss every ~4 s on average, 3 s long
  for (size_t c = secs(u(rng) * 4); c < n; c += secs(2 + 4 * u(rng)))
    for (size_t i = 0; i < 3 * FS && c + i < n; ++i)
      v[c + i] += static_cast<float>(2.0 * std::sin(M_PI * i / (3.0 * FS)) * hiss[c + i]);
  // horns: 0.3 s two-tone, every ~15 s on average
  for (size_t c = secs(u(rng) * 15); c < n; c += secs(8 + 14 * u(rng)))
    for (size_t i = 0; i < 0.3 * FS && c + i < n; ++i)
    {
      const double t = double(i) / FS;
      v[c + i] +=
          static_cast<float>(0.8 * (std::sin(2 * M_PI * 415 * t) + std::sin(2 * M_PI * 523 * t)));
    }
  return v;
}

std::vector<float> cafeNoise(size_t n, std::mt19937& rng,
                             const std::vector<std::vector<float>>& babble, bool reversed)
{
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<float> v(n, 0.0f);
  for (int talker = 0; talker < 4; ++talker)
  {
    size_t at = secs(u(rng));
    while (at < n)
    {
      const auto& s = babble[static_cast<size_t>(u(rng) * babble.size()) % babble.size()];
      const double gain = (0.5 + 0.5 * u(rng)) / 8000.0;
      for (size_t i = 0; i < s.size() && at + i < n; ++i)
        v[at + i] += static_cast<float>(gain * s[reversed ? s.size() - 1 - i : i]);
      at += s.size() + secs(u(rng) * 0.8);
    }
  }
  std::vector<float> hiss(n);
  for (auto& h : hiss)
    h = static_cast<float>(0.05 * g(rng));
  lowpass(hiss, 3000);
  for (size_t i = 0; i < n; ++i)
    v[i] += hiss[i];
  // clatter: decaying high-pitched clicks, ~1 per second
  for (size_t c = secs(u(rng)); c < n; c += secs(0.3 + 1.4 * u(rng)))
  {
    const double f = 2500 + 3000 * u(rng), amp = 0.3 + 0.7 * u(rng);
    for (size_t i = 0; i < 0.08 * FS && c + i < n; ++i)
      v[c + i] += static_cast<float>(amp * std::exp(-double(i) / (0.015 * FS)) *
                                     std::sin(2 * M_PI * f * i / FS));
  }
  return v;
}

std::vector<float> indoorNoise(size_t n, std::mt19937& rng,
                               const std::vector<std::vector<float>>& tv)
{
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<float> v(n), air(n), speech(n, 0.0f);
  for (auto& a : air)
    a = static_cast<float>(g(rng));
  lowpass(air, 600);
  lowpass(air, 600);
  for (size_t i = 0; i < n; ++i)
  {
    const double t = double(i) / FS;
    v[i] = static_cast<float>(
        3.0 * air[i] + 0.08 * (std::sin(2 * M_PI * 50 * t) + 0.4 * std::sin(2 * M_PI * 100 * t)));
  }
  // a television in the next room: speech low-passed, with two echoes
  for (size_t at = secs(u(rng)); at < n;)
  {
    const auto& s = tv[static_cast<size_t>(u(rng) * tv.size()) % tv.size()];
    for (size_t i = 0; i < s.size() && at + i < n; ++i)
      speech[at + i] += s[i] / 12000.0f;
    at += s.size() + secs(0.2 + 0.6 * u(rng));
  }
  lowpass(speech, 1200);
  for (size_t i = n; i-- > 0;)
    speech[i] += (i >= secs(0.03) ? 0.5f * speech[i - secs(0.03)] : 0.0f) +
                 (i >= secs(0.07) ? 0.25f * speech[i - secs(0.07)] : 0.0f);
  for (size_t i = 0; i < n; ++i)
    v[i] += 0.6f * speech[i];
  // footsteps and doors: low thumps, every ~3 s on average
  for (size_t c = secs(u(rng) * 3); c < n; c += secs(1 + 4 * u(rng)))
  {
    const double amp = 0.5 + 1.5 * u(rng), f = 60 + 80 * u(rng);
    for (size_t i = 0; i < 0.15 * FS && c + i < n; ++i)
      v[c + i] += static_cast<float>(amp * std::exp(-double(i) / (0.03 * FS)) *
                                     std::sin(2 * M_PI * f * i / FS));
  }
  return v;
}

std::vector<int16_t> mix(const std::vector<float>& clean,
                         const std::vector<std::pair<size_t, size_t>>& spans,
                         const std::vector<float>& noise, double snr_db)
{
  double ps = 0;
  size_t ns = 0;
  for (const auto& sp : spans)
    for (size_t i = sp.first; i < sp.second; ++i, ++ns)
      ps += double(clean[i]) * clean[i];
  const double speech_rms = ns ? std::sqrt(ps / ns) : 1000.0;
  const double noise_rms = std::max(1e-9, rms(noise, 0, noise.size()));
  const double k = speech_rms / std::pow(10.0, snr_db / 20.0) / noise_rms;
  std::vector<int16_t> out(clean.size());
  for (size_t i = 0; i < clean.size(); ++i)
    out[i] =
        static_cast<int16_t>(std::clamp(std::lround(clean[i] + k * noise[i]), -32768L, 32767L));
  return out;
}
}  // namespace bench
}  // namespace assistive_voice
