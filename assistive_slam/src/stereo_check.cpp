#include "assistive_slam/stereo_check.h"
#include "pnp_pose.h"
#include <map>
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

/// P3P RANSAC of b's view against the reference points, LM on the inliers, then the inliers must
/// also reproject into b's right image; T_a_b: b's camera in the reference frame.
StereoCheckResult verify(const Correspondences& c, const Keyframe& b, const StereoModel& cam, const StereoCheckOptions& o)
{
  StereoCheckResult r;
  r.matches = static_cast<int>(c.obj.size());
  if (r.matches < std::max(6, o.min_inliers))
    return r;
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
  const Eigen::Isometry3d T_b_a = isometryFromRvecTvec(rvec, tvec);
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
