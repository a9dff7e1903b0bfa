#include <assistive_description/conversions.h>
#include <gtest/gtest.h>

using namespace assistive_description;

TEST(Conversions, RoundTrip)
{
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.distortion_model = "rational_polynomial";
  c.D = {-0.1, 0.01, 0.001, 0.002, 0.0, 0.1, 0.2, 0.3};
  c.K = cv::Matx33d(500, 0, 320, 0, 501, 240, 0, 0, 1);
  c.R = cv::Matx33d(0.99, -0.01, 0.0, 0.01, 0.99, 0.0, 0.0, 0.0, 1.0);
  c.P = cv::Matx34d(480, 0, 318, -57.6, 0, 480, 242, 0, 0, 0, 1, 0);
  const sensor_msgs::CameraInfo m = toMsg(c);
  EXPECT_EQ(m.width, 640u);
  EXPECT_EQ(m.K[4], 501.0);  // row-major
  EXPECT_EQ(m.K[5], 240.0);
  EXPECT_EQ(m.R[1], -0.01);
  EXPECT_EQ(m.P[3], -57.6);
  EXPECT_EQ(m.P[6], 242.0);
  EXPECT_EQ(m.D.size(), 8u);
  EXPECT_TRUE(fromMsg(m) == c);
  EXPECT_NEAR(fromMsg(m).baseline(), 0.12, 1e-12);
}

TEST(Conversions, UncalibratedInfoIsNotCalibrated)
{
  sensor_msgs::CameraInfo m;  // what camera_info_manager gives without a calibration file
  EXPECT_FALSE(fromMsg(m).isCalibrated());
}
