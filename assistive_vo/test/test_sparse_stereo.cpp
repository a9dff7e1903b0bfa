#include <gtest/gtest.h>
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

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
