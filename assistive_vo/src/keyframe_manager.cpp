#include "assistive_vo/keyframe_manager.h"
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include "cpu_clock.h"

namespace assistive_vo
{
using internal::Clock;
using internal::angleOf;
using internal::msSince;

KeyframeManager::KeyframeManager(const VoParams& p, const StereoCamera& cam) : p_(p), cam_(cam), detector_(p)
{
}

void KeyframeManager::setParams(const VoParams& p)
{
  p_ = p;
  detector_.setParams(p);
}

void KeyframeManager::reset()
{
  valid_ = false;
  kf_.T_w_kf = kf_.T_kf_prev = Eigen::Isometry3d::Identity();
  kf_.covariance.setZero();
  kf_.R_prev_vision.setIdentity();
}

void KeyframeManager::start(const cv::Mat& left, const cv::Mat& right, bool from_current_tracks,
                            FeatureTracker& tracker, const Eigen::Isometry3d& T_w_cur,
                            const Eigen::Matrix<double, 6, 6>& cov_cur, double stamp, FrameStats& st)
{
  const auto t0 = Clock::now();
  std::vector<PointTrack> kept;
  std::vector<cv::Point2f> existing;
  if (from_current_tracks)
  {
    for (auto& tr : tracker.points())
    {
      if (tr.cur_disp <= 0)
        continue;
      PointTrack n;
      const cv::Point2f& g = tr.cur_geo;
      n.X_kf = cam_.triangulate(g.x, g.y, tr.cur_geo_disp);
      n.kf_obs = StereoObservation{g.x, g.y, g.x - tr.cur_geo_disp, tr.kf_obs.sigma_scale};
      n.prev = n.cur = tr.cur;
      n.cur_disp = tr.cur_disp;
      n.cur_geo = g;
      n.cur_geo_disp = tr.cur_geo_disp;
      n.coarse = tr.coarse;
      if (p_.keyframe_alignment && !tr.coarse)
        n.patch = KeyframePatch::extract(left, tr.cur, p_.alignment_half_window, p_.alignment_min_eigen_ratio);
      kept.push_back(n);
      existing.push_back(tr.cur);
    }
  }
  const int wanted = std::max(0, p_.target_features - static_cast<int>(kept.size()));
  std::vector<cv::Point2f> fresh = detector_.detect(left, existing, wanted);
  // Low texture: the threshold has just been lowered, try again (at most twice) before giving up.
  for (int retry = 0; retry < 2 && static_cast<int>(fresh.size() + kept.size()) < p_.target_features / 2 &&
                      detector_.threshold() < detector_.lastThresholdUsed();
       ++retry)
    fresh = detector_.detect(left, existing, wanted);
  st.fast_threshold = detector_.threshold();
  st.detected += static_cast<int>(fresh.size());
  const double max_d = maxDisparity(p_, cam_);
  std::vector<float> disp = tracker.stereo().match(left, right, fresh, max_d);
  // Farthest useful depth: max_depth_m, or farther when the stereo rig still resolves the point
  // with min_triangulation_disparity_px there (wide baseline / long focal length).
  const double max_depth =
      std::max(p_.max_depth_m, cam_.fx * cam_.baseline / std::max(0.5, p_.min_triangulation_disparity_px));
  int added = 0;
  for (size_t i = 0; i < fresh.size(); ++i)
  {
    if (disp[i] <= 0)
      continue;
    PointTrack n;
    if (!newTrack(tracker, fresh[i], disp[i], max_depth, 1.0, n))
      continue;
    if (p_.keyframe_alignment)
      n.patch = KeyframePatch::extract(left, fresh[i], p_.alignment_half_window, p_.alignment_min_eigen_ratio);
    kept.push_back(n);
    ++added;
  }
  if (static_cast<double>(kept.size()) < p_.coarse_min_ratio * p_.target_features)
    added += addCoarseCorners(left, right, tracker, max_depth, kept, st);
  tracker.points().swap(kept);
  kf_.tracks_started = static_cast<int>(tracker.points().size());
  kf_.cells_started = tracker.occupiedCells();
  tracker.startKeyframeLines(left, right, from_current_tracks, kf_.tracks_started);
  st.new_features = added;
  st.keyframe = true;
  kf_.T_w_kf = T_w_cur;
  kf_.T_kf_prev = Eigen::Isometry3d::Identity();
  kf_.R_gyro.setIdentity();
  kf_.R_prev_vision.setIdentity();
  kf_.gyro_rate.setZero();
  kf_.gyro_since = true;
  kf_.stamp = stamp;
  kf_.covariance = cov_cur;
  // With lines, a stereo segment counts as a feature (it constrains the motion as much as a point
  // or more: 4 rows of the trifocal system against a point's 3).
  valid_ = kf_.tracks_started + static_cast<int>(tracker.lines().size()) >= std::max(4, p_.min_inliers);
  st.ms_detect += msSince(t0);
}

bool KeyframeManager::newTrack(const FeatureTracker& tracker, const cv::Point2f& corner, float disp, double max_depth,
                               double sigma_scale, PointTrack& n) const
{
  tracker.undoRollingShutter(corner, disp, n.cur_geo, n.cur_geo_disp);
  const cv::Point2f& g = n.cur_geo;
  const Eigen::Vector3d X = cam_.triangulate(g.x, g.y, n.cur_geo_disp);
  if (X.z() > max_depth || X.z() < p_.min_depth_m)
    return false;
  n.X_kf = X;
  n.kf_obs = StereoObservation{g.x, g.y, g.x - n.cur_geo_disp, sigma_scale};
  n.prev = n.cur = corner;
  n.cur_disp = disp;
  return true;
}

int KeyframeManager::addCoarseCorners(const cv::Mat& left, const cv::Mat& right, FeatureTracker& tracker,
                                      double max_depth, std::vector<PointTrack>& kept, FrameStats& st)
{
  const cv::Mat& smooth = tracker.smoothedLeft(left);  // half resolution
  // Shi-Tomasi on the smoothed image, over a window as wide as the smoothing (the blobs' corners),
  // away from the border and from the corners kept
  const int border = std::max(p_.border_px / 2, p_.coarse_half_window + 2);
  if (smooth.cols <= 2 * border || smooth.rows <= 2 * border)
    return 0;
  const double spacing = p_.min_feature_distance_px;  // twice the corners' spacing at full resolution
  cv::Mat mask = cv::Mat::zeros(smooth.size(), CV_8U);
  mask(cv::Rect(border, border, smooth.cols - 2 * border, smooth.rows - 2 * border)).setTo(255);
  for (const PointTrack& t : kept)
    cv::circle(mask, 0.5f * t.cur, static_cast<int>(spacing), 0, -1);
  const int wanted = p_.target_features - static_cast<int>(kept.size());
  std::vector<cv::Point2f> corners;
  const int block = 2 * static_cast<int>(std::lround(p_.coarse_sigma_px)) + 1;
  cv::goodFeaturesToTrack(smooth, corners, std::max(1, wanted), 0.005, spacing, mask, block);
  for (cv::Point2f& c : corners)
    c *= 2.f;
  st.detected += static_cast<int>(corners.size());
  const std::vector<float> disp = tracker.matchCoarse(left, right, corners);
  std::vector<PointTrack> coarse;
  for (size_t i = 0; i < corners.size(); ++i)
  {
    if (disp[i] <= 0)
      continue;
    PointTrack n;
    if (!newTrack(tracker, corners[i], disp[i], max_depth, p_.coarse_sigma_scale, n))
      continue;
    n.coarse = true;
    coarse.push_back(n);
  }
  // a trickle of them tracks badly (on a wall with no texture at all the VO rather coasts)
  if (static_cast<int>(coarse.size()) < p_.coarse_min_corners)
    return 0;
  kept.insert(kept.end(), coarse.begin(), coarse.end());
  st.coarse_features = static_cast<int>(coarse.size());
  return st.coarse_features;
}

bool KeyframeManager::needed(const Eigen::Isometry3d& T_kf_cur, const FeatureTracker& tracker) const
{
  const int tracks = static_cast<int>(tracker.points().size());
  return tracks < p_.replenish_ratio * kf_.tracks_started ||
         tracker.occupiedCells() < p_.replenish_coverage_ratio * kf_.cells_started || tracks < p_.min_tracks ||
         angleOf(T_kf_cur.linear()) > p_.max_rotation_from_keyframe_deg * M_PI / 180.0;
}

void KeyframeManager::addGyro(bool have_gyro, const Eigen::Matrix3d& R_gyro_opt)
{
  if (have_gyro)
    kf_.R_gyro = kf_.R_gyro * R_gyro_opt;
  else
    kf_.gyro_since = false;
}
}  // namespace assistive_vo
