// FastSLAM 2.0 with active matching (fastslam.h): exact answers on hand-made cases.
#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include <opencv2/imgproc.hpp>
#include "assistive_slam/fastslam.h"

using namespace assistive_slam;

namespace
{
StereoModel camera()
{
  StereoModel c;
  c.fx = c.fy = 100;
  c.cx = c.cy = 0;
  c.baseline = 0.1;
  return c;
}
}  // namespace

TEST(FastSlam, StereoNoiseIsTheSeedsClosedForm)
{
  // eq. 3.21 with f = fx = fy: Sigma = (B/d)^2 [[su^2 + sd^2 u^2/d^2, sd^2 u v/d^2, sd^2 u f/d^2], ...]
  const StereoModel c = camera();
  const double u = 20, v = -10, d = 5, su = 0.1, sd = 0.4, B = 0.1, f = 100;
  Eigen::Vector3d X;
  Eigen::Matrix3d C;
  ASSERT_TRUE(stereoPoint(c, u, v, d, su, sd, &X, &C));
  EXPECT_NEAR(X.z(), f * B / d, 1e-12);
  EXPECT_NEAR(X.x(), u * B / d, 1e-12);
  EXPECT_NEAR(X.y(), v * B / d, 1e-12);
  const double k = (B / d) * (B / d), sd2 = sd * sd, d2 = d * d;
  Eigen::Matrix3d E;
  E << su * su + sd2 * u * u / d2, sd2 * u * v / d2, sd2 * u * f / d2,  //
      sd2 * u * v / d2, su * su + sd2 * v * v / d2, sd2 * v * f / d2,   //
      sd2 * u * f / d2, sd2 * v * f / d2, sd2 * f * f / d2;
  EXPECT_LT((C - k * E).norm(), 1e-15);
  EXPECT_FALSE(stereoPoint(c, u, v, 0, su, sd, &X, &C));
}

TEST(FastSlam, ProjectionJacobiansMatchFiniteDifferences)
{
  StereoModel c = camera();
  c.cx = 320;
  c.cy = 240;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, -0.4).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.5, -0.2, 0.1);
  const Eigen::Vector3d X = T * Eigen::Vector3d(0.4, -0.3, 3.0);
  Eigen::Vector2d z, zp, zm;
  Matrix26d Hs;
  Matrix23d Ht;
  ASSERT_TRUE(projectWithJacobians(c, T, X, &z, &Hs, &Ht));
  const double h = 1e-6;
  for (int i = 0; i < 6; ++i)
  {
    Vector6d d = Vector6d::Zero();
    d(i) = h;
    projectWithJacobians(c, applyPerturbation(T, d), X, &zp, nullptr, nullptr);
    projectWithJacobians(c, applyPerturbation(T, -d), X, &zm, nullptr, nullptr);
    EXPECT_LT(((zp - zm) / (2 * h) - Hs.col(i)).norm(), 1e-5) << i;
  }
  for (int i = 0; i < 3; ++i)
  {
    const Eigen::Vector3d d = Eigen::Vector3d::Unit(i) * h;
    projectWithJacobians(c, T, X + d, &zp, nullptr, nullptr);
    projectWithJacobians(c, T, X - d, &zm, nullptr, nullptr);
    EXPECT_LT(((zp - zm) / (2 * h) - Ht.col(i)).norm(), 1e-5) << i;
  }
}

TEST(FastSlam, LandmarkUpdateMatchesTheClosedForm)
{
  // Camera at the origin, landmark at (0, 0, 2), isotropic prior s^2 I: the projection's Jacobian is
  // H = [[f/z, 0, 0], [0, f/z, 0]] at x = y = 0, so x and y are scalar Kalman updates and z stays.
  const StereoModel c = camera();
  LandmarkEstimate prior;
  prior.mean = Eigen::Vector3d(0, 0, 2);
  const double s2 = 0.01, r = 0.5, h = 100.0 / 2.0;
  prior.cov = Eigen::Matrix3d::Identity() * s2;
  const Eigen::Vector2d z(3, -1);
  const LandmarkEstimate post = updateLandmark(prior, c, Eigen::Isometry3d::Identity(), z, r);
  const double k = s2 * h / (h * h * s2 + r * r);  // scalar gain
  EXPECT_NEAR(post.mean.x(), k * 3, 1e-12);
  EXPECT_NEAR(post.mean.y(), k * -1, 1e-12);
  EXPECT_NEAR(post.mean.z(), 2.0, 1e-12);
  EXPECT_NEAR(post.cov(0, 0), (1 - k * h) * s2, 1e-15);
  EXPECT_NEAR(post.cov(1, 1), (1 - k * h) * s2, 1e-15);
  EXPECT_NEAR(post.cov(2, 2), s2, 1e-15);
  EXPECT_NEAR(post.cov(0, 1), 0.0, 1e-15);
}

