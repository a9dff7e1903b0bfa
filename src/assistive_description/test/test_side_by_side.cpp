#include <assistive_description/frame_source.h>
#include <assistive_description/side_by_side.h>
#include <gtest/gtest.h>

using namespace assistive_description;

TEST(SideBySide, LeftHalfToLeftRightHalfToRight)
{
  // Left half all 10, right half all 200.
  cv::Mat frame(4, 8, CV_8UC3, cv::Scalar::all(10));
  frame(cv::Rect(4, 0, 4, 4)).setTo(cv::Scalar::all(200));
  frame.at<cv::Vec3b>(1, 2) = cv::Vec3b(1, 2, 3);  // marker in the left half
  frame.at<cv::Vec3b>(3, 5) = cv::Vec3b(7, 8, 9);  // marker in the right half, column 1
  cv::Mat l, r;
  ASSERT_TRUE(splitSideBySide(frame, false, l, r));
  ASSERT_EQ(l.size(), cv::Size(4, 4));
  ASSERT_EQ(r.size(), cv::Size(4, 4));
  EXPECT_EQ(l.at<cv::Vec3b>(0, 0), cv::Vec3b(10, 10, 10));
  EXPECT_EQ(r.at<cv::Vec3b>(0, 0), cv::Vec3b(200, 200, 200));
  EXPECT_EQ(l.at<cv::Vec3b>(1, 2), cv::Vec3b(1, 2, 3));
  EXPECT_EQ(r.at<cv::Vec3b>(3, 1), cv::Vec3b(7, 8, 9));

  ASSERT_TRUE(splitSideBySide(frame, true, l, r));
  EXPECT_EQ(l.at<cv::Vec3b>(0, 0), cv::Vec3b(200, 200, 200));
  EXPECT_EQ(r.at<cv::Vec3b>(1, 2), cv::Vec3b(1, 2, 3));
}

TEST(SideBySide, RejectsOddOrEmptyFrames)
{
  cv::Mat l, r;
  std::string err;
  EXPECT_FALSE(splitSideBySide(cv::Mat(4, 7, CV_8UC1), false, l, r, &err));
  EXPECT_NE(err.find("odd"), std::string::npos);
  EXPECT_FALSE(splitSideBySide(cv::Mat(), false, l, r, &err));
}

TEST(SideBySide, SyntheticFrameHalvesMatchThePattern)
{
  const int w = 320, h = 120, d = 16;
  cv::Mat frame = SyntheticFrameSource::makeFrame(w, h, d);
  cv::Mat l, r, lm, rm;
  ASSERT_TRUE(splitSideBySide(frame, false, l, r));
  ASSERT_TRUE(toMono8(l, lm));
  ASSERT_TRUE(toMono8(r, rm));
  ASSERT_EQ(lm.type(), CV_8UC1);
  int mismatches = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w / 2; ++x)
    {
      mismatches += lm.at<uchar>(y, x) != SyntheticFrameSource::pattern(x, y);
      mismatches += rm.at<uchar>(y, x) != SyntheticFrameSource::pattern(x + d, y);
    }
  EXPECT_EQ(mismatches, 0);
  // The two halves really differ (a swapped split would be caught).
  EXPECT_GT(cv::norm(lm, rm, cv::NORM_L1), 1000.0);
  // Right pixel (x, y) shows the scene point the left image shows at (x + d, y).
  EXPECT_EQ(cv::norm(lm(cv::Rect(d, 0, w / 2 - d, h)), rm(cv::Rect(0, 0, w / 2 - d, h)),
                     cv::NORM_L1),
            0.0);
}

TEST(SideBySide, MonoConversion)
{
  cv::Mat out;
  cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(0, 0, 255));  // pure red
  ASSERT_TRUE(toMono8(bgr, out));
  EXPECT_EQ(out.type(), CV_8UC1);
  EXPECT_NEAR(out.at<uchar>(0, 0), 76, 1);  // 0.299 * 255
  cv::Mat mono(2, 2, CV_8UC1, cv::Scalar(42));
  ASSERT_TRUE(toMono8(mono, out));
  EXPECT_EQ(out.at<uchar>(1, 1), 42);
  EXPECT_NE(out.data, mono.data);  // a copy
  cv::Mat bgra(2, 2, CV_8UC4, cv::Scalar(90, 90, 90, 255));
  ASSERT_TRUE(toMono8(bgra, out));
  EXPECT_EQ(out.at<uchar>(0, 1), 90);
  std::string err;
  EXPECT_FALSE(toMono8(cv::Mat(2, 2, CV_16UC1), out, &err));
  EXPECT_FALSE(err.empty());
}
