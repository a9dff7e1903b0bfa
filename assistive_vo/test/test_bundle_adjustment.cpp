#include <gtest/gtest.h>
#include <cstdio>
#include <Eigen/Eigenvalues>
#include "assistive_vo/bundle_adjustment.h"
#include "synthetic.h"

using namespace assistive_vo;

namespace
{
struct Problem
{
  Vec3List X_true, X_init;
  std::vector<StereoObservation> ref, cur;
};

Problem makeProblem(const StereoCamera& cam, const Eigen::Isometry3d& T, double noise_px, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise_px);
  Problem p;
  p.X_true = test::randomVisiblePoints(cam, T, 150, rng);
  for (const auto& X : p.X_true)
  {
    const Eigen::Vector3d Xc = T.inverse() * X;
    StereoObservation a{cam.projectLeft(X).x() + n(rng), cam.projectLeft(X).y() + n(rng), cam.projectRightU(X) + n(rng)};
    StereoObservation b{cam.projectLeft(Xc).x() + n(rng), cam.projectLeft(Xc).y() + n(rng),
                        cam.projectRightU(Xc) + n(rng)};
    p.ref.push_back(a);
    p.cur.push_back(b);
    // initial structure: triangulated from the (noisy) reference observations, like the pipeline
    p.X_init.push_back(cam.triangulate(a.u, a.v, a.u - a.ur));
  }
  return p;
}

double rotErr(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}
}  // namespace

TEST(BundleAdjustment, ConvergesExactlyOnNoiseFreeData)
{
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(0.01, 0.05, -0.02, 0.1, 0.02, 0.3);
  Problem p = makeProblem(cam, T, 0.0, 3);
  // perturbed start: 1 degree, 5 cm
  const Eigen::Isometry3d T0 = T * test::makePose(0.01, -0.012, 0.008, 0.03, -0.03, 0.03);
  TwoFrameBundleAdjuster ba;
  TwoFrameBundleAdjuster::Options o;
  o.iterations = 20;
  Vec3List X = p.X_init;
  const BundleAdjustmentResult r = ba.optimize(cam, T0, X, p.ref, p.cur, o);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.final_cost, 1e-12);
  EXPECT_GT(r.initial_cost, 100.0);
  EXPECT_LT((r.T_ref_cur.translation() - T.translation()).norm(), 1e-6);
  EXPECT_LT(rotErr(r.T_ref_cur, T), 1e-8);
  for (size_t i = 0; i < X.size(); ++i)
    EXPECT_LT((X[i] - p.X_true[i]).norm(), 1e-5);
}

TEST(BundleAdjustment, ImprovesPerturbedSolutionUnderNoise)
{
  // Seed fig. 2.8: BA refines the minimal-set solution. With 0.5 px noise the refined pose is
  // within a few mm / a twentieth of a degree while the start was 5 cm / 1.2 degrees off.
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(-0.02, 0.08, 0.0, -0.2, 0.0, 0.4);
  Problem p = makeProblem(cam, T, 0.5, 11);
  const Eigen::Isometry3d T0 = T * test::makePose(0.015, -0.012, 0.01, 0.03, 0.03, -0.03);
  TwoFrameBundleAdjuster ba;
  TwoFrameBundleAdjuster::Options o;
  Vec3List X = p.X_init;
  const BundleAdjustmentResult r = ba.optimize(cam, T0, X, p.ref, p.cur, o);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.final_cost, r.initial_cost);
  const double t0 = (T0.translation() - T.translation()).norm();
  const double t1 = (r.T_ref_cur.translation() - T.translation()).norm();
  EXPECT_LT(t1, 0.1 * t0);
  EXPECT_LT(t1, 0.01);
  EXPECT_LT(rotErr(r.T_ref_cur, T), 0.1 * rotErr(T0, T));
  EXPECT_LT(rotErr(r.T_ref_cur, T) * 180 / M_PI, 0.1);
  // structure improves as well (mean error vs truth)
  double e0 = 0, e1 = 0;
  for (size_t i = 0; i < X.size(); ++i)
  {
    e0 += (p.X_init[i] - p.X_true[i]).norm();
    e1 += (X[i] - p.X_true[i]).norm();
  }
  EXPECT_LT(e1, e0);
  // covariance: symmetric positive definite, small
  const Eigen::Matrix<double, 6, 6> C = r.covariance;
  EXPECT_LT((C - C.transpose()).norm(), 1e-9);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(C);
  EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
  EXPECT_LT(es.eigenvalues().maxCoeff(), 1e-3);
}

