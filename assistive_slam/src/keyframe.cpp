#include "assistive_slam/keyframe.h"
#include <cmath>
#include <map>

namespace assistive_slam
{
double angleDeg(const Eigen::Isometry3d& T)
{
  return Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI;
}

StereoFeatureExtractor::StereoFeatureExtractor(const SlamParams& p) : p_(p)
{
  orb_ = cv::ORB::create(p.orb_features, 1.2f, 8, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31, p.orb_fast_threshold);
}

void StereoFeatureExtractor::extract(const cv::Mat& left, const cv::Mat& right, const StereoModel& cam,
                                     Keyframe& kf) const
{
  std::vector<cv::KeyPoint> kl, kr;
  cv::Mat dl, dr;
  orb_->detectAndCompute(left, cv::noArray(), kl, dl);
  // More features on the right so that most left features find their partner.
  orb_->detectAndCompute(right, cv::noArray(), kr, dr);
  kf.keypoints.clear();
  kf.u_right.clear();
  kf.points.clear();
  kf.landmark.clear();
  kf.descriptors.release();
  if (kl.empty() || kr.empty() || !cam.valid())
    return;
  // Right features by row band: a rectified match lies on the same row (within the tolerance).
  std::multimap<int, int> by_row;
  for (int j = 0; j < static_cast<int>(kr.size()); ++j)
    by_row.emplace(static_cast<int>(std::lround(kr[j].pt.y)), j);
  const double min_disp = cam.fx * cam.baseline / p_.max_depth_m;
  const double max_disp = cam.fx * cam.baseline / p_.min_depth_m;
  const int tol = static_cast<int>(std::ceil(p_.stereo_max_row_diff_px));
  std::vector<cv::Mat> rows;
  for (int i = 0; i < static_cast<int>(kl.size()); ++i)
  {
    const cv::KeyPoint& a = kl[i];
    int best = -1, best_d = 257, second_d = 257;
    const int y = static_cast<int>(std::lround(a.pt.y));
    for (auto it = by_row.lower_bound(y - tol); it != by_row.end() && it->first <= y + tol; ++it)
    {
      const cv::KeyPoint& b = kr[it->second];
      const double disp = a.pt.x - b.pt.x;
      if (disp < min_disp || disp > max_disp || std::abs(a.pt.y - b.pt.y) > p_.stereo_max_row_diff_px ||
          std::abs(a.octave - b.octave) > 1)
        continue;
      const int d = static_cast<int>(cv::norm(dl.row(i), dr.row(it->second), cv::NORM_HAMMING));
      if (d < best_d)
      {
        second_d = best_d;
        best_d = d;
        best = it->second;
      }
      else if (d < second_d)
        second_d = d;
    }
    // Unique and close enough: look-alike texture along a row gives several near-equal partners.
    if (best < 0 || best_d > p_.stereo_max_hamming || best_d > 0.9 * second_d)
      continue;
    const double disp = a.pt.x - kr[best].pt.x;
    const double z = cam.fx * cam.baseline / disp;
    const Eigen::Vector3d X((a.pt.x - cam.cx) * z / cam.fx, (a.pt.y - cam.cy) * z / cam.fy, z);
    kf.keypoints.push_back(a);
    kf.u_right.push_back(kr[best].pt.x);
    kf.points.push_back(X);
    kf.landmark.push_back(-1);
    rows.push_back(dl.row(i));
  }
  if (!rows.empty())
    cv::vconcat(rows, kf.descriptors);
}

bool KeyframePolicy::take(const Eigen::Isometry3d& T_odom_cam, bool vo_replenished)
{
  if (!have_last_)
  {
    have_last_ = true;
    last_ = T_odom_cam;
    return true;
  }
  const Eigen::Isometry3d d = last_.inverse() * T_odom_cam;
  const double dist = d.translation().norm(), ang = angleDeg(d);
  const bool far = dist >= p_.keyframe_max_distance_m || ang >= p_.keyframe_max_angle_deg;
  const bool moved = dist >= p_.keyframe_min_distance_m || ang >= p_.keyframe_min_angle_deg;
  if (far || (vo_replenished && moved))
  {
    last_ = T_odom_cam;
    return true;
  }
  return false;
}

}  // namespace assistive_slam
