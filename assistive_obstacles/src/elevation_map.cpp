#include <assistive_obstacles/elevation_map.h>

#include <algorithm>
#include <cmath>

namespace assistive_obstacles
{
Window Window::around(double x, double y, double r, double res)
{
  Window w;
  w.res = res;
  w.radius = r;
  w.cx = x;
  w.cy = y;
  const int half = static_cast<int>(std::ceil(r / res)) + 1;
  w.n = 2 * half;
  w.ox = static_cast<int>(std::floor(x / res)) - half + 1;
  w.oy = static_cast<int>(std::floor(y / res)) - half + 1;
  return w;
}

bool Window::localOf(double x, double y, int& lx, int& ly) const
{
  lx = static_cast<int>(std::floor(x / res)) - ox;
  ly = static_cast<int>(std::floor(y / res)) - oy;
  return lx >= 0 && ly >= 0 && lx < n && ly < n;
}

bool Window::inCircle(int lx, int ly) const
{
  const double dx = centerX(lx) - cx, dy = centerY(ly) - cy;
  return dx * dx + dy * dy <= radius * radius;
}

void ElevationMap::build(const std::vector<Eigen::Vector3f>& points, const Window& window, float z_max,
                         float z_elevated)
{
  fine_ = std::max(1, params_.fine_factor);
  const int fs = window.n * fine_;
  fine_count_.assign(static_cast<size_t>(fs) * fs, 0);
  const float finv = static_cast<float>(fine_ / window.res);
  window_ = window;
  const int cells = window.n * window.n;
  raw_count_.assign(cells, 0);
  offset_.assign(cells + 1, 0);
  cell_of_point_.resize(points.size());
  const float inv = static_cast<float>(1.0 / window.res);
  const float r2 = static_cast<float>(window.radius * window.radius);
  const float cx = static_cast<float>(window.cx), cy = static_cast<float>(window.cy);
  binned_ = 0;
  // Pass 1: cell of every point, counts.
  for (size_t i = 0; i < points.size(); ++i)
  {
    const Eigen::Vector3f& p = points[i];
    cell_of_point_[i] = -1;
    if (!(p.z() <= z_max)) continue;  // also rejects NaN
    const float dx = p.x() - cx, dy = p.y() - cy;
    if (!(dx * dx + dy * dy <= r2)) continue;
    const int lx = static_cast<int>(std::floor(p.x() * inv)) - window.ox;
    const int ly = static_cast<int>(std::floor(p.y() * inv)) - window.oy;
    if (lx < 0 || ly < 0 || lx >= window.n || ly >= window.n) continue;
    const int idx = ly * window.n + lx;
    cell_of_point_[i] = idx;
    ++raw_count_[idx];
    if (p.z() > z_elevated)
    {
      const int fx = std::min(fs - 1, std::max(0, static_cast<int>(std::floor(p.x() * finv)) - window.ox * fine_));
      const int fy = std::min(fs - 1, std::max(0, static_cast<int>(std::floor(p.y() * finv)) - window.oy * fine_));
      uint16_t& fc = fine_count_[static_cast<size_t>(fy) * fs + fx];
      if (fc < 65535) ++fc;
    }
  }
  // Pass 2: prefix sums, scatter heights, sort each cell.
  for (int c = 0; c < cells; ++c) offset_[c + 1] = offset_[c] + raw_count_[c];
  binned_ = static_cast<size_t>(offset_[cells]);
  heights_.resize(binned_);
  fill_.assign(offset_.begin(), offset_.end() - 1);
  for (size_t i = 0; i < points.size(); ++i)
  {
    const int idx = cell_of_point_[i];
    if (idx >= 0) heights_[fill_[idx]++] = points[i].z();
  }
  for (int c = 0; c < cells; ++c)
    if (raw_count_[c] >= params_.min_points_per_cell)
      std::sort(heights_.begin() + offset_[c], heights_.begin() + offset_[c + 1]);
}

}  // namespace assistive_obstacles
