#include <assistive_description/rectifier.h>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <cmath>

using namespace assistive_description;

namespace
{
// A smooth scene, as seen by the ideal (undistorted) camera at pixel (u, v).
double scene(double u, double v)
{
  return 128.0 + 90.0 * std::sin(u / 9.0) * std::cos(v / 11.0);
}

CameraCalibration makeCalibration(const std::string& model, std::vector<double> D)
{
  CameraCalibration c;
  c.width = 320;
  c.height = 240;
  c.distortion_model = model;
  c.D = std::move(D);
  c.K = cv::Matx33d(300, 0, 162, 0, 300, 118, 0, 0, 1);
  c.R = cv::Matx33d::eye();
  c.P = cv::Matx34d(300, 0, 160, 0, 0, 300, 120, 0, 0, 0, 1, 0);
  return c;
}

// The raw image the distorted camera records: raw pixel p shows the scene at the ideal pixel
// P * undistort(p). Undistortion by OpenCV's iterative undistortPoints, run to convergence.
cv::Mat makeRaw(const CameraCalibration& c)
{
  std::vector<cv::Point2d> raw_pts;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) raw_pts.emplace_back(x, y);
  std::vector<cv::Point2d> ideal;
  cv::undistortPoints(raw_pts, ideal, cv::Mat(c.K), cv::Mat(c.D), cv::Mat(c.R),
                      cv::Mat(c.P).colRange(0, 3),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
  cv::Mat raw(c.height, c.width, CV_8UC1);
  for (std::size_t i = 0; i < raw_pts.size(); ++i)
    raw.at<uchar>(static_cast<int>(raw_pts[i].y), static_cast<int>(raw_pts[i].x)) =
        cv::saturate_cast<uchar>(scene(ideal[i].x, ideal[i].y));
  return raw;
}

// Mean absolute error between `img` and the scene over the central region (away from borders
// that the distortion maps outside the raw image).
double meanError(const cv::Mat& img, int margin)
{
  double sum = 0.0;
  int n = 0;
  for (int y = margin; y < img.rows - margin; ++y)
    for (int x = margin; x < img.cols - margin; ++x, ++n)
      sum += std::abs(img.at<uchar>(y, x) - scene(x, y));
  return sum / n;
}
}  // namespace

TEST(Rectifier, UndistortsASyntheticDistortedFrame)
{
  const CameraCalibration c = makeCalibration("plumb_bob", {-0.3, 0.08, 0.001, -0.001, 0.0});
  const cv::Mat raw = makeRaw(c);
  Rectifier r;
  std::string err;
  ASSERT_TRUE(r.configure(c, &err)) << err;
  cv::Mat rect;
  ASSERT_TRUE(r.rectify(raw, rect));
  ASSERT_EQ(rect.size(), raw.size());
  ASSERT_EQ(rect.type(), CV_8UC1);
  // Known answer: the rectified image is the ideal view of the scene (up to interpolation
  // and 8-bit rounding), while the raw one is far from it.
  EXPECT_LT(meanError(rect, 30), 1.0);
  EXPECT_GT(meanError(raw, 30), 10.0);
  // A single pixel in the middle of the image, and one near a corner where distortion is large.
  EXPECT_NEAR(rect.at<uchar>(120, 160), scene(160, 120), 2.0);
  EXPECT_NEAR(rect.at<uchar>(40, 50), scene(50, 40), 2.0);
}