TEST(FastSlam, ProposalMatchesAHandComputedCase)
{
  // Camera at the origin, an exact landmark at (0, 0, 2), f = 100, pixel sigma 1; Q = 1e-4 I.
  // u depends on rho_x (-50 px/m) and omega_y (-100 px/rad) only: h = [-50, -100], h^T Q h = 1.25,
  // so an innovation of +1 px in u gives delta = Q h / (1 + 1.25) = (-1/450, -1/225), and
  // L = diag(2.25, 2.25): log w = -0.5 / 2.25 - log(2 pi 2.25).
  const StereoModel c = camera();
  PoseObservation o;
  o.landmark.mean = Eigen::Vector3d(0, 0, 2);
  o.landmark.cov.setZero();
  o.z = Eigen::Vector2d(1, 0);
  const Matrix6d Q = Matrix6d::Identity() * 1e-4;
  const ProposalResult r = fastslamProposal(c, Eigen::Isometry3d::Identity(), Q, {o}, 1.0);
  EXPECT_EQ(r.used, 1);
  EXPECT_NEAR(r.mean.translation().x(), -1.0 / 450.0, 1e-12);
  EXPECT_NEAR(r.mean.translation().y(), 0.0, 1e-15);
  const Eigen::AngleAxisd aa(r.mean.linear());
  EXPECT_NEAR((aa.angle() * aa.axis()).y(), -1.0 / 225.0, 1e-12);
  EXPECT_NEAR(r.log_weight, -0.5 / 2.25 - std::log(2 * M_PI * 2.25), 1e-12);
  // Sherman-Morrison: the covariance in the (rho_x, omega_y) plane is Q - Q h h^T Q / 2.25
  EXPECT_NEAR(r.cov(0, 0), 1e-4 - 1e-8 * 2500 / 2.25, 1e-15);
  EXPECT_NEAR(r.cov(4, 4), 1e-4 - 1e-8 * 10000 / 2.25, 1e-15);
  EXPECT_NEAR(r.cov(0, 4), -1e-8 * 5000 / 2.25, 1e-15);
  EXPECT_NEAR(r.cov(2, 2), 1e-4, 1e-15);  // depth is not observed by one pixel
}

TEST(FastSlam, WeightsSurviveLogWeightsOfMinus1e4)
{
  // exp(-1e4) is 0 in double: without subtracting the maximum the sum would be 0 / 0.
  const std::vector<double> lw = {-1e4, -1e4 - std::log(2.0), -1e4 - std::log(4.0), -2e4};
  const std::vector<double> w = normaliseLogWeights(lw);
  const double s = 1 + 0.5 + 0.25;
  EXPECT_NEAR(w[0], 1 / s, 1e-12);
  EXPECT_NEAR(w[1], 0.5 / s, 1e-12);
  EXPECT_NEAR(w[2], 0.25 / s, 1e-12);
  EXPECT_EQ(w[3], 0.0);
  EXPECT_NEAR(effectiveSampleSize(w), 1.0 / ((1 + 0.25 + 0.0625) / (s * s)), 1e-12);
  EXPECT_NEAR(effectiveSampleSize(std::vector<double>(10, 0.1)), 10.0, 1e-12);
}

TEST(FastSlam, SystematicResamplingStatistics)
{
  // Systematic resampling copies particle k either floor(n w_k) or ceil(n w_k) times, whatever u0.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(0, 1);
  const int n = 1000;
  std::vector<double> w(n);
  double sum = 0;
  for (double& v : w)
    sum += (v = std::pow(uni(rng), 4));
  for (double& v : w)
    v /= sum;
  for (double u0 : {0.0, 0.37 / n, 0.999 / n})
  {
    const std::vector<int> idx = systematicResample(w, u0);
    ASSERT_EQ(static_cast<int>(idx.size()), n);
    std::vector<int> count(n, 0);
    for (size_t i = 0; i < idx.size(); ++i)
    {
      ++count[static_cast<size_t>(idx[i])];
      if (i > 0)
      {
        EXPECT_LE(idx[i - 1], idx[i]);
      }
    }
    for (int k = 0; k < n; ++k)
      EXPECT_LT(std::abs(count[static_cast<size_t>(k)] - n * w[static_cast<size_t>(k)]), 1.0 + 1e-9) << k;
  }
  // One dominant particle takes every copy.
  std::vector<double> one(5, 0.0);
  one[2] = 1.0;
  for (int i : systematicResample(one, 0.1))
    EXPECT_EQ(i, 2);
}

