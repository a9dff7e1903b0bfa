// Stereo rectification of a calibrated pair (EuRoC import; OpenCV stereoRectify).
#include <assistive_eval/datasets.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace assistive_eval
{
StereoRectifier makeStereoRectifier(const cv::Mat& K0, const cv::Mat& D0, const cv::Mat& K1, const cv::Mat& D1,
                                    const cv::Size& size, const Eigen::Isometry3d& T_c1_c0)
{
  cv::Mat R(3, 3, CV_64F), T(3, 1, CV_64F);
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
      R.at<double>(r, c) = T_c1_c0.linear()(r, c);
    T.at<double>(r, 0) = T_c1_c0.translation()(r);
  }
  cv::Mat R1, R2, P1, P2, Q;
  cv::stereoRectify(K0, D0, K1, D1, size, R, T, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0.0, size);
  StereoRectifier s;
  cv::initUndistortRectifyMap(K0, D0, R1, P1, size, CV_32FC1, s.map0x, s.map0y);
  cv::initUndistortRectifyMap(K1, D1, R2, P2, size, CV_32FC1, s.map1x, s.map1y);
  s.calib.width = size.width;
  s.calib.height = size.height;
  s.calib.fx = P1.at<double>(0, 0);
  s.calib.fy = P1.at<double>(1, 1);
  s.calib.cx = P1.at<double>(0, 2);
  s.calib.cy = P1.at<double>(1, 2);
  s.calib.baseline = -P2.at<double>(0, 3) / P2.at<double>(0, 0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      s.R_rect_raw0(r, c) = R1.at<double>(r, c);
  return s;
}

void StereoRectifier::rectify(const cv::Mat& raw0, const cv::Mat& raw1, cv::Mat& out0, cv::Mat& out1) const
{
  cv::remap(raw0, out0, map0x, map0y, cv::INTER_LINEAR);
  cv::remap(raw1, out1, map1x, map1y, cv::INTER_LINEAR);
}
}  // namespace assistive_eval
