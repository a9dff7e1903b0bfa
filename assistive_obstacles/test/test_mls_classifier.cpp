#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <assistive_obstacles/mls_classifier.h>

using namespace assistive_obstacles;

namespace
{
std::vector<float> range(float z0, float z1, int n)
{
  std::vector<float> h;
  for (int i = 0; i < n; ++i) h.push_back(z0 + (z1 - z0) * i / std::max(1, n - 1));
  return h;
}
std::vector<float> concat(std::vector<float> a, const std::vector<float>& b)
{
  a.insert(a.end(), b.begin(), b.end());
  std::sort(a.begin(), a.end());
  return a;
}
}  // namespace

TEST(MlsClassifier, DoorwayFloorAndLintelInOneCellIsHorizontal)
{
  MlsClassifier mls;  // G = 1.9 m, T = 0.2 m
  // Floor at 0 and the wall above a 2.05 m door (2.05..2.5 m) in the same cell.
  const auto h = concat(range(-0.01f, 0.01f, 25), range(2.05f, 2.5f, 20));
  std::vector<HeightInterval> iv;
  mls.intervals(h.data(), static_cast<int>(h.size()), iv);
  ASSERT_EQ(iv.size(), 2u);
  EXPECT_NEAR(iv[0].median, 0.0f, 0.02f);
  EXPECT_GT(iv[1].bottom, 2.0f);
  float g = -1.f;
  EXPECT_EQ(mls.analyse(h.data(), static_cast<int>(h.size()), g), CellKind::HORIZONTAL);
  EXPECT_NEAR(g, 0.0f, 0.02f);
}

TEST(MlsClassifier, LowDoorIsVertical)
{
  MlsClassifier mls;
  // A 1.5 m opening: the gap (1.5 m) is below G, floor and wall merge into one thick interval.
  const auto h = concat(range(0.f, 0.01f, 25), range(1.5f, 2.0f, 20));
  float g;
  EXPECT_EQ(mls.analyse(h.data(), static_cast<int>(h.size()), g), CellKind::VERTICAL);
}

TEST(MlsClassifier, OutliersDoNotMakeFloorVertical)
{
  MlsClassifier mls;
  auto h = range(-0.02f, 0.02f, 40);
  h.push_back(0.9f);  // two isolated stereo outliers
  h.push_back(1.3f);
  std::sort(h.begin(), h.end());
  float g;
  EXPECT_EQ(mls.analyse(h.data(), static_cast<int>(h.size()), g), CellKind::HORIZONTAL);
}

TEST(MlsClassifier, StepIsHorizontalTallBoxIsVertical)
{
  MlsClassifier mls;
  const auto step = concat(range(0.f, 0.01f, 20), range(0.15f, 0.16f, 20));  // 15 cm riser
  float g;
  EXPECT_EQ(mls.analyse(step.data(), static_cast<int>(step.size()), g), CellKind::HORIZONTAL);
  const auto box = concat(range(0.f, 0.01f, 20), range(0.0f, 0.5f, 30));
  EXPECT_EQ(mls.analyse(box.data(), static_cast<int>(box.size()), g), CellKind::VERTICAL);
  const auto few = range(0.f, 0.01f, 9);  // fewer than min_points_per_cell
  EXPECT_EQ(mls.analyse(few.data(), static_cast<int>(few.size()), g), CellKind::EMPTY);
}

// A matcher's errors are shared by the pixels of a block (block_size^2 at its scale): the heights of
// a plain floor's cell come as a smooth field, not as independent draws. Counted as independent,
// n heights made the ground's standard error about 4x too small, and neighbouring cells a few
// centimetres apart read as steps (a generated corridor's plain floor: 83,000 false step cells,
// none from true depth). Counted per block, the standard error covers the grounds' real spread.
TEST(MlsClassifier, GroundErrorCountsTheMatchersBlocksNotItsPixels)
{
  ObstaclesParams p;
  p.step_se_per_block = true;
  ASSERT_EQ(p.point_stride, 1);
  const int block = p.block_size | 1, cell = 10, cells = 30;  // 10 x 10 pixels a cell
  // the matcher's height error: white noise averaged over its block, 3 cm
  cv::Mat noise(cells * cell, cells * cell, CV_32F), field;
  cv::RNG rng(5);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  cv::blur(noise, field, cv::Size(block, block));
  cv::Scalar mean, sd;
  cv::meanStdDev(field, mean, sd);
  field = (field - mean[0]) * (0.03 / sd[0]);
  auto spread = [&](const ObstaclesParams& q, double& se_mean) {
    MlsClassifier mls(q);
    std::vector<double> grounds;
    se_mean = 0.0;
    for (int cy = 0; cy < cells; ++cy)
      for (int cx = 0; cx < cells; ++cx)
      {
        std::vector<float> h;
        for (int v = 0; v < cell; ++v)
          for (int u = 0; u < cell; ++u) h.push_back(field.at<float>(cy * cell + v, cx * cell + u));
        std::sort(h.begin(), h.end());
        float g = 0.f, se = 0.f;
        EXPECT_EQ(mls.analyse(h.data(), static_cast<int>(h.size()), g, false, &se), CellKind::HORIZONTAL);
        grounds.push_back(g);
        se_mean += se;
      }
    se_mean /= grounds.size();
    double m = 0.0, v = 0.0;
    for (double g : grounds) m += g;
    m /= grounds.size();
    for (double g : grounds) v += (g - m) * (g - m);
    return std::sqrt(v / (grounds.size() - 1));
  };
  double se_block = 0.0, se_each = 0.0;
  const double sd_block = spread(p, se_block);
  ObstaclesParams each = p;
  each.step_se_per_block = false;
  const double sd_each = spread(each, se_each);
  EXPECT_DOUBLE_EQ(sd_block, sd_each);  // the grounds themselves do not change
  std::printf("grounds' spread %.4f m; standard error per block %.4f, per pixel %.4f\n", sd_block, se_block, se_each);
  EXPECT_GT(se_block, 0.8 * sd_block);
  EXPECT_LT(se_block, 2.5 * sd_block);
  EXPECT_LT(se_each, 0.4 * sd_block);
}
