#include <gtest/gtest.h>
#include "assistive_vo/feature_detector.h"
#include "synthetic.h"

using namespace assistive_vo;

TEST(FeatureDetector, SpreadAndKeepsAwayFromExisting)
{
  cv::Mat img = test::randomTexture(640, 4)(cv::Rect(0, 0, 640, 480)).clone();
  VoParams p;
  FeatureDetector d(p);
  const std::vector<cv::Point2f> existing{cv::Point2f(320, 240), cv::Point2f(100, 100)};
  const std::vector<cv::Point2f> f = d.detect(img, existing, 150);
  EXPECT_GT(f.size(), 100u);
  EXPECT_LE(f.size(), 150u);
  for (const auto& q : f)
  {
    EXPECT_GE(q.x, p.border_px);
    EXPECT_GE(q.y, p.border_px);
    EXPECT_LT(q.x, img.cols - p.border_px);
    EXPECT_LT(q.y, img.rows - p.border_px);
    for (const auto& e : existing)
      EXPECT_GE(cv::norm(q - e), p.min_feature_distance_px * 0.99);
  }
  // every grid row of the image gets corners
  const cv::Size grid = bucketGrid(p, img.cols, img.rows);
  EXPECT_EQ(grid, cv::Size(8, 6));
  std::vector<int> rows(static_cast<size_t>(grid.height), 0);
  for (const auto& q : f)
    ++rows[static_cast<size_t>(q.y * grid.height / img.rows)];
  for (int r : rows)
    EXPECT_GT(r, 0);
}

TEST(FeatureDetector, SquareCellsOnAWideImage)
{
  // KITTI's 1242x375: about square 80 px cells (16 x 5), not 8 x 6 cells of 155 x 62 px. Corners
  // then spread over every column band of the wide image, as many in the outer quarters (which
  // constrain forward motion) as the texture allows.
  VoParams p;
  EXPECT_EQ(bucketGrid(p, 1242, 375), cv::Size(16, 5));
  EXPECT_EQ(bucketGrid(p, 752, 480), cv::Size(9, 6));
  cv::Mat img = test::randomTexture(1242, 6)(cv::Rect(0, 0, 1242, 375)).clone();
  FeatureDetector d(p);
  const std::vector<cv::Point2f> f = d.detect(img, {}, 250);
  EXPECT_GT(f.size(), 200u);
  std::vector<int> cols(16, 0);
  for (const auto& q : f)
    ++cols[static_cast<size_t>(q.x * 16 / img.cols)];
  const int per_cell_max = 250 / 80 + 1;
  for (int c : cols)
  {
    EXPECT_GT(c, 0);
    EXPECT_LE(c, 5 * per_cell_max);  // at most the per-cell quota in each of the 5 cells
  }
}

TEST(FeatureDetector, ThresholdAdaptsToTexture)
{
  VoParams p;
  FeatureDetector d(p);
  EXPECT_EQ(d.threshold(), 40);
  // low-contrast image: few corners at 40 -> threshold goes down
  cv::Mat tex = test::randomTexture(640, 5)(cv::Rect(0, 0, 640, 480)).clone();
  cv::Mat low;
  tex.convertTo(low, CV_8U, 0.15, 100);
  d.detect(low, {}, p.target_features);
  const int raw = d.lastRawCount();
  EXPECT_LT(raw, 2 * p.target_features);
  // below the target: two steps down, below twice the target: one step
  EXPECT_EQ(d.threshold(), 40 - (raw < p.target_features ? 2 : 1) * p.fast_threshold_step);
  for (int i = 0; i < 20; ++i)
    d.detect(low, {}, p.target_features);
  EXPECT_LT(d.threshold(), 20);
  EXPECT_GE(d.threshold(), p.fast_threshold_min);
  // noise image: thousands of corners -> threshold goes up
  cv::Mat noise(480, 640, CV_8UC1);
  cv::randu(noise, 0, 255);
  const int before = d.threshold();
  d.detect(noise, {}, p.target_features);
  EXPECT_EQ(d.threshold(), before + p.fast_threshold_step);
  // wrong type: nothing, no crash
  EXPECT_TRUE(d.detect(cv::Mat(10, 10, CV_32F), {}, 10).empty());
}
