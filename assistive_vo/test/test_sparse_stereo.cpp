#include <gtest/gtest.h>
#include <iostream>
#include "assistive_vo/sparse_stereo.h"
#include "synthetic.h"

using namespace assistive_vo;

namespace
{
/// Right image = left shifted by a constant sub-pixel disparity d: R(x) = L(x + d).
cv::Mat shifted(const cv::Mat& L, double d)
{
  cv::Mat R;
  cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, -d, 0, 1, 0);
  cv::warpAffine(L, R, M, L.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  return R;
}
}  // namespace

TEST(SparseStereo, SubPixelDisparityOfAShiftedTexture)
{
  cv::Mat L = test::randomTexture(640, 9)(cv::Rect(0, 0, 640, 480)).clone();
  for (double d : {7.0, 12.3, 40.75})
  {
    cv::Mat R = shifted(L, d);
    SparseStereo s;
    std::vector<cv::Point2f> pts;
    for (int i = 0; i < 20; ++i)
      pts.emplace_back(200.f + 17.3f * i, 100.f + 13.1f * i);
    const std::vector<float> disp = s.match(L, R, pts, 128);
    int ok = 0;
    double sum_abs = 0;
    for (float v : disp)
      if (v > 0)
      {
        ++ok;
        EXPECT_NEAR(v, d, 0.1) << "d=" << d;
        sum_abs += std::abs(v - d);
      }
    EXPECT_GE(ok, 18);
    EXPECT_LT(sum_abs / std::max(ok, 1), 0.04) << "d=" << d;
  }
}

TEST(SparseStereo, SubPixelDisparityUnbiasedOverTheFraction)
{
  // Both images sampled like a camera does (pixel area integration) from one fine-grained texture
  // at 8x resolution, the right one shifted by a disparity in steps of 1/8 px. A sub-pixel
  // refinement whose error depends on the fractional disparity (pixel locking) would turn into
  // depth errors of percent at small disparities (far points, KITTI); the mean error must stay
  // small for every fraction.
  const int k8 = 8, W = 640, H = 240;
  cv::Mat t(H * k8, (W + 32) * k8, CV_32F);
  cv::RNG rng(3);
  rng.fill(t, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(t, t, cv::Size(0, 0), 0.6 * k8);
  cv::normalize(t, t, 0, 255, cv::NORM_MINMAX);
  auto sample = [&](int shift8) {
    cv::Mat small, out;
    cv::resize(t(cv::Rect(shift8, 0, W * k8, H * k8)), small, cv::Size(W, H), 0, 0, cv::INTER_AREA);
    small.convertTo(out, CV_8U);
    return out;
  };
  // the left pixel x sees texture x + 16, the right one x + 16 + d: u_right = u_left - d
  const cv::Mat L = sample(16 * k8);
  SparseStereo s;
  std::vector<cv::Point2f> pts;
  for (int i = 0; i < 60; ++i)
    pts.emplace_back(150.f + 7.f * i, 20.f + 3.f * i);
  double worst = 0;
  for (int f = 0; f < k8; ++f)
  {
    const double d = 6.0 + static_cast<double>(f) / k8;
    const cv::Mat R = sample(16 * k8 + 6 * k8 + f);
    const std::vector<float> disp = s.match(L, R, pts, 64);
    double sum = 0;
    int ok = 0;
    for (float v : disp)
      if (v > 0)
      {
        sum += v - d;
        ++ok;
      }
    ASSERT_GE(ok, 50) << "d=" << d;
    worst = std::max(worst, std::abs(sum / ok));
    EXPECT_LT(std::abs(sum / ok), 0.03) << "mean error at d=" << d;
  }
  std::cout << "largest mean disparity error over the fraction: " << worst << " px\n";
}

TEST(SparseStereo, NoMatchOnFlatImageOrOutsideRange)
{
  cv::Mat flat(480, 640, CV_8UC1, cv::Scalar(128));
  SparseStereo s;
  EXPECT_LT(s.matchOne(flat, flat, cv::Point2f(300, 200), 64), 0.f);
  cv::Mat L = test::randomTexture(640, 9)(cv::Rect(0, 0, 640, 480)).clone();
  cv::Mat R = shifted(L, 90.0);
  EXPECT_LT(s.matchOne(L, R, cv::Point2f(300, 200), 64), 0.f);   // true disparity beyond the range
  EXPECT_LT(s.matchOne(L, R, cv::Point2f(2, 200), 64), 0.f);     // at the border
  // mismatched sizes: every point unmatched, no crash
  const std::vector<float> d = s.match(L, cv::Mat(100, 100, CV_8UC1), {cv::Point2f(300, 200)}, 64);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_LT(d[0], 0.f);
}
