#include "assistive_vo/motion_refiner.h"
#include <algorithm>
#include <cmath>
#include "assistive_vo/pointline_refine.h"
#include "cpu_clock.h"

namespace assistive_vo
{
using internal::Clock;
using internal::msSince;

MotionRefiner::MotionRefiner(const VoParams& p, const StereoCamera& cam) : p_(p), cam_(cam)
{
}

void MotionRefiner::refine(const FeatureTracker& tracker, const MotionPrior& prior, FrameStats& st,
                           MotionEstimate& m)
{
  const auto t0 = Clock::now();
  const std::vector<PointTrack>& tracks = tracker.points();
  std::vector<StereoObservation> oref, ocur;
  m.X_in.reserve(m.rr.inliers.size());
  for (int i : m.rr.inliers)
  {
    const PointTrack& t = tracks[static_cast<size_t>(i)];
    m.X_in.push_back(t.X_kf);
    oref.push_back(t.kf_obs);
    ocur.push_back(StereoObservation{t.cur_geo.x, t.cur_geo.y, t.cur_geo_disp > 0 ? t.cur_geo.x - t.cur_geo_disp : -1.0,
                                     t.kf_obs.sigma_scale});
  }
  if (m.with_lines)
    refinePointsLines(tracker, prior, ocur, m);
  else
  {
    TwoFrameBundleAdjuster::Options bo;
    bo.iterations = p_.ba_iterations;
    bo.huber_px = p_.ba_huber_px;
    bo.pixel_sigma_px = p_.pixel_sigma_px;
    m.br = ba_.optimize(cam_, m.rr.T_ref_cur, m.X_in, oref, ocur, bo);
    // Vision-only rotation (kept for the online gyro bias estimate).
    m.R_vision = m.br.ok ? Eigen::Matrix3d(m.br.T_ref_cur.linear()) : Eigen::Matrix3d(m.rr.T_ref_cur.linear());
    m.cov_vision = m.br.covariance;
    if (m.br.ok && prior.gyro)
    {
      // Second pass with the integrated (bias-corrected) gyro as a rotation prior: angle random
      // walk + bias uncertainty over the keyframe span.
      bo.use_rotation_prior = true;
      bo.rotation_prior = prior.R_kf_gyro;
      bo.rotation_prior_weight = p_.pixel_sigma_px * p_.pixel_sigma_px / prior.gyro_variance;
      bo.iterations = std::max(2, p_.ba_iterations / 2);
      const BundleAdjustmentResult b2 = ba_.optimize(cam_, m.br.T_ref_cur, m.X_in, oref, ocur, bo);
      if (b2.ok)
        m.br = b2;
    }
  }
  st.ms_ba = msSince(t0);
  m.T_kf_cur = m.br.ok ? m.br.T_ref_cur : m.rr.T_ref_cur;
  m.T_prev_cur = prior.T_kf_prev.inverse() * m.T_kf_cur;
}

void MotionRefiner::refinePointsLines(const FeatureTracker& tracker, const MotionPrior& prior,
                                      const std::vector<StereoObservation>& ocur, MotionEstimate& m) const
{
  // points_lines: the motion refined on the point and the line inliers together (structure
  // fixed): with the points alone it was the few points that decided (README figures).
  StereoLineObservations lo;
  for (const LineTrack& t : tracker.lines())
  {
    StereoLineObservation l;
    if (!t.stereo || !triangulateStereoSegment(cam_, t.kf_left, t.kf_right, p_.min_disparity_px, l.P, l.Q))
      continue;
    l.left_p = t.cur.p, l.left_q = t.cur.q, l.right_p = t.cur_right.p, l.right_q = t.cur_right.q;
    lo.push_back(l);
  }
  PointLineRefineOptions ro;
  ro.iterations = std::max(1, p_.ba_iterations);
  ro.huber_px = p_.ba_huber_px;
  ro.pixel_sigma_px = p_.pixel_sigma_px;
  // The constant-velocity prediction as a prior: the corridor's end wall leaves only its
  // vertical door jambs, which say nothing of the motion along them (without it 6-11 cm a frame
  // off in v there, README "Point+line in the loop").
  const Eigen::Isometry3d& T_kf_pred = prior.T_kf_pred;
  const double sig_t = p_.pointline_prior_sigma_m, sig_r = p_.pointline_prior_sigma_deg * M_PI / 180.0;
  ro.use_translation_prior = sig_t > 0;
  ro.translation_prior = T_kf_pred.translation();
  ro.translation_prior_weight = sig_t > 0 ? p_.pixel_sigma_px * p_.pixel_sigma_px / (sig_t * sig_t) : 0.0;
  // vision-only rotation first (the gyro bias estimate needs it), then with the gyro prior;
  // without a gyro the predicted rotation is the prior
  ro.use_rotation_prior = !prior.gyro && sig_r > 0;
  if (ro.use_rotation_prior)
  {
    ro.rotation_prior = T_kf_pred.linear();
    ro.rotation_prior_weight = p_.pixel_sigma_px * p_.pixel_sigma_px / (sig_r * sig_r);
  }
  // a point or two only where they are checked by others
  const bool points_checked = static_cast<int>(m.X_in.size()) >= p_.pointline_min_points;
  m.lines_only = !points_checked;
  const Vec3List no_points;
  const std::vector<StereoObservation> no_obs;
  const Vec3List& X_ref = points_checked ? m.X_in : no_points;
  const std::vector<StereoObservation>& X_obs = points_checked ? ocur : no_obs;
  m.br = refineMotionPointsLines(cam_, m.rr.T_ref_cur, X_ref, X_obs, lo, ro);
  m.R_vision = m.br.ok ? Eigen::Matrix3d(m.br.T_ref_cur.linear()) : Eigen::Matrix3d(m.rr.T_ref_cur.linear());
  m.cov_vision = m.br.covariance;
  if (m.br.ok && prior.gyro)
  {
    ro.use_rotation_prior = true;
    ro.rotation_prior = prior.R_kf_gyro;
    ro.rotation_prior_weight = p_.pixel_sigma_px * p_.pixel_sigma_px / prior.gyro_variance;
    const BundleAdjustmentResult b2 = refineMotionPointsLines(cam_, m.br.T_ref_cur, X_ref, X_obs, lo, ro);
    if (b2.ok)
      m.br = b2;
  }
}
}  // namespace assistive_vo
