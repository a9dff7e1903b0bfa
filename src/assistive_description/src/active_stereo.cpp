#include <assistive_description/active_stereo.h>

#include <cerrno>
#include <cmath>
#include <cstring>

#include <fcntl.h>
#include <linux/usb/video.h>
#include <linux/uvcvideo.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <opencv2/imgproc.hpp>

namespace assistive_description
{
bool splitInterleaved(const cv::Mat& frame, int width, int height, cv::Mat& left, cv::Mat& right, std::string* error)
{
  const size_t bytes = static_cast<size_t>(width) * height * 2;
  const bool shaped = frame.rows == height && frame.cols == width && (frame.type() == CV_8UC2 || frame.type() == CV_16UC1);
  const bool raw = frame.type() == CV_8UC1 && frame.isContinuous() && frame.total() == bytes;
  if (width < 1 || height < 1 || frame.empty() || !(shaped || raw))
  {
    if (error)
      *error = "an interleaved (Y8I) frame of " + std::to_string(width) + "x" + std::to_string(height) +
               " needs " + std::to_string(bytes) + " bytes (CV_8UC2, CV_16UC1 or raw CV_8UC1), got " +
               std::to_string(frame.cols) + "x" + std::to_string(frame.rows) + " of type " + std::to_string(frame.type());
    return false;
  }
  // Bytes 2i and 2i+1 of each pixel (CV_16UC1 on a little-endian host: the same layout).
  const cv::Mat c = frame.isContinuous() ? frame : frame.clone();
  const cv::Mat pairs(height, width, CV_8UC2, const_cast<uchar*>(c.ptr<uchar>()));
  left.create(height, width, CV_8UC1);
  right.create(height, width, CV_8UC1);
  cv::Mat out[] = { left, right };
  cv::split(pairs, out);
  return true;
}

double dotEnergy(const cv::Mat& mono8)
{
  if (mono8.empty()) return 0.0;
  cv::Mat lap;
  cv::Laplacian(mono8, lap, CV_16S, 1);
  return cv::mean(cv::abs(lap))[0];
}

bool EmitterPhase::classify(double e)
{
  const bool expected = started_ ? !prev_on_ : false;
  bool on = expected;
  if (locked())
    on = e > std::sqrt(level_on_ * level_off_);
  else if (started_ && e > contrast_ * prev_energy_)
    on = true;
  else if (started_ && contrast_ * e < prev_energy_)
    on = false;
  if (started_ && on != expected) ++resyncs_;
  // the running level of the kind this frame was judged (a few frames' memory: the scene changes)
  double& level = on ? level_on_ : level_off_;
  level = level > 0.0 ? level + 0.25 * (e - level) : e;
  ++(on ? seen_on_ : seen_off_);
  started_ = true;
  prev_on_ = on;
  prev_energy_ = e;
  return on;
}

bool EmitterPhase::locked() const
{
  return seen_on_ >= 3 && seen_off_ >= 3 && level_on_ > contrast_ * level_off_;
}

V4l2EmitterControl::V4l2EmitterControl(std::string device, int unit, int selector)
  : device_(std::move(device)), unit_(unit), selector_(selector)
{
}

V4l2EmitterControl::~V4l2EmitterControl()
{
  if (fd_ >= 0) ::close(fd_);
}

bool V4l2EmitterControl::set(bool on)
{
  if (fd_ < 0)
  {
    const std::string path = !device_.empty() && device_.find('/') == std::string::npos ? "/dev/video" + device_ : device_;
    fd_ = ::open(path.c_str(), O_RDWR | O_NONBLOCK);
    if (fd_ < 0)
    {
      last_error_ = "cannot open " + path + " for the emitter control: " + std::strerror(errno);
      return false;
    }
  }
  uint8_t value = on ? 1 : 0;
  uvc_xu_control_query q{};
  q.unit = static_cast<__u8>(unit_);
  q.selector = static_cast<__u8>(selector_);
  q.query = UVC_SET_CUR;
  q.size = 1;
  q.data = &value;
  if (::ioctl(fd_, UVCIOC_CTRL_QUERY, &q) != 0)
  {
    last_error_ = "the emitter control (UVC extension unit " + std::to_string(unit_) + ", selector " +
                  std::to_string(selector_) + ") was refused: " + std::strerror(errno);
    return false;
  }
  last_error_.clear();
  return true;
}

}  // namespace assistive_description