TEST(Rectifier, AppliesTheRectificationRotation)
{
  // A stereo-rectified eye: R turns the camera by 3 degrees about its y axis and 1 about x.
  CameraCalibration c = makeCalibration("plumb_bob", {-0.1, 0.01, 0.0, 0.0, 0.0});
  cv::Matx33d Ry, Rx;
  cv::Rodrigues(cv::Vec3d(0, 3.0 * CV_PI / 180.0, 0), Ry);
  cv::Rodrigues(cv::Vec3d(1.0 * CV_PI / 180.0, 0, 0), Rx);
  c.R = Rx * Ry;
  const cv::Mat raw = makeRaw(c);
  Rectifier r;
  ASSERT_TRUE(r.configure(c));
  cv::Mat rect;
  ASSERT_TRUE(r.rectify(raw, rect));
  EXPECT_LT(meanError(rect, 40), 1.0);
  // Without R (distortion only) the result is off by the rotation (~16 px): clearly worse.
  CameraCalibration no_r = c;
  no_r.R = cv::Matx33d::eye();
  Rectifier r2;
  ASSERT_TRUE(r2.configure(no_r));
  cv::Mat rect2;
  ASSERT_TRUE(r2.rectify(raw, rect2));
  EXPECT_GT(meanError(rect2, 40), 10.0);
}

TEST(Rectifier, EquidistantModel)
{
  const CameraCalibration c = makeCalibration("equidistant", {0.05, -0.01, 0.0, 0.0});
  // Build the raw image with the fisheye model's own undistortion.
  std::vector<cv::Point2d> raw_pts, ideal;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) raw_pts.emplace_back(x, y);
  cv::fisheye::undistortPoints(raw_pts, ideal, cv::Mat(c.K), cv::Mat(c.D), cv::Mat(c.R),
                               cv::Mat(c.P).colRange(0, 3));
  cv::Mat raw(c.height, c.width, CV_8UC1);
  for (std::size_t i = 0; i < raw_pts.size(); ++i)
    raw.at<uchar>(static_cast<int>(raw_pts[i].y), static_cast<int>(raw_pts[i].x)) =
        cv::saturate_cast<uchar>(scene(ideal[i].x, ideal[i].y));
  Rectifier r;
  ASSERT_TRUE(r.configure(c));
  cv::Mat rect;
  ASSERT_TRUE(r.rectify(raw, rect));
  EXPECT_LT(meanError(rect, 30), 1.0);
  EXPECT_GT(meanError(raw, 30), 5.0);
}

TEST(Rectifier, RectifiedCalibrationHasNoDistortion)
{
  const CameraCalibration c = makeCalibration("plumb_bob", {-0.3, 0.08, 0.0, 0.0, 0.0});
  Rectifier r;
  ASSERT_TRUE(r.configure(c));
  const CameraCalibration& rc = r.rectifiedCalibration();
  EXPECT_EQ(rc.width, 320);
  EXPECT_EQ(rc.height, 240);
  ASSERT_EQ(rc.D.size(), 5u);
  for (double d : rc.D) EXPECT_EQ(d, 0.0);
  EXPECT_EQ(rc.R, cv::Matx33d::eye());
  EXPECT_EQ(rc.P, c.P);
  EXPECT_EQ(rc.K, cv::Matx33d(300, 0, 160, 0, 300, 120, 0, 0, 1));
}

TEST(Rectifier, RejectsBadCalibrationsAndSizes)
{
  Rectifier r;
  std::string err;
  EXPECT_FALSE(r.configure(CameraCalibration(), &err));  // uncalibrated: zeros
  EXPECT_FALSE(err.empty());
  EXPECT_FALSE(r.configure(makeCalibration("wobbly", {0, 0, 0, 0, 0}), &err));
  EXPECT_NE(err.find("wobbly"), std::string::npos);
  EXPECT_FALSE(r.configure(makeCalibration("equidistant", {0, 0, 0, 0, 0}), &err));
  EXPECT_FALSE(r.configured());
  ASSERT_TRUE(r.configure(makeCalibration("plumb_bob", {})));
  cv::Mat rect;
  EXPECT_FALSE(r.rectify(cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)), rect));
  EXPECT_TRUE(r.rectify(cv::Mat(240, 320, CV_8UC1, cv::Scalar(7)), rect));
  EXPECT_EQ(rect.at<uchar>(120, 160), 7);
}
