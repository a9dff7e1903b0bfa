#include "assistive_vo/feature_tracker.h"
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include "assistive_vo/feature_detector.h"
#include "cpu_clock.h"

namespace assistive_vo
{
using internal::Clock;
using internal::msSince;

namespace
{
VoParams coarseStereoParams(VoParams p)
{
  p.stereo_half_window = p.coarse_half_window;
  return p;
}
}  // namespace

FeatureTracker::FeatureTracker(const VoParams& p, const StereoCamera& cam)
  : p_(p), cam_(cam), stereo_(p), coarse_stereo_(coarseStereoParams(p))
{
  pointline_ = usesPointLine(p);
}

void FeatureTracker::setParams(const VoParams& p)
{
  p_ = p;
  stereo_.setParams(p);
  coarse_stereo_.setParams(coarseStereoParams(p));
  pointline_ = usesPointLine(p);
}

namespace
{
/// `img` at half resolution, then smoothed (coarse_sigma in full-resolution pixels in all), into
/// `out` once per frame (`built`: the frame_index_ it holds).
void halfSmoothedOnce(const cv::Mat& img, double sigma_full_px, unsigned long frame, cv::Mat& out,
                      unsigned long& built)
{
  if (built == frame && !out.empty())
    return;
  cv::pyrDown(img, out);
  cv::GaussianBlur(out, out, cv::Size(), std::max(0.5, 0.5 * sigma_full_px));
  built = frame;
}
}  // namespace

const cv::Mat& FeatureTracker::smoothedLeft(const cv::Mat& left)
{
  halfSmoothedOnce(left, p_.coarse_sigma_px, frame_index_, smooth_left_, smooth_frame_);
  return smooth_left_;
}

std::vector<float> FeatureTracker::matchCoarse(const cv::Mat& left, const cv::Mat& right,
                                               const std::vector<cv::Point2f>& pts)
{
  smoothedLeft(left);
  halfSmoothedOnce(right, p_.coarse_sigma_px, frame_index_, smooth_right_, smooth_right_frame_);
  // at half resolution (pyrDown: half-resolution pixel i is centred on full-resolution 2i)
  std::vector<cv::Point2f> half(pts.size());
  for (size_t i = 0; i < pts.size(); ++i)
    half[i] = 0.5f * pts[i];
  coarse_stereo_.setOffset(0.5 * stereo_.offset());
  std::vector<float> d = coarse_stereo_.match(smooth_left_, smooth_right_, half, 0.5 * maxDisparity(p_, cam_));
  for (float& x : d)
    if (x > 0)
      x *= 2.f;
  return d;
}

void FeatureTracker::reset()
{
  points_.clear();
  clearOverlay();
}

void FeatureTracker::buildPyramid(const cv::Mat& left)
{
  const cv::Size win(p_.klt_window, p_.klt_window);
  cv::buildOpticalFlowPyramid(left, cur_pyr_, win, p_.klt_levels, true);
}


void FeatureTracker::trackPoints(const cv::Mat& left, const Eigen::Isometry3d& T_kf_pred, FrameStats& st)
{
  const auto t0 = Clock::now();
  const cv::Size win(p_.klt_window, p_.klt_window);
  const Eigen::Isometry3d T_pred_kf = T_kf_pred.inverse();
  std::vector<cv::Point2f> p0(points_.size()), p1(points_.size());
  for (size_t i = 0; i < points_.size(); ++i)
  {
    p0[i] = points_[i].cur;
    const Eigen::Vector3d Xc = T_pred_kf * points_[i].X_kf;
    if (Xc.z() > 0.05)
    {
      const Eigen::Vector2d q = cam_.projectLeft(Xc);
      p1[i] = cv::Point2f(static_cast<float>(q.x()), static_cast<float>(q.y()));
      if (!(q.allFinite()) || q.x() < 0 || q.y() < 0 || q.x() >= cam_.width || q.y() >= cam_.height)
        p1[i] = p0[i];
    }
    else
      p1[i] = p0[i];
  }
  std::vector<uint8_t> status;
  std::vector<float> err;
  if (!p0.empty())
    cv::calcOpticalFlowPyrLK(prev_pyr_, cur_pyr_, p0, p1, status, err, win, p_.klt_levels,
                             cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, p_.klt_iterations,
                                              p_.klt_epsilon),
                             cv::OPTFLOW_USE_INITIAL_FLOW, p_.klt_min_eigen);
  clearOverlay();
  {
    std::vector<PointTrack> alive;
    alive.reserve(points_.size());
    const float b = 2.f;
    for (size_t i = 0; i < points_.size(); ++i)
    {
      if (!status[i] || !(p1[i].x >= b && p1[i].y >= b && p1[i].x < cam_.width - b && p1[i].y < cam_.height - b))
        continue;
      PointTrack t = points_[i];
      t.prev = p0[i];
      t.cur = p1[i];
      alive.push_back(t);
    }
    points_.swap(alive);
  }
  // Refine against the keyframe patch (affine): removes the frame-to-frame KLT drift.
  for (auto& t : points_)
  {
    if (!t.patch)
      continue;
    cv::Point2f c = t.cur;
    Eigen::Matrix2f A = t.warp;
    float ncc = 0.f;
    if (t.patch->align(left, c, A, p_.alignment_iterations, &ncc) && ncc >= p_.alignment_min_ncc &&
        std::hypot(c.x - t.cur.x, c.y - t.cur.y) <= p_.alignment_max_shift_px)
    {
      t.cur = c;
      t.warp = A;
      ++st.aligned;
    }
  }
  // the rolling shutter's rotation undone already for the epipolar filter (no disparity yet)
  for (auto& t : points_)
    undoRollingShutter(t.cur, -1.f, t.cur_geo, t.cur_geo_disp);
  st.klt_tracked = static_cast<int>(points_.size());
  st.ms_klt = msSince(t0);
}

