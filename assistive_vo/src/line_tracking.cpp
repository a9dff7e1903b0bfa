#include "assistive_vo/line_tracking.h"

#include <algorithm>
#include <cmath>
#include <Eigen/Eigenvalues>
#include <opencv2/video/tracking.hpp>

namespace assistive_vo
{
namespace
{
/// x of the segment's line at row y.
double xAt(const LineSegment& s, double y)
{
  const Eigen::Vector2d d = s.q - s.p;
  return s.p.x() + (y - s.p.y()) * d.x() / d.y();
}

/// The disparities of a stereo segment pair at two rows: in range and consistent along the line.
bool consistentDisparities(double d0, double d1, const LineMatchParams& p)
{
  return std::min(d0, d1) >= p.min_disparity && std::max(d0, d1) <= p.max_disparity &&
         std::abs(d0 - d1) <= p.max_disparity_spread;
}
}  // namespace

std::vector<int> matchStereoSegments(const LineSegments& left, const LineSegments& right, const LineMatchParams& p)
{
  std::vector<int> match(left.size(), -1);
  const double cos_max = std::cos(p.max_angle_deg * M_PI / 180.0);
  for (size_t i = 0; i < left.size(); ++i)
  {
    const LineSegment& L = left[i];
    const Eigen::Vector2d dl = (L.q - L.p).normalized();
    if (std::abs(dl.y()) < p.min_vertical_sin)
      continue;
    const double l0 = std::min(L.p.y(), L.q.y()), l1 = std::max(L.p.y(), L.q.y());
    int best = -1;
    double best_spread = 1e9, second = 1e9;
    for (size_t j = 0; j < right.size(); ++j)
    {
      const LineSegment& R = right[j];
      const Eigen::Vector2d dr = (R.q - R.p).normalized();
      if (std::abs(dl.dot(dr)) < cos_max || std::abs(dr.y()) < p.min_vertical_sin)
        continue;
      if (L.gradient.dot(R.gradient) <= 0)
        continue;  // opposite polarity: the other side of a bar, not the same edge
      const double r0 = std::min(R.p.y(), R.q.y()), r1 = std::max(R.p.y(), R.q.y());
      const double o0 = std::max(l0, r0), o1 = std::min(l1, r1);
      if (o1 - o0 < p.min_row_overlap * std::min(l1 - l0, r1 - r0))
        continue;
      const double d0 = xAt(L, o0) - xAt(R, o0), d1 = xAt(L, o1) - xAt(R, o1);
      if (!consistentDisparities(d0, d1, p))
        continue;
      const double spread = std::abs(d0 - d1);
      // prefer the nearest consistent candidate in x (smallest disparity difference is not a
      // criterion: several parallel edges can be consistent; keep the one with the least spread)
      if (spread < best_spread)
      {
        second = best_spread;
        best_spread = spread;
        best = static_cast<int>(j);
      }
      else
        second = std::min(second, spread);
    }
    if (best >= 0 && second - best_spread > 0.2)
      match[i] = best;
  }
  return match;
}

namespace
{
/// KLT along each segment from `prev` to `next`; `shift_p` / `shift_q` (when not empty): the
/// initial displacement of each segment's ends (interpolated along it), else none.
LineSegments trackSegmentsFrom(cv::InputArray prev, cv::InputArray next, const LineSegments& segs,
                               const std::vector<Eigen::Vector2d>& shift_p, const std::vector<Eigen::Vector2d>& shift_q,
                               const LineMatchParams& p, std::vector<bool>& ok)
{
  LineSegments out(segs.size());
  ok.assign(segs.size(), false);
  if (segs.empty() || prev.empty() || next.empty())
    return out;
  const bool guess = shift_p.size() == segs.size() && shift_q.size() == segs.size();
  const int ns = std::max(2, p.klt_samples);
  std::vector<cv::Point2f> a, b;
  for (size_t i = 0; i < segs.size(); ++i)
    for (int k = 0; k < ns; ++k)
    {
      const double t = (k + 0.5) / ns;
      const Eigen::Vector2d x = segs[i].p + (segs[i].q - segs[i].p) * t;
      a.emplace_back(static_cast<float>(x.x()), static_cast<float>(x.y()));
      if (guess)
      {
        const Eigen::Vector2d y = x + shift_p[i] + (shift_q[i] - shift_p[i]) * t;
        b.emplace_back(static_cast<float>(y.x()), static_cast<float>(y.y()));
      }
    }
  std::vector<uchar> st;
  std::vector<float> err;
  // Points on a straight edge have a nearly rank-1 structure tensor (the aperture problem): OpenCV's
  // default minimum eigenvalue (1e-4) drops most of them; they still move right across the edge,
  // which is all a line needs (sliding along it does not change the line).
  cv::calcOpticalFlowPyrLK(prev, next, a, b, st, err, cv::Size(kLineKltWindow, kLineKltWindow), guess ? 1 : kLineKltLevels,
                           cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01),
                           guess ? cv::OPTFLOW_USE_INITIAL_FLOW : 0, 1e-7);
  for (size_t i = 0; i < segs.size(); ++i)
  {
    std::vector<Eigen::Vector2d> pts;
    std::vector<double> ts;
    for (int k = 0; k < ns; ++k)
    {
      const size_t m = i * static_cast<size_t>(ns) + static_cast<size_t>(k);
      if (st[m])
      {
        pts.emplace_back(b[m].x, b[m].y);
        ts.push_back((k + 0.5) / ns);
      }
    }
    if (static_cast<int>(pts.size()) < p.klt_min_tracked)
      continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& x : pts)
      mean += x;
    mean /= static_cast<double>(pts.size());
    Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
    for (const auto& x : pts)
      C += (x - mean) * (x - mean).transpose();
    C /= static_cast<double>(pts.size());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C);
    const Eigen::Vector2d dir = es.eigenvectors().col(1), nrm = es.eigenvectors().col(0);
    double worst = 0, a0 = 1e300, a1 = -1e300;
    for (const auto& x : pts)
    {
      worst = std::max(worst, std::abs((x - mean).dot(nrm)));
      const double t = (x - mean).dot(dir);
      a0 = std::min(a0, t), a1 = std::max(a1, t);
    }
    if (worst > p.klt_max_residual)
      continue;  // the samples no longer lie on one line: lost (or slid onto another edge)
    // the end points: the original extent, scaled by how far the tracked samples spread
    const double span_prev = (ts.back() - ts.front()) * segs[i].length();
    const double scale = span_prev > 1e-6 ? (a1 - a0) / span_prev : 1.0;
    LineSegment s = segs[i];
    const double half = 0.5 * segs[i].length() * scale;
    Eigen::Vector2d d = dir;
    if (d.dot(segs[i].q - segs[i].p) < 0)
      d = -d;
    const double mid = 0.5 * (a0 + a1);
    s.p = mean + (mid - half) * d;
    s.q = mean + (mid + half) * d;
    s.mean = mean;
    s.covariance = C;
    s.thickness = 2 * worst;
    s.points = static_cast<int>(pts.size());
    out[i] = s;
    ok[i] = true;
  }
  return out;
}

