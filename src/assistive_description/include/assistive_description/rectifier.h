#pragma once
// Rectification of one camera with OpenCV: the maps are computed once, in configure().
#include <assistive_description/camera_calibration.h>
#include <opencv2/core.hpp>
#include <string>

namespace assistive_description
{
class Rectifier
{
public:
  /// Build the undistort/rectify maps for `calib` (plumb_bob, rational_polynomial or
  /// equidistant). False with a message when it is uncalibrated or the model is unknown.
  bool configure(const CameraCalibration& calib, std::string* error = nullptr);
  bool configured() const { return !map1_.empty(); }
  /// Raw image (calibration size, any type remap accepts) -> rectified image (bilinear).
  /// False when the raw image has the wrong size or no maps were built.
  bool rectify(const cv::Mat& raw, cv::Mat& rect) const;
  const CameraCalibration& calibration() const { return calib_; }
  /// The rectified image's calibration (D = 0, R = I, P unchanged).
  const CameraCalibration& rectifiedCalibration() const { return rectified_; }
  cv::Size size() const { return cv::Size(calib_.width, calib_.height); }

private:
  CameraCalibration calib_, rectified_;
  cv::Mat map1_, map2_;
};

}  // namespace assistive_description
