#pragma once
// The pose OpenCV's solvePnP* returns (Rodrigues rotation vector and translation, CV_64F) as an
// Eigen isometry; shared by the loop verifier and the stereo check.
#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace assistive_slam
{
inline Eigen::Isometry3d isometryFromRvecTvec(const cv::Mat& rvec, const cv::Mat& tvec)
{
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  cv::cv2eigen(R, Re);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Re;
  T.translation() = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  return T;
}
}  // namespace assistive_slam
