#include <assistive_description/rectifier.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace assistive_description
{
bool Rectifier::configure(const CameraCalibration& calib, std::string* error)
{
  map1_.release();
  map2_.release();
  if (!calib.isCalibrated())
  {
    if (error) *error = "camera is not calibrated (K or P is zero, or no image size)";
    return false;
  }
  const cv::Size size(calib.width, calib.height);
  const cv::Mat K(calib.K), R(calib.R);
  const cv::Mat P = cv::Mat(calib.P).colRange(0, 3).clone();
  cv::Mat map1, map2;
  if (calib.distortion_model == "plumb_bob" || calib.distortion_model == "rational_polynomial")
  {
    const std::size_t n = calib.D.size();
    if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14)
    {
      if (error) *error = "distortion model " + calib.distortion_model + " with " +
                          std::to_string(n) + " coefficients is not supported";
      return false;
    }
    cv::Mat D = n ? cv::Mat(calib.D).clone() : cv::Mat::zeros(1, 5, CV_64F);
    cv::initUndistortRectifyMap(K, D, R, P, size, CV_16SC2, map1, map2);
  }
  else if (calib.distortion_model == "equidistant")
  {
    if (calib.D.size() != 4)
    {
      if (error) *error = "equidistant distortion needs 4 coefficients, got " +
                          std::to_string(calib.D.size());
      return false;
    }
    cv::fisheye::initUndistortRectifyMap(K, cv::Mat(calib.D).clone(), R, P, size, CV_16SC2, map1,
                                         map2);
  }
  else
  {
    if (error) *error = "unknown distortion model '" + calib.distortion_model +
                        "' (plumb_bob, rational_polynomial or equidistant)";
    return false;
  }
  calib_ = calib;
  rectified_ = calib.rectified();
  map1_ = map1;
  map2_ = map2;
  return true;
}

bool Rectifier::rectify(const cv::Mat& raw, cv::Mat& rect) const
{
  if (!configured() || raw.cols != calib_.width || raw.rows != calib_.height) return false;
  cv::remap(raw, rect, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return true;
}

}  // namespace assistive_description
