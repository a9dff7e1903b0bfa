#include "assistive_voice/speaker.h"

#include <espeak-ng/speak_lib.h>

#include <cstring>
#include <mutex>

namespace assistive_voice
{
namespace
{
enum class Mode { CLOSED, PLAYBACK, SYNTHESIS };
Mode g_mode = Mode::CLOSED;
int g_rate = 22050;
std::mutex g_mutex;
std::vector<int16_t>* g_sink = nullptr;

int collect(short* wav, int n, espeak_EVENT*)
{
  if (wav && n > 0 && g_sink)
    g_sink->insert(g_sink->end(), wav, wav + n);
  return 0;
}

bool open(espeak_AUDIO_OUTPUT out, Mode m, std::string* err)
{
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_mode == m)
    return true;
  if (g_mode != Mode::CLOSED)
    espeak_Terminate();
  const int rate = espeak_Initialize(out, 200, nullptr, 0);
  if (rate <= 0)
  {
    if (err)
      *err = "espeak-ng could not start (espeak-ng-data missing or no sound output)";
    g_mode = Mode::CLOSED;
    return false;
  }
  g_rate = rate;
  g_mode = m;
  if (m == Mode::SYNTHESIS)
    espeak_SetSynthCallback(collect);
  return true;
}
}  // namespace

bool Speaker::openPlayback(std::string* err) { return open(AUDIO_OUTPUT_PLAYBACK, Mode::PLAYBACK, err); }
bool Speaker::openSynthesis(std::string* err) { return open(AUDIO_OUTPUT_SYNCHRONOUS, Mode::SYNTHESIS, err); }
int Speaker::sampleRate() { return g_rate; }

bool Speaker::setVoice(const std::string& voice, int rate_wpm)
{
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_mode == Mode::CLOSED)
    return false;
  const bool ok = espeak_SetVoiceByName(voice.c_str()) == EE_OK;
  espeak_SetParameter(espeakRATE, rate_wpm, 0);
  return ok;
}

bool Speaker::say(const std::string& text)
{
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_mode != Mode::PLAYBACK)
    return false;
  return espeak_Synth(text.c_str(), text.size() + 1, 0, POS_CHARACTER, 0, espeakCHARS_UTF8, nullptr, nullptr) == EE_OK;
}

Audio Speaker::synth(const std::string& text)
{
  std::lock_guard<std::mutex> lock(g_mutex);
  Audio a;
  a.rate = g_rate;
  if (g_mode != Mode::SYNTHESIS)
    return a;
  g_sink = &a.samples;
  espeak_Synth(text.c_str(), text.size() + 1, 0, POS_CHARACTER, 0, espeakCHARS_UTF8, nullptr, nullptr);
  espeak_Synchronize();
  g_sink = nullptr;
  return a;
}

void Speaker::stop()
{
  if (g_mode == Mode::PLAYBACK)
    espeak_Cancel();
}

bool Speaker::speaking()
{
  return g_mode == Mode::PLAYBACK && espeak_IsPlaying() == 1;
}
}  // namespace assistive_voice
