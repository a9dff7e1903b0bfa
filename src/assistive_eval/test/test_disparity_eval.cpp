// Dense-stereo scoring (disparity_eval.h) on hand-made disparities with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <assistive_eval/disparity_eval.h>

#include <opencv2/imgproc.hpp>

using namespace assistive_eval;

TEST(DisparityEval, KnownAnswers)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat gt = (cv::Mat_<float>(1, 5) << 10.f, 100.f, 20.f, nan, 50.f);
  cv::Mat est = (cv::Mat_<float>(1, 5) << 10.5f, 104.f, 23.5f, 7.f, -1.f);
  // px 0: ok; px 1: err 4 > 3 but < 5 % of 100 -> not D1, > 2 -> bad2; px 2: err 3.5 -> D1 and bad2;
  // px 3: no GT; px 4: no estimate -> error in both.
  const DisparityScore s = scoreDisparity(est, gt);
  EXPECT_EQ(s.valid, 4u);
  EXPECT_DOUBLE_EQ(s.d1_pct, 50.0);
  EXPECT_DOUBLE_EQ(s.bad2_pct, 75.0);
  EXPECT_DOUBLE_EQ(s.density_pct, 75.0);
}

TEST(DisparityEval, PeerSgbmFindsTheShiftOfATexturedPair)
{
  // A random texture (blobs of about 2 px) and the same texture 8 px further left in the right
  // image (a fronto-parallel plane at disparity 8): the SGBM peer reports 8 wherever it has an
  // estimate, and has one on most pixels.
  cv::Mat noise(60, 100, CV_8UC1), tex;
  cv::RNG(5).fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::resize(noise, tex, cv::Size(200, 120), 0, 0, cv::INTER_LINEAR);
  const cv::Mat left = tex(cv::Rect(0, 0, 160, 120)).clone(), right = tex(cv::Rect(8, 0, 160, 120)).clone();
  const cv::Mat d = peerSgbm(left, right, 32);
  ASSERT_EQ(d.type(), CV_32F);
  ASSERT_EQ(d.size(), left.size());
  int valid = 0, right_answer = 0;
  for (int v = 0; v < d.rows; ++v)
    for (int u = 40; u < d.cols; ++u)  // columns a 32-disparity search can match
    {
      const float x = d.at<float>(v, u);
      if (x <= 0.f)
        continue;
      ++valid;
      right_answer += std::abs(x - 8.f) <= 0.5f;
    }
  EXPECT_GT(valid, 0.8 * d.rows * (d.cols - 40));
  EXPECT_GT(right_answer, 0.95 * valid);
}
