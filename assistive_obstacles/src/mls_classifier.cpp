#include <assistive_obstacles/mls_classifier.h>

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace assistive_obstacles
{
namespace
{
/// The standard error of the q-quantile h[j] of the sorted heights h[a, b): sqrt(q (1 - q) / n) over
/// the heights' density there, read off the sqrt(n) heights either side (Siddiqui-Bloch-Gastwirth).
/// Local, so a cell holding a curb's edge (two levels) is judged by the level its quantile is on.
float quantileSe(const float* h, int a, int b, int j, double q)
{
  const int n = b - a;
  const int m = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(n)))));
  const int lo = std::max(a, j - m), hi = std::min(b - 1, j + m);
  if (hi <= lo) return 0.f;
  return static_cast<float>(std::sqrt(q * (1.0 - q) * n) * (h[hi] - h[lo]) / (hi - lo));
}

/// How much a cell's standard error grows because its heights are not independent: one match of the
/// disparity matcher (a block_size^2 block at its scale) gives its error to every point of its block,
/// so n heights taken every point_stride pixels hold about n (point_stride / block_size)^2 independent
/// ones. Counted as independent, a plain floor's matching noise (heights spread by centimetres
/// from cell to cell) read as steps a few centimetres high (a generated corridor: 83,000 false step
/// cells, none with the renderer's true depth).
float matchCorrelation(const ObstaclesParams& p)
{
  if (!p.step_se_per_block) return 1.f;
  return std::max(1.f, static_cast<float>(p.block_size | 1) / static_cast<float>(std::max(1, p.point_stride)));
}
}  // namespace

void MlsClassifier::intervals(const float* h, int n, std::vector<HeightInterval>& out) const
{
  out.clear();
  const float cgap = static_cast<float>(params_.cluster_gap);
  const float G = static_cast<float>(params_.gap_height);
  const double trim = std::clamp(params_.thickness_trim, 0.0, 0.45);
  const double gq = std::clamp(params_.ground_quantile, 0.0, 1.0);
  const float se_scale = matchCorrelation(params_);
  int cur_a = -1, cur_b = -1;  // index range [a, b) of the interval being built
  auto flush = [&]() {
    if (cur_a < 0) return;
    const int cnt = cur_b - cur_a;
    const int k = static_cast<int>(std::floor(trim * cnt));
    HeightInterval iv;
    iv.bottom = h[cur_a + k];
    iv.top = h[cur_b - 1 - k];
    const int jm = cur_a + cnt / 2, jg = cur_a + static_cast<int>(std::lround(gq * (cnt - 1)));
    iv.median = h[jm];
    iv.ground = h[jg];
    iv.median_se = quantileSe(h, cur_a, cur_b, jm, 0.5) * se_scale;
    iv.ground_se = quantileSe(h, cur_a, cur_b, jg, gq) * se_scale;
    iv.points = cnt;
    out.push_back(iv);
    cur_a = cur_b = -1;
  };
  int i = 0;
  while (i < n)
  {
    int j = i + 1;
    while (j < n && h[j] - h[j - 1] <= cgap) ++j;
    // sub-cluster [i, j)
    if (j - i >= params_.min_cluster_points)
    {
      if (cur_a >= 0 && h[i] - h[cur_b - 1] >= G) flush();
      if (cur_a < 0) cur_a = i;
      cur_b = j;
    }
    i = j;
  }
  flush();
}

CellKind MlsClassifier::analyse(const float* h, int n, float& ground, bool median, float* ground_se) const
{
  if (n < params_.min_points_per_cell) return CellKind::EMPTY;
  intervals(h, n, scratch_);
  if (scratch_.empty()) return CellKind::EMPTY;
  // Only the lowest interval can touch the wearer: every other one starts more than G above it.
  const HeightInterval& low = scratch_.front();
  ground = median ? low.median : low.ground;
  if (ground_se) *ground_se = median ? low.median_se : low.ground_se;
  if (low.top - low.bottom > static_cast<float>(params_.step_height)) return CellKind::VERTICAL;
  return CellKind::HORIZONTAL;
}

void MlsClassifier::classify(const ElevationMap& map, float feet_z, std::vector<FrameLabel>& labels)
{
  const int cells = map.window().n * map.window().n;
  kind_.assign(cells, CellKind::EMPTY);
  ground_.assign(cells, 0.f);
  ground_se_.assign(cells, 0.f);
  labels.assign(cells, FrameLabel::NONE);
  filled_.assign(cells, 0);
  spill_.assign(cells, 0);
  analyseCells(map, feet_z);
  if (params_.peak_fraction > 0.0)
    dropSpill(map, feet_z);
  labelByEdges(map.window(), labels);
  if (params_.closing_radius > 0)
    closeObstacles(map.window().n, labels);
}

void MlsClassifier::analyseCells(const ElevationMap& map, float feet_z)
{
  const float rise = static_cast<float>(params_.max_surface_rise);
  const float drop = static_cast<float>(params_.max_surface_drop);
  const int cells = map.window().n * map.window().n;
  for (int c = 0; c < cells; ++c)
  {
    const int cnt = map.count(c);
    if (cnt == 0) continue;
    float g = 0.f, se = 0.f;
    CellKind k = analyse(map.heights(c), cnt, g, false, &se);
    // A surface far above the feet (table top, sign seen without the floor under it) or far
    // below them (drop-off) is not walkable.
    if (k == CellKind::HORIZONTAL && (g > feet_z + rise || g < feet_z - drop)) k = CellKind::VERTICAL;
    kind_[c] = k;
    ground_[c] = g;
    ground_se_[c] = se;
  }
}

