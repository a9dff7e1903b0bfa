#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include <opencv2/imgproc.hpp>

#include <assistive_obstacles/disparity.h>

using namespace assistive_obstacles;

namespace
{
// Random texture; the right image is the left shifted by d px (a fronto-parallel plane).
void makePair(int d, cv::Mat& l, cv::Mat& r)
{
  cv::Mat big(480, 640 + d, CV_8U);
  cv::RNG rng(3);
  rng.fill(big, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(big, big, cv::Size(3, 3), 0.8);
  l = big(cv::Rect(0, 0, 640, 480)).clone();
  r = big(cv::Rect(d, 0, 640, 480)).clone();  // right(x - d) = left(x)
}

// The points of the pair (l, r) left of column 300 (textured) and right of 360 (flat), in the
// default rig's full-resolution columns.
void countHalves(const cv::Mat& l, const cv::Mat& r, const ObstaclesParams& q, int& textured, int& flat)
{
  const StereoModel m;
  DisparityEstimator est(q);
  cv::Mat d;
  ASSERT_TRUE(est.compute(l, r, d));
  std::vector<Eigen::Vector3f> pts;
  est.toPoints(d, m, pts);
  textured = flat = 0;
  for (const auto& x : pts)
  {
    const double u = x.x() / x.z() * m.fx + m.cx;
    textured += u < 300;
    flat += u > 360;
  }
}
}  // namespace

TEST(Disparity, PlaneAtKnownDisparityAndDepth)
{
  cv::Mat l, r;
  makePair(40, l, r);
  ObstaclesParams p;  // half scale
  DisparityEstimator est(p);
  cv::Mat full;
  ASSERT_TRUE(est.computeFullRes(l, r, full));
  ASSERT_EQ(full.size(), l.size());
  cv::Mat roi = full(cv::Rect(200, 100, 300, 280));
  int good = 0;
  for (int v = 0; v < roi.rows; ++v)
    for (int u = 0; u < roi.cols; ++u) good += std::abs(roi.at<float>(v, u) - 40.f) < 1.0f;
  EXPECT_GT(good, 0.95 * roi.total());

  cv::Mat small;
  ASSERT_TRUE(est.compute(l, r, small));
  EXPECT_EQ(small.cols, 320);
  StereoModel m;  // fx 500, B 0.12 -> z = 60 / 40 = 1.5 m
  std::vector<Eigen::Vector3f> pts;
  est.toPoints(small, m, pts);
  ASSERT_GT(pts.size(), 40000u);
  int near = 0;
  for (const auto& q : pts) near += std::abs(q.z() - 1.5f) < 0.05f;
  EXPECT_GT(near, 0.95 * pts.size());
}

// Normals from the disparity gradient: a wall to the left (x = -0.8 m in the optical frame) seen
// at grazing angles, and a fronto-parallel plane.
TEST(Disparity, SurfaceNormalsFromTheDisparityGradient)
{
  StereoModel m;  // fx 500 at 640x480, B 0.12; disparity at half scale: fx 250, cx 159.5
  ObstaclesParams p;
  DisparityEstimator est(p);
  cv::Mat wall(240, 320, CV_32F, cv::Scalar(-1.f));
  for (int v = 0; v < 240; ++v)
    for (int u = 0; u < 150; ++u) wall.at<float>(v, u) = 0.12f * (159.5f - u) / 0.8f;  // d = B (cx - u) / 0.8
  std::vector<Eigen::Vector3f> pts, normals;
  est.toPoints(wall, m, pts, &normals);
  ASSERT_EQ(pts.size(), normals.size());
  ASSERT_GT(pts.size(), 10000u);
  int good = 0;
  for (size_t i = 0; i < pts.size(); ++i)
  {
    EXPECT_NEAR(pts[i].x(), -0.8f, 1e-3f);
    good += normals[i].dot(Eigen::Vector3f(1, 0, 0)) > 0.999f;
  }
  EXPECT_GT(good, 0.98 * pts.size());

  const cv::Mat front(240, 320, CV_32F, cv::Scalar(20.f));
  est.toPoints(front, m, pts, &normals);
  ASSERT_EQ(pts.size(), normals.size());
  good = 0;
  for (size_t i = 0; i < pts.size(); ++i) good += normals[i].dot(Eigen::Vector3f(0, 0, -1)) > 0.999f;
  EXPECT_GT(good, 0.95 * pts.size());  // all but a 4 px border, where the ray stands in
}

// A plane at 1.5 m whose right half has no texture: there the disparity is a guess (smoothness
// fills it in), its Cramer-Rao bound is unbounded, and it gives no point.
TEST(Disparity, TexturelessPixelsGiveNoPoint)
{
  cv::Mat l, r;
  makePair(40, l, r);
  l.colRange(330, 640).setTo(120);
  r.colRange(290, 640).setTo(120);  // right(x - 40) = left(x): the flat part, shifted
  ObstaclesParams p;
  ASSERT_GT(p.texture_max_depth_sigma, 0.0);
  int textured = 0, flat = 0;
  countHalves(l, r, p, textured, flat);
  EXPECT_GT(textured, 20000);
  EXPECT_EQ(flat, 0);
  p.texture_max_depth_sigma = 0.0;  // off: the matcher's guesses on the flat half come through
  int textured_off = 0, flat_off = 0;
  countHalves(l, r, p, textured_off, flat_off);
  EXPECT_GT(flat_off, 1000);
  EXPECT_NEAR(textured_off, textured, 0.02 * textured);  // textured pixels pass the bound
}

// The same plane, with the camera's pixel noise (sigma 2, independent in the two images) on
// both halves, seen by an active camera (the flat half: beyond the dots' reach): the noise's own
// gradient energy would pass the bound as texture, and the matcher's guesses on the flat half (the
// textured half's disparity, smoothed in) became points there. A passive camera keeps the raw
// energy.
TEST(Disparity, PixelNoiseIsNoTexture)
{
  cv::Mat l, r;
  makePair(40, l, r);
  l.colRange(330, 640).setTo(120);
  r.colRange(290, 640).setTo(120);
  cv::Mat nl(l.size(), CV_16S), nr(r.size(), CV_16S);
  cv::RNG rng(11);
  rng.fill(nl, cv::RNG::NORMAL, 0, 2.0);
  rng.fill(nr, cv::RNG::NORMAL, 0, 2.0);
  l.convertTo(l, CV_16S);
  r.convertTo(r, CV_16S);
  cv::add(l, nl, l);
  cv::add(r, nr, r);
  l.convertTo(l, CV_8U);
  r.convertTo(r, CV_8U);
  ObstaclesParams p;
  ASSERT_DOUBLE_EQ(p.image_noise_sigma, 2.0);
  ASSERT_GT(p.texture_min_snr, 0.0);
  p.projected = true;
  int textured = 0, flat = 0;
  countHalves(l, r, p, textured, flat);
  EXPECT_GT(textured, 20000);
  // 1 % of the noise's blocks pass the test, and few of those give a point: at most 0.1 % of the
  // flat half's 140 x 240 pixels at the matcher's scale
  EXPECT_LT(flat, 34);
  p.texture_min_snr = 0.0;  // the raw energy, noise and all
  int textured_raw = 0, flat_raw = 0;
  countHalves(l, r, p, textured_raw, flat_raw);
  std::printf("points on the flat half: %d, with the raw energy %d\n", flat, flat_raw);
  EXPECT_GT(flat_raw, 10 * flat);
  EXPECT_NEAR(textured_raw, textured, 0.02 * textured);  // real texture stands far above the noise
  p.texture_min_snr = 3.0;
  p.projected = false;  // a passive camera: the raw energy
  int textured_passive = 0, flat_passive = 0;
  countHalves(l, r, p, textured_passive, flat_passive);
  EXPECT_EQ(flat_passive, flat_raw);
  EXPECT_EQ(textured_passive, textured_raw);
}

TEST(Disparity, BadInputIsRejected)
{
  DisparityEstimator est;
  cv::Mat d;
  EXPECT_FALSE(est.compute(cv::Mat(), cv::Mat(), d));
  EXPECT_FALSE(est.compute(cv::Mat(480, 640, CV_8U), cv::Mat(240, 320, CV_8U), d));
  EXPECT_TRUE(d.empty());
}
