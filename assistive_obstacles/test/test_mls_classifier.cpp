#include <gtest/gtest.h>

#include <vector>

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