bool MlsClassifier::holdsDensityPeak(const ElevationMap& map, int lx, int ly) const
{
  const int f = map.fine(), fs = map.fineSide();
  const std::vector<uint16_t>& fc = map.fineCounts();
  const int R = 2;
  for (int fy = ly * f; fy < (ly + 1) * f; ++fy)
    for (int fx = lx * f; fx < (lx + 1) * f; ++fx)
    {
      const int v = fc[static_cast<size_t>(fy) * fs + fx];
      if (v == 0) continue;
      int mx = 0;
      for (int y = std::max(0, fy - R); y <= std::min(fs - 1, fy + R); ++y)
        for (int x = std::max(0, fx - R); x <= std::min(fs - 1, fx + R); ++x)
          mx = std::max<int>(mx, fc[static_cast<size_t>(y) * fs + x]);
      if (v >= params_.peak_fraction * mx) return true;
    }
  return false;
}

void MlsClassifier::dropSpill(const ElevationMap& map, float feet_z)
{
  // Sub-cell check of vertical cells: keep only those holding a local density peak of elevated
  // points (the surface itself), not the tail of a neighbour's depth noise.
  const Window& w = map.window();
  const float rise = static_cast<float>(params_.max_surface_rise);
  const float drop = static_cast<float>(params_.max_surface_drop);
  for (int ly = 0; ly < w.n; ++ly)
    for (int lx = 0; lx < w.n; ++lx)
    {
      const int c = w.index(lx, ly);
      if (kind_[c] != CellKind::VERTICAL || holdsDensityPeak(map, lx, ly)) continue;
      // Re-analyse the cell without its elevated points: the floor under the spill.
      const float* h = map.heights(c);
      int cnt = map.count(c);
      const float elev = feet_z + static_cast<float>(params_.step_height);
      while (cnt > 0 && h[cnt - 1] > elev) --cnt;
      float g = 0.f, se = 0.f;
      // Median: the foot of the obstacle (up to T high) is still in the cell and would lift a higher quantile.
      const CellKind k = cnt >= params_.min_points_per_cell ? analyse(h, cnt, g, true, &se) : CellKind::EMPTY;
      kind_[c] = (k == CellKind::HORIZONTAL && g <= feet_z + rise && g >= feet_z - drop) ? k : CellKind::EMPTY;
      ground_[c] = g;
      ground_se_[c] = se;
      spill_[c] = 1;
    }
}

FrameLabel MlsClassifier::edgeLabel(const Window& w, int lx, int ly) const
{
  const int c = w.index(lx, ly), n = w.n;
  const float T = static_cast<float>(params_.step_height);
  const float smin = static_cast<float>(params_.min_step);
  const int need = params_.min_traversable_edges;
  const float sigmas = static_cast<float>(params_.step_sigmas);
  int compat = 0, unobserved = 0;
  bool step = false, unsure_step = false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
    {
      if (!dx && !dy) continue;
      const int x = lx + dx, y = ly + dy;
      if (x < 0 || y < 0 || x >= n || y >= n)
      {
        ++unobserved;
        continue;
      }
      const int o = w.index(x, y);
      if (kind_[o] == CellKind::EMPTY)
        ++unobserved;
      else if (kind_[o] == CellKind::HORIZONTAL)
      {
        const float d = std::abs(ground_[o] - ground_[c]);
        if (d <= T)
        {
          ++compat;
          // A step only where the heights say so beyond their noise (a far floor's heights spread
          // by centimetres); a difference within it is neither a step nor proof of none.
          const float margin = sigmas * std::sqrt(ground_se_[c] * ground_se_[c] + ground_se_[o] * ground_se_[o]);
          if (d > smin + margin)
            step = true;
          else if (d > smin)
            unsure_step = true;
        }
      }
    }
  if (compat >= need) return step ? FrameLabel::STEP : unsure_step ? FrameLabel::NONE : FrameLabel::FREE;
  if (compat + unobserved >= need) return FrameLabel::NONE;  // short of edges only because neighbours were not seen
  return FrameLabel::OBSTACLE;
}

void MlsClassifier::labelByEdges(const Window& w, std::vector<FrameLabel>& labels) const
{
  // Graph pass: compatible 8-neighbour edges between horizontal cells.
  for (int ly = 0; ly < w.n; ++ly)
    for (int lx = 0; lx < w.n; ++lx)
    {
      const int c = w.index(lx, ly);
      if (kind_[c] == CellKind::EMPTY) continue;
      labels[c] = kind_[c] == CellKind::VERTICAL ? FrameLabel::OBSTACLE : edgeLabel(w, lx, ly);
    }
}

void MlsClassifier::closeObstacles(int n, std::vector<FrameLabel>& labels)
{
  // Morphological closing (dilate then erode) of the obstacle mask.
  const int r = params_.closing_radius, cells = n * n;
  mask_.assign(cells, 0);
  for (int c = 0; c < cells; ++c) mask_[c] = labels[c] == FrameLabel::OBSTACLE ? 255 : 0;
  cv::Mat m(n, n, CV_8U, mask_.data());
  cv::Mat closed;
  const cv::Mat k = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1));
  cv::morphologyEx(m, closed, cv::MORPH_CLOSE, k, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  // The closing fills holes of the depth map between obstacles (seed 4.2.3): cells without a
  // vote this frame. A cell seen as floor this very frame keeps its label.
  for (int c = 0; c < cells; ++c)
    if (closed.data[c] && labels[c] == FrameLabel::NONE)
    {
      labels[c] = FrameLabel::OBSTACLE;
      filled_[c] = 1;
    }
}

}  // namespace assistive_obstacles
