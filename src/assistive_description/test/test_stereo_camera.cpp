#include <assistive_description/stereo_camera.h>
#include <gtest/gtest.h>

#include <deque>

using namespace assistive_description;

namespace
{
CameraCalibration calib(int w, int h, double tx)
{
  CameraCalibration c;
  c.width = w;
  c.height = h;
  c.D = {0, 0, 0, 0, 0};
  c.K = cv::Matx33d(200, 0, w / 2.0, 0, 200, h / 2.0, 0, 0, 1);
  c.P = cv::Matx34d(200, 0, w / 2.0, tx, 0, 200, h / 2.0, 0, 0, 0, 1, 0);
  return c;
}

// A scripted source: open() fails while `fail_opens` > 0; read() serves `frames` (with their
// stamps) and fails once they run out.
class ScriptedSource : public FrameSource
{
public:
  int fail_opens = 0;
  int opens = 0;
  std::deque<std::pair<cv::Mat, double>> frames;
  bool open() override
  {
    ++opens;
    if (fail_opens > 0)
    {
      --fail_opens;
      last_error_ = "/dev/video9 does not exist";
      return false;
    }
    open_ = true;
    return true;
  }
  bool read(cv::Mat& f, double& s) override
  {
    if (frames.empty())
    {
      last_error_ = "stopped delivering frames";
      return false;
    }
    f = frames.front().first;
    s = frames.front().second;
    frames.pop_front();
    return true;
  }
  void close() override { open_ = false; }
  bool isOpen() const override { return open_; }
  std::string describe() const override { return "scripted"; }

private:
  bool open_ = false;
};
}  // namespace

TEST(StereoCamera, SyntheticPairsShareOneStampAndSplitCorrectly)
{
  StereoCameraParams p;
  p.width = 320;
  p.height = 120;
  auto src = std::make_unique<SyntheticFrameSource>(320, 120, 20.0, 8, false, 1000.0);
  StereoCamera cam(std::move(src), p);
  std::string err;
  ASSERT_TRUE(cam.setCalibration(calib(160, 120, 0.0), calib(160, 120, -200 * 0.12), &err)) << err;
  StereoOutput out;
  for (int k = 0; k < 3; ++k)
  {
    ASSERT_EQ(cam.grab(0.0, out), GrabStatus::OK) << cam.lastError();
    EXPECT_DOUBLE_EQ(out.stamp, 1000.0 + k / 20.0);  // one stamp for both eyes, from the source
    ASSERT_TRUE(out.rectified);
    ASSERT_EQ(out.left_rect.size(), cv::Size(160, 120));
    ASSERT_EQ(out.right_rect.type(), CV_8UC1);
    // Zero distortion, P = K: rectification is the identity, so the pattern survives.
    EXPECT_EQ(out.left_rect.at<uchar>(50, 70), SyntheticFrameSource::pattern(70, 50));
    EXPECT_EQ(out.right_rect.at<uchar>(50, 70), SyntheticFrameSource::pattern(78, 50));
  }
  EXPECT_EQ(cam.frames(), 3u);
  EXPECT_NEAR(cam.frameRate(), 20.0, 1e-6);
}

TEST(StereoCamera, SwapHalves)
{
  StereoCameraParams p;
  p.swap_halves = true;
  StereoCamera cam(std::make_unique<SyntheticFrameSource>(320, 120, 20.0, 8, false, 1.0), p);
  StereoOutput out;
  ASSERT_EQ(cam.grab(0.0, out), GrabStatus::OK);
  EXPECT_FALSE(out.rectified);  // no calibration
  EXPECT_FALSE(cam.lastWarning().empty());
  EXPECT_EQ(out.left_mono.at<uchar>(10, 20), SyntheticFrameSource::pattern(28, 10));
  EXPECT_EQ(out.right_mono.at<uchar>(10, 20), SyntheticFrameSource::pattern(20, 10));
}

TEST(StereoCamera, MissingDeviceRetriesEveryRetryPeriod)
{
  StereoCameraParams p;
  p.retry_period = 2.0;
  auto owned = std::make_unique<ScriptedSource>();
  ScriptedSource* src = owned.get();
  src->fail_opens = 2;
  src->frames.emplace_back(cv::Mat(4, 8, CV_8UC1, cv::Scalar(5)), 10.0);
  StereoCamera cam(std::move(owned), p);
  StereoOutput out;
  EXPECT_EQ(cam.grab(100.0, out), GrabStatus::OPEN_FAILED);
  EXPECT_NE(cam.lastError().find("does not exist"), std::string::npos);
  EXPECT_EQ(cam.grab(101.0, out), GrabStatus::WAITING_TO_RETRY);
  EXPECT_EQ(cam.grab(101.9, out), GrabStatus::WAITING_TO_RETRY);
  EXPECT_EQ(src->opens, 1);
  EXPECT_EQ(cam.grab(102.0, out), GrabStatus::OPEN_FAILED);
  EXPECT_EQ(src->opens, 2);
  EXPECT_EQ(cam.grab(104.0, out), GrabStatus::OK);  // third attempt opens and reads
  EXPECT_EQ(out.stamp, 10.0);
  // The device stops: closed, and reopened only after the retry period.
  EXPECT_EQ(cam.grab(104.1, out), GrabStatus::READ_FAILED);
  EXPECT_FALSE(cam.isOpen());
  EXPECT_EQ(cam.grab(105.0, out), GrabStatus::WAITING_TO_RETRY);
  EXPECT_EQ(src->opens, 3);
  EXPECT_EQ(cam.grab(106.1, out), GrabStatus::READ_FAILED);  // reopened, still no frames
  EXPECT_EQ(src->opens, 4);
}