TEST(BundleAdjustment, NoisyObservationsWeighedByTheirSigma)
{
  // Half the points seen 3 px noisy (coarse corners), half 0.2 px: told their sigma, the noisy
  // half no longer pulls the motion off; the cost counts them in their own sigma.
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(-0.02, 0.08, 0.0, -0.2, 0.0, 0.4);
  Problem fine = makeProblem(cam, T, 0.2, 21), noisy = makeProblem(cam, T, 3.0, 22);
  Problem p = fine;
  p.X_init.insert(p.X_init.end(), noisy.X_init.begin(), noisy.X_init.end());
  p.ref.insert(p.ref.end(), noisy.ref.begin(), noisy.ref.end());
  p.cur.insert(p.cur.end(), noisy.cur.begin(), noisy.cur.end());
  Problem weighed = p;
  for (size_t i = fine.ref.size(); i < p.ref.size(); ++i)
    weighed.ref[i].sigma_scale = weighed.cur[i].sigma_scale = 15.0;
  TwoFrameBundleAdjuster ba;
  TwoFrameBundleAdjuster::Options o;
  o.huber_px = 1e6;  // plain least squares: the weights alone
  Vec3List X1 = p.X_init, X2 = weighed.X_init;
  const BundleAdjustmentResult equal = ba.optimize(cam, T, X1, p.ref, p.cur, o);
  const BundleAdjustmentResult told = ba.optimize(cam, T, X2, weighed.ref, weighed.cur, o);
  ASSERT_TRUE(equal.ok && told.ok);
  const double e_equal = (equal.T_ref_cur.translation() - T.translation()).norm();
  const double e_told = (told.T_ref_cur.translation() - T.translation()).norm();
  std::printf("noisy half weighed equal: %.2f mm off; told its sigma: %.2f mm\n", 1e3 * e_equal, 1e3 * e_told);
  EXPECT_LT(e_told, 0.5 * e_equal);
  // one observation at sigma_scale s costs 1/s^2 of its residual squared
  std::vector<StereoObservation> r1{p.ref[0]}, c1{p.cur[0]}, r2 = r1, c2 = c1;
  c1[0].u += 0.5;
  c2[0].u += 0.5;
  r2[0].sigma_scale = c2[0].sigma_scale = 2.0;
  const Vec3List X0{p.X_init[0]};
  EXPECT_NEAR(TwoFrameBundleAdjuster::cost(cam, T, X0, r2, c2, 1e6),
              0.25 * TwoFrameBundleAdjuster::cost(cam, T, X0, r1, c1, 1e6), 1e-12);
}

TEST(BundleAdjustment, MotionOnlyWithoutRightObservations)
{
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(0.0, 0.03, 0.0, 0.05, 0.0, 0.2);
  Problem p = makeProblem(cam, T, 0.0, 5);
  for (auto& o : p.cur)
    o.ur = -1;  // current frame: left image only
  TwoFrameBundleAdjuster ba;
  TwoFrameBundleAdjuster::Options o;
  o.refine_points = false;
  o.iterations = 20;
  Vec3List X = p.X_true;
  const BundleAdjustmentResult r = ba.optimize(cam, T * test::makePose(0.01, 0, 0, 0.02, 0, 0), X, p.ref, p.cur, o);
  ASSERT_TRUE(r.ok);
  EXPECT_LT((r.T_ref_cur.translation() - T.translation()).norm(), 1e-6);
  EXPECT_EQ(X, p.X_true);  // points untouched
}

TEST(BundleAdjustment, RotationPriorPullsTowardsTheGyro)
{
  const StereoCamera cam = test::makeCamera();
  const Eigen::Isometry3d T = test::makePose(-0.02, 0.08, 0.0, -0.2, 0.0, 0.4);
  Problem p = makeProblem(cam, T, 0.5, 11);
  TwoFrameBundleAdjuster ba;
  TwoFrameBundleAdjuster::Options o;
  o.iterations = 20;
  Vec3List X = p.X_init;
  const BundleAdjustmentResult free_r = ba.optimize(cam, T, X, p.ref, p.cur, o);
  // exact prior with a strong weight: the rotation lands on it
  o.use_rotation_prior = true;
  o.rotation_prior = T.linear();
  o.rotation_prior_weight = 1e12;
  X = p.X_init;
  const BundleAdjustmentResult prior_r = ba.optimize(cam, T, X, p.ref, p.cur, o);
  ASSERT_TRUE(free_r.ok && prior_r.ok);
  EXPECT_GT(rotErr(free_r.T_ref_cur, T), 1e-4);
  EXPECT_LT(rotErr(prior_r.T_ref_cur, T), 1e-6);
  // translation is still estimated from the images and gets better with the right rotation
  EXPECT_LT((prior_r.T_ref_cur.translation() - T.translation()).norm(),
            (free_r.T_ref_cur.translation() - T.translation()).norm());
  // weight 0: identical to no prior
  o.rotation_prior_weight = 0.0;
  X = p.X_init;
  const BundleAdjustmentResult zero_r = ba.optimize(cam, T, X, p.ref, p.cur, o);
  EXPECT_TRUE(zero_r.T_ref_cur.isApprox(free_r.T_ref_cur, 1e-12));
}

TEST(BundleAdjustment, RejectsDegenerateInput)
{
  TwoFrameBundleAdjuster ba;
  Vec3List X{Eigen::Vector3d(0, 0, 5)};
  std::vector<StereoObservation> o(1);
  EXPECT_FALSE(ba.optimize(test::makeCamera(), Eigen::Isometry3d::Identity(), X, o, o, {}).ok);
}
