#include "assistive_slam/stereo_check.h"
#include "pnp_pose.h"
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace assistive_slam
{
StereoCheckResult stereoCheck(const Keyframe& a, const Keyframe& b, const StereoModel& cam, const StereoCheckOptions& o)
{
  StereoCheckResult r;
  if (a.descriptors.empty() || b.descriptors.empty())
    return r;
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(b.descriptors, a.descriptors, knn, 2);
  std::vector<cv::Point3f> obj;
  std::vector<cv::Point2f> img;
  std::vector<std::pair<int, int>> pairs;  // (a index, b index)
  for (const auto& m : knn)
  {
    if (m.empty() || m[0].distance > o.max_hamming || (m.size() > 1 && m[0].distance > o.ratio * m[1].distance))
      continue;
    const Eigen::Vector3d& X = a.points[m[0].trainIdx];
    obj.emplace_back(X.x(), X.y(), X.z());
    img.push_back(b.keypoints[m[0].queryIdx].pt);
    pairs.emplace_back(m[0].trainIdx, m[0].queryIdx);
  }
  r.matches = static_cast<int>(obj.size());
  if (r.matches < std::max(6, o.min_inliers))
    return r;
  const cv::Mat K = (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inl;
  if (!cv::solvePnPRansac(obj, img, K, cv::noArray(), rvec, tvec, false, 300, o.inlier_px, 0.999, inl,
                          cv::SOLVEPNP_AP3P) ||
      static_cast<int>(inl.size()) < o.min_inliers)
    return r;
  // Refine on the inliers (Levenberg-Marquardt).
  std::vector<cv::Point3f> o_in;
  std::vector<cv::Point2f> i_in;
  for (int k : inl)
  {
    o_in.push_back(obj[k]);
    i_in.push_back(img[k]);
  }
  cv::solvePnPRefineLM(o_in, i_in, K, cv::noArray(), rvec, tvec);
  const Eigen::Isometry3d T_b_a = isometryFromRvecTvec(rvec, tvec);
  // The inliers must also agree with b's own stereo depth (a wrong pose fits the left view of a
  // look-alike scene more easily than both views): reprojection of a's point in b's right image.
  int agree = 0;
  for (int k : inl)
  {
    const auto [ia, ib] = pairs[k];
    const Eigen::Vector3d Xb = T_b_a * a.points[ia];
    if (Xb.z() <= 0)
      continue;
    const Eigen::Vector3d uvr = cam.project(Xb);
    const Eigen::Vector3d z(b.keypoints[ib].pt.x, b.keypoints[ib].pt.y, b.u_right[ib]);
    if ((uvr - z).cwiseAbs().maxCoeff() <= 2.0 * o.inlier_px)
      ++agree;
  }
  r.inliers = agree;
  r.T_a_b = T_b_a.inverse();
  r.accepted = agree >= o.min_inliers && agree >= o.min_inlier_ratio * r.matches;
  return r;
}

}  // namespace assistive_slam
