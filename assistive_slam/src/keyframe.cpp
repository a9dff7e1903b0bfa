#include "assistive_slam/keyframe.h"
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>

namespace assistive_slam
{
double angleDeg(const Eigen::Isometry3d& T)
{
  return Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI;
}

namespace
{
/// Sub-pixel disparity of the left pixel (xl, y): Gauss-Newton on the 9x9 patch's squared
/// differences against the right image sampled bilinearly along the row, from integer disparity
/// d. Returns false when it leaves the image or does not settle within a pixel of d.
bool alignAlongRow(const cv::Mat& left, const cv::Mat& right, int xl, int y, double* d)
{
  constexpr int kHalf = 4, kW = 2 * kHalf + 1;
  cv::Mat L;
  left(cv::Rect(xl - kHalf, y - kHalf, kW, kW)).convertTo(L, CV_32F);
  const double d0 = *d;
  for (int it = 0; it < 10; ++it)
  {
    const double xr = xl - *d;
    if (xr - kHalf - 2 < 0 || xr + kHalf + 2 >= right.cols)
      return false;
    cv::Mat P;  // one column more on either side for the gradient
    cv::getRectSubPix(right, cv::Size(kW + 2, kW), cv::Point2f(static_cast<float>(xr), static_cast<float>(y)), P, CV_32F);
    double num = 0, den = 0;
    for (int r = 0; r < kW; ++r)
      for (int c = 0; c < kW; ++c)
      {
        const double g = 0.5 * (P.at<float>(r, c + 2) - P.at<float>(r, c));
        const double e = L.at<float>(r, c) - P.at<float>(r, c + 1);
        num += g * e;  // d(residual)/d(disparity) = +g
        den += g * g;
      }
    if (den <= 1e-9)
      return false;
    const double step = -num / den;
    *d += step;
    if (std::abs(*d - d0) > 1.0)
      return false;
    if (std::abs(step) < 1e-4)
      break;
  }
  return true;
}

double refineDisparity(const cv::Mat& left, const cv::Mat& right, const cv::Point2f& pt, double disp)
{
  // ORB's keypoints on its coarse levels sit on a grid 1.2^level px wide in both images: far points'
  // small disparities are then off by a pixel or more. The left patch (full resolution, centred on
  // the rounded keypoint) is searched along the right image's row within 2 px of ORB's disparity
  // (sum of absolute differences), then aligned to a fraction of a pixel (alignAlongRow); ORB's
  // disparity is kept when the patch leaves the image, the minimum lies on the search's edge or the
  // alignment does not settle.
  constexpr int kHalf = 4, kSearch = 2;
  const int xl = static_cast<int>(std::lround(pt.x)), y = static_cast<int>(std::lround(pt.y));
  const int d0 = static_cast<int>(std::lround(xl - (pt.x - disp)));  // ORB's disparity, rounded
  if (y - kHalf < 0 || y + kHalf >= left.rows || xl - kHalf < 0 || xl + kHalf >= left.cols ||
      xl - d0 - kSearch - 1 - kHalf < 0 || xl - d0 + kSearch + 1 + kHalf >= right.cols)
    return disp;
  const cv::Mat patch = left(cv::Rect(xl - kHalf, y - kHalf, 2 * kHalf + 1, 2 * kHalf + 1));
  double cost[2 * kSearch + 3];
  for (int k = -kSearch - 1; k <= kSearch + 1; ++k)
  {
    const int xr = xl - d0 - k;
    cost[k + kSearch + 1] = cv::norm(patch, right(cv::Rect(xr - kHalf, y - kHalf, 2 * kHalf + 1, 2 * kHalf + 1)), cv::NORM_L1);
  }
  int best = 1;
  for (int i = 2; i <= 2 * kSearch + 1; ++i)
    if (cost[i] < cost[best])
      best = i;
  if (cost[best] >= cost[0] || cost[best] >= cost[2 * kSearch + 2])
    return disp;  // no interior minimum
  double d = d0 + (best - kSearch - 1);
  return alignAlongRow(left, right, xl, y, &d) ? d : disp;
}
}  // namespace

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
    double disp = a.pt.x - kr[best].pt.x;
    if (p_.stereo_subpixel)
      disp = refineDisparity(left, right, a.pt, disp);
    if (disp < min_disp || disp > max_disp)
      continue;
    const double z = cam.fx * cam.baseline / disp;
    const Eigen::Vector3d X((a.pt.x - cam.cx) * z / cam.fx, (a.pt.y - cam.cy) * z / cam.fy, z);
    kf.keypoints.push_back(a);
    kf.u_right.push_back(a.pt.x - disp);
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
