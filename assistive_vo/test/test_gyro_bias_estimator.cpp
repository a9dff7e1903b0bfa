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

namespace
{
/// A head turning at `w` (rad/s, camera_link) with gyro bias `b`: the vision rotation (optical axes)
/// of a span of `dt` s, off by `vision_error` (rad, camera_link), and the gyro's, as the VO gives
/// them to the estimator (the current estimate taken out).
struct Span
{
  Eigen::Matrix3d R_vision, R_gyro;
};
Span turningSpan(const GyroBiasEstimator& e, const Eigen::Vector3d& w, const Eigen::Vector3d& b, double dt,
                 const Eigen::Vector3d& vision_error = Eigen::Vector3d::Zero())
{
  const Eigen::Matrix3d Rl = e.correct(Eigen::Quaterniond(expmap((w + b) * dt)), dt);
  const Eigen::Matrix3d R_lo = R_link_optical();
  return {R_lo.transpose() * expmap(w * dt + vision_error) * R_lo, R_lo.transpose() * Rl * R_lo};
}
}  // namespace

TEST(GyroBiasEstimator, KeyframesOnEveryFrameTeachTheBiasThroughTheirChain)
{
  // A plain room: a new keyframe every frame (1/15 s), no single span long enough (0.3 s).
  const Eigen::Vector3d w(0.0, 0.0, 0.5), b(0.002, -0.003, 0.004);
  VoParams p;
  p.gyro_bias_chain_spans = true;
  GyroBiasEstimator chained(p);
  p.gyro_bias_chain_spans = false;
  GyroBiasEstimator dropped(p);
  chained.initialise();
  dropped.initialise();
  for (int k = 0; k < 30; ++k)
  {
    const Span a = turningSpan(chained, w, b, 1.0 / 15), d = turningSpan(dropped, w, b, 1.0 / 15);
    chained.addSpan(a.R_vision, a.R_gyro, 1.0 / 15, 1e-8, k > 0);
    dropped.addSpan(d.R_vision, d.R_gyro, 1.0 / 15, 1e-8, k > 0);
  }
  EXPECT_EQ(dropped.bias(), Eigen::Vector3d::Zero());  // the control: short spans alone teach nothing
  EXPECT_LT((chained.bias() - b).norm(), 0.1 * b.norm());
  // a loss between spans breaks the chain: four spans of 1/15 s in two halves never update
  p.gyro_bias_chain_spans = true;
  GyroBiasEstimator broken(p);
  broken.initialise();
  for (int k = 0; k < 4; ++k)
  {
    const Span s = turningSpan(broken, w, b, 1.0 / 15);
    broken.addSpan(s.R_vision, s.R_gyro, 1.0 / 15, 1e-8, k != 2);
  }
  EXPECT_EQ(broken.bias(), Eigen::Vector3d::Zero());
}

TEST(GyroBiasEstimator, ALongSpanIsOneUpdateWithoutTheShortOnesBeforeIt)
{
  const Eigen::Vector3d w(0.0, 0.0, 0.3), b(0.002, -0.003, 0.004);
  GyroBiasEstimator e, alone;
  e.initialise();
  alone.initialise();
  // a short span whose vision rotation is 0.01 rad off, then a good 0.8 s span
  const Span bad = turningSpan(e, w, b, 0.2, Eigen::Vector3d(0.0, 0.0, 0.01));
  e.addSpan(bad.R_vision, bad.R_gyro, 0.2, 1e-8, false);
  const Span good = turningSpan(e, w, b, 0.8);
  e.addSpan(good.R_vision, good.R_gyro, 0.8, 1e-8, true);
  alone.addSpan(good.R_vision, good.R_gyro, 0.8, 1e-8, false);
  EXPECT_TRUE(e.bias().isApprox(alone.bias(), 1e-12));
  EXPECT_DOUBLE_EQ(e.variance(), alone.variance());
  EXPECT_LT((e.bias() - b).norm(), 0.1 * b.norm());  // (a turn's rotation and the bias do not commute)
  // the control: chained with the bad span, the update is pulled 0.01 rad / 1 s off
  VoParams p;
  p.gyro_bias_chain_spans = true;
  p.gyro_bias_min_span_s = 1.0;  // both spans short: one chain of 1 s
  GyroBiasEstimator chained(p);
  chained.initialise();
  chained.addSpan(bad.R_vision, bad.R_gyro, 0.2, 1e-8, false);
  chained.addSpan(good.R_vision, good.R_gyro, 0.8, 1e-8, true);
  EXPECT_GT((chained.bias() - b).norm(), 0.005);
}

TEST(GyroBiasEstimator, ALongChainCannotPullAnEstimateSurerThanItsSystematicError)
{
  VoParams p;
  p.gyro_bias_chain_spans = true;
  const Eigen::Vector3d w(0.0, 0.0, 0.5), b(0.002, -0.003, 0.004);
  // long spans measure the bias well (sigma well under gyro_bias_chain_sigma)
  GyroBiasEstimator e(p);
  e.initialise();
  for (int k = 0; k < 5; ++k)
  {
    const Span s = turningSpan(e, w, b, 1.0);
    e.addSpan(s.R_vision, s.R_gyro, 1.0, 1e-8, k > 0);
  }
  ASSERT_LT(std::sqrt(e.variance()), p.gyro_bias_chain_sigma);
  const Eigen::Vector3d before = e.bias();
  // then frame-long spans whose vision is off by 0.002 rad/s: five of them make one chain of 1/3 s
  const Eigen::Vector3d off(0.0, 0.002, 0.0);
  for (int k = 0; k < 5; ++k)
  {
    const Span s = turningSpan(e, w, b, 1.0 / 15, off / 15);
    e.addSpan(s.R_vision, s.R_gyro, 1.0 / 15, 1e-8, true);
  }
  EXPECT_EQ(e.bias(), before);
  // the control: the same chain moves a fresh estimate by most of its error
  GyroBiasEstimator fresh(p);
  fresh.initialise();
  for (int k = 0; k < 5; ++k)
  {
    const Span s = turningSpan(fresh, w, b, 1.0 / 15, off / 15);
    fresh.addSpan(s.R_vision, s.R_gyro, 1.0 / 15, 1e-8, k > 0);
  }
  EXPECT_LT((fresh.bias() - (b - off)).norm(), 0.5 * b.norm());
  EXPECT_GT((fresh.bias() - Eigen::Vector3d::Zero()).norm(), 0.5 * b.norm());
}
