// Geometric verification of loop-closure candidates. See loop_verifier.h.
#include "assistive_slam/loop_verifier.h"
#include "pnp_pose.h"

#include <cmath>
#include <sstream>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/features2d.hpp>

namespace assistive_slam
{
namespace
{
// every descriptor row needs its keypoint (and, for stereo, its 3D point, NaN allowed)
bool wellFormed(const LoopKeyframe& k, bool need_points)
{
  const std::size_t n = static_cast<std::size_t>(k.descriptors.rows);
  return k.keypoints.size() == n && (!need_points || k.points.size() == n);
}

bool finite(const cv::Point3f& p)
{
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && p.z > 0.f;
}

double angleDeg(const Eigen::Matrix3d& R)
{
  return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI;
}

struct PnpResult
{
  bool ok = false;
  int inliers = 0;
  Eigen::Isometry3d T_cam_obj = Eigen::Isometry3d::Identity();  // x_cam = T * x_obj
};

// 3D points of `obj` against the 2D keypoints of `cam`: AP3P RANSAC, then Levenberg-Marquardt on
// the inliers.
PnpResult pnp(const LoopKeyframe& cam, const LoopKeyframe& obj, const std::vector<cv::DMatch>& m, bool obj_is_train,
              const cv::Matx33d& K, const VerifierParams& p)
{
  PnpResult r;
  std::vector<cv::Point3f> X;
  std::vector<cv::Point2f> x;
  for (const auto& d : m)
  {
    const int io = obj_is_train ? d.trainIdx : d.queryIdx;
    const int ic = obj_is_train ? d.queryIdx : d.trainIdx;
    if (io >= static_cast<int>(obj.points.size()) || !finite(obj.points[io]))
      continue;
    X.push_back(obj.points[io]);
    x.push_back(cam.keypoints[ic]);
  }
  if (static_cast<int>(X.size()) < std::max(4, p.min_inliers))
    return r;
  cv::Mat rvec, tvec, inl;
  if (!cv::solvePnPRansac(X, x, cv::Mat(K), cv::noArray(), rvec, tvec, false, p.ransac_iterations,
                          static_cast<float>(p.reprojection_px), p.confidence, inl, cv::SOLVEPNP_AP3P))
    return r;
  if (inl.rows < 4)
    return r;
  std::vector<cv::Point3f> Xi;
  std::vector<cv::Point2f> xi;
  for (int i = 0; i < inl.rows; ++i)
  {
    Xi.push_back(X[inl.at<int>(i)]);
    xi.push_back(x[inl.at<int>(i)]);
  }
  cv::solvePnPRefineLM(Xi, xi, cv::Mat(K), cv::noArray(), rvec, tvec);
  r.ok = true;
  r.inliers = inl.rows;
  r.T_cam_obj = isometryFromRvecTvec(rvec, tvec);
  return r;
}
}  // namespace

LoopVerifier::LoopVerifier(const cv::Matx33d& K, const VerifierParams& params) : K_(K), params_(params) {}

std::vector<cv::DMatch> LoopVerifier::match(const cv::Mat& query, const cv::Mat& train) const
{
  std::vector<cv::DMatch> out;
  if (query.empty() || train.empty() || query.type() != train.type() || query.cols != train.cols || train.rows < 2 ||
      query.rows < 2)
    return out;
  const int norm = query.depth() == CV_8U ? cv::NORM_HAMMING : cv::NORM_L2;
  cv::BFMatcher bf(norm, false);
  std::vector<std::vector<cv::DMatch>> fwd, bwd;
  bf.knnMatch(query, train, fwd, 2);
  bf.knnMatch(train, query, bwd, 1);
  for (const auto& k : fwd)
  {
    if (k.size() < 2 || k[0].distance >= params_.ratio * k[1].distance)
      continue;
    const auto& b = bwd[k[0].trainIdx];
    if (b.empty() || b[0].trainIdx != k[0].queryIdx)
      continue;  // not mutual
    out.push_back(k[0]);
  }
  return out;
}

LoopVerification LoopVerifier::verifyStereo(const LoopKeyframe& query, const LoopKeyframe& match_kf) const
{
  LoopVerification v;
  if (!wellFormed(query, true) || !wellFormed(match_kf, true))
  {
    v.reason = "keyframe malformed: keypoints, descriptors and 3D points differ in number";
    return v;
  }
  const auto m = match(query.descriptors, match_kf.descriptors);
  v.matches = static_cast<int>(m.size());
  if (v.matches < params_.min_inliers)
  {
    v.reason = "too few descriptor matches (" + std::to_string(v.matches) + ")";
    return v;
  }
  // both directions: the match keyframe's 3D seen by the query camera, and the other way round
  const PnpResult qm = pnp(query, match_kf, m, true, K_, params_);
  const PnpResult mq = pnp(match_kf, query, m, false, K_, params_);
  if (!qm.ok || !mq.ok)
  {
    v.reason = "P3P RANSAC found no pose";
    return v;
  }
  v.inliers = std::min(qm.inliers, mq.inliers);
  const Eigen::Isometry3d a = qm.T_cam_obj.inverse();  // T_match_query from the match's 3D
  const Eigen::Isometry3d& b = mq.T_cam_obj;           // T_match_query from the query's 3D
  std::ostringstream why;
  if (v.inliers < params_.min_inliers)
    why << "too few inliers (" << v.inliers << " < " << params_.min_inliers << ")";
  else if (v.inliers < params_.min_inlier_ratio * v.matches)
    why << "inlier ratio " << static_cast<double>(v.inliers) / v.matches << " < " << params_.min_inlier_ratio;
  else
  {
    const double dt = (a.translation() - b.translation()).norm();
    const double dr = angleDeg(a.linear().transpose() * b.linear());
    if (dt > params_.consistency_m || dr > params_.consistency_deg)
      why << "the two directions disagree (" << dt << " m, " << dr << " deg)";
  }
  // the mean of the two estimates (their difference is bounded by the consistency check)
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  v.T_match_query = Eigen::Isometry3d::Identity();
  v.T_match_query.linear() = qa.slerp(0.5, qb).toRotationMatrix();
  v.T_match_query.translation() = 0.5 * (a.translation() + b.translation());
  if (why.str().empty() && v.T_match_query.translation().norm() > params_.max_translation_m)
    why << "implausible revisit distance " << v.T_match_query.translation().norm() << " m";
  v.reason = why.str();
  v.accepted = v.reason.empty();
  return v;
}

LoopVerification LoopVerifier::verifyEpipolar(const LoopKeyframe& query, const LoopKeyframe& match_kf) const
{
  LoopVerification v;
  if (!wellFormed(query, false) || !wellFormed(match_kf, false))
  {
    v.reason = "keyframe malformed: keypoints and descriptors differ in number";
    return v;
  }
  const auto m = match(query.descriptors, match_kf.descriptors);
  v.matches = static_cast<int>(m.size());
  if (v.matches < std::max(5, params_.min_inliers_epipolar))
  {
    v.reason = "too few descriptor matches (" + std::to_string(v.matches) + ")";
    return v;
  }
  std::vector<cv::Point2f> pq, pm;
  for (const auto& d : m)
  {
    pq.push_back(query.keypoints[d.queryIdx]);
    pm.push_back(match_kf.keypoints[d.trainIdx]);
  }
  cv::Mat mask;
  cv::Mat E = cv::findEssentialMat(pq, pm, cv::Mat(K_), cv::RANSAC, params_.confidence, params_.epipolar_px, mask);
  if (E.rows != 3 || E.cols != 3)
  {
    v.reason = "no essential matrix";
    return v;
  }
  // RANSAC keeps a minimal-sample model: re-fit on its inliers (least median of squares, which the
  // inliers satisfy) for an accurate pose
  std::vector<cv::Point2f> iq, im;
  for (int i = 0; i < mask.rows; ++i)
    if (mask.at<std::uint8_t>(i))
    {
      iq.push_back(pq[i]);
      im.push_back(pm[i]);
    }
  if (static_cast<int>(iq.size()) >= std::max(5, params_.min_inliers_epipolar))
  {
    cv::Mat mask2;
    const cv::Mat E2 = cv::findEssentialMat(iq, im, cv::Mat(K_), cv::LMEDS, params_.confidence, params_.epipolar_px, mask2);
    if (E2.rows == 3 && E2.cols == 3)
    {
      pq.swap(iq);
      pm.swap(im);
      mask = mask2;
      E2.copyTo(E);
    }
  }
  cv::Mat R, t;
  // x_match = R x_query + t: recoverPose's (points1 -> points2) convention with points1 = query
  v.inliers = cv::recoverPose(E, pq, pm, cv::Mat(K_), R, t, mask);
  Eigen::Matrix3d Re;
  cv::cv2eigen(R, Re);
  v.T_match_query.linear() = Re;
  v.T_match_query.translation() = Eigen::Vector3d(t.at<double>(0), t.at<double>(1), t.at<double>(2));
  std::ostringstream why;
  if (v.inliers < params_.min_inliers_epipolar)
    why << "too few inliers (" << v.inliers << " < " << params_.min_inliers_epipolar << ")";
  else if (v.inliers < params_.min_inlier_ratio * v.matches)
    why << "inlier ratio " << static_cast<double>(v.inliers) / v.matches << " < " << params_.min_inlier_ratio;
  v.reason = why.str();
  v.accepted = v.reason.empty();
  return v;
}
}  // namespace assistive_slam
