// The loop verifier on synthetic keyframes with a known relative pose: stereo P3P and the epipolar
// variant recover it; a wrong pair (same descriptors, unrelated geometry) is rejected.
#include <gtest/gtest.h>

#include <random>

#include "assistive_slam/loop_verifier.h"

using assistive_slam::LoopKeyframe;
using assistive_slam::LoopVerifier;

namespace
{
const cv::Matx33d K(500, 0, 320, 0, 500, 240, 0, 0, 1);

struct Pair
{
  LoopKeyframe query, match;
  Eigen::Isometry3d T_match_query;
};

cv::Point2f project(const Eigen::Vector3d& X)
{
  return cv::Point2f(static_cast<float>(500 * X.x() / X.z() + 320), static_cast<float>(500 * X.y() / X.z() + 240));
}

// 300 points seen by both cameras; every 5th point of the query has a wrong 3D and keypoint
// (outliers); descriptors random and shared by the two views of a point.
Pair makePair(unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-3, 3), uy(-2, 2), uz(4, 10);
  std::uniform_real_distribution<float> ud(0.f, 100.f);
  Pair p;
  p.T_match_query = Eigen::Isometry3d::Identity();
  p.T_match_query.linear() = Eigen::AngleAxisd(10.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                             Eigen::AngleAxisd(3.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  p.T_match_query.translation() = Eigen::Vector3d(0.3, -0.05, 0.2);
  const Eigen::Isometry3d T_qm = p.T_match_query.inverse();
  const int n = 300;
  p.query.descriptors.create(n, 32, CV_32F);
  p.match.descriptors.create(n, 32, CV_32F);
  for (int i = 0; i < n; ++i)
  {
    const Eigen::Vector3d Xm(ux(rng), uy(rng), uz(rng));
    Eigen::Vector3d Xq = T_qm * Xm;
    for (int c = 0; c < 32; ++c)
      p.query.descriptors.at<float>(i, c) = p.match.descriptors.at<float>(i, c) = ud(rng);
    p.match.keypoints.push_back(project(Xm));
    p.match.points.emplace_back(Xm.x(), Xm.y(), Xm.z());
    if (i % 5 == 0)
      Xq = Eigen::Vector3d(ux(rng), uy(rng), uz(rng));  // outlier
    p.query.keypoints.push_back(project(Xq));
    p.query.points.emplace_back(Xq.x(), Xq.y(), Xq.z());
  }
  p.query.points[1] = cv::Point3f(NAN, NAN, NAN);  // no stereo depth: skipped, not a crash
  return p;
}

double angleDeg(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI; }
}  // namespace

TEST(LoopVerifier, StereoRecoversTheRelativePose)
{
  const Pair p = makePair(1);
  const auto v = LoopVerifier(K).verifyStereo(p.query, p.match);
  ASSERT_TRUE(v.accepted) << v.reason;
  EXPECT_EQ(v.matches, 300);
  EXPECT_GE(v.inliers, 235);  // 240 inliers less the point without depth
  EXPECT_LE(v.inliers, 241);
  const Eigen::Isometry3d E = p.T_match_query.inverse() * v.T_match_query;
  EXPECT_LT(E.translation().norm(), 1e-4);
  EXPECT_LT(angleDeg(E.linear()), 1e-3);
}

TEST(LoopVerifier, EpipolarRecoversRotationAndDirection)
{
  const Pair p = makePair(2);
  const auto v = LoopVerifier(K).verifyEpipolar(p.query, p.match);
  ASSERT_TRUE(v.accepted) << v.reason;
  EXPECT_LT(angleDeg(p.T_match_query.linear().transpose() * v.T_match_query.linear()), 0.05);
  const Eigen::Vector3d d = p.T_match_query.translation().normalized();
  EXPECT_GT(d.dot(v.T_match_query.translation().normalized()), std::cos(0.5 * M_PI / 180.0));
}

TEST(LoopVerifier, RejectsAWrongPair)
{
  // The same descriptors but the query's geometry scrambled: matches, but no consistent pose.
  Pair p = makePair(3);
  std::mt19937 rng(4);
  std::shuffle(p.query.keypoints.begin(), p.query.keypoints.end(), rng);
  std::shuffle(p.query.points.begin(), p.query.points.end(), rng);
  const LoopVerifier lv(K);
  const auto s = lv.verifyStereo(p.query, p.match);
  EXPECT_FALSE(s.accepted);
  EXPECT_FALSE(s.reason.empty());
  EXPECT_FALSE(lv.verifyEpipolar(p.query, p.match).accepted);
  // unrelated descriptors: too few matches
  Pair other = makePair(5);
  const auto u = lv.verifyStereo(other.query, p.match);
  EXPECT_FALSE(u.accepted);
  EXPECT_LT(u.matches, 25);
  // empty or malformed input: a reason, no crash
  EXPECT_FALSE(lv.verifyStereo(LoopKeyframe(), p.match).accepted);
  LoopKeyframe bad = other.query;
  bad.keypoints.resize(10);
  const auto b = lv.verifyStereo(bad, p.match);
  EXPECT_FALSE(b.accepted);
  EXPECT_NE(b.reason.find("malformed"), std::string::npos);
  EXPECT_FALSE(lv.verifyEpipolar(bad, p.match).accepted);
}
