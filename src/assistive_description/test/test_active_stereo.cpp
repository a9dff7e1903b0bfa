// The active camera (issue 35): an interleaved (Y8I) pair split into its eyes, and the frames
// exposed with the emitter on told from the others by their dots, through an unknown latency of
// the switch and dropped frames, as the driver core runs it on synthetic UVC frames.
#include <assistive_description/active_stereo.h>
#include <assistive_description/frame_source.h>
#include <assistive_description/stereo_camera.h>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

using namespace assistive_description;

TEST(ActiveStereo, InterleavedFrameSplitsIntoLowAndHighBytes)
{
  // 3 x 2 pixels: left = 10 * index, right = 10 * index + 1
  cv::Mat raw(1, 12, CV_8UC1);
  for (int i = 0; i < 6; ++i)
  {
    raw.at<uint8_t>(0, 2 * i) = static_cast<uint8_t>(10 * i);
    raw.at<uint8_t>(0, 2 * i + 1) = static_cast<uint8_t>(10 * i + 1);
  }
  cv::Mat left, right;
  ASSERT_TRUE(splitInterleaved(raw, 3, 2, left, right));
  ASSERT_EQ(left.size(), cv::Size(3, 2));
  ASSERT_EQ(left.type(), CV_8UC1);
  EXPECT_EQ(left.at<uint8_t>(1, 2), 50);
  EXPECT_EQ(right.at<uint8_t>(1, 2), 51);
  EXPECT_EQ(left.at<uint8_t>(0, 1), 10);
  EXPECT_EQ(right.at<uint8_t>(0, 0), 1);
  // the same bytes as 16-bit pixels (low byte left) and as two channels
  const cv::Mat as16(2, 3, CV_16UC1, raw.data), as2(2, 3, CV_8UC2, raw.data);
  cv::Mat l2, r2;
  ASSERT_TRUE(splitInterleaved(as16, 3, 2, l2, r2));
  EXPECT_EQ(cv::norm(l2, left, cv::NORM_INF), 0.0);
  ASSERT_TRUE(splitInterleaved(as2, 3, 2, l2, r2));
  EXPECT_EQ(cv::norm(r2, right, cv::NORM_INF), 0.0);
  // a frame of the wrong size or type says what it needed
  std::string err;
  EXPECT_FALSE(splitInterleaved(raw, 4, 2, left, right, &err));
  EXPECT_NE(err.find("16 bytes"), std::string::npos) << err;
  EXPECT_FALSE(splitInterleaved(cv::Mat(2, 3, CV_8UC3), 3, 2, left, right, &err));
}

TEST(ActiveStereo, EmitterPhaseFollowsTheDotsThroughLatencyAndDrops)
{
  // energies: 1 without dots, 3 with; the camera alternates on/off with the phase shifting by one
  // at a dropped frame (frame 9: two "off" in a row)
  const std::vector<bool> truth{ false, true, false, true, false, true, false, true, false, false, true, false,
                                 true, false, true, true, false, true, false, true };
  EmitterPhase phase;
  int wrong = 0;
  for (size_t k = 0; k < truth.size(); ++k)
  {
    const double e = (truth[k] ? 3.0 : 1.0) * (1.0 + 0.05 * std::sin(double(k)));
    if (phase.classify(e) != truth[k]) ++wrong;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_TRUE(phase.locked());
  EXPECT_EQ(phase.resyncs(), 2u);  // the two frames that broke the alternation
  // washed out (daylight): nothing tells the frames apart; they alternate and it is not locked
  EmitterPhase day;
  int on = 0;
  for (int k = 0; k < 10; ++k) on += day.classify(1.0 + 0.01 * (k % 3));
  EXPECT_EQ(on, 5);
  EXPECT_FALSE(day.locked());
}

namespace
{
StereoCameraParams activeParams()
{
  StereoCameraParams p;
  p.device = "synthetic";
  p.layout = "interleaved";
  p.emitter = "alternate";
  p.width = 160;
  p.height = 120;
  p.fps = 30.0;
  p.synthetic_disparity = 8.0;
  return p;
}
}  // namespace

TEST(ActiveStereo, DriverCoreTellsEmitterFramesOfASyntheticCameraWithLatencyAndDrops)
{
  for (const int latency : { 0, 1, 2 })
    for (const int drop_every : { 0, 7 })
    {
      StereoCameraParams p = activeParams();
      auto src = std::make_unique<SyntheticActiveSource>(p.width, p.height, p.fps, 8, false, latency, drop_every, 100.0);
      SyntheticActiveSource* source = src.get();
      std::unique_ptr<EmitterControl> control = makeEmitterControl(p, *src);
      ASSERT_TRUE(control);
      StereoCamera cam(std::move(src), p, std::move(control));
      int wrong = 0, on = 0, off = 0;
      for (int k = 0; k < 60; ++k)
      {
        StereoOutput out;
        ASSERT_EQ(cam.grab(0.0, out), GrabStatus::OK);
        ASSERT_EQ(out.left_mono.size(), cv::Size(160, 120));
        // (the frames before the switch first reaches the sensor are all "off": judged from frame 4)
        if (k >= 4)
        {
          wrong += out.emitter_on != source->lastEmitterOn();
          (out.emitter_on ? on : off) += 1;
        }
        if (out.emitter_on)
        {
          // the dots lie where the plane is: 8 px apart between the eyes
          const cv::Mat l = out.left_mono(cv::Rect(8, 0, 152, 120)), r = out.right_mono(cv::Rect(0, 0, 152, 120));
          EXPECT_EQ(cv::norm(l, r, cv::NORM_INF), 0.0);
        }
      }
      EXPECT_EQ(wrong, 0) << "latency " << latency << ", a drop every " << drop_every;
      EXPECT_GT(on, 20);
      EXPECT_GT(off, 20);
      EXPECT_TRUE(cam.emitterPhase().locked());
    }
}

TEST(ActiveStereo, PassiveSettingsLeaveTheEmitterAlone)
{
  StereoCameraParams p = activeParams();
  p.emitter = "none";
  auto src = std::make_unique<SyntheticActiveSource>(p.width, p.height, p.fps, 8, false, 0, 0, 100.0);
  EXPECT_FALSE(makeEmitterControl(p, *src));
  StereoCamera cam(std::move(src), p);
  StereoOutput out;
  for (int k = 0; k < 5; ++k)
  {
    ASSERT_EQ(cam.grab(0.0, out), GrabStatus::OK);
    EXPECT_FALSE(out.emitter_on);
  }
  // unknown layout / emitter words fall back, with a message each
  StereoCameraParams q;
  q.layout = "stacked";
  q.emitter = "blink";
  EXPECT_EQ(q.clamp().size(), 2u);
  EXPECT_EQ(q.layout, "side_by_side");
  EXPECT_EQ(q.emitter, "none");
}
