// Line detector (seed 2.1.3.2): Sobel + eq. 2.16 suppression + divide-and-conquer linking on 8x8
// cells. Synthetic images with known straight edges: the segments lie within 1 px of them.
#include <gtest/gtest.h>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include "assistive_vo/line_detector.h"

using namespace assistive_vo;

namespace
{
/// Distance of a point to the infinite line through a, b.
double distToLine(const Eigen::Vector2d& x, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const Eigen::Vector2d d = (b - a).normalized();
  const Eigen::Vector2d r = x - a;
  return std::abs(r.x() * d.y() - r.y() * d.x());
}
}  // namespace

TEST(LineDetector, FlatImageHasNoSegments)
{
  const cv::Mat img(240, 320, CV_8U, cv::Scalar(128));
  EXPECT_TRUE(LineDetector().detect(img).empty());
  EXPECT_TRUE(LineDetector().detect(cv::Mat()).empty());
}

TEST(LineDetector, RectangleEdgesWithinOnePixel)
{
  cv::Mat img(240, 320, CV_8U, cv::Scalar(200));
  cv::rectangle(img, cv::Point(80, 60), cv::Point(239, 179), cv::Scalar(60), cv::FILLED);
  // true edges: the boundaries between pixel rows/columns 59|60, 179|180, 79|80, 239|240
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> truth = {
      {{0, 59.5}, {1, 59.5}}, {{0, 179.5}, {1, 179.5}}, {{79.5, 0}, {79.5, 1}}, {{239.5, 0}, {239.5, 1}}};
  const LineSegments segs = LineDetector().detect(img);
  ASSERT_GE(segs.size(), 4u);
  std::vector<double> longest(4, 0.0);
  for (const LineSegment& s : segs)
  {
    double best = 1e9;
    int k = -1;
    for (int i = 0; i < 4; ++i)
    {
      const double d = std::max(distToLine(s.p, truth[i].first, truth[i].second),
                                distToLine(s.q, truth[i].first, truth[i].second));
      if (d < best)
        best = d, k = i;
    }
    EXPECT_LT(best, 1.0) << "segment " << s.p.transpose() << " - " << s.q.transpose();
    longest[static_cast<size_t>(k)] = std::max(longest[static_cast<size_t>(k)], s.length());
    EXPECT_TRUE(s.covariance.allFinite());
    EXPECT_LE(s.thickness, LineDetectorParams().max_thickness);
  }
  // every side found, nearly whole (the corner cells hold two edges and are not lines)
  for (double l : longest)
    EXPECT_GT(l, 90.0);
}

TEST(LineDetector, SlantedEdgeWithinOnePixel)
{
  cv::Mat img(240, 320, CV_8U, cv::Scalar(40));
  // the half plane below the line through (20, 40) and (300, 200), anti-aliased
  const Eigen::Vector2d a(20, 40), b(300, 200);
  std::vector<cv::Point> poly = {cv::Point(20 * 16, 40 * 16), cv::Point(300 * 16, 200 * 16),
                                 cv::Point(300 * 16, 239 * 16 + 15), cv::Point(20 * 16, 239 * 16 + 15)};
  cv::fillPoly(img, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(190), cv::LINE_AA, 4);
  const LineSegments segs = LineDetector().detect(img);
  double total = 0;
  for (const LineSegment& s : segs)
  {
    const Eigen::Vector2d d = (s.q - s.p).normalized();
    if (std::abs(d.dot((b - a).normalized())) < 0.99)
      continue;  // the polygon's vertical sides
    EXPECT_LT(distToLine(s.mean, a, b), 1.0);
    total += s.length();
  }
  EXPECT_GT(total, 200.0);  // of the 322 px edge
}
