#include "assistive_voice/audio_cleaner.h"

#include <speex/speex_preprocess.h>
#include <webrtc/modules/audio_processing/include/audio_processing.h>
#include <webrtc/modules/interface/module_common_types.h>

#include <algorithm>
#include <stdexcept>

#include "assistive_voice/audio.h"

namespace assistive_voice
{
namespace
{
constexpr int FRAME = RECOGNIZER_RATE / 100;  // 10 ms: WebRTC's frame; speex takes the same
}

struct AudioCleaner::Impl
{
  SpeexPreprocessState* speex = nullptr;
  std::unique_ptr<webrtc::AudioProcessing> apm;
  webrtc::AudioFrame frame;
};

AudioCleaner::AudioCleaner(const std::string& kind) : kind_(kind), impl_(std::make_unique<Impl>())
{
  if (kind_ == "speex")
  {
    impl_->speex = speex_preprocess_state_init(FRAME, RECOGNIZER_RATE);
    if (!impl_->speex)
      throw std::invalid_argument("speexdsp: the preprocessor does not start");
    // VAD stays off (its default): pocketsphinx's detector cuts the utterances
    int on = 1;
    speex_preprocess_ctl(impl_->speex, SPEEX_PREPROCESS_SET_DENOISE, &on);
    speex_preprocess_ctl(impl_->speex, SPEEX_PREPROCESS_SET_AGC, &on);
  }
  else if (kind_ == "webrtc")
  {
    impl_->apm.reset(webrtc::AudioProcessing::Create());
    if (!impl_->apm)
      throw std::invalid_argument("webrtc-audio-processing: does not start");
    impl_->apm->high_pass_filter()->Enable(true);
    impl_->apm->noise_suppression()->set_level(webrtc::NoiseSuppression::kHigh);
    impl_->apm->noise_suppression()->Enable(true);
    impl_->apm->gain_control()->set_mode(webrtc::GainControl::kAdaptiveDigital);
    impl_->apm->gain_control()->Enable(true);
    impl_->frame.sample_rate_hz_ = RECOGNIZER_RATE;
    impl_->frame.num_channels_ = 1;
    impl_->frame.samples_per_channel_ = FRAME;
  }
  else if (kind_ != "off")
    throw std::invalid_argument("audio_cleanup must be off, speex or webrtc, not '" + kind_ + "'");
}

AudioCleaner::~AudioCleaner()
{
  if (impl_->speex)
    speex_preprocess_state_destroy(impl_->speex);
}

std::vector<int16_t> AudioCleaner::process(const int16_t* s, size_t n)
{
  if (kind_ == "off")
    return std::vector<int16_t>(s, s + n);
  pending_.insert(pending_.end(), s, s + n);
  const size_t whole = pending_.size() / FRAME * FRAME;
  std::vector<int16_t> out(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(whole));
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(whole));
  for (size_t f = 0; f < whole; f += FRAME)
  {
    if (impl_->speex)
    {
      speex_preprocess_run(impl_->speex, out.data() + f);
      continue;
    }
    std::copy(out.begin() + f, out.begin() + f + FRAME, impl_->frame.data_);
    impl_->apm->ProcessStream(&impl_->frame);
    std::copy(impl_->frame.data_, impl_->frame.data_ + FRAME, out.begin() + f);
  }
  return out;
}
}  // namespace assistive_voice
