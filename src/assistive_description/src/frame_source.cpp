#include <assistive_description/frame_source.h>

#include <opencv2/videoio.hpp>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <deque>
#include <functional>
#include <chrono>
#include <cmath>
#include <thread>

namespace assistive_description
{
double wallNow()
{
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double monotonicNow()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double monotonicToWall(double mono_stamp, double mono_now, double wall_now, double max_age)
{
  const double age = mono_now - mono_stamp;
  if (!(mono_stamp > 0.0) || !(age >= 0.0) || age > max_age) return wall_now;
  return wall_now - age;
}

// ---------------------------------------------------------------------------------------------
V4l2FrameSource::V4l2FrameSource(std::string device, int width, int height, double fps,
                                 std::string fourcc)
  : device_(std::move(device)), width_(width), height_(height), fps_(fps), fourcc_(std::move(fourcc))
{
}

V4l2FrameSource::~V4l2FrameSource() { close(); }

std::string V4l2FrameSource::describe() const
{
  return "V4L2 " + device_ + " " + std::to_string(width_) + "x" + std::to_string(height_) + " " +
         fourcc_;
}

bool V4l2FrameSource::open()
{
  close();
  const bool is_index =
      !device_.empty() && std::all_of(device_.begin(), device_.end(), [](unsigned char c) {
        return std::isdigit(c) != 0;
      });
  if (!is_index)
  {
    if (::access(device_.c_str(), F_OK) != 0)
    {
      last_error_ = device_ + " does not exist (camera unplugged? check `ls /dev/video*`)";
      return false;
    }
    if (::access(device_.c_str(), R_OK | W_OK) != 0)
    {
      last_error_ = device_ + ": permission denied (add the user to group `video`)";
      return false;
    }
  }
  cap_ = std::make_unique<cv::VideoCapture>();
  const bool ok = is_index ? cap_->open(std::stoi(device_), cv::CAP_V4L2)
                           : cap_->open(device_, cv::CAP_V4L2);
  if (!ok || !cap_->isOpened())
  {
    last_error_ = device_ + " exists but cannot be opened as a V4L2 capture device";
    cap_.reset();
    return false;
  }
  if (fourcc_.size() == 4)
    cap_->set(cv::CAP_PROP_FOURCC,
              cv::VideoWriter::fourcc(fourcc_[0], fourcc_[1], fourcc_[2], fourcc_[3]));
  // a format OpenCV does not decode (an active camera's interleaved Y8I) is handed over raw
  if (fourcc_ == "Y8I ") cap_->set(cv::CAP_PROP_CONVERT_RGB, 0);
  cap_->set(cv::CAP_PROP_FRAME_WIDTH, width_);
  cap_->set(cv::CAP_PROP_FRAME_HEIGHT, height_);
  cap_->set(cv::CAP_PROP_FPS, fps_);
  const int w = static_cast<int>(cap_->get(cv::CAP_PROP_FRAME_WIDTH));
  const int h = static_cast<int>(cap_->get(cv::CAP_PROP_FRAME_HEIGHT));
  if (w != width_ || h != height_)
  {
    last_error_ = device_ + " refused " + std::to_string(width_) + "x" + std::to_string(height_) +
                  " (it offers " + std::to_string(w) + "x" + std::to_string(h) +
                  "; list modes with `v4l2-ctl --list-formats-ext`)";
    close();
    return false;
  }
  last_error_.clear();
  return true;
}

bool V4l2FrameSource::read(cv::Mat& frame, double& stamp)
{
  if (!cap_ || !cap_->isOpened())
  {
    last_error_ = device_ + " is not open";
    return false;
  }
  if (!cap_->grab())
  {
    last_error_ = device_ + " stopped delivering frames (unplugged or hung)";
    return false;
  }
  const double wall = wallNow(), mono = monotonicNow();
  // The V4L2 back-end reports the driver's buffer time stamp (CLOCK_MONOTONIC) in ms.
  const double mono_stamp = cap_->get(cv::CAP_PROP_POS_MSEC) / 1000.0;
  if (!cap_->retrieve(frame) || frame.empty())
  {
    last_error_ = device_ + " delivered a frame that could not be decoded";
    return false;
  }
  stamp = monotonicToWall(mono_stamp, mono, wall);
  return true;
}

void V4l2FrameSource::close()
{
  if (cap_) cap_->release();
  cap_.reset();
}

bool V4l2FrameSource::isOpen() const { return cap_ && cap_->isOpened(); }

// ---------------------------------------------------------------------------------------------
SyntheticFrameSource::SyntheticFrameSource(int width, int height, double fps, int disparity,
                                           bool pace, double start_stamp)
  : width_(width), height_(height), fps_(fps), disparity_(disparity), pace_(pace),
    start_param_(start_stamp)
{
}

std::string SyntheticFrameSource::describe() const
{
  return "synthetic " + std::to_string(width_) + "x" + std::to_string(height_) + " disparity " +
         std::to_string(disparity_) + " px";
}

unsigned char SyntheticFrameSource::pattern(int x, int y)
{
  // 16 px checkerboard (strong corners) plus a finer diagonal ramp (texture inside squares).
  const int fx = x >= 0 ? x / 16 : (x - 15) / 16;
  const int fy = y >= 0 ? y / 16 : (y - 15) / 16;
  const int base = ((fx + fy) & 1) ? 170 : 40;
  const int ramp = ((x * 5 + y * 3) % 64 + 64) % 64;
  return static_cast<unsigned char>(base + ramp);
}

cv::Mat SyntheticFrameSource::makeFrame(int width, int height, int disparity)
{
  cv::Mat frame(height, width, CV_8UC3);
  const int half = width / 2;
  for (int y = 0; y < height; ++y)
  {
    auto* row = frame.ptr<cv::Vec3b>(y);
    for (int x = 0; x < width; ++x)
    {
      const unsigned char v = x < half ? pattern(x, y) : pattern(x - half + disparity, y);
      row[x] = cv::Vec3b(v, v, v);
    }
  }
  return frame;
}

bool SyntheticFrameSource::open()
{
  if (width_ < 2 || height_ < 1 || !(fps_ > 0.0))
  {
    last_error_ = "synthetic source: bad size or rate";
    return false;
  }
  frame_ = makeFrame(width_, height_, disparity_);
  start_ = start_param_ >= 0.0 ? start_param_ : wallNow();
  index_ = 0;
  open_ = true;
  last_error_.clear();
  return true;
}

bool SyntheticFrameSource::read(cv::Mat& frame, double& stamp)
{
  if (!open_)
  {
    last_error_ = "synthetic source is not open";
    return false;
  }
  stamp = start_ + static_cast<double>(index_) / fps_;
  ++index_;
  if (pace_)
  {
    const double wait = stamp - wallNow();
    if (wait > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(std::min(wait, 1.0)));
  }
  frame = frame_.clone();
  return true;
}

// ---------------------------------------------------------------------------------------------
struct SyntheticActiveSource::Switch
{
  std::deque<bool> commanded;  ///< the emitter as set, newest last
};

namespace
{
class SyntheticEmitterControl : public EmitterControl
{
public:
  explicit SyntheticEmitterControl(std::function<void(bool)> set) : set_(std::move(set)) {}
  bool set(bool on) override
  {
    set_(on);
    return true;
  }

private:
  std::function<void(bool)> set_;
};
}  // namespace

SyntheticActiveSource::SyntheticActiveSource(int width, int height, double fps, int disparity, bool pace, int latency,
                                             int drop_every, double start_stamp)
  : width_(width), height_(height), fps_(fps), disparity_(disparity), pace_(pace), latency_(std::max(0, latency)),
    drop_every_(std::max(0, drop_every)), start_param_(start_stamp), switch_(std::make_shared<Switch>())
{
}

std::string SyntheticActiveSource::describe() const
{
  return "synthetic active (Y8I) " + std::to_string(width_) + "x" + std::to_string(height_) + " disparity " +
         std::to_string(disparity_) + ", emitter latency " + std::to_string(latency_) + " frames";
}

std::unique_ptr<EmitterControl> SyntheticActiveSource::control()
{
  std::shared_ptr<Switch> sw = switch_;
  return std::make_unique<SyntheticEmitterControl>([sw](bool on) { sw->commanded.push_back(on); });
}

bool SyntheticActiveSource::open()
{
  if (width_ < 2 || height_ < 1 || !(fps_ > 0.0))
  {
    last_error_ = "synthetic source: bad size or rate";
    return false;
  }
  // a plain plane: a faint, smooth shading; the dots a fixed pattern of single bright pixels
  plain_.create(height_, width_ + disparity_, CV_8UC1);
  for (int y = 0; y < plain_.rows; ++y)
    for (int x = 0; x < plain_.cols; ++x) plain_.at<uint8_t>(y, x) = static_cast<uint8_t>(110 + (x + y) / 40 % 3);
  cv::Mat dots = cv::Mat::zeros(plain_.size(), CV_8UC1);
  cv::RNG rng(435);
  for (int k = 0; k < plain_.total() / 25; ++k) dots.at<uint8_t>(rng.uniform(0, dots.rows), rng.uniform(0, dots.cols)) = 90;
  dots_left_ = dots(cv::Rect(0, 0, width_, height_)).clone();
  dots_right_ = dots(cv::Rect(disparity_, 0, width_, height_)).clone();
  start_ = start_param_ >= 0.0 ? start_param_ : wallNow();
  exposure_ = 0;
  switch_->commanded.clear();
  open_ = true;
  last_error_.clear();
  return true;
}

bool SyntheticActiveSource::read(cv::Mat& frame, double& stamp)
{
  if (!open_)
  {
    last_error_ = "synthetic source is not open";
    return false;
  }
  if (drop_every_ > 0 && (exposure_ + 1) % drop_every_ == 0) ++exposure_;  // lost on the way
  stamp = start_ + static_cast<double>(exposure_) / fps_;
  if (pace_)
  {
    const double wait = stamp - wallNow();
    if (wait > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(std::min(wait, 1.0)));
  }
  // the emitter as commanded `latency` settings ago (off before any)
  std::deque<bool>& c = switch_->commanded;
  last_on_ = c.size() > static_cast<size_t>(latency_) ? c[c.size() - 1 - latency_] : false;
  while (c.size() > static_cast<size_t>(latency_) + 8) c.pop_front();
  cv::Mat left = plain_(cv::Rect(0, 0, width_, height_)).clone(), right = plain_(cv::Rect(disparity_, 0, width_, height_)).clone();
  if (last_on_)
  {
    left += dots_left_;
    right += dots_right_;
  }
  cv::Mat planes[] = { left, right };
  cv::merge(planes, 2, frame);
  ++exposure_;
  return true;
}

std::unique_ptr<EmitterControl> makeEmitterControl(const StereoCameraParams& p, FrameSource& source)
{
  if (p.emitter != "alternate") return nullptr;
  if (auto* active = dynamic_cast<SyntheticActiveSource*>(&source)) return active->control();
  if (p.device == "synthetic") return nullptr;
  return std::make_unique<V4l2EmitterControl>(p.device, p.emitter_xu_unit, p.emitter_xu_selector);
}

std::unique_ptr<FrameSource> makeFrameSource(const StereoCameraParams& p)
{
  if (p.device == "synthetic" && p.layout == "interleaved")
    return std::make_unique<SyntheticActiveSource>(p.width, p.height, p.fps,
                                                   static_cast<int>(std::lround(p.synthetic_disparity)), true);
  if (p.device == "synthetic")
    return std::make_unique<SyntheticFrameSource>(
        p.width, p.height, p.fps, static_cast<int>(std::lround(p.synthetic_disparity)), true);
  return std::make_unique<V4l2FrameSource>(p.device, p.width, p.height, p.fps, p.fourcc);
}

}  // namespace assistive_description
