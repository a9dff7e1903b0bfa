// Mover segmentation on hand-built scene flow: a wearer walking and turning, a static floor and
// wall, and two boxes of points (people) moving; the ego-motion is known exactly.
#include <cmath>

#include <gtest/gtest.h>

#include <assistive_obstacles/mover_segmentation.h>

using namespace assistive_obstacles;

namespace
{
/// Camera at (x, y, z) looking along world yaw `yaw` (optical z forward, x right, y down).
Eigen::Isometry3d cameraPose(double x, double y, double z, double yaw)
{
  Eigen::Matrix3d look;
  look << 0, 0, 1,
      -1, 0, 0,
       0, -1, 0;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * look;
  t.translation() = Eigen::Vector3d(x, y, z);
  return t;
}

struct Scene
{
  Eigen::Isometry3d T_world_prev = cameraPose(0.0, 0.0, 1.6, 0.0);
  Eigen::Isometry3d T_world_cur = cameraPose(0.1, 0.02, 1.6, 0.035);  // 10 cm forward, 2 degrees left
  std::vector<SceneFlowPoint> flow;
  std::vector<uint8_t> truth_moving;

  Eigen::Isometry3d egoMotion() const { return T_world_cur.inverse() * T_world_prev; }
  /// A world point `w` (now) that moved by `d` (world) since the previous frame.
  void add(const Eigen::Vector3d& w, const Eigen::Vector3d& d = Eigen::Vector3d::Zero())
  {
    SceneFlowPoint f;
    f.prev = T_world_prev.inverse() * (w - d);
    f.cur = T_world_cur.inverse() * w;
    flow.push_back(f);
    truth_moving.push_back(d.norm() > 0.0 ? 1 : 0);
  }
  /// A person-sized box of points centred at (cx, cy), nx x ny columns 0.1 m apart, heights
  /// 0.1 .. 1.7 m every 0.2 m; its centroid is exactly (cx, cy).
  int box(double cx, double cy, int nx, int ny, const Eigen::Vector3d& d)
  {
    int n = 0;
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j)
        for (int k = 0; k < 9; ++k, ++n)
          add(Eigen::Vector3d(cx + 0.1 * (i - (nx - 1) / 2.0), cy + 0.1 * (j - (ny - 1) / 2.0), 0.1 + 0.2 * k), d);
    return n;
  }
  void staticScene()
  {
    for (double x = 1.05; x < 5.0; x += 0.1)
      for (double y = -1.95; y < 2.0; y += 0.1) add(Eigen::Vector3d(x, y, 0.0));      // floor
    for (double y = -1.95; y < 2.0; y += 0.1)
      for (double z = 0.05; z < 2.2; z += 0.1) add(Eigen::Vector3d(5.5, y, z));        // wall
  }
};
}  // namespace

TEST(MoverSegmentation, StereoSigmaScalesTheThreshold)
{
  MoverSegmentation seg;  // 500 px, 12 cm, 0.3 px: sigma_Z = Z^2 / 200
  EXPECT_DOUBLE_EQ(stereoDepthSigma(seg.params(), 2.0), 0.02);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  SceneFlowPoint f;
  // 0.3 m along the ray: 9.05 sigmas at 2 m (moving), 2.45 at 4 m (depth noise).
  f.prev = Eigen::Vector3d(0, 0, 2.0);
  f.cur = Eigen::Vector3d(0, 0, 2.3);
  EXPECT_NEAR(residualSigmas(seg.params(), f, I), 0.3 / std::hypot(0.02, 2.3 * 2.3 / 200), 1e-12);
  EXPECT_TRUE(seg.isMoving(f, I));
  f.prev = Eigen::Vector3d(0, 0, 4.0);
  f.cur = Eigen::Vector3d(0, 0, 4.3);
  EXPECT_NEAR(residualSigmas(seg.params(), f, I), 0.3 / std::hypot(0.08, 4.3 * 4.3 / 200), 1e-12);
  EXPECT_FALSE(seg.isMoving(f, I));
  // Across the ray the pixel error is small: 6 cm at 4 m is motion, 4 cm is below min_residual.
  f.cur = Eigen::Vector3d(0.06, 0, 4.0);
  EXPECT_TRUE(seg.isMoving(f, I));
  f.cur = Eigen::Vector3d(0.04, 0, 4.0);
  EXPECT_FALSE(seg.isMoving(f, I));
  // Not in front of the camera: never a mover.
  f.cur = Eigen::Vector3d(1.0, 0, -4.0);
  EXPECT_EQ(residualSigmas(seg.params(), f, I), 0.0);
  EXPECT_FALSE(seg.isMoving(f, I));
}

