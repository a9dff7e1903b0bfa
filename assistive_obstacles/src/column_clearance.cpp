#include <assistive_obstacles/column_clearance.h>

#include <algorithm>
#include <cmath>

namespace assistive_obstacles
{
std::vector<float> columnBandHeights(const ObstaclesParams& p)
{
  std::vector<float> h;
  const int n = std::clamp(p.column_bands, 0, 8);
  for (int i = 0; i < n; ++i)
    h.push_back(static_cast<float>(n == 1 ? p.column_band_high
                                          : p.column_band_low + (p.column_band_high - p.column_band_low) * i / (n - 1)));
  return h;
}

uint8_t columnOccupiedBits(const ObstaclesParams& p, float feet_z, const float* h, int n)
{
  const std::vector<float> b = columnBandHeights(p);
  if (b.empty() || n <= 0) return 0;
  const float half = b.size() > 1 ? 0.5f * (b[1] - b[0]) : 1e9f;
  uint8_t bits = 0;
  for (size_t i = 0; i < b.size(); ++i)
  {
    const float lo = i == 0 ? feet_z + static_cast<float>(p.step_height) : feet_z + b[i] - half;
    const float hi = i + 1 == b.size() ? h[n - 1] + 1.f : feet_z + b[i] + half;
    const int cnt = static_cast<int>(std::lower_bound(h, h + n, hi) - std::lower_bound(h, h + n, lo));
    if (cnt >= std::max(1, p.min_cluster_points)) bits |= static_cast<uint8_t>(1u << i);
  }
  return bits;
}

ColumnClearance::ColumnClearance(const ObstaclesParams& p, const StereoModel& m, const cv::Mat& disp,
                                 const Eigen::Isometry3f& T_world_cam, float feet_z)
  : m_(m), disp_(disp), T_cam_world_(T_world_cam.inverse())
{
  for (const float h : columnBandHeights(p)) z_.push_back(feet_z + h);
  sx_ = static_cast<float>(disp.cols) / m.width;
  sy_ = static_cast<float>(disp.rows) / m.height;
  fb_ = static_cast<float>(m.fx * m.baseline);  // full-resolution px * m
  margin_ = static_cast<float>(p.column_clear_margin);
  // 2 sigma_Z = 2 Z^2 sigma_d / (f B): the measured depth must lie beyond the band by more than that
  k_sigma_ = fb_ > 0.f ? static_cast<float>(2.0 * p.disparity_sigma) / fb_ : 0.f;
  min_z_ = static_cast<float>(p.min_depth);
  max_z_ = static_cast<float>(p.max_depth);
  block_depth_ = static_cast<float>(p.column_block_depth);
}

ColumnClearance::Bits ColumnClearance::bits(float x, float y) const
{
  Bits b;
  if (disp_.empty() || disp_.type() != CV_32F || !(fb_ > 0.f)) return b;
  for (size_t i = 0; i < z_.size(); ++i)
  {
    const Eigen::Vector3f pc = T_cam_world_ * Eigen::Vector3f(x, y, z_[i]);
    if (!(pc.z() >= min_z_ && pc.z() <= max_z_)) continue;
    const float u = (static_cast<float>(m_.fx) * pc.x() / pc.z() + static_cast<float>(m_.cx) + 0.5f) * sx_ - 0.5f;
    const float v = (static_cast<float>(m_.fy) * pc.y() / pc.z() + static_cast<float>(m_.cy) + 0.5f) * sy_ - 0.5f;
    const int iu = static_cast<int>(std::lround(u)), iv = static_cast<int>(std::lround(v));
    if (iu < 0 || iv < 0 || iu >= disp_.cols || iv >= disp_.rows) continue;
    const float d = disp_.at<float>(iv, iu);
    if (!(d > 0.f)) continue;
    const float z = fb_ * sx_ / d;
    const float tol = std::max(margin_, k_sigma_ * pc.z() * pc.z());
    if (z > pc.z() + tol)
      b.clear |= static_cast<uint8_t>(1u << i);
    else if (z < pc.z() - tol && z >= pc.z() - block_depth_)
      b.blocked |= static_cast<uint8_t>(1u << i);
  }
  return b;
}

}  // namespace assistive_obstacles
