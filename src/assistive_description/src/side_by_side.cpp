#include <assistive_description/side_by_side.h>

#include <opencv2/imgproc.hpp>

namespace assistive_description
{
bool splitSideBySide(const cv::Mat& frame, bool swap_halves, cv::Mat& left, cv::Mat& right,
                     std::string* error)
{
  if (frame.empty() || frame.cols < 2)
  {
    if (error) *error = "empty frame";
    return false;
  }
  if (frame.cols % 2 != 0)
  {
    if (error)
      *error = "frame width " + std::to_string(frame.cols) +
               " is odd: not a side-by-side stereo frame (check width/height params)";
    return false;
  }
  const int half = frame.cols / 2;
  cv::Mat a = frame(cv::Rect(0, 0, half, frame.rows));
  cv::Mat b = frame(cv::Rect(half, 0, half, frame.rows));
  left = swap_halves ? b : a;
  right = swap_halves ? a : b;
  return true;
}

bool toMono8(const cv::Mat& in, cv::Mat& out, std::string* error)
{
  switch (in.type())
  {
    case CV_8UC1:
      in.copyTo(out);
      return true;
    case CV_8UC3:
      cv::cvtColor(in, out, cv::COLOR_BGR2GRAY);
      return true;
    case CV_8UC4:
      cv::cvtColor(in, out, cv::COLOR_BGRA2GRAY);
      return true;
    default:
      if (error) *error = "unsupported pixel type " + std::to_string(in.type()) + " (need 8-bit)";
      return false;
  }
}

}  // namespace assistive_description