TEST(MoverSegmentation, StaticSceneUnderEgoMotionHasNoMover)
{
  Scene s;
  s.staticScene();
  s.box(2.5, 0.6, 4, 5, Eigen::Vector3d::Zero());  // a person standing still: an ordinary obstacle
  MoverSegmentation seg;
  EXPECT_TRUE(seg.segment(s.flow, s.egoMotion(), s.T_world_cur).empty());
  for (uint8_t m : seg.moving()) EXPECT_EQ(m, 0);
  // The same scene judged with the wrong ego-motion (the VO said "standing still") is all moving.
  seg.segment(s.flow, Eigen::Isometry3d::Identity(), s.T_world_cur);
  size_t moving = 0;
  for (uint8_t m : seg.moving()) moving += m;
  EXPECT_GT(moving, s.flow.size() / 2);
}

TEST(MoverSegmentation, TwoMovingBoxesExactSegmentationAndCentroids)
{
  Scene s;
  s.staticScene();
  const size_t first_a = s.flow.size();
  const int na = s.box(2.5, 0.6, 4, 5, Eigen::Vector3d(0.0, -0.12, 0.0));   // crossing to the right, 1.2 m/s at 10 Hz
  const size_t first_b = s.flow.size();
  const int nb = s.box(3.5, -1.0, 3, 4, Eigen::Vector3d(-0.05, 0.15, 0.0)); // crossing to the left
  // A mismatched feature: one lone "moving" point, too few for a mover.
  const size_t outlier = s.flow.size();
  s.add(Eigen::Vector3d(4.0, 1.5, 0.0), Eigen::Vector3d(0.3, 0.0, 0.0));
  ASSERT_EQ(na, 180);
  ASSERT_EQ(nb, 108);

  MoverSegmentation seg;
  const std::vector<MoverDetection>& d = seg.segment(s.flow, s.egoMotion(), s.T_world_cur);
  // Exact segmentation: every point's label is the truth.
  ASSERT_EQ(seg.moving().size(), s.flow.size());
  for (size_t i = 0; i < s.flow.size(); ++i) EXPECT_EQ(seg.moving()[i], s.truth_moving[i]) << "point " << i;
  ASSERT_EQ(d.size(), 2u);
  for (size_t i = 0; i < s.flow.size(); ++i)
  {
    const int want = (i >= first_a && i < first_b) ? 0 : (i >= first_b && i < outlier) ? 1 : -1;
    EXPECT_EQ(seg.cluster()[i], want) << "point " << i;
  }
  // The larger box first; centroids, extents, radius and displacement exact.
  EXPECT_EQ(d[0].points, 180);
  EXPECT_NEAR(d[0].centroid.x(), 2.5, 1e-9);
  EXPECT_NEAR(d[0].centroid.y(), 0.6, 1e-9);
  EXPECT_NEAR(d[0].min.x(), 2.35, 1e-9);
  EXPECT_NEAR(d[0].max.x(), 2.65, 1e-9);
  EXPECT_NEAR(d[0].min.y(), 0.4, 1e-9);
  EXPECT_NEAR(d[0].max.y(), 0.8, 1e-9);
  EXPECT_NEAR(d[0].radius, 0.25 + 0.1, 1e-9);
  EXPECT_NEAR(d[0].displacement.x(), 0.0, 1e-9);
  EXPECT_NEAR(d[0].displacement.y(), -0.12, 1e-9);
  EXPECT_NEAR(d[0].min_z, 0.1, 1e-9);
  EXPECT_NEAR(d[0].max_z, 1.7, 1e-9);
  EXPECT_EQ(d[1].points, 108);
  EXPECT_NEAR(d[1].centroid.x(), 3.5, 1e-9);
  EXPECT_NEAR(d[1].centroid.y(), -1.0, 1e-9);
  EXPECT_NEAR(d[1].radius, std::hypot(0.1, 0.15) + 0.1, 1e-9);
  EXPECT_NEAR(d[1].displacement.x(), -0.05, 1e-9);
  EXPECT_NEAR(d[1].displacement.y(), 0.15, 1e-9);
}

TEST(MoverSegmentation, TouchingBoxesMergeDistantOnesDoNot)
{
  // Two boxes whose bins touch (8-connected) are one mover; one empty bin between them splits.
  for (const double gap : {0.2, 0.5})
  {
    Scene s;
    s.box(2.55, 0.05, 1, 1, Eigen::Vector3d(0.0, 0.1, 0.0));
    s.box(2.55 + gap, 0.05, 1, 1, Eigen::Vector3d(0.0, 0.1, 0.0));
    MoverSegmentation seg;
    seg.segment(s.flow, s.egoMotion(), s.T_world_cur);
    EXPECT_EQ(seg.detections().size(), gap < 0.3 ? 1u : 2u) << "gap " << gap;
  }
}