void FeatureTracker::filterEpipolar(FrameStats& st)
{
  const auto t0 = Clock::now();
  if (p_.epipolar_filter && points_.size() >= 15)
  {
    std::vector<cv::Point2f> a(points_.size()), c(points_.size());
    double flow = 0;
    for (size_t i = 0; i < points_.size(); ++i)
    {
      a[i] = cv::Point2f(static_cast<float>(points_[i].kf_obs.u), static_cast<float>(points_[i].kf_obs.v));
      c[i] = points_[i].cur_geo;
      flow += cv::norm(a[i] - c[i]);
    }
    flow /= static_cast<double>(points_.size());
    if (flow > p_.epipolar_min_flow_px)
    {
      std::vector<uint8_t> mask;
      cv::Mat F = cv::findFundamentalMat(a, c, cv::FM_RANSAC, p_.epipolar_threshold_px, 0.99, 200, mask);
      if (!F.empty() && mask.size() == points_.size())
      {
        size_t nin = 0;
        for (uint8_t m : mask)
          nin += m != 0;
        // Only trust F when it explains most tracks (near-degenerate motion can fit nonsense).
        if (nin >= points_.size() / 2)
        {
          std::vector<PointTrack> keep;
          keep.reserve(nin);
          for (size_t i = 0; i < points_.size(); ++i)
            if (mask[i])
              keep.push_back(points_[i]);
            else
              addOverlay(points_[i], false);
          points_.swap(keep);
        }
      }
    }
  }
  st.epipolar_kept = static_cast<int>(points_.size());
  st.ms_epipolar = msSince(t0);
}

void FeatureTracker::matchStereo(const cv::Mat& left, const cv::Mat& right, FrameStats& st)
{
  const auto t0 = Clock::now();
  std::vector<cv::Point2f> fine, coarse;
  for (const PointTrack& t : points_)
    (t.coarse ? coarse : fine).push_back(t.cur);
  const std::vector<float> d = stereo_.match(left, right, fine, maxDisparity(p_, cam_));
  const std::vector<float> dc = coarse.empty() ? std::vector<float>() : matchCoarse(left, right, coarse);
  size_t i_fine = 0, i_coarse = 0;
  for (PointTrack& t : points_)
  {
    t.cur_disp = t.coarse ? dc[i_coarse++] : d[i_fine++];
    undoRollingShutter(t.cur, t.cur_disp, t.cur_geo, t.cur_geo_disp);
  }
  st.ms_stereo = msSince(t0);
}

void FeatureTracker::undoRollingShutter(const cv::Point2f& c, float d, cv::Point2f& geo, float& geo_disp) const
{
  double u = c.x, v = c.y, dd = d;
  rs_.undo(u, v, dd);
  geo = cv::Point2f(static_cast<float>(u), static_cast<float>(v));
  geo_disp = d > 0 && dd > 0 ? static_cast<float>(dd) : d;
}

