#pragma once
// ROS-free mirror of sensor_msgs/CameraInfo's calibration fields (conversions.h converts).
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace assistive_description
{
struct CameraCalibration
{
  int width = 0;   ///< image size the calibration was made for, px
  int height = 0;
  std::string distortion_model = "plumb_bob";  ///< plumb_bob, rational_polynomial, equidistant
  std::vector<double> D;                       ///< distortion coefficients
  cv::Matx33d K = cv::Matx33d::zeros();        ///< raw intrinsics
  cv::Matx33d R = cv::Matx33d::eye();          ///< rectification rotation
  cv::Matx34d P = cv::Matx34d::zeros();        ///< rectified projection (P(0,3) = -fx * baseline)

  /// True when K and P hold a usable calibration (camera_info_manager gives zeros otherwise).
  bool isCalibrated() const;

  /// The calibration of the rectified image: same size and P, K = P's left 3x3, D = 0, R = I.
  CameraCalibration rectified() const;

  /// Stereo baseline in metres from a right camera's P: -P(0,3) / P(0,0) (0 when uncalibrated).
  double baseline() const;

  bool operator==(const CameraCalibration& o) const;
  bool operator!=(const CameraCalibration& o) const { return !(*this == o); }
};

}  // namespace assistive_description
