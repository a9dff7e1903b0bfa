#include "assistive_slam/stereo_check.h"
#include "pnp_pose.h"
#include <map>
#include <random>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace assistive_slam
{
namespace
{
/// 3D points of a reference frame matched to the query keyframe's pixels.
struct Correspondences
{
  std::vector<cv::Point3f> obj;
  std::vector<cv::Point2f> img;
  std::vector<Eigen::Vector3d> X;  ///< obj in double
  std::vector<int> query;          ///< the query feature of each
  std::vector<float> dist;         ///< Hamming distance of each
  std::vector<int> owner, train;   ///< the keyframe (index in the local map) and its feature
};

/// ORB matches of query b against keyframe a (ratio test), a's points in the reference frame.
void matchInto(const Keyframe& a, const Eigen::Isometry3d& T_ref_a, int owner, const Keyframe& b,
               const StereoCheckOptions& o, Correspondences& c)
{
  if (a.descriptors.empty() || b.descriptors.empty())
    return;
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(b.descriptors, a.descriptors, knn, 2);
  for (const auto& m : knn)
  {
    if (m.empty() || m[0].distance > o.max_hamming || (m.size() > 1 && m[0].distance > o.ratio * m[1].distance))
      continue;
    const Eigen::Vector3d X = T_ref_a * a.points[m[0].trainIdx];
    c.obj.emplace_back(X.x(), X.y(), X.z());
    c.img.push_back(b.keypoints[m[0].queryIdx].pt);
    c.X.push_back(X);
    c.query.push_back(m[0].queryIdx);
    c.dist.push_back(m[0].distance);
    c.owner.push_back(owner);
    c.train.push_back(m[0].trainIdx);
  }
}

/// The inliers of b's pose `T_b_a` that also reproject into b's right image: the result (into `r`).
StereoCheckResult agreeInRightImage(const Correspondences& c, const Keyframe& b, const StereoModel& cam,
                                    const StereoCheckOptions& o, const Eigen::Isometry3d& T_b_a, const std::vector<int>& inl,
                                    StereoCheckResult r);

/// b's camera centre in the reference frame, its rotation `R` known: each match gives two linear
/// equations (its pixel's ray through the point), least squares over `idx`. False: degenerate.
bool positionGivenRotation(const Correspondences& c, const std::vector<int>& idx, const Eigen::Matrix3d& R,
                           const StereoModel& cam, Eigen::Vector3d& centre)
{
  // p = R^T X - w (w = R^T centre); x = p.x / p.z: w.x - x w.z = q.x - x q.z (and y alike)
  Eigen::MatrixXd A(2 * idx.size(), 3);
  Eigen::VectorXd y(2 * idx.size());
  for (size_t k = 0; k < idx.size(); ++k)
  {
    const Eigen::Vector3d q = R.transpose() * c.X[idx[k]];
    const double x = (c.img[idx[k]].x - cam.cx) / cam.fx, yy = (c.img[idx[k]].y - cam.cy) / cam.fy;
    A.row(2 * k) << 1.0, 0.0, -x;
    A.row(2 * k + 1) << 0.0, 1.0, -yy;
    y(2 * k) = q.x() - x * q.z();
    y(2 * k + 1) = q.y() - yy * q.z();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 3)
    return false;
  centre = R * qr.solve(y);
  return centre.allFinite();
}

/// The matches whose point reprojects within inlier_px into b's left image at (R, centre).
std::vector<int> reprojectionInliers(const Correspondences& c, const Eigen::Matrix3d& R, const Eigen::Vector3d& centre,
                                     const StereoModel& cam, double inlier_px)
{
  std::vector<int> inl;
  for (size_t k = 0; k < c.X.size(); ++k)
  {
    const Eigen::Vector3d p = R.transpose() * (c.X[k] - centre);
    if (p.z() <= 1e-3)
      continue;
    const double du = cam.fx * p.x() / p.z() + cam.cx - c.img[k].x, dv = cam.fy * p.y() / p.z() + cam.cy - c.img[k].y;
    if (std::max(std::fabs(du), std::fabs(dv)) <= inlier_px)
      inl.push_back(static_cast<int>(k));
  }
  return inl;
}

/// RANSAC over pairs of matches for b's position at the known rotation, least squares on the
/// inliers (twice); seeded, so a replay gives the same answer. False: too few inliers.
bool poseGivenRotation(const Correspondences& c, const StereoModel& cam, const StereoCheckOptions& o, Eigen::Isometry3d& T_b_a,
                       std::vector<int>& inl)
{
  const Eigen::Matrix3d& R = *o.R_ref_b;
  const int n = static_cast<int>(c.X.size());
  std::mt19937 rng(12345);
  std::uniform_int_distribution<int> pick(0, n - 1);
  Eigen::Vector3d best_centre = Eigen::Vector3d::Zero();
  inl.clear();
  for (int it = 0; it < 300; ++it)
  {
    const int i = pick(rng), j = pick(rng);
    Eigen::Vector3d centre;
    if (i == j || !positionGivenRotation(c, { i, j }, R, cam, centre))
      continue;
    std::vector<int> cand = reprojectionInliers(c, R, centre, cam, o.inlier_px);
    if (cand.size() > inl.size())
    {
      inl = std::move(cand);
      best_centre = centre;
    }
  }
  for (int k = 0; k < 2 && static_cast<int>(inl.size()) >= 2; ++k)
  {
    Eigen::Vector3d centre;
    if (!positionGivenRotation(c, inl, R, cam, centre))
      break;
    std::vector<int> again = reprojectionInliers(c, R, centre, cam, o.inlier_px);
    if (again.size() < inl.size())
      break;
    inl = std::move(again);
    best_centre = centre;
  }
  if (static_cast<int>(inl.size()) < o.min_inliers)
    return false;
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();
  T_a_b.linear() = R;
  T_a_b.translation() = best_centre;
  T_b_a = T_a_b.inverse();
  return true;
}

/// P3P RANSAC of b's view against the reference points, LM on the inliers (or b's position alone at
/// a known rotation), then the inliers must also reproject into b's right image; T_a_b: b's camera
/// in the reference frame.
StereoCheckResult verify(const Correspondences& c, const Keyframe& b, const StereoModel& cam, const StereoCheckOptions& o)
{
  StereoCheckResult r;
  r.matches = static_cast<int>(c.obj.size());
  if (r.matches < std::max(6, o.min_inliers))
    return r;
  if (o.R_ref_b)
  {
    Eigen::Isometry3d T_b_a;
    std::vector<int> inl;
    if (!poseGivenRotation(c, cam, o, T_b_a, inl))
      return r;
    return agreeInRightImage(c, b, cam, o, T_b_a, inl, r);
  }
  const cv::Mat K = (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inl;
  if (!cv::solvePnPRansac(c.obj, c.img, K, cv::noArray(), rvec, tvec, false, 300, o.inlier_px, 0.999, inl,
                          cv::SOLVEPNP_AP3P) ||
      static_cast<int>(inl.size()) < o.min_inliers)
    return r;
  // Refine on the inliers (Levenberg-Marquardt).
  std::vector<cv::Point3f> o_in;
  std::vector<cv::Point2f> i_in;
  for (int k : inl)
  {
    o_in.push_back(c.obj[k]);
    i_in.push_back(c.img[k]);
  }
  cv::solvePnPRefineLM(o_in, i_in, K, cv::noArray(), rvec, tvec);
  return agreeInRightImage(c, b, cam, o, isometryFromRvecTvec(rvec, tvec), inl, r);
}

StereoCheckResult agreeInRightImage(const Correspondences& c, const Keyframe& b, const StereoModel& cam,
                                    const StereoCheckOptions& o, const Eigen::Isometry3d& T_b_a, const std::vector<int>& inl,
                                    StereoCheckResult r)
{
  // The inliers must also agree with b's own stereo depth (a wrong pose fits the left view of a
  // look-alike scene more easily than both views): reprojection of a's point in b's right image.
  int agree = 0;
  for (int k : inl)
  {
    const int ib = c.query[k];
    const Eigen::Vector3d Xb = T_b_a * c.X[k];
    if (Xb.z() <= 0)
      continue;
    const Eigen::Vector3d uvr = cam.project(Xb);
    const Eigen::Vector3d z(b.keypoints[ib].pt.x, b.keypoints[ib].pt.y, b.u_right[ib]);
    if ((uvr - z).cwiseAbs().maxCoeff() > 2.0 * o.inlier_px)
      continue;
    ++agree;
    r.inlier_matches.push_back({c.owner[k], c.train[k], ib});
  }
  r.inliers = agree;
  r.T_a_b = T_b_a.inverse();
  r.accepted = agree >= o.min_inliers && agree >= o.min_inlier_ratio * r.matches;
  return r;
}
}  // namespace

StereoCheckResult stereoCheck(const Keyframe& a, const Keyframe& b, const StereoModel& cam, const StereoCheckOptions& o)
{
  Correspondences c;
  matchInto(a, Eigen::Isometry3d::Identity(), 0, b, o, c);
  return verify(c, b, cam, o);
}

StereoCheckResult localMapCheck(const std::vector<std::pair<const Keyframe*, Eigen::Isometry3d>>& local, const Keyframe& b,
                                const StereoModel& cam, const StereoCheckOptions& o)
{
  Correspondences all;
  for (size_t i = 0; i < local.size(); ++i)
    matchInto(*local[i].first, local[i].second, static_cast<int>(i), b, o, all);
  // One match per query feature (the nearest descriptor): a landmark seen by several keyframes
  // would otherwise count several times.
  std::map<int, size_t> best;
  for (size_t i = 0; i < all.query.size(); ++i)
  {
    auto it = best.find(all.query[i]);
    if (it == best.end() || all.dist[i] < all.dist[it->second])
      best[all.query[i]] = i;
  }
  Correspondences c;
  for (const auto& [q, i] : best)
  {
    c.obj.push_back(all.obj[i]);
    c.img.push_back(all.img[i]);
    c.X.push_back(all.X[i]);
    c.query.push_back(q);
    c.dist.push_back(all.dist[i]);
    c.owner.push_back(all.owner[i]);
    c.train.push_back(all.train[i]);
  }
  return verify(c, b, cam, o);
}

}  // namespace assistive_slam