/// Sum of absolute differences between the left strip across the segment at the sampled rows
/// and the right one shifted by d (nearest pixel), for every integer d in [d0, d1].
void sweepCosts(const cv::Mat& left, const cv::Mat& right, const std::vector<cv::Point>& samples, int half_width,
                int d0, int d1, std::vector<double>& cost)
{
  cost.assign(static_cast<size_t>(std::max(0, d1 - d0 + 1)), 1e9);
  for (int d = d0; d <= d1; ++d)
  {
    int sum = 0, n = 0;
    for (const cv::Point& x : samples)
    {
      const uchar* l = left.ptr<uchar>(x.y);
      const uchar* r = right.ptr<uchar>(x.y);
      for (int j = -half_width; j <= half_width; ++j)
      {
        const int xl = x.x + j, xr = xl - d;
        if (xl < 0 || xl >= left.cols || xr < 0 || xr >= right.cols)
          continue;
        sum += std::abs(static_cast<int>(l[xl]) - static_cast<int>(r[xr]));
        ++n;
      }
    }
    if (n >= static_cast<int>(samples.size()) * (half_width + 1))
      cost[static_cast<size_t>(d - d0)] = static_cast<double>(sum) / n;
  }
}

/// The best disparity of a cost curve with a parabola's sub-pixel offset; false when not unique
/// (a minimum 3 px or more away within `margin`) or above `max_cost`.
bool bestDisparity(const std::vector<double>& cost, int d0, double max_cost, double margin, double& d)
{
  if (cost.empty())
    return false;
  const auto it = std::min_element(cost.begin(), cost.end());
  const int k = static_cast<int>(it - cost.begin());
  if (!(*it <= max_cost))
    return false;
  for (int j = 0; j < static_cast<int>(cost.size()); ++j)
    if (std::abs(j - k) >= 3 && cost[static_cast<size_t>(j)] < *it + margin)
      return false;
  double off = 0;
  if (k > 0 && k + 1 < static_cast<int>(cost.size()))
  {
    const double a = cost[static_cast<size_t>(k - 1)], b = *it, c = cost[static_cast<size_t>(k + 1)];
    const double den = a - 2 * b + c;
    if (den > 1e-9)
      off = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
  }
  d = d0 + k + off;
  return true;
}
}  // namespace

