// Local bundle adjustment on an exact synthetic window: perturbed poses and points return to the
// truth; the oldest two keyframes (fixed) do not move.
#include <random>
#include <gtest/gtest.h>
#include "assistive_slam/local_ba.h"
#include "synthetic_camera.h"

using namespace assistive_slam;
using slam_test::camera;

namespace
{
struct Window
{
  std::vector<Eigen::Isometry3d> poses;
  std::map<int64_t, Eigen::Vector3d> points;
};

Window makeWindow(int frames)
{
  Window w;
  for (int k = 0; k < frames; ++k)
  {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.05 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0.3 * k, 0.02 * k, 0.25 * k);  // optical frame: z forward
    w.poses.push_back(T);
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-3, 5), uy(-1.5, 1.5), uz(3, 10);
  for (int64_t i = 0; i < 300; ++i)
    w.points[i] = Eigen::Vector3d(ux(rng), uy(rng), uz(rng));
  return w;
}

BaProblem observe(const Window& w, const StereoModel& cam)
{
  BaProblem pb;
  pb.poses = w.poses;
  pb.fixed.assign(w.poses.size(), false);
  pb.fixed[0] = pb.fixed[1] = true;
  for (size_t k = 0; k < w.poses.size(); ++k)
    for (const auto& [id, X] : w.points)
    {
      const Eigen::Vector3d Xc = w.poses[k].inverse() * X;
      if (Xc.z() < 0.5)
        continue;
      const Eigen::Vector3d uvr = cam.project(Xc);
      if (uvr.x() < 0 || uvr.x() > 640 || uvr.y() < 0 || uvr.y() > 480 || uvr.z() < 0)
        continue;
      pb.observations.push_back({static_cast<int>(k), id, uvr});
      pb.landmarks[id] = X;  // only observed points are in the problem
    }
  return pb;
}
}  // namespace

TEST(LocalBundleAdjustment, PerturbedWindowReturnsToTruth)
{
  const StereoModel cam = camera();
  const Window w = makeWindow(6);
  BaProblem pb = observe(w, cam);
  ASSERT_GT(pb.observations.size(), 600u);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, 1);
  for (size_t k = 2; k < pb.poses.size(); ++k)
  {
    pb.poses[k].translation() += 0.05 * Eigen::Vector3d(n(rng), n(rng), n(rng));
    pb.poses[k].linear() = pb.poses[k].linear() *
        Eigen::AngleAxisd(0.02, Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized()).toRotationMatrix();
  }
  for (auto& [id, X] : pb.landmarks)
    X += 0.03 * Eigen::Vector3d(n(rng), n(rng), n(rng));
  BaOptions o;
  o.max_iterations = 50;
  const BaResult r = bundleAdjust(pb, cam, o);
  ASSERT_TRUE(r.solved);
  EXPECT_GT(r.initial_rms_px, 2.0);
  EXPECT_LT(r.final_rms_px, 1e-6);
  for (size_t k = 0; k < pb.poses.size(); ++k)
  {
    EXPECT_NEAR((pb.poses[k].translation() - w.poses[k].translation()).norm(), 0.0, 1e-6) << k;
    EXPECT_NEAR(Eigen::AngleAxisd(pb.poses[k].linear().transpose() * w.poses[k].linear()).angle(), 0.0, 1e-7) << k;
  }
  ASSERT_GT(pb.landmarks.size(), 150u);
  for (const auto& [id, X] : pb.landmarks)
    EXPECT_NEAR((X - w.points.at(id)).norm(), 0.0, 1e-5) << id;
}

TEST(LocalBundleAdjustment, OutlierObservationsDoNotPullTheWindow)
{
  const StereoModel cam = camera();
  const Window w = makeWindow(5);
  BaProblem pb = observe(w, cam);
  // 3 % wrong associations, 30 px off: the Huber loss keeps the poses within 5 mm
  for (size_t i = 0; i < pb.observations.size(); i += 33)
    pb.observations[i].uvr += Eigen::Vector3d(30, -20, 30);
  for (size_t k = 2; k < pb.poses.size(); ++k)
    pb.poses[k].translation() += Eigen::Vector3d(0.04, -0.03, 0.05);
  BaOptions o;
  o.max_iterations = 50;
  ASSERT_TRUE(bundleAdjust(pb, cam, o).solved);
  for (size_t k = 0; k < pb.poses.size(); ++k)
    EXPECT_LT((pb.poses[k].translation() - w.poses[k].translation()).norm(), 5e-3) << k;
}

TEST(LocalBundleAdjustment, EmptyProblemIsNotSolved)
{
  BaProblem pb;
  EXPECT_FALSE(bundleAdjust(pb, camera(), BaOptions()).solved);
}
