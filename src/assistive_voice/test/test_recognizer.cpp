// espeak-ng speaks, pocketsphinx hears: the recognizer on real (synthesised) audio, both modes,
// and the WAV round trip. Deterministic: the same library versions give the same samples.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>

#include "assistive_voice/audio.h"
#include "assistive_voice/commands.h"
#include "assistive_voice/recognizer.h"
#include "assistive_voice/speaker.h"

using namespace assistive_voice;

namespace
{
std::vector<int16_t> say(const std::string& text)
{
  Speaker::setVoice("en-us", 170);
  return resample(Speaker::synth(text), RECOGNIZER_RATE).samples;
}
std::vector<int16_t> silence(double s) { return std::vector<int16_t>(static_cast<size_t>(s * RECOGNIZER_RATE), 0); }
void append(std::vector<int16_t>& a, const std::vector<int16_t>& b) { a.insert(a.end(), b.begin(), b.end()); }

std::vector<Recognition> run(Recognizer& r, const std::vector<int16_t>& clip)
{
  std::vector<Recognition> out;
  for (size_t i = 0; i < clip.size(); i += 320)
    for (const Recognition& x : r.feed(clip.data() + i, std::min<size_t>(320, clip.size() - i)))
      out.push_back(x);
  return out;
}
}  // namespace

class RecognizerTest : public ::testing::Test
{
protected:
  static void SetUpTestSuite() { ASSERT_TRUE(Speaker::openSynthesis()); }
};

TEST_F(RecognizerTest, WavRoundTrip)
{
  Audio a;
  a.rate = 22050;
  a.samples = {0, 1, -1, 32767, -32768, 1234};
  const std::string path = testing::TempDir() + "/assistive_voice_test_roundtrip_" + std::to_string(::getpid()) + ".wav";
  ASSERT_TRUE(writeWav(path, a));
  Audio b;
  std::string err;
  ASSERT_TRUE(readWav(path, &b, &err)) << err;
  EXPECT_EQ(b.rate, 22050);
  EXPECT_EQ(b.samples, a.samples);
  std::remove(path.c_str());
  const Audio r = resample(a, 11025);
  EXPECT_EQ(r.samples.size(), 3u);
}

TEST_F(RecognizerTest, PushToTalkHearsEveryKindOfCommand)
{
  RecognizerConfig c;
  c.mode = "push_to_talk";
  Recognizer r(c);
  for (const char* s : {"take me back to the door", "save place kitchen", "where am i", "pause"})
  {
    std::vector<int16_t> clip = silence(0.3);
    append(clip, say(s));
    append(clip, silence(1.5));
    EXPECT_TRUE(run(r, clip).empty()) << "nothing is decoded before the press";
    r.listen();
    const std::vector<Recognition> got = run(r, clip);
    ASSERT_EQ(got.size(), 1u) << s;
    EXPECT_FALSE(got[0].keyword);
    EXPECT_EQ(parseCommand(got[0].text), parseCommand(s)) << "'" << got[0].text << "' for '" << s << "'";
  }
}

TEST_F(RecognizerTest, KeywordThenCommand)
{
  RecognizerConfig c;  // keyword mode, "hello navigator"
  Recognizer r(c);
  std::vector<int16_t> clip = silence(0.5);
  append(clip, say("what is ahead"));  // no keyphrase: ignored
  append(clip, silence(1.0));
  append(clip, say("hello navigator"));
  append(clip, silence(0.4));
  append(clip, say("take me back"));
  append(clip, silence(1.5));
  const std::vector<Recognition> got = run(r, clip);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_TRUE(got[0].keyword);
  EXPECT_FALSE(got[1].keyword);
  EXPECT_EQ(parseCommand(got[1].text), (Command{Action::GUIDE_BACK, ""})) << got[1].text;
}

TEST_F(RecognizerTest, AnswerWindowHearsYesAndNo)
{
  RecognizerConfig c;
  c.mode = "push_to_talk";
  Recognizer r(c);
  for (const char* s : {"yes", "no"})
  {
    std::vector<int16_t> clip = silence(0.3);
    append(clip, say(s));
    append(clip, silence(1.5));
    r.listen(true);
    const std::vector<Recognition> got = run(r, clip);
    ASSERT_EQ(got.size(), 1u) << s;
    EXPECT_EQ(got[0].text, s);
    EXPECT_FALSE(got[0].rejected);
  }
}

TEST_F(RecognizerTest, OtherSpeechIsRejectedAgainstThePhoneLoop)
{
  RecognizerConfig c;  // the phone loop and the default thresholds of VoiceParams
  c.mode = "push_to_talk";
  const VoiceParams p;
  c.min_confidence = p.min_confidence;
  Recognizer r(c);
  std::vector<int16_t> clip = silence(0.3);
  append(clip, say("where am i"));
  append(clip, silence(1.5));
  r.listen();
  std::vector<Recognition> got = run(r, clip);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].text, "where am i");
  EXPECT_FALSE(got[0].rejected) << got[0].confidence;
  EXPECT_GE(got[0].confidence, p.min_confidence);

  clip = silence(0.3);
  append(clip, say("the weather was lovely at the seaside"));
  append(clip, silence(1.5));
  r.listen();
  got = run(r, clip);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_TRUE(got[0].text.empty() || got[0].rejected)
      << "'" << got[0].text << "' at " << got[0].confidence;
}
