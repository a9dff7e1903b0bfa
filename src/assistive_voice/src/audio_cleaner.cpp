#include "assistive_voice/audio_cleaner.h"

#include <speex/speex_preprocess.h>

#include <algorithm>
#include <stdexcept>

#include "assistive_voice/audio.h"

namespace assistive_voice
{
namespace
{
constexpr int FRAME = RECOGNIZER_RATE / 100;  // 10 ms
}

struct AudioCleaner::Impl
{
  SpeexPreprocessState* speex = nullptr;
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
  else if (kind_ != "off")
    throw std::invalid_argument("audio_cleanup must be off or speex, not '" + kind_ + "'");
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
    speex_preprocess_run(impl_->speex, out.data() + f);
  return out;
}
}  // namespace assistive_voice
