#include "assistive_vo/sparse_stereo.h"
#include <algorithm>
#include <cmath>
#include <limits>

namespace assistive_vo
{
namespace
{
}  // namespace

float SparseStereo::matchOne(const cv::Mat& left, const cv::Mat& right, const cv::Point2f& pt,
                             int max_disparity) const
{
  const int h = std::clamp(p_.stereo_half_window, 1, 15);
  const int w = 2 * h + 1;
  const int u = static_cast<int>(std::lround(pt.x)), v = static_cast<int>(std::lround(pt.y));
  if (u - h < 1 || v - h < 1 || u + h >= left.cols - 2 || v + h >= left.rows - 2)
    return -1.f;
  const int dmax = std::min(max_disparity, u - h - 1);
  const int dmin = std::max(0, static_cast<int>(std::floor(p_.min_disparity_px)));
  if (dmax <= dmin + 1)
    return -1.f;

  // Left patch, and its texture (flat patches never match reliably).
  int lp[32 * 32];
  int sum = 0, sum2 = 0;
  for (int y = 0; y < w; ++y)
  {
    const uint8_t* row = left.ptr<uint8_t>(v - h + y) + (u - h);
    for (int x = 0; x < w; ++x)
    {
      lp[y * w + x] = row[x];
      sum += row[x];
      sum2 += row[x] * row[x];
    }
  }
  const double n = w * w;
  const double var = sum2 / n - (sum / n) * (sum / n);
  if (var < 4.0)
    return -1.f;

  // SAD over the row (costs per disparity kept for the uniqueness test and the parabola), all
  // disparities at once per window pixel: the innermost loop runs over the disparities and
  // vectorises (the same integer sums as window by window, a fifth of the time).
  int costs[1024];
  const int nd = std::min(dmax - dmin + 1, 1024);
  std::fill(costs, costs + nd, 0);
  // (the right row copied reversed into a buffer of its own: a uint8_t pointer may alias the
  // costs, which kept the compiler from vectorising)
  uint8_t rev[1024 + 32];
  for (int y = 0; y < w; ++y)
  {
    const uint8_t* row = right.ptr<uint8_t>(v - h + y) + (u - h - dmin);
    // rev[j] = row[w - 1 - j]: the pixel at window column x and disparity dmin + k is rev[w - 1 - x + k]
    for (int j = 0; j < nd + w - 1; ++j)
      rev[j] = row[w - 1 - j];
    for (int x = 0; x < w; ++x)
    {
      const int l = lp[y * w + x];
      const uint8_t* r = rev + (w - 1 - x);
      for (int k = 0; k < nd; ++k)
        costs[k] += std::abs(l - static_cast<int>(r[k]));
    }
  }
  int best = std::numeric_limits<int>::max(), best_d = -1;
  for (int k = 0; k < nd; ++k)
    if (costs[k] < best)
    {
      best = costs[k];
      best_d = k;
    }
  if (best_d < 0 || best > p_.stereo_max_mean_sad * n)
    return -1.f;
  int second = std::numeric_limits<int>::max();
  for (int k = 0; k < nd; ++k)
    if (std::abs(k - best_d) > 1)
      second = std::min(second, costs[k]);
  if (second != std::numeric_limits<int>::max() && best > p_.stereo_uniqueness * second)
    return -1.f;
  if (best_d == 0 || best_d == nd - 1)
    return -1.f;  // minimum at the edge of the search range: not localised

  // Parabola for the start, then 1-D Lucas-Kanade on the disparity: the left window stays on
  // integer pixels (no interpolation), the right one is sampled between pixels of the same row.
  const double c0 = costs[best_d - 1], c1 = costs[best_d], c2 = costs[best_d + 1];
  const double den = c0 - 2 * c1 + c2;
  double d = dmin + best_d + (den > 1e-9 ? 0.5 * (c0 - c2) / den : 0.0);
  for (int it = 0; it < 6; ++it)
  {
    const double xr0 = u - d - h;
    const int xi = static_cast<int>(std::floor(xr0));
    const double a = xr0 - xi;
    if (xi < 1 || xi + w + 2 >= right.cols)
      return -1.f;
    double jtj = 0, jtr = 0;
    for (int y = 0; y < w; ++y)
    {
      const uint8_t* row = right.ptr<uint8_t>(v - h + y) + xi;
      const int* l = lp + y * w;
      for (int x = 0; x < w; ++x)
      {
        const double ir = (1 - a) * row[x] + a * row[x + 1];
        const double gx = row[x + 1] - row[x];  // exact derivative of the linear interpolant
        // r(d) = I_L - I_R(u - d): dr/dd = +gx
        const double r = l[x] - ir;
        jtj += gx * gx;
        jtr += gx * r;
      }
    }
    if (jtj < 1e-6)
      break;
    const double step = std::clamp(-jtr / jtj, -0.5, 0.5);  // Gauss-Newton on sum r^2
    d += step;
    if (std::abs(step) < 0.005)
      break;
  }
  if (std::abs(d - (dmin + best_d)) > 1.5 || d + offset_ < p_.min_disparity_px)
    return -1.f;
  return static_cast<float>(d + offset_);
}

std::vector<float> SparseStereo::match(const cv::Mat& left, const cv::Mat& right,
                                       const std::vector<cv::Point2f>& pts, double max_disparity) const
{
  std::vector<float> out(pts.size(), -1.f);
  if (left.empty() || right.empty() || left.size() != right.size() || left.type() != CV_8UC1 ||
      right.type() != CV_8UC1)
    return out;
  const int dmax = std::max(2, std::min(static_cast<int>(max_disparity), 1000));
  for (size_t i = 0; i < pts.size(); ++i)
    out[i] = matchOne(left, right, pts[i], dmax);
  return out;
}
}  // namespace assistive_vo
