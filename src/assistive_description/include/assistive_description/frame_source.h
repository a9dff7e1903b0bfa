#pragma once
// Where side-by-side frames come from: a V4L2 device or a synthetic pattern (tests, demos).
#include <assistive_description/active_stereo.h>
#include <assistive_description/params.h>
#include <opencv2/core.hpp>
#include <memory>
#include <string>

namespace cv
{
class VideoCapture;
}

namespace assistive_description
{
/// One camera delivering both eyes side by side in one frame.
class FrameSource
{
public:
  virtual ~FrameSource() = default;
  /// Open the device; false (and lastError()) when it is missing or refuses the format.
  virtual bool open() = 0;
  /// Next frame (BGR or mono) and its capture stamp in seconds on the system (wall) clock.
  /// Blocks until a frame arrives; false when the device failed (it then needs close()/open()).
  virtual bool read(cv::Mat& frame, double& stamp) = 0;
  virtual void close() = 0;
  virtual bool isOpen() const = 0;
  /// Human-readable name for logs and diagnostics.
  virtual std::string describe() const = 0;
  /// Why the last open() or read() failed.
  const std::string& lastError() const { return last_error_; }

protected:
  std::string last_error_;
};

/// A V4L2 (UVC) camera through OpenCV's V4L2 back-end.
class V4l2FrameSource : public FrameSource
{
public:
  V4l2FrameSource(std::string device, int width, int height, double fps, std::string fourcc);
  ~V4l2FrameSource() override;
  bool open() override;
  bool read(cv::Mat& frame, double& stamp) override;
  void close() override;
  bool isOpen() const override;
  std::string describe() const override;

private:
  std::string device_;
  int width_, height_;
  double fps_;
  std::string fourcc_;
  std::unique_ptr<cv::VideoCapture> cap_;
};

/// A fronto-parallel textured plane seen with a constant disparity: the left half shows
/// pattern(x, y), the right half pattern(x + disparity, y) (x counted within each half), in
/// BGR with equal channels. Stamps are start + k / fps exactly.
class SyntheticFrameSource : public FrameSource
{
public:
  /// start_stamp < 0: the wall clock at open(). pace: read() sleeps to deliver fps in real time.
  SyntheticFrameSource(int width, int height, double fps, int disparity, bool pace,
                       double start_stamp = -1.0);
  bool open() override;
  bool read(cv::Mat& frame, double& stamp) override;
  void close() override { open_ = false; }
  bool isOpen() const override { return open_; }
  std::string describe() const override;

  /// The texture, 0..255, defined for any integer x, y.
  static unsigned char pattern(int x, int y);
  /// The full side-by-side frame (width x height, CV_8UC3).
  static cv::Mat makeFrame(int width, int height, int disparity);

private:
  int width_, height_;
  double fps_;
  int disparity_;
  bool pace_;
  double start_param_, start_ = 0.0;
  long long index_ = 0;
  bool open_ = false;
  cv::Mat frame_;
};

/// An active camera's infrared pair (Y8I, CV_8UC2: channel 0 the left eye) looking at a plain
/// plane at a constant disparity: faint texture only, and the projector's dots (a fixed random
/// pattern, where the projector beside the left eye puts them: `disparity` px apart between the
/// eyes, as the plane's) on the exposures made with the emitter on. The emitter is what control()
/// last set `latency` frames before the exposure; with `drop_every` > 0 every n-th exposure is lost
/// on the way (a USB hiccup), so the delivered frames' phase shifts. Stamps: start + k / fps.
class SyntheticActiveSource : public FrameSource
{
public:
  SyntheticActiveSource(int width, int height, double fps, int disparity, bool pace, int latency = 1,
                        int drop_every = 0, double start_stamp = -1.0);
  bool open() override;
  bool read(cv::Mat& frame, double& stamp) override;
  void close() override { open_ = false; }
  bool isOpen() const override { return open_; }
  std::string describe() const override;
  /// The emitter switch of this camera.
  std::unique_ptr<EmitterControl> control();
  /// Was the emitter on for the last frame read() delivered (the truth, for tests)?
  bool lastEmitterOn() const { return last_on_; }

private:
  struct Switch;
  int width_, height_;
  double fps_;
  int disparity_;
  bool pace_;
  int latency_, drop_every_;
  double start_param_, start_ = 0.0;
  long long exposure_ = 0;
  bool open_ = false, last_on_ = false;
  std::shared_ptr<Switch> switch_;
  cv::Mat plain_, dots_left_, dots_right_;
};

/// The factory the nodelet uses: "synthetic" gives a paced SyntheticFrameSource (with
/// `layout: interleaved`, a SyntheticActiveSource, latency 1).
std::unique_ptr<FrameSource> makeFrameSource(const StereoCameraParams& p);
/// The emitter switch for `emitter: alternate` (null otherwise): the synthetic active camera's own,
/// else the UVC extension unit control of `device`.
std::unique_ptr<EmitterControl> makeEmitterControl(const StereoCameraParams& p, FrameSource& source);

/// Convert a capture stamp on the monotonic clock to the wall clock. Falls back to wall_now
/// when the monotonic stamp is implausible (missing, in the future, or older than max_age s).
double monotonicToWall(double mono_stamp, double mono_now, double wall_now, double max_age = 1.0);

/// Seconds on the wall (system) clock and on the monotonic (steady) clock.
double wallNow();
double monotonicNow();

}  // namespace assistive_description