void buildLinePyramid(const cv::Mat& image, std::vector<cv::Mat>& pyramid)
{
  cv::buildOpticalFlowPyramid(image, pyramid, cv::Size(kLineKltWindow, kLineKltWindow), kLineKltLevels, true);
}

LineSegments trackSegments(cv::InputArray prev, cv::InputArray next, const LineSegments& segs, const LineMatchParams& p,
                           std::vector<bool>& ok)
{
  return trackSegmentsFrom(prev, next, segs, {}, {}, p, ok);
}

LineSegments sweepStereoSegments(const cv::Mat& left, const cv::Mat& right, const LineSegments& segs,
                                 const LineMatchParams& p, std::vector<bool>& ok, cv::InputArray left_pyr,
                                 cv::InputArray right_pyr)
{
  ok.assign(segs.size(), false);
  LineSegments none(segs.size());
  if (segs.empty() || left.empty() || left.type() != CV_8UC1 || right.type() != CV_8UC1 || left.size() != right.size())
    return none;
  const int d0 = std::max(0, static_cast<int>(std::ceil(p.min_disparity)));
  const int d1 = static_cast<int>(std::floor(p.max_disparity));
  const int rows = std::max(2, p.sweep_rows / 2);
  std::vector<size_t> idx;
  std::vector<Eigen::Vector2d> shift_p, shift_q;
  LineSegments cand;
  std::vector<double> cost;
  std::vector<cv::Point> samples;
  for (size_t i = 0; i < segs.size(); ++i)
  {
    const LineSegment& L = segs[i];
    const Eigen::Vector2d dir = L.q - L.p;
    if (!(std::abs(dir.y()) >= p.min_vertical_sin * dir.norm()))
      continue;  // near-horizontal: no stereo
    // each half of the segment on its own: the disparity of a line is affine along it
    double dh[2];
    bool good = true;
    for (int h = 0; h < 2 && good; ++h)
    {
      samples.clear();
      for (int k = 0; k < rows; ++k)
      {
        const Eigen::Vector2d x = L.p + dir * (0.5 * h + 0.5 * (k + 0.5) / rows);
        const cv::Point px(static_cast<int>(std::lround(x.x())), static_cast<int>(std::lround(x.y())));
        if (px.y >= 0 && px.y < left.rows)
          samples.push_back(px);
      }
      sweepCosts(left, right, samples, p.sweep_half_width, d0, d1, cost);
      good = samples.size() >= 2 && bestDisparity(cost, d0, p.sweep_max_cost, p.sweep_min_margin, dh[h]);
    }
    if (!good || std::abs(dh[0] - dh[1]) > p.max_disparity_spread + 1.0)
      continue;
    // the half-centres (t = 1/4, 3/4) extrapolated to the ends
    const double dp = 1.5 * dh[0] - 0.5 * dh[1], dq = 1.5 * dh[1] - 0.5 * dh[0];
    idx.push_back(i);
    cand.push_back(L);
    shift_p.emplace_back(-dp, 0.0);
    shift_q.emplace_back(-dq, 0.0);
  }
  // sub-pixel: KLT along the segment from the left image into the right one, from the sweep's shift
  std::vector<bool> tracked;
  const bool pyramids = !left_pyr.empty() && !right_pyr.empty();
  const LineSegments found = pyramids ? trackSegmentsFrom(left_pyr, right_pyr, cand, shift_p, shift_q, p, tracked)
                                      : trackSegmentsFrom(left, right, cand, shift_p, shift_q, p, tracked);
  LineSegments out(segs.size());
  const double cos_max = std::cos(p.max_angle_deg * M_PI / 180.0);
  for (size_t c = 0; c < cand.size(); ++c)
  {
    if (!tracked[c])
      continue;
    const LineSegment& L = cand[c];
    const LineSegment& R = found[c];
    // a rectified pair: the same rows, the disparity the sweep found (within 1 px), positive
    const Eigen::Vector2d dr = (R.q - R.p).normalized(), dl = (L.q - L.p).normalized();
    if (std::abs(dr.dot(dl)) < cos_max)
      continue;
    // the right segment's line on the left ends' rows
    const double xr0 = xAt(R, L.p.y()), xr1 = xAt(R, L.q.y());
    const double e0 = L.p.x() - xr0, e1 = L.q.x() - xr1;
    if (std::abs(e0 + shift_p[c].x()) > 1.0 || std::abs(e1 + shift_q[c].x()) > 1.0 || !consistentDisparities(e0, e1, p))
      continue;
    LineSegment s = R;
    // the right segment spans the left one's rows (its ends on the left ends' rows)
    s.p = Eigen::Vector2d(xr0, L.p.y());
    s.q = Eigen::Vector2d(xr1, L.q.y());
    out[idx[c]] = s;
    ok[idx[c]] = true;
  }
  return out;
}
}  // namespace assistive_vo
