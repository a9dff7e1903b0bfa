// voice_benchmark: the wearer's voice commands, measured offline (no roscore, no microphone).
// Every command of the grammar is spoken by espeak-ng in several voices and two rates, mixed with
// generated street and cafe noise at 10 dB SNR, and decoded by the Recognizer as the nodelet runs
// it (keyword mode: "<keyphrase>, <command>"; push-to-talk: the command alone). Unrelated sentences
// read by espeak-ng over the same noise give the false commands; noise alone the idle CPU.
// Readable table, then one JSON line (SPEC "Benchmarks").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <assistive_eval/benchmark.h>

#include "assistive_voice/audio.h"
#include "assistive_voice/commands.h"
#include "assistive_voice/controller.h"
#include "assistive_voice/params.h"
#include "assistive_voice/recognizer.h"
#include "assistive_voice/speaker.h"

using namespace assistive_voice;
namespace ae = assistive_eval;

namespace
{
constexpr int FS = RECOGNIZER_RATE;

// Every shape of the grammar (names, with and without "the").
const std::vector<std::string> COMMANDS = {
    "save place", "save place door", "save place kitchen", "save place bus stop", "take me back",
    "take me back to the door", "take me back to the office", "take me back to car", "pause", "resume",
    "where am i", "what is ahead"};
// Fixed before measuring: two US, one British, one Caribbean; one female variant.
const std::vector<std::string> VOICES = {"en-us", "en-gb", "en-us+f3", "en-029"};
const std::vector<int> RATES = {150, 200};
// Unrelated speech, some with the commands' words in other sentences.
const std::vector<std::string> SENTENCES = {
    "The bus to the city centre leaves every ten minutes from the other side of the road.",
    "Could you tell me whether the pharmacy is still open at this time of the evening?",
    "I would like a large coffee with milk and a slice of that chocolate cake, please.",
    "We walked along the river for an hour before it started to rain again.",
    "Please pause the music for a moment while I answer the phone.",
    "She said she would take me back to the station after the meeting.",
    "Where is the nearest place to buy a newspaper around here?",
    "The weather forecast says it will be sunny tomorrow with a light breeze from the west.",
    "My brother is moving to a new flat near the park next month.",
    "Can we resume the conversation about the holiday plans after lunch?",
    "The train was delayed because of a signal failure outside the main station.",
    "There is a new bakery that opened just ahead of the traffic lights.",
    "I left my umbrella at the office, so I got completely wet on the way home.",
    "Do you remember the name of the restaurant where we had dinner last week?",
    "The children are playing football in the garden behind the school.",
    "Save some of the soup for later, it tastes even better the next day.",
    "He asked the waiter for the bill and left a small tip on the table.",
    "What time does the film start on Saturday evening?",
    "The library is closed on Sundays but the reading room opens at nine.",
    "Turn left at the corner and you will see the entrance to the car park.",
};

double rms(const std::vector<float>& v, size_t a, size_t b)
{
  double s = 0;
  for (size_t i = a; i < b; ++i)
    s += double(v[i]) * v[i];
  return b > a ? std::sqrt(s / (b - a)) : 0.0;
}

/// espeak-ng speech at 16 kHz, silence trimmed (first/last sample above 2 % of the peak).
std::vector<float> speak(const std::string& text, const std::string& voice, int rate)
{
  Speaker::setVoice(voice, rate);
  const Audio a = resample(Speaker::synth(text), FS);
  int peak = 1;
  for (int16_t s : a.samples)
    peak = std::max(peak, std::abs(int(s)));
  size_t b = 0, e = a.samples.size();
  while (b < e && std::abs(int(a.samples[b])) < peak / 50)
    ++b;
  while (e > b && std::abs(int(a.samples[e - 1])) < peak / 50)
    --e;
  return std::vector<float>(a.samples.begin() + b, a.samples.begin() + e);
}

/// One-pole low-pass.
void lowpass(std::vector<float>& v, double fc)
{
  const double a = std::exp(-2 * M_PI * fc / FS);
  double y = 0;
  for (float& x : v)
    x = static_cast<float>(y = (1 - a) * x + a * y);
}

/// Street: brown rumble, engine hum with a slow swell, passing cars (noise swells), rare horns.
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
    const double hum = (0.6 + 0.4 * std::sin(2 * M_PI * 0.13 * t)) * (std::sin(2 * M_PI * 70 * t) + 0.5 * std::sin(2 * M_PI * 140 * t));
    v[i] = static_cast<float>(brown + 0.3 * hum);
  }
  lowpass(hiss, 1500);
  // cars: a swell of hiss every ~4 s on average, 3 s long
  for (size_t c = static_cast<size_t>(u(rng) * 4 * FS); c < n; c += static_cast<size_t>((2 + 4 * u(rng)) * FS))
    for (size_t i = 0; i < 3 * FS && c + i < n; ++i)
      v[c + i] += static_cast<float>(2.0 * std::sin(M_PI * i / (3.0 * FS)) * hiss[c + i]);
  // horns: 0.3 s two-tone, every ~15 s on average
  for (size_t c = static_cast<size_t>(u(rng) * 15 * FS); c < n; c += static_cast<size_t>((8 + 14 * u(rng)) * FS))
    for (size_t i = 0; i < 0.3 * FS && c + i < n; ++i)
    {
      const double t = double(i) / FS;
      v[c + i] += static_cast<float>(0.8 * (std::sin(2 * M_PI * 415 * t) + std::sin(2 * M_PI * 523 * t)));
    }
  return v;
}

