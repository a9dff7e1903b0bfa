#include "assistive_vo/p3p_ransac.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <opengv/absolute_pose/CentralAbsoluteAdapter.hpp>
#include <opengv/absolute_pose/methods.hpp>

namespace assistive_vo
{
int P3PRansac::trialCount(double p, double w, int n, int max_trials)
{
  if (w >= 1.0)
    return 1;
  if (w <= 0.0)
    return max_trials;
  const double denom = std::log(1.0 - std::pow(w, n));
  if (!(denom < 0.0))
    return max_trials;
  const double k = std::log(1.0 - p) / denom;
  if (!std::isfinite(k) || k > max_trials)
    return max_trials;
  return std::max(1, static_cast<int>(std::ceil(k)));
}

void P3PRansac::reprojectionErrors(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur,
                                   const Vec3List& points_ref, const Vec2List& pixels_cur,
                                   std::vector<double>& sq_err)
{
  const Eigen::Matrix3d Rt = T_ref_cur.linear().transpose();
  const Eigen::Vector3d t = -Rt * T_ref_cur.translation();
  sq_err.resize(points_ref.size());
  for (size_t i = 0; i < points_ref.size(); ++i)
  {
    const Eigen::Vector3d pc = Rt * points_ref[i] + t;
    if (pc.z() < 1e-3)
    {
      sq_err[i] = 1e12;
      continue;
    }
    const double du = cam.fx * pc.x() / pc.z() + cam.cx - pixels_cur[i].x();
    const double dv = cam.fy * pc.y() / pc.z() + cam.cy - pixels_cur[i].y();
    sq_err[i] = du * du + dv * dv;
  }
}

RansacResult P3PRansac::estimate(const StereoCamera& cam, const Vec3List& points_ref,
                                 const Vec2List& pixels_cur, const RansacOptions& opt,
                                 const Eigen::Isometry3d* prior_T_ref_cur)
{
  RansacResult res;
  const int n = static_cast<int>(points_ref.size());
  if (n < 4 || pixels_cur.size() != points_ref.size() || !cam.valid())
    return res;

  opengv::bearingVectors_t bearings(static_cast<size_t>(n));
  opengv::points_t points(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
  {
    bearings[static_cast<size_t>(i)] = cam.bearing(pixels_cur[static_cast<size_t>(i)].x(),
                                                   pixels_cur[static_cast<size_t>(i)].y());
    points[static_cast<size_t>(i)] = points_ref[static_cast<size_t>(i)];
  }
  opengv::absolute_pose::CentralAbsoluteAdapter adapter(bearings, points);

  const size_t mid = static_cast<size_t>(n / 2);
  double best_med = std::numeric_limits<double>::max();
  Eigen::Isometry3d best = Eigen::Isometry3d::Identity();
  double w = 0.0;
  const double thr2_cap = opt.threshold_max_px * opt.threshold_max_px;

  auto score = [&](const Eigen::Isometry3d& T) {
    reprojectionErrors(cam, T, points_ref, pixels_cur, err_);
    tmp_ = err_;
    std::nth_element(tmp_.begin(), tmp_.begin() + static_cast<long>(mid), tmp_.end());
    const double med = tmp_[mid];
    if (med < best_med)
    {
      best_med = med;
      best = T;
      int cnt = 0;
      for (double e : err_)
        cnt += e < thr2_cap;
      w = std::max(w, static_cast<double>(cnt) / n);
    }
  };

  if (prior_T_ref_cur)
    score(*prior_T_ref_cur);

  std::uniform_int_distribution<int> pick(0, n - 1);
  int k = opt.max_trials;
  int trials = 0;
  std::vector<int> idx(3);
  while (trials < std::max(k, opt.min_trials) && trials < opt.max_trials)
  {
    ++trials;
    idx[0] = pick(rng_);
    do
      idx[1] = pick(rng_);
    while (idx[1] == idx[0]);
    do
      idx[2] = pick(rng_);
    while (idx[2] == idx[0] || idx[2] == idx[1]);
    // Reject nearly collinear / coincident samples (unstable P3P).
    const Eigen::Vector3d a = points_ref[static_cast<size_t>(idx[1])] - points_ref[static_cast<size_t>(idx[0])];
    const Eigen::Vector3d b = points_ref[static_cast<size_t>(idx[2])] - points_ref[static_cast<size_t>(idx[0])];
    if (a.cross(b).norm() < 1e-6)
      continue;
    const opengv::transformations_t sols = opengv::absolute_pose::p3p_kneip(adapter, idx);
    for (const auto& s : sols)
    {
      if (!s.allFinite())
        continue;
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = s.block<3, 3>(0, 0);
      T.translation() = s.col(3);
      score(T);
    }
    k = trialCount(opt.probability, w, 3, opt.max_trials);
  }
  res.trials = trials;
  if (best_med == std::numeric_limits<double>::max())
    return res;

  // LMedS inlier threshold: robust sigma = 1.4826 (1 + 5/(n-3)) sqrt(median), inliers < 2.5 sigma.
  const double sigma = 1.4826 * (1.0 + 5.0 / std::max(1, n - 3)) * std::sqrt(best_med);
  const double thr = std::clamp(2.5 * sigma, opt.threshold_min_px, opt.threshold_max_px);
  reprojectionErrors(cam, best, points_ref, pixels_cur, err_);
  for (int i = 0; i < n; ++i)
    if (err_[static_cast<size_t>(i)] < thr * thr)
      res.inliers.push_back(i);
  res.T_ref_cur = best;
  res.median_sq_error = best_med;
  res.threshold_px = thr;
  res.ok = res.inliers.size() >= 4;
  return res;
}
}  // namespace assistive_vo
