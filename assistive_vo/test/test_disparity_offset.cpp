// DisparityOffsetEstimator against exact synthetic stereo: points from 1 to 12 m, a known motion
// between keyframe and current frame, and every disparity shifted by a known offset (what a right
// camera turned about its vertical axis does).
#include <gtest/gtest.h>
#include <random>
#include <Eigen/Geometry>
#include "assistive_vo/disparity_offset.h"

using assistive_vo::DisparityOffsetEstimator;
using assistive_vo::StereoCamera;

namespace
{
StereoCamera camera()
{
  StereoCamera c;
  c.fx = c.fy = 450;
  c.cx = 320;
  c.cy = 240;
  c.baseline = 0.12;
  c.width = 640;
  c.height = 480;
  return c;
}

// Feeds `frames` frames whose disparities are the true ones minus `offset` (+ noise); returns the
// estimate of what must be added.
bool estimate(double offset, double noise_px, int frames, double& out)
{
  const StereoCamera cam = camera();
  DisparityOffsetEstimator est;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1), Z(1.0, 12.0);
  std::normal_distribution<double> N(0, noise_px);
  for (int f = 0; f < frames; ++f)
  {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.05 * U(rng), Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d t(0.05 * U(rng), 0.02 * U(rng), -0.3 - 0.1 * U(rng));  // walking forward
    std::vector<DisparityOffsetEstimator::Obs> kf, cur;
    while (kf.size() < 60)
    {
      const double z = Z(rng);
      const Eigen::Vector3d X(U(rng) * z * 0.6, U(rng) * z * 0.4, z);
      const Eigen::Vector3d Xc = R * X + t;
      if (Xc.z() < 0.5)
        continue;
      kf.push_back({cam.fx * X.x() / X.z() + cam.cx, cam.fy * X.y() / X.z() + cam.cy,
                    cam.fx * cam.baseline / X.z() - offset + N(rng)});
      cur.push_back({cam.fx * Xc.x() / Xc.z() + cam.cx, cam.fy * Xc.y() / Xc.z() + cam.cy,
                     cam.fx * cam.baseline / Xc.z() - offset + N(rng)});
    }
    EXPECT_TRUE(est.add(cam, kf, cur, R, t.norm()));
  }
  return est.take(out);
}
}  // namespace

TEST(DisparityOffset, RecoversKnownOffsetExactly)
{
  for (const double off : {-1.2, -0.4, 0.0, 0.75, 1.5})
  {
    double e = 99;
    ASSERT_TRUE(estimate(off, 0.0, 25, e)) << off;
    EXPECT_NEAR(e, off, 0.02) << off;
  }
}

TEST(DisparityOffset, RecoversKnownOffsetWithStereoNoise)
{
  double e = 99;
  ASSERT_TRUE(estimate(0.8, 0.1, 25, e));
  EXPECT_NEAR(e, 0.8, 0.1);
}

TEST(DisparityOffset, NeedsMotionAndFrames)
{
  const StereoCamera cam = camera();
  DisparityOffsetEstimator est;
  std::vector<DisparityOffsetEstimator::Obs> a(30, {320, 240, 10}), b = a;
  EXPECT_FALSE(est.add(cam, a, b, Eigen::Matrix3d::Identity(), 0.01));  // too little translation
  double e;
  EXPECT_FALSE(est.take(e));  // nothing accumulated
}