/// Cafe: reversed espeak-ng babble of several voices (speech-shaped, no words), clatter, hiss.
std::vector<float> cafeNoise(size_t n, std::mt19937& rng, const std::vector<std::vector<float>>& babble)
{
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<float> v(n, 0.0f);
  for (int talker = 0; talker < 4; ++talker)
  {
    size_t at = static_cast<size_t>(u(rng) * FS);
    while (at < n)
    {
      const auto& s = babble[static_cast<size_t>(u(rng) * babble.size()) % babble.size()];
      const double gain = (0.5 + 0.5 * u(rng)) / 8000.0;
      for (size_t i = 0; i < s.size() && at + i < n; ++i)
        v[at + i] += static_cast<float>(gain * s[s.size() - 1 - i]);
      at += s.size() + static_cast<size_t>(u(rng) * 0.8 * FS);
    }
  }
  std::vector<float> hiss(n);
  for (auto& h : hiss)
    h = static_cast<float>(0.05 * g(rng));
  lowpass(hiss, 3000);
  for (size_t i = 0; i < n; ++i)
    v[i] += hiss[i];
  // clatter: decaying high-pitched clicks, ~1 per second
  for (size_t c = static_cast<size_t>(u(rng) * FS); c < n; c += static_cast<size_t>((0.3 + 1.4 * u(rng)) * FS))
  {
    const double f = 2500 + 3000 * u(rng), amp = 0.3 + 0.7 * u(rng);
    for (size_t i = 0; i < 0.08 * FS && c + i < n; ++i)
      v[c + i] += static_cast<float>(amp * std::exp(-double(i) / (0.015 * FS)) * std::sin(2 * M_PI * f * i / FS));
  }
  return v;
}

/// speech + noise scaled to `snr_db` (speech RMS over the speech samples, noise RMS over all).
std::vector<int16_t> mix(const std::vector<float>& clean, const std::vector<std::pair<size_t, size_t>>& speech_spans,
                         std::vector<float> noise, double snr_db)
{
  double ps = 0;
  size_t ns = 0;
  for (const auto& sp : speech_spans)
    for (size_t i = sp.first; i < sp.second; ++i, ++ns)
      ps += double(clean[i]) * clean[i];
  const double speech_rms = ns ? std::sqrt(ps / ns) : 1000.0;
  const double noise_rms = std::max(1e-9, rms(noise, 0, noise.size()));
  const double k = speech_rms / std::pow(10.0, snr_db / 20.0) / noise_rms;
  std::vector<int16_t> out(clean.size());
  for (size_t i = 0; i < clean.size(); ++i)
    out[i] = static_cast<int16_t>(std::clamp(std::lround(clean[i] + k * noise[i]), -32768L, 32767L));
  return out;
}

struct ClipResult
{
  bool keyword = false;
  std::string text;
  double ms_to_action = NAN;
};

