// Affine keyframe-patch alignment against images warped by a known affine map.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include "assistive_vo/patch_alignment.h"

using assistive_vo::KeyframePatch;

namespace
{
cv::Mat texture(int seed)
{
  cv::Mat f(240, 320, CV_32F);
  cv::RNG rng(seed);
  rng.fill(f, cv::RNG::NORMAL, 0, 1);
  cv::GaussianBlur(f, f, cv::Size(0, 0), 2.0);
  cv::normalize(f, f, 30, 220, cv::NORM_MINMAX);
  cv::Mat u8;
  f.convertTo(u8, CV_8U);
  return u8;
}

/// cur(x) = gain * kf(M^-1 (x - t)) + offset: the keyframe point p appears at t + M p.
cv::Mat warp(const cv::Mat& kf, const Eigen::Matrix2f& M, const Eigen::Vector2f& t, double gain = 1, double offset = 0)
{
  cv::Mat Mt = (cv::Mat_<double>(2, 3) << M(0, 0), M(0, 1), t.x(), M(1, 0), M(1, 1), t.y());
  cv::Mat out, f;
  cv::warpAffine(kf, out, Mt, kf.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  out.convertTo(out, CV_8U, gain, offset);
  return out;
}
}  // namespace

TEST(PatchAlignment, RecoversShiftScaleAndShear)
{
  const cv::Mat kf = texture(3);
  Eigen::Matrix2f M;
  M << 1.06f, 0.03f, -0.02f, 1.04f;  // walking closer: about 5 % larger, a little shear
  const Eigen::Vector2f t(-6.3f, 4.7f);
  const cv::Mat cur = warp(kf, M, t);
  int n = 0;
  double err2 = 0;
  for (float y = 60; y <= 180; y += 30)
    for (float x = 80; x <= 240; x += 40)
    {
      const cv::Point2f p(x + 0.25f, y - 0.4f);
      const auto patch = KeyframePatch::extract(kf, p, 7);
      ASSERT_TRUE(patch);
      const Eigen::Vector2f truth = t + M * Eigen::Vector2f(p.x, p.y);
      // initial guess as from KLT: 0.8 px off, no warp
      cv::Point2f c(truth.x() + 0.6f, truth.y() - 0.5f);
      Eigen::Matrix2f A = Eigen::Matrix2f::Identity();
      ASSERT_TRUE(patch->align(cur, c, A, 20)) << x << "," << y;
      err2 += std::pow(c.x - truth.x(), 2) + std::pow(c.y - truth.y(), 2);
      EXPECT_NEAR((A - M).cwiseAbs().maxCoeff(), 0.f, 0.02f);
      ++n;
    }
  EXPECT_LT(std::sqrt(err2 / n), 0.05);  // translation-only KLT is biased by ~0.1-0.3 px here
}

TEST(PatchAlignment, IgnoresGainAndOffset)
{
  const cv::Mat kf = texture(5);
  const Eigen::Matrix2f M = Eigen::Matrix2f::Identity();
  const Eigen::Vector2f t(2.4f, -1.3f);
  const cv::Mat cur = warp(kf, M, t, 0.8, 25);
  const cv::Point2f p(160, 120);
  const auto patch = KeyframePatch::extract(kf, p, 7);
  ASSERT_TRUE(patch);
  cv::Point2f c(p.x + t.x() - 0.7f, p.y + t.y() + 0.4f);
  Eigen::Matrix2f A = Eigen::Matrix2f::Identity();
  ASSERT_TRUE(patch->align(cur, c, A, 20));
  // 0.1 px: the darker image is quantised more coarsely (a fifth fewer grey levels)
  EXPECT_NEAR(c.x, p.x + t.x(), 0.1);
  EXPECT_NEAR(c.y, p.y + t.y(), 0.1);
}

TEST(PatchAlignment, RejectsFlatPatchesBordersAndLostTargets)
{
  const cv::Mat flat(100, 100, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(KeyframePatch::extract(flat, cv::Point2f(50, 50), 7));
  const cv::Mat kf = texture(7);
  EXPECT_FALSE(KeyframePatch::extract(kf, cv::Point2f(3, 50), 7));  // too close to the border
  const auto patch = KeyframePatch::extract(kf, cv::Point2f(160, 120), 7);
  ASSERT_TRUE(patch);
  // The target image is flat: no convergence, and the estimate stays where it was.
  const cv::Mat blank(240, 320, CV_8UC1, cv::Scalar(90));
  cv::Point2f c(161.f, 119.f);
  Eigen::Matrix2f A = Eigen::Matrix2f::Identity();
  EXPECT_FALSE(patch->align(blank, c, A, 10));
  EXPECT_EQ(c, cv::Point2f(161.f, 119.f));
  EXPECT_TRUE(A.isIdentity());
}
