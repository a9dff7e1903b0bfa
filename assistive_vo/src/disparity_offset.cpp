#include "assistive_vo/disparity_offset.h"
#include <algorithm>
#include <cmath>

namespace assistive_vo
{
void DisparityOffsetEstimator::clear()
{
  cost_.clear();
  frames_ = 0;
}

bool DisparityOffsetEstimator::add(const StereoCamera& cam, const std::vector<Obs>& kf, const std::vector<Obs>& cur,
                                   const Eigen::Matrix3d& R_cur_kf, double translation_m)
{
  const size_t n = std::min(kf.size(), cur.size());
  if (translation_m < o_.min_translation_m || static_cast<int>(n) < o_.min_points || !cam.valid())
    return false;
  const int steps = static_cast<int>(std::lround(o_.range_px / o_.step_px));
  const int ng = 2 * steps + 1;
  // For each offset: the translation that best moves the keyframe points (with the offset) onto
  // their current observations, in pixels (u, v and disparity with the offset: stereo noise is
  // the same in pixels at any depth, so the costs compare across offsets), robust (capped).
  const double fb = cam.fx * cam.baseline;
  std::vector<char> use(n, 0);
  for (size_t i = 0; i < n; ++i)
    use[i] = kf[i].d - o_.range_px >= o_.min_disparity_px && cur[i].d - o_.range_px >= o_.min_disparity_px;
  std::vector<double> c(static_cast<size_t>(ng), 0.0);
  std::vector<Eigen::Vector3d> X(n);
  const double cap = 4.0;  // px^2 per point
  for (int j = 0; j < ng; ++j)
  {
    const double g = (j - steps) * o_.step_px;
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    double sw = 0;
    for (size_t i = 0; i < n; ++i)
    {
      if (!use[i])
        continue;
      X[i] = R_cur_kf * cam.triangulate(kf[i].u, kf[i].v, kf[i].d + g);
      const double wi = (kf[i].d + g) * (kf[i].d + g);
      t += wi * (cam.triangulate(cur[i].u, cur[i].v, cur[i].d + g) - X[i]);
      sw += wi;
    }
    if (sw <= 0)
      return false;
    t /= sw;
    double cost = 0;
    for (int it = 0; it < 4; ++it)
    {
      Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
      Eigen::Vector3d b = Eigen::Vector3d::Zero();
      cost = 0;
      for (size_t i = 0; i < n; ++i)
      {
        if (!use[i])
          continue;
        const Eigen::Vector3d P = X[i] + t;
        if (P.z() < 0.05)
        {
          cost += cap;
          continue;
        }
        const double iz = 1.0 / P.z();
        const Eigen::Vector3d r(cam.fx * P.x() * iz + cam.cx - cur[i].u, cam.fy * P.y() * iz + cam.cy - cur[i].v,
                                fb * iz - (cur[i].d + g));
        const double r2 = r.squaredNorm();
        cost += std::min(r2, cap);
        if (r2 > cap)
          continue;
        Eigen::Matrix3d J;
        J << cam.fx * iz, 0, -cam.fx * P.x() * iz * iz, 0, cam.fy * iz, -cam.fy * P.y() * iz * iz, 0, 0, -fb * iz * iz;
        H += J.transpose() * J;
        b += J.transpose() * r;
      }
      if (it == 3 || H.determinant() <= 1e-12)
        break;
      t -= H.ldlt().solve(b);
    }
    c[static_cast<size_t>(j)] = cost;
  }
  // each frame counts once whatever its number of points (normalised by its best cost); a
  // frame whose points disagree at every offset (an outlier) cannot pull the minimum far
  const double cmin = *std::min_element(c.begin(), c.end());
  if (!(cmin > 0) || !std::isfinite(cmin))
    return false;
  if (cost_.size() != c.size())
    cost_.assign(c.size(), 0.0);
  for (size_t j = 0; j < c.size(); ++j)
    cost_[j] += std::min(c[j] / cmin, 10.0);
  ++frames_;
  return true;
}

bool DisparityOffsetEstimator::take(double& offset_px)
{
  if (frames_ < o_.frames_per_update || cost_.size() < 3)
    return false;
  const auto it = std::min_element(cost_.begin(), cost_.end());
  const int j = static_cast<int>(it - cost_.begin());
  const int steps = static_cast<int>(cost_.size() / 2);
  bool ok = j > 0 && j + 1 < static_cast<int>(cost_.size());
  offset_px = (j - steps) * o_.step_px;
  if (ok)
  {
    const double c0 = cost_[static_cast<size_t>(j - 1)], c1 = cost_[static_cast<size_t>(j)],
                 c2 = cost_[static_cast<size_t>(j + 1)];
    const double den = c0 - 2 * c1 + c2;
    offset_px = ((j - steps) + (den > 1e-12 ? 0.5 * (c0 - c2) / den : 0.0)) * o_.step_px;
  }
  clear();
  return ok;
}
}  // namespace assistive_vo
