// Plots: files are written, the paths and the scored-map colours land where they should.
#include <assistive_eval/plots.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <vector>
#include <opencv2/imgcodecs.hpp>

using namespace assistive_eval;

TEST(Plots, TopDownAndSideViewAreWritten)
{
  Grid floor{0.0, 0.0, 0.2, 60, 30, std::vector<int8_t>(60 * 30, CELL_FREE)};  // origin, 0.2 m, 60 x 30
  for (int x = 0; x < 60; ++x)
    floor.data[static_cast<size_t>(29) * 60 + x] = CELL_OBSTACLE;
  PlotSeries gt{"truth", {}, cv::Scalar(0, 160, 0)}, est{"estimate", {}, cv::Scalar(0, 0, 255)};
  for (int i = 0; i < 100; ++i)
  {
    gt.points.emplace_back(0.1 * i, 3.0, 1.6);
    est.points.emplace_back(0.1 * i, 3.0 + 0.01 * i, 1.6 + 0.002 * i);
  }
  PlotOptions o;
  const cv::Mat top = plotTopDown({gt, est}, &floor, o);
  const cv::Mat side = plotSideView({gt, est}, o);
  ASSERT_EQ(top.cols, o.width);
  ASSERT_EQ(top.rows, o.height);
  ASSERT_FALSE(side.empty());
  // both path colours are present
  auto count = [](const cv::Mat& m, const cv::Scalar& c) {
    cv::Mat mask;
    cv::inRange(m, c, c, mask);
    return cv::countNonZero(mask);
  };
  EXPECT_GT(count(top, gt.color), 50);
  EXPECT_GT(count(top, est.color), 50);
  EXPECT_GT(count(side, est.color), 50);
  const std::string path = testing::TempDir() + "/plot_topdown_test.png";
  ASSERT_TRUE(writePng(path, top));
  const cv::Mat back = cv::imread(path);
  EXPECT_EQ(back.cols, top.cols);
  std::remove(path.c_str());
  std::string err;
  EXPECT_FALSE(writePng("/nonexistent_dir/x.png", top, &err));
  EXPECT_FALSE(err.empty());
}

TEST(Plots, ScoredMapColoursTpFpFn)
{
  Grid gt, est;
  gt.resolution = est.resolution = 1.0;
  gt.width = gt.height = est.width = est.height = 10;
  gt.data.assign(100, CELL_FREE);
  est.data.assign(100, CELL_FREE);
  gt.data[5 * 10 + 5] = CELL_OBSTACLE;   // TP
  est.data[5 * 10 + 5] = CELL_OBSTACLE;
  gt.data[5 * 10 + 6] = CELL_OBSTACLE;   // FN
  est.data[4 * 10 + 4] = CELL_OBSTACLE;  // FP
  const int px = 10;
  const cv::Mat img = plotMapScore(gt, est, Eigen::Vector2d(5.0, 5.0), 4.0, Eigen::Isometry2d::Identity(), px);
  ASSERT_FALSE(img.empty());
  // the window (radius + 2 m around (5, 5)) covers the whole 10 x 10 grid
  const int margin = 30;
  auto colourAt = [&](int cx, int cy) {
    return img.at<cv::Vec3b>(margin + (10 - 1 - cy) * px + px / 2, margin + cx * px + px / 2);
  };
  EXPECT_EQ(colourAt(5, 5), cv::Vec3b(60, 180, 60));  // TP green
  EXPECT_EQ(colourAt(6, 5), cv::Vec3b(40, 40, 220));  // FN red
  EXPECT_EQ(colourAt(4, 4), cv::Vec3b(0, 140, 255));  // FP orange
}
