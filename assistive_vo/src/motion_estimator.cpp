#include "assistive_vo/motion_estimator.h"
#include <algorithm>
#include <cmath>
#include "cpu_clock.h"

namespace assistive_vo
{
using internal::Clock;
using internal::msSince;

namespace
{
/// Smaller / larger eigenvalue of the structure tensor over the 7x7 window at c (0 near the
/// border): about 0 on a straight edge, up to 1 on an isotropic corner.
double cornerEigenRatio(const cv::Mat& img, const cv::Point2f& c)
{
  const int x0 = static_cast<int>(std::lround(c.x)), y0 = static_cast<int>(std::lround(c.y));
  if (x0 < 5 || y0 < 5 || x0 >= img.cols - 5 || y0 >= img.rows - 5)
    return 0.0;
  double a = 0, b = 0, d = 0;
  for (int y = y0 - 3; y <= y0 + 3; ++y)
  {
    const uchar* r = img.ptr<uchar>(y);
    const uchar* up = img.ptr<uchar>(y - 1);
    const uchar* dn = img.ptr<uchar>(y + 1);
    for (int x = x0 - 3; x <= x0 + 3; ++x)
    {
      const double gx = 0.5 * (r[x + 1] - r[x - 1]), gy = 0.5 * (dn[x] - up[x]);
      a += gx * gx, b += gx * gy, d += gy * gy;
    }
  }
  const double tr = a + d, det = a * d - b * b, disc = std::sqrt(std::max(0.0, tr * tr / 4 - det));
  const double l1 = tr / 2 + disc, l2 = tr / 2 - disc;
  return l1 > 0 ? std::max(0.0, l2) / l1 : 0.0;
}
}  // namespace

MotionEstimator::MotionEstimator(const VoParams& p, const StereoCamera& cam) : p_(p), cam_(cam)
{
  pointline_ = usesPointLine(p);
}

void MotionEstimator::setParams(const VoParams& p)
{
  p_ = p;
  pointline_ = usesPointLine(p);
}

bool MotionEstimator::estimate(const Eigen::Isometry3d& T_kf_pred, bool have_imu, FeatureTracker& tracker, FrameStats& st,
                               MotionEstimate& m)
{
  const std::vector<PointTrack>& tracks = tracker.points();
  const std::vector<LineTrack>& lines = tracker.lines();
  // pointline: the point+line RANSAC while stereo line tracks exist; without any it would be
  // the quaternion solver on points alone, slower than P3P and no better (README figures).
  // Where corners are plenty (3 x min_inliers tracks), P3P too: the lines only help where points are few.
  const bool with_lines = pointline_ && static_cast<int>(tracks.size()) < 3 * p_.min_inliers &&
                          std::any_of(lines.begin(), lines.end(), [](const LineTrack& t) { return t.stereo; });
  // With the IMU the points first and the lines only where the points alone fail: a weak frame
  // coasts well on the IMU, and the lines of one wall were no better than the few corners there
  // (shipped worlds and generated ones with the IMU: as many bags worse as better, README).
  if (with_lines && have_imu)
  {
    if (estimatePoints(T_kf_pred, tracker, st, m))
      return true;
    m = MotionEstimate();
    return estimatePointsLines(tracker, st, m);
  }
  return with_lines ? estimatePointsLines(tracker, st, m) : estimatePoints(T_kf_pred, tracker, st, m);
}

bool MotionEstimator::estimatePoints(const Eigen::Isometry3d& T_kf_pred, const FeatureTracker& tracker, FrameStats& st,
                                     MotionEstimate& m)
{
  const auto t0 = Clock::now();
  const std::vector<PointTrack>& tracks = tracker.points();
  Vec3List X(tracks.size());
  Vec2List x(tracks.size());
  for (size_t i = 0; i < tracks.size(); ++i)
  {
    X[i] = tracks[i].X_kf;
    x[i] = Eigen::Vector2d(tracks[i].cur_geo.x, tracks[i].cur_geo.y);
  }
  RansacOptions ro;
  ro.probability = p_.ransac_probability;
  ro.max_trials = p_.ransac_max_trials;
  ro.min_trials = p_.ransac_min_trials;
  ro.threshold_max_px = p_.inlier_threshold_px;
  ro.threshold_min_px = p_.inlier_threshold_min_px;
  m.rr = ransac_.estimate(cam_, X, x, ro, &T_kf_pred);
  st.ransac_trials = m.rr.trials;
  st.ms_ransac = msSince(t0);
  if (!m.rr.ok || static_cast<int>(m.rr.inliers.size()) < p_.min_inliers)
  {
    st.inliers = static_cast<int>(m.rr.inliers.size());
    return false;
  }
  return true;
}

bool MotionEstimator::estimatePointsLines(FeatureTracker& tracker, FrameStats& st, MotionEstimate& m)
{
  const auto t0 = Clock::now();
  const std::vector<PointTrack>& tracks = tracker.points();
  std::vector<LineTrack>& lines = tracker.lines();
  const auto norm = [this](double u, double v) { return Eigen::Vector2d((u - cam_.cx) / cam_.fx, (v - cam_.cy) / cam_.fy); };
  StereoRig rig;
  rig.t0 = Eigen::Vector3d(-cam_.baseline, 0.0, 0.0);
  PointQuads pq;
  std::vector<int> pq_track;
  // Corners on a straight edge slide along it (the aperture problem): with the lines they add
  // nothing across the edge and mislead along it (the corridor's end: all the corners on the
  // door jambs, 12-28 px off in v at the true motion). Only clear corners join the lines.
  std::vector<uint8_t> edge_like(tracks.size(), 0);
  for (size_t i = 0; i < tracks.size(); ++i)
    edge_like[i] = p_.pointline_min_corner_ratio > 0 &&
                   cornerEigenRatio(tracker.currentImage(), tracks[i].cur) < p_.pointline_min_corner_ratio;
  for (size_t i = 0; i < tracks.size(); ++i)
  {
    const PointTrack& t = tracks[i];
    if (t.cur_geo_disp <= 0 || t.kf_obs.ur < 0 || edge_like[i])
      continue;
    PointQuad q;
    q.x[0] = norm(t.kf_obs.u, t.kf_obs.v);
    q.x[1] = norm(t.kf_obs.ur, t.kf_obs.v);
    q.x[2] = norm(t.cur_geo.x, t.cur_geo.y);
    q.x[3] = norm(t.cur_geo.x - t.cur_geo_disp, t.cur_geo.y);
    pq.push_back(q);
    pq_track.push_back(static_cast<int>(i));
  }
  LineQuads lq;
  std::vector<int> lq_track;
  for (size_t i = 0; i < lines.size(); ++i)
  {
    const LineTrack& t = lines[i];
    if (!t.stereo)
      continue;
    LineQuad q;
    const LineSegment* v[4] = {&t.kf_left, &t.kf_right, &t.cur, &t.cur_right};
    for (int k = 0; k < 4; ++k)
    {
      q.p[k] = norm(v[k]->p.x(), v[k]->p.y());
      q.q[k] = norm(v[k]->q.x(), v[k]->q.y());
    }
    lq.push_back(q);
    lq_track.push_back(static_cast<int>(i));
  }
  PointLineRansacOptions ro;
  ro.sample_size = 5;  // quaternion-5, as the seed's real-data runs
  ro.threshold_px = p_.inlier_threshold_px;
  ro.focal_px = cam_.fx;
  ro.probability = p_.ransac_probability;
  ro.max_trials = p_.ransac_max_trials;
  const PointLineRansacResult r = pl_ransac_.estimate(rig, pq, lq, ro);
  m.rr = RansacResult();
  m.with_lines = true;
  m.rr.trials = r.trials;
  st.ransac_trials = r.trials;
  int line_in = 0;
  if (r.ok)
  {
    Eigen::Isometry3d T_cur_kf = Eigen::Isometry3d::Identity();
    T_cur_kf.linear() = r.motion.R;
    T_cur_kf.translation() = r.motion.t;
    m.rr.ok = true;
    m.rr.T_ref_cur = T_cur_kf.inverse();
    m.rr.threshold_px = ro.threshold_px;
    std::vector<uint8_t> is_in(tracks.size(), 0);
    for (int k : r.point_inliers)
      is_in[static_cast<size_t>(pq_track[static_cast<size_t>(k)])] = 1;
    // tracks without a stereo match now: inliers by their left reprojection at this motion
    for (size_t i = 0; i < tracks.size(); ++i)
    {
      const PointTrack& t = tracks[i];
      if ((t.cur_geo_disp > 0 && t.kf_obs.ur >= 0) || edge_like[i])
        continue;
      const Eigen::Vector3d Xc = T_cur_kf * t.X_kf;
      if (Xc.z() > 0.05 && (cam_.projectLeft(Xc) - Eigen::Vector2d(t.cur_geo.x, t.cur_geo.y)).norm() < ro.threshold_px)
        is_in[i] = 1;
    }
    for (size_t i = 0; i < tracks.size(); ++i)
      if (is_in[i])
        m.rr.inliers.push_back(static_cast<int>(i));
    // the line tracks kept: the inliers (outliers and lines without a stereo match now dropped)
    std::vector<LineTrack> keep;
    for (int k : r.line_inliers)
      keep.push_back(lines[static_cast<size_t>(lq_track[static_cast<size_t>(k)])]);
    lines.swap(keep);
    line_in = static_cast<int>(lines.size());
  }
  st.line_inliers = line_in;
  st.ms_ransac = msSince(t0);
  // Enough constraints: a stereo line gives 4 rows against a stereo point's 3, counted as such
  // (the corridor's end wall: a point or two and 8-10 door-frame lines, re-initialised every
  // other frame when each line counted as one point).
  if (!m.rr.ok || 3 * static_cast<int>(m.rr.inliers.size()) + 4 * line_in < 3 * p_.min_inliers)
  {
    st.inliers = static_cast<int>(m.rr.inliers.size());
    return false;
  }
  return true;
}
}  // namespace assistive_vo
