#include <gtest/gtest.h>
#include <cmath>
#include "assistive_vo/frames.h"
#include "assistive_vo/gyro_bias_estimator.h"

using namespace assistive_vo;

namespace
{
Eigen::Matrix3d expmap(const Eigen::Vector3d& w)
{
  return w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
}
/// The gyro rotation over `dt` of a head at rest, bias `b` (camera_link), as the VO sees it after
/// the current estimate is taken out (optical axes).
Eigen::Matrix3d gyroAtRest(const GyroBiasEstimator& e, const Eigen::Vector3d& b, double dt)
{
  const Eigen::Matrix3d Rl = e.correct(Eigen::Quaterniond(expmap(b * dt)), dt);
  return R_link_optical().transpose() * Rl * R_link_optical();
}
}  // namespace

TEST(GyroBiasEstimator, StartsAtTheConfiguredUncertainty)
{
  VoParams p;
  GyroBiasEstimator e(p);
  EXPECT_LT(e.variance(), 0);
  e.initialise();
  EXPECT_DOUBLE_EQ(e.variance(), p.gyro_bias_sigma * p.gyro_bias_sigma);
  // prior variance over 0.5 s: angle random walk + bias uncertainty
  EXPECT_DOUBLE_EQ(e.rotationVariance(0.5), p.gyro_noise_density * p.gyro_noise_density * 0.5 +
                                                p.gyro_bias_sigma * p.gyro_bias_sigma * 0.25 + 1e-10);
  EXPECT_TRUE(e.correct(Eigen::Quaterniond(expmap(Eigen::Vector3d(0.1, 0, 0))), 0.1)
                  .isApprox(expmap(Eigen::Vector3d(0.1, 0, 0))));  // zero bias: unchanged
}

TEST(GyroBiasEstimator, ConvergesToTheBiasFromVisionAtRest)
{
  VoParams p;
  GyroBiasEstimator e(p);
  e.initialise();
  const Eigen::Vector3d b(0.004, -0.002, 0.003);  // rad/s, camera_link
  const double dt = 1.0;
  for (int k = 0; k < 5; ++k)
    e.update(Eigen::Matrix3d::Identity(), gyroAtRest(e, b, dt), dt, 1e-8);
  EXPECT_LT((e.bias() - b).norm(), 1e-3 * b.norm());
  EXPECT_LT(e.variance(), 1e-6);
  // once estimated, correct() removes it
  EXPECT_LT(Eigen::AngleAxisd(e.correct(Eigen::Quaterniond(expmap(b * 0.5)), 0.5)).angle(), 1e-5);
}

TEST(GyroBiasEstimator, IgnoresAnErrorTooLargeToBeABias)
{
  GyroBiasEstimator e;
  e.initialise();
  const double v = e.variance();
  e.update(Eigen::Matrix3d::Identity(), gyroAtRest(e, Eigen::Vector3d(0.2, 0, 0), 1.0), 1.0, 1e-8);
  EXPECT_EQ(e.bias(), Eigen::Vector3d::Zero());
  EXPECT_EQ(e.variance(), v);
  e.reset();
  EXPECT_LT(e.variance(), 0);
}

TEST(GyroBiasEstimator, AFixedBiasIsHeldThroughUpdatesAndResets)
{
  GyroBiasEstimator e;
  const Eigen::Vector3d b(0.003, -0.001, 0.002), other(-0.004, 0.0, 0.001);  // rad/s, camera_link
  e.fix(b, 1e-4);
  EXPECT_TRUE(e.fixed());
  e.initialise();  // a running variance is kept
  EXPECT_DOUBLE_EQ(e.variance(), 1e-8);
  // vision says the bias is `other`: a free estimator would move, a fixed one does not
  for (int k = 0; k < 5; ++k)
    e.update(Eigen::Matrix3d::Identity(), gyroAtRest(e, other, 1.0), 1.0, 1e-8);
  EXPECT_EQ(e.bias(), b);
  EXPECT_DOUBLE_EQ(e.variance(), 1e-8);
  e.reset();
  EXPECT_EQ(e.bias(), b);
  EXPECT_DOUBLE_EQ(e.variance(), 1e-8);
  // the control: the same updates move an estimator that is not fixed
  GyroBiasEstimator f;
  f.initialise();
  for (int k = 0; k < 5; ++k)
    f.update(Eigen::Matrix3d::Identity(), gyroAtRest(f, other, 1.0), 1.0, 1e-8);
  EXPECT_LT((f.bias() - other).norm(), 1e-3 * other.norm());
  EXPECT_FALSE(f.fixed());
}