void FeatureTracker::startLines(const cv::Mat& left, const cv::Mat& right)
{
  // Lines detected in the left image only; each one's right segment found by a disparity sweep
  // and KLT (line_tracking.h): detecting the right image too cost as much again.
  const LineSegments L = line_detector_.detect(left);
  line_match_.min_disparity = p_.min_disparity_px;
  line_match_.max_disparity = maxDisparity(p_, cam_);
  std::vector<bool> ok;
  // the KLT pyramids: the left one the points use, the right one this frame's line tracking built
  // (else built here and kept for the next frame's)
  const bool pyramids = pointPyramidsServeLines() && !cur_pyr_.empty() && !L.empty();
  if (pyramids && prev_right_pyr_frame_ != frame_index_)
  {
    buildLinePyramid(right, prev_right_pyr_);
    prev_right_pyr_frame_ = frame_index_;
  }
  const LineSegments R = pyramids ? sweepStereoSegments(left, right, L, line_match_, ok, cur_pyr_, prev_right_pyr_)
                                  : sweepStereoSegments(left, right, L, line_match_, ok);
  for (size_t i = 0; i < L.size(); ++i)
  {
    if (!ok[i])
      continue;
    LineTrack t;
    t.kf_left = t.cur = L[i];
    t.kf_right = t.cur_right = R[i];
    t.stereo = true;
    lines_.push_back(t);
  }
  setPrevRight(right);
}

bool FeatureTracker::pointPyramidsServeLines() const
{
  return p_.klt_window >= kLineKltWindow && p_.klt_levels >= kLineKltLevels;
}

void FeatureTracker::setPrevRight(const cv::Mat& right)
{
  right.copyTo(prev_right_);
  prev_right_frame_ = frame_index_;
}

void FeatureTracker::trackLines(const cv::Mat& right, FrameStats& st)
{
  const auto t0 = Clock::now();
  ++frames_since_line_detect_;
  if (!lines_.empty() && !prev_pyr_.empty() && !cur_pyr_.empty())
  {
    // Both segments of a line tracked by KLT along them, the left one in the left images, the
    // right one in the right images (detecting the right image's segments again on every frame
    // cost three times as much).
    LineSegments prev_l, prev_r;
    prev_l.reserve(lines_.size());
    prev_r.reserve(lines_.size());
    for (const LineTrack& t : lines_)
    {
      prev_l.push_back(t.cur);
      prev_r.push_back(t.cur_right);
    }
    std::vector<bool> ok_l, ok_r;
    // the KLT pyramids of the left images when built for a window at least the lines':
    // calcOpticalFlowPyrLK would build both again
    const bool pyramids = pointPyramidsServeLines();
    const LineSegments next_l = pyramids ? trackSegments(prev_pyr_, cur_pyr_, prev_l, line_match_, ok_l)
                                         : trackSegments(prev_pyr_[0], cur_pyr_[0], prev_l, line_match_, ok_l);
    // the right images' pyramids: this one's kept for the next frame (one build a frame)
    std::vector<cv::Mat> right_pyr;
    if (pyramids)
    {
      buildLinePyramid(right, right_pyr);
      if (prev_right_pyr_frame_ != prev_right_frame_ || prev_right_pyr_.empty())
        buildLinePyramid(prev_right_, prev_right_pyr_);
    }
    const LineSegments next_r = pyramids ? trackSegments(prev_right_pyr_, right_pyr, prev_r, line_match_, ok_r)
                                         : trackSegments(prev_right_, right, prev_r, line_match_, ok_r);
    if (pyramids)
    {
      prev_right_pyr_.swap(right_pyr);
      prev_right_pyr_frame_ = frame_index_;
    }
    std::vector<LineTrack> alive;
    for (size_t i = 0; i < lines_.size(); ++i)
      if (ok_l[i] && ok_r[i])
      {
        LineTrack t = lines_[i];
        t.cur = next_l[i];
        t.cur_right = next_r[i];
        t.stereo = true;
        alive.push_back(t);
      }
    lines_.swap(alive);
    st.lines = static_cast<int>(lines_.size());
  }
  else
    lines_.clear();
  setPrevRight(right);
  st.ms_lines = msSince(t0);
}