TEST(StereoCamera, StampsGetOffsetAndMustIncrease)
{
  StereoCameraParams p;
  p.time_offset = -0.05;
  auto owned = std::make_unique<ScriptedSource>();
  ScriptedSource* src = owned.get();
  const cv::Mat f(4, 8, CV_8UC3, cv::Scalar::all(1));
  src->frames = {{f, 10.0}, {f, 10.0}, {f, 9.9}, {f, 10.1}, {cv::Mat(4, 7, CV_8UC3), 10.2}};
  StereoCamera cam(std::move(owned), p);
  StereoOutput out;
  ASSERT_EQ(cam.grab(0.0, out), GrabStatus::OK);
  EXPECT_DOUBLE_EQ(out.stamp, 9.95);
  EXPECT_EQ(cam.grab(0.0, out), GrabStatus::STALE_STAMP);  // duplicate
  EXPECT_EQ(cam.grab(0.0, out), GrabStatus::STALE_STAMP);  // going back
  ASSERT_EQ(cam.grab(0.0, out), GrabStatus::OK);
  EXPECT_DOUBLE_EQ(out.stamp, 10.05);
  EXPECT_EQ(cam.grab(0.0, out), GrabStatus::BAD_FRAME);  // odd width
  EXPECT_TRUE(cam.isOpen());                             // a bad frame does not close the device
  EXPECT_EQ(cam.frames(), 2u);
}

TEST(StereoCamera, CalibrationSizeMismatchPublishesNoRectifiedImages)
{
  StereoCameraParams p;
  StereoCamera cam(std::make_unique<SyntheticFrameSource>(320, 120, 20.0, 8, false, 1.0), p);
  ASSERT_TRUE(cam.setCalibration(calib(640, 480, 0.0), calib(640, 480, -24.0)));
  StereoOutput out;
  ASSERT_EQ(cam.grab(0.0, out), GrabStatus::OK);
  EXPECT_FALSE(out.rectified);
  EXPECT_TRUE(out.left_rect.empty());
  EXPECT_NE(cam.lastWarning().find("640x480"), std::string::npos);
}

TEST(StereoCamera, CalibrationChecks)
{
  StereoCamera cam(std::make_unique<SyntheticFrameSource>(320, 120, 20.0, 8, false, 1.0),
                   StereoCameraParams());
  std::string err;
  std::vector<std::string> warnings;
  EXPECT_FALSE(cam.setCalibration(CameraCalibration(), calib(160, 120, -24.0), &err));
  EXPECT_EQ(err.rfind("left:", 0), 0u);
  EXPECT_FALSE(cam.setCalibration(calib(160, 120, 0.0), calib(320, 120, -24.0), &err));
  EXPECT_FALSE(cam.calibrated());
  // Positive right Tx: accepted with a warning (swapped halves?).
  EXPECT_TRUE(cam.setCalibration(calib(160, 120, 0.0), calib(160, 120, 24.0), &err, &warnings));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("swap"), std::string::npos);
  EXPECT_NEAR(calib(160, 120, -24.0).baseline(), 0.12, 1e-12);
}

TEST(FrameStamper, RateAndMonotonicConversion)
{
  FrameStamper s;
  double out;
  for (int k = 0; k < 50; ++k) ASSERT_TRUE(s.stamp(k * 0.04, out));
  EXPECT_NEAR(s.rate(), 25.0, 1e-6);
  EXPECT_DOUBLE_EQ(monotonicToWall(99.98, 100.0, 5000.0), 4999.98);
  EXPECT_DOUBLE_EQ(monotonicToWall(0.0, 100.0, 5000.0), 5000.0);    // no driver stamp
  EXPECT_DOUBLE_EQ(monotonicToWall(100.5, 100.0, 5000.0), 5000.0);  // in the future
  EXPECT_DOUBLE_EQ(monotonicToWall(50.0, 100.0, 5000.0), 5000.0);   // implausibly old
}

TEST(StereoCameraParams, ClampFixesBadValues)
{
  StereoCameraParams p;
  EXPECT_TRUE(p.clamp().empty());
  p.width = 641;
  p.fps = -3.0;
  p.retry_period = 0.0;
  p.fourcc = "MJPEG";
  const auto msgs = p.clamp();
  EXPECT_EQ(msgs.size(), 4u);
  EXPECT_EQ(p.width, 642);
  EXPECT_EQ(p.fps, 0.5);
  EXPECT_EQ(p.retry_period, 0.1);
  EXPECT_EQ(p.fourcc, "MJPG");
}

TEST(V4l2FrameSource, MissingDeviceFailsWithAClearMessage)
{
  V4l2FrameSource src("/dev/video_does_not_exist_42", 1280, 480, 30.0, "MJPG");
  EXPECT_FALSE(src.open());
  EXPECT_FALSE(src.isOpen());
  EXPECT_NE(src.lastError().find("does not exist"), std::string::npos);
  cv::Mat f;
  double s;
  EXPECT_FALSE(src.read(f, s));
}

TEST(V4l2FrameSource, NonCameraDeviceFailsWithAClearMessage)
{
  V4l2FrameSource src("/dev/null", 1280, 480, 30.0, "MJPG");  // exists, is not a camera
  EXPECT_FALSE(src.open());
  EXPECT_FALSE(src.isOpen());
  EXPECT_NE(src.lastError().find("cannot be opened"), std::string::npos) << src.lastError();
}