TEST(FastSlam, ActiveMatchingWindowHoldsTheTrueProjectionAtItsConfidence)
{
  // Truth: camera at the origin, landmark at (0.3, -0.2, 3). Each trial draws M particles whose
  // pose and landmark estimates are truth + noise from the covariances the window uses, and a
  // measurement noise: the true measurement must fall in the 99 % window in 99 % of the trials.
  const StereoModel c = camera();
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0, 1);
  const Eigen::Vector3d Xt(0.3, -0.2, 3);
  Matrix6d Q = Matrix6d::Zero();
  Q.diagonal() << 4e-4, 4e-4, 4e-4, 1e-4, 1e-4, 1e-4;
  const Eigen::Matrix3d S = Eigen::Vector3d(4e-3, 2e-3, 1e-2).asDiagonal();
  const double sigma = 0.5, conf = 0.99, chi2 = chi2Radius2d(conf);
  const Eigen::LLT<Matrix6d> lq(Q);
  const Eigen::LLT<Eigen::Matrix3d> ls(S);
  const int trials = 4000, M = 1;
  int inside = 0;
  for (int t = 0; t < trials; ++t)
  {
    std::vector<Eigen::Vector2d> mu;
    std::vector<Eigen::Matrix2d> lam;
    for (int m = 0; m < M; ++m)
    {
      Vector6d e;
      for (int i = 0; i < 6; ++i)
        e(i) = g(rng);
      Eigen::Vector3d el(g(rng), g(rng), g(rng));
      const Eigen::Isometry3d T = applyPerturbation(Eigen::Isometry3d::Identity(), lq.matrixL() * e);
      const Eigen::Vector3d X = Xt + ls.matrixL() * el;
      Eigen::Vector2d z;
      Matrix26d Hs;
      Matrix23d Ht;
      ASSERT_TRUE(projectWithJacobians(c, T, X, &z, &Hs, &Ht));
      mu.push_back(z);
      lam.push_back(Eigen::Matrix2d::Identity() * sigma * sigma + Ht * S * Ht.transpose() + Hs * Q * Hs.transpose());
    }
    const SearchWindow win = fuseProjections(mu, lam);
    Eigen::Vector2d zt;
    ASSERT_TRUE(projectWithJacobians(c, Eigen::Isometry3d::Identity(), Xt, &zt, nullptr, nullptr));
    zt += Eigen::Vector2d(g(rng), g(rng)) * sigma;
    inside += win.contains(zt, chi2) ? 1 : 0;
  }
  // binomial(4000, 0.99): sd 0.16 %; the linearisation is good to well inside that here
  EXPECT_NEAR(static_cast<double>(inside) / trials, conf, 0.006);
}

TEST(FastSlam, FusedWindowIsTheMixtureMoments)
{
  const std::vector<Eigen::Vector2d> mu = {{0, 0}, {2, 0}};
  const std::vector<Eigen::Matrix2d> cov = {Eigen::Matrix2d::Identity(), Eigen::Matrix2d::Identity() * 3};
  const SearchWindow w = fuseProjections(mu, cov);
  EXPECT_NEAR(w.mean.x(), 1.0, 1e-15);
  EXPECT_NEAR(w.cov(0, 0), 2.0 + 1.0, 1e-15);  // mean of the covariances + spread of the means
  EXPECT_NEAR(w.cov(1, 1), 2.0, 1e-15);
  EXPECT_NEAR(chi2Radius2d(0.99), 9.210340371976184, 1e-12);
}

TEST(FastSlam, TemplateFoundInsideTheWindowOnly)
{
  cv::Mat img(120, 160, CV_8U);
  cv::randu(img, 0, 255);
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0);
  cv::Mat t;
  img(cv::Rect(70 - 6, 50 - 6, 13, 13)).convertTo(t, CV_32F);
  SearchWindow w;
  w.mean = Eigen::Vector2d(73, 48);
  w.cov = Eigen::Matrix2d::Identity() * 4;
  Eigen::Vector2d best;
  int searched = 0;
  EXPECT_GT(matchInWindow(img, t, w, chi2Radius2d(0.99), &best, &searched), 0.999);
  EXPECT_NEAR(best.x(), 70, 0.5);
  EXPECT_NEAR(best.y(), 50, 0.5);
  EXPECT_LE(searched, static_cast<int>(M_PI * 4 * 9.22) + 10);  // the ellipse, not the image
  w.mean = Eigen::Vector2d(120, 90);                            // window elsewhere: no match there
  EXPECT_LT(matchInWindow(img, t, w, chi2Radius2d(0.99), &best), 0.8);
}