int FeatureTracker::occupiedCells() const
{
  // Image coverage of the tracks on the detector's bucketing grid. Tracks that crowd into part of
  // the image (forward motion: they leave at the edges and the far ones in the centre remain)
  // constrain the motion poorly even while many are left.
  const cv::Size grid = bucketGrid(p_, cam_.width, cam_.height);
  const int gc = grid.width, gr = grid.height;
  std::vector<uint8_t> occ(static_cast<size_t>(gc * gr), 0);
  int n = 0;
  for (const auto& t : points_)
  {
    const int x = std::clamp(static_cast<int>(t.cur.x * gc / std::max(1, cam_.width)), 0, gc - 1);
    const int y = std::clamp(static_cast<int>(t.cur.y * gr / std::max(1, cam_.height)), 0, gr - 1);
    uint8_t& o = occ[static_cast<size_t>(y * gc + x)];
    n += o == 0;
    o = 1;
  }
  return n;
}

void FeatureTracker::clearOverlay()
{
  ov_from_.clear();
  ov_to_.clear();
  ov_inlier_.clear();
}

void FeatureTracker::addOverlay(const PointTrack& t, bool inlier)
{
  ov_from_.push_back(t.prev);
  ov_to_.push_back(t.cur);
  ov_inlier_.push_back(inlier ? 1 : 0);
}
void FeatureTracker::startKeyframeLines(const cv::Mat& left, const cv::Mat& right, bool from_current_tracks,
                                        int points_started)
{
  // Lines: the tracked ones carry on into the new keyframe while at least half of those started
  // (and 8) are left: the line detector (3-8 ms an image) is the dearest step of a keyframe.
  const bool keep_lines = pointline_ && from_current_tracks &&
                          static_cast<int>(lines_.size()) >= std::max(8, lines_started_ / 2);
  if (keep_lines)
  {
    for (LineTrack& t : lines_)
    {
      t.kf_left = t.cur;
      t.kf_right = t.cur_right;
    }
    setPrevRight(right);
    return;
  }
  lines_.clear();
  // ... and new lines are looked for at most every kLineDetectFrames frames (keyframes come
  // every 2-3 frames where corners are few)
  // and only while the keyframe's corners are not plenty (twice the 3 x min_inliers below which
  // the lines are used: the span runs down to there before the next keyframe; 10 x detected on
  // 16 % of the corridor's frames for the same drift, bare corridor 1.388 -> 1.279 % at 6 x)
  if (pointline_ && (!from_current_tracks || frames_since_line_detect_ >= kLineDetectFrames) &&
      points_started < 6 * p_.min_inliers)
  {
    startLines(left, right);
    frames_since_line_detect_ = 0;
  }
  lines_started_ = static_cast<int>(lines_.size());
}

void FeatureTracker::keepInliers(const std::vector<int>& inliers, const Vec3List& X_refined)
{
  std::vector<uint8_t> is_in(points_.size(), 0);
  for (size_t k = 0; k < inliers.size(); ++k)
  {
    const size_t i = static_cast<size_t>(inliers[k]);
    is_in[i] = 1;
    points_[i].X_kf = X_refined[k];  // refined by the bundle adjustment
  }
  std::vector<PointTrack> keep;
  keep.reserve(inliers.size());
  for (size_t i = 0; i < points_.size(); ++i)
  {
    addOverlay(points_[i], is_in[i] != 0);
    if (is_in[i])
      keep.push_back(points_[i]);
  }
  points_.swap(keep);
}

void FeatureTracker::drawOverlay(cv::Mat& out) const
{
  for (size_t i = 0; i < ov_from_.size(); ++i)
  {
    const cv::Scalar c = ov_inlier_[i] ? cv::Scalar(0, 220, 0) : cv::Scalar(0, 0, 255);
    cv::line(out, ov_from_[i], ov_to_[i], c, 1, cv::LINE_AA);
    cv::circle(out, ov_to_[i], 2, c, -1, cv::LINE_AA);
  }
  for (const auto& t : points_)
    if (t.prev == t.cur)  // fresh corners of a new keyframe
      cv::circle(out, t.cur, 2, cv::Scalar(255, 160, 0), -1, cv::LINE_AA);
  // line tracks (motion_solver pointline): magenta
  for (const auto& l : lines_)
    cv::line(out, cv::Point2d(l.cur.p.x(), l.cur.p.y()), cv::Point2d(l.cur.q.x(), l.cur.q.y()),
             cv::Scalar(255, 0, 255), 2, cv::LINE_AA);
}
}  // namespace assistive_vo