/// Decodes a clip as the nodelet does (20 ms chunks); `speech_end`: the command's last sample.
ClipResult decode(Recognizer& r, const std::vector<int16_t>& clip, size_t speech_end, bool push_to_talk)
{
  r.reset();
  if (push_to_talk)
    r.listen();
  const int64_t base = r.samplesFed();
  ClipResult res;
  VoiceController ctl;
  for (size_t i = 0; i < clip.size(); i += 320)
  {
    ae::Stopwatch sw;
    for (const Recognition& rec : r.feed(clip.data() + i, std::min<size_t>(320, clip.size() - i)))
    {
      if (rec.keyword)
      {
        res.keyword = true;
        continue;
      }
      res.text = rec.text;
      ctl.onCommand(parseCommand(rec.text), 0.0);  // the action, as the nodelet takes it
      const double audio_ms = 1000.0 * (double(rec.decided_at - base) - double(speech_end)) / FS;
      res.ms_to_action = std::max(0.0, audio_ms) + sw.wallMs();
      return res;
    }
  }
  return res;
}
}  // namespace

int main(int argc, char** argv)
{
  const std::string usage =
      "usage: voice_benchmark [--snr DB] [--minutes M] [--seed N] [--ptt-only] [--set name=value]...\n"
      "  Every command of the grammar spoken by espeak-ng (voices en-us, en-gb, en-us+f3, en-029; 150 and 200\n"
      "  words/min) over generated street and cafe noise at --snr dB (10), decoded in keyword mode (the default)\n"
      "  and in push-to-talk mode; --minutes (10) of unrelated sentences over noise for the false commands.\n";
  double snr = 10.0, minutes = 10.0;
  long seed = 1;
  bool ptt_only = false;
  ae::CommandLine::Sets sets;
  ae::CommandLine cl("voice_benchmark", usage);
  cl.number("--snr", &snr).number("--minutes", &minutes).count("--seed", &seed, 0L).flag("--ptt-only", &ptt_only).sets(&sets);
  if (const int rc = cl.parse(argc, argv); rc >= 0)
    return rc;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  VoiceParams p;
  if (!ae::applySets(cl, sets, p))
    return 2;
  std::string err;
  if (!Speaker::openSynthesis(&err))
  {
    std::cerr << "voice_benchmark: " << err << "\n";
    return 1;
  }
  RecognizerConfig kc;
  kc.mode = "keyword";
  kc.keyphrase = p.keyphrase;
  kc.max_utterance_s = p.max_utterance_s;
  kc.listen_window_s = p.listen_window_s;
  kc.stable_s = p.stable_s;
  kc.vad_postspeech_frames = p.vad_postspeech_frames;
  kc.hmm = p.hmm;
  kc.dict = p.dict;
  RecognizerConfig pc = kc;
  pc.mode = "push_to_talk";
  std::unique_ptr<Recognizer> kws, ptt;
  try
  {
    kws = std::make_unique<Recognizer>(kc);
    ptt = std::make_unique<Recognizer>(pc);
  }
  catch (const std::exception& e)
  {
    std::cerr << "voice_benchmark: " << e.what() << "\n";
    return 1;
  }

  std::mt19937 rng(static_cast<unsigned>(seed));
  std::vector<std::vector<float>> babble;
  for (size_t i = 0; i < SENTENCES.size(); i += 2)
    babble.push_back(speak(SENTENCES[i], VOICES[i / 2 % VOICES.size()], 170));
  const std::vector<std::string> noises = {"street", "cafe"};
  auto noise = [&](const std::string& kind, size_t n) {
    return kind == "street" ? streetNoise(n, rng) : cafeNoise(n, rng, babble);
  };

  // ---- commands
  std::map<std::string, std::pair<int, int>> by_voice, by_noise, by_rate, by_cmd, ptt_by_noise;
  int ok = 0, total = 0, ptt_ok = 0, kw_hits = 0;
  std::vector<double> ms;
  std::vector<std::string> misses;
  for (const std::string& voice : VOICES)
    for (int rate : RATES)
    {
      std::fprintf(stderr, "voice_benchmark: %s at %d words/min (%d of %d right so far)\n", voice.c_str(), rate, ok, total);
      const std::vector<float> key = speak(p.keyphrase, voice, rate);
      for (const std::string& cmd : COMMANDS)
      {
        const std::vector<float> say = speak(cmd, voice, rate);
        const Command want = parseCommand(cmd);
        for (const std::string& nk : noises)
        {
          // keyword mode: 0.8 s, keyphrase, 0.4 s, command, 1.5 s
          const size_t lead = FS * 8 / 10, gap = FS * 4 / 10, tail = FS * 3 / 2;
          std::vector<float> clean(lead + key.size() + gap + say.size() + tail, 0.0f);
          std::copy(key.begin(), key.end(), clean.begin() + lead);
          const size_t cmd_at = lead + key.size() + gap;
          std::copy(say.begin(), say.end(), clean.begin() + cmd_at);
          const std::vector<int16_t> clip =
              mix(clean, {{lead, lead + key.size()}, {cmd_at, cmd_at + say.size()}}, noise(nk, clean.size()), snr);
          bool good_k = false;
          if (!ptt_only)
          {
            const ClipResult rk = decode(*kws, clip, cmd_at + say.size(), false);
            kw_hits += rk.keyword;
            good_k = rk.keyword && parseCommand(rk.text) == want;
            if (good_k)
              ms.push_back(rk.ms_to_action);
            else
              misses.push_back(voice + "/" + std::to_string(rate) + "/" + nk + ": '" + cmd + "' -> " +
                               (rk.keyword ? "'" + rk.text + "'" : "no keyword"));
          }
          // push-to-talk: 0.3 s, command, 1.5 s (the press opens the window at the clip's start)
          const size_t plead = FS * 3 / 10;
          std::vector<float> pclean(plead + say.size() + tail, 0.0f);
          std::copy(say.begin(), say.end(), pclean.begin() + plead);
          const std::vector<int16_t> pclip = mix(pclean, {{plead, plead + say.size()}}, noise(nk, pclean.size()), snr);
          const ClipResult rp = decode(*ptt, pclip, plead + say.size(), true);
          const bool good_p = parseCommand(rp.text) == want;
          if (ptt_only && good_p)
            ms.push_back(rp.ms_to_action);
          const bool good = ptt_only ? good_p : good_k;
          ok += good;
          ptt_ok += good_p;
          ++total;
          for (auto* m : {&by_voice, &by_noise, &by_rate, &by_cmd})
          {
            const std::string key_name = m == &by_voice ? voice : m == &by_noise ? nk : m == &by_rate ? std::to_string(rate) : cmd;
            (*m)[key_name].first += good;
            (*m)[key_name].second += 1;
          }
          ptt_by_noise[nk].first += good_p;
          ptt_by_noise[nk].second += 1;
        }
      }
    }

  // ---- false commands: unrelated sentences over noise, keyword mode, as one long stream
  const size_t stream_n = static_cast<size_t>(minutes * 60 * FS);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<float> clean(stream_n, 0.0f);
  std::vector<std::pair<size_t, size_t>> spans;
  size_t at = FS;
  double speech_s = 0;
  while (at < stream_n)
  {
    const std::vector<float> s = speak(SENTENCES[static_cast<size_t>(u(rng) * SENTENCES.size()) % SENTENCES.size()],
                                       VOICES[static_cast<size_t>(u(rng) * VOICES.size()) % VOICES.size()],
                                       RATES[static_cast<size_t>(u(rng) * RATES.size()) % RATES.size()]);
    const size_t end = std::min(stream_n, at + s.size());
    std::copy(s.begin(), s.begin() + (end - at), clean.begin() + at);
    spans.emplace_back(at, end);
    speech_s += double(end - at) / FS;
    at = end + static_cast<size_t>((0.5 + 1.5 * u(rng)) * FS);
  }
  // the noise alternates street and cafe every minute
  std::vector<float> nz(stream_n);
  for (size_t s = 0; s < stream_n; s += 60 * FS)
  {
    const size_t n = std::min<size_t>(60 * FS, stream_n - s);
    const std::vector<float> part = noise(noises[(s / (60 * FS)) % 2], n);
    const double r = std::max(1e-9, rms(part, 0, n));
    for (size_t i = 0; i < n; ++i)
      nz[s + i] = static_cast<float>(part[i] / r * 1000.0);
  }
  const std::vector<int16_t> stream = mix(clean, spans, nz, snr);
  int false_cmds = 0, false_keywords = 0;
  std::vector<std::string> false_texts;
  kws->reset();
  for (size_t i = 0; i < stream.size(); i += 320)
    for (const Recognition& rec : kws->feed(stream.data() + i, std::min<size_t>(320, stream.size() - i)))
    {
      if (rec.keyword)
        ++false_keywords;
      else if (!rec.text.empty())
      {
        ++false_cmds;
        false_texts.push_back(rec.text);
      }
    }
  const double stream_min = double(stream_n) / FS / 60.0;

  // ---- idle CPU: 60 s of noise only, keyword mode, fed in 20 ms chunks
  std::vector<float> idle_clean(60 * FS, 0.0f);
  std::vector<float> idle_noise = noise("street", 30 * FS), idle_cafe = noise("cafe", 30 * FS);
  idle_noise.insert(idle_noise.end(), idle_cafe.begin(), idle_cafe.end());
  const float idle_gain = 300.0f / static_cast<float>(std::max(1e-9, rms(idle_noise, 0, idle_noise.size())));
  for (auto& x : idle_noise)
    x *= idle_gain;
  std::vector<int16_t> idle(idle_noise.size());
  for (size_t i = 0; i < idle.size(); ++i)
    idle[i] = static_cast<int16_t>(std::clamp(std::lround(idle_noise[i]), -32768L, 32767L));
  kws->reset();
  const double cpu0 = ae::threadCpuMs();
  int idle_events = 0;
  for (size_t i = 0; i < idle.size(); i += 320)
    idle_events += static_cast<int>(kws->feed(idle.data() + i, std::min<size_t>(320, idle.size() - i)).size());
  const double idle_cpu_pct = (ae::threadCpuMs() - cpu0) / (1000.0 * idle.size() / FS) * 100.0;

  // ---- report
  const double acc = total ? double(ok) / total : NAN;
  const double acc_ptt = total ? double(ptt_ok) / total : NAN;
  const double fc10 = false_cmds / stream_min * 10.0;
  const double p95 = ae::percentileNearestRank(ms, 0.95);
  std::printf("voice_benchmark: %zu commands x %zu voices x %zu rates x %zu noises at %.0f dB SNR, mode %s\n",
              COMMANDS.size(), VOICES.size(), RATES.size(), noises.size(), snr, ptt_only ? "push_to_talk" : "keyword");
  auto row = [](const std::string& k, const std::pair<int, int>& v) {
    std::printf("  %-28s %3d / %3d  %.3f\n", k.c_str(), v.first, v.second, double(v.first) / v.second);
  };
  std::printf("accuracy by voice:\n");
  for (const auto& kv : by_voice) row(kv.first, kv.second);
  std::printf("accuracy by rate (words/min):\n");
  for (const auto& kv : by_rate) row(kv.first, kv.second);
  std::printf("accuracy by noise:\n");
  for (const auto& kv : by_noise) row(kv.first, kv.second);
  std::printf("push-to-talk accuracy by noise:\n");
  for (const auto& kv : ptt_by_noise) row(kv.first, kv.second);
  std::printf("accuracy by command:\n");
  for (const auto& kv : by_cmd) row(kv.first, kv.second);
  std::printf("misses (keyword mode): %zu\n", misses.size());
  for (size_t i = 0; i < misses.size() && i < 20; ++i)
    std::printf("  %s\n", misses[i].c_str());
  std::printf("false commands: %d in %.1f min (%.1f min of speech), keyword detections %d", false_cmds, stream_min,
              speech_s / 60.0, false_keywords);
  for (const auto& t : false_texts)
    std::printf(" ['%s']", t.c_str());
  std::printf("\nidle: %.2f %% of one core over 60 s of noise (%d events)\n", idle_cpu_pct, idle_events);
  std::printf("%-28s %10s %10s\n", "figure", "value", "target");
  std::printf("%-28s %10.3f %10s\n", "command_accuracy", acc, ">= 0.95");
  std::printf("%-28s %10.3f %10s\n", "command_accuracy_push_to_talk", acc_ptt, ">= 0.95");
  std::printf("%-28s %10.2f %10s\n", "false_commands_per_10min", fc10, "<= 1");
  std::printf("%-28s %10.1f %10s\n", "ms_to_action_p95", p95, "<= 500");
  std::printf("%-28s %10.2f %10s\n", "idle_cpu_pct", idle_cpu_pct, "<= 10");

  ae::JsonLine js;
  js.add("command_accuracy", ae::jsonNumber(acc, 4))
      .add("false_commands_per_10min", ae::jsonNumber(fc10, 4))
      .add("ms_to_action_p95", ae::jsonNumber(p95, 4))
      .add("idle_cpu_pct", ae::jsonNumber(idle_cpu_pct, 3))
      .add("command_accuracy_push_to_talk", ae::jsonNumber(acc_ptt, 4))
      .add("keyword_detection_rate", ae::jsonNumber(ptt_only ? NAN : double(kw_hits) / total, 4))
      .add("false_keywords_per_10min", ae::jsonNumber(false_keywords / stream_min * 10.0, 4))
      .add("clips", total)
      .add("snr_db", ae::jsonNumber(snr, 3))
      .add("listen_mode", ptt_only ? "\"push_to_talk\"" : "\"keyword\"");
  std::cout << js.str() << std::endl;
  return 0;
}