TEST(FastSlam, PatchWarpFollowsThePlane)
{
  // A fronto-parallel patch seen from twice as close is twice as large: current offsets map to
  // half as large reference offsets; a pure sideways move leaves it unwarped.
  const StereoModel c = camera();
  const Eigen::Vector3d X(0, 0, 4), n(0, 0, -1);
  Eigen::Isometry3d cur = Eigen::Isometry3d::Identity();
  cur.translation() = Eigen::Vector3d(0, 0, 2);
  Eigen::Matrix2d A = patchAffine(c, Eigen::Isometry3d::Identity(), cur, X, n);
  EXPECT_NEAR(A(0, 0), 0.5, 1e-9);
  EXPECT_NEAR(A(1, 1), 0.5, 1e-9);
  EXPECT_NEAR(A(0, 1), 0.0, 1e-9);
  cur.translation() = Eigen::Vector3d(1, 0, 0);
  A = patchAffine(c, Eigen::Isometry3d::Identity(), cur, X, n);
  EXPECT_NEAR((A - Eigen::Matrix2d::Identity()).norm(), 0.0, 1e-9);
  // warpTemplate with A = I returns the centre of the reference patch
  cv::Mat ref(41, 41, CV_32F);
  for (int r = 0; r < 41; ++r)
    for (int q = 0; q < 41; ++q)
      ref.at<float>(r, q) = static_cast<float>(r * 100 + q);
  cv::Mat out;
  ASSERT_TRUE(warpTemplate(ref, Eigen::Matrix2d::Identity(), 13, &out));
  EXPECT_FLOAT_EQ(out.at<float>(0, 0), 14 * 100 + 14);
  ASSERT_TRUE(warpTemplate(ref, Eigen::Matrix2d::Identity() * 0.5, 13, &out));
  EXPECT_FLOAT_EQ(out.at<float>(0, 0), 17 * 100 + 17);
  EXPECT_FALSE(warpTemplate(ref, Eigen::Matrix2d::Identity() * 4, 13, &out));  // leaves the patch
}

TEST(FastSlam, CopyOnWriteSharesUntouchedLandmarks)
{
  PersistentArray<LandmarkEstimate> a;
  const int N = 1024;  // depth 10
  for (int i = 0; i < N; ++i)
  {
    LandmarkEstimate l;
    l.mean = Eigen::Vector3d(i, 0, 0);
    a.set(static_cast<uint32_t>(i), l);
  }
  const size_t alone = PersistentArray<LandmarkEstimate>::distinctNodes({&a});
  EXPECT_EQ(alone, size_t(2 * N - 1 + N));  // a full binary trie plus the values
  std::vector<PersistentArray<LandmarkEstimate>> copies(50, a);
  std::vector<const PersistentArray<LandmarkEstimate>*> all{&a};
  for (auto& c : copies)
    all.push_back(&c);
  EXPECT_EQ(PersistentArray<LandmarkEstimate>::distinctNodes(all), alone);  // copies cost nothing
  LandmarkEstimate l;
  l.mean = Eigen::Vector3d(-1, -1, -1);
  copies[7].set(5, l);
  // one path (root + 10 levels) and one value are new; the original is untouched
  EXPECT_EQ(PersistentArray<LandmarkEstimate>::distinctNodes(all), alone + 11 + 1);
  EXPECT_EQ(a.get(5)->mean.x(), 5.0);
  EXPECT_EQ(copies[7].get(5)->mean.x(), -1.0);
  EXPECT_EQ(copies[8].get(5)->mean.x(), 5.0);
  // a second write to the same copy reuses its own path in place
  l.mean.x() = -2;
  copies[7].set(6, l);
  EXPECT_EQ(PersistentArray<LandmarkEstimate>::distinctNodes(all), alone + 11 + 1 + 2 + 1);  // keys 5 and 6 part below level 2
  EXPECT_EQ(copies[7].get(6)->mean.x(), -2.0);
  EXPECT_EQ(copies[7].get(5)->mean.x(), -1.0);
  EXPECT_EQ(copies[7].size(), size_t(N));
  EXPECT_EQ(a.get(N), nullptr);
}
