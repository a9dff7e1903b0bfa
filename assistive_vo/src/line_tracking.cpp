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
      if (std::min(d0, d1) < p.min_disparity || std::max(d0, d1) > p.max_disparity)
        continue;
      const double spread = std::abs(d0 - d1);
      if (spread > p.max_disparity_spread)
        continue;
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

LineSegments trackSegments(const cv::Mat& prev, const cv::Mat& next, const LineSegments& segs, const LineMatchParams& p,
                           std::vector<bool>& ok)
{
  LineSegments out(segs.size());
  ok.assign(segs.size(), false);
  if (segs.empty() || prev.empty() || next.empty())
    return out;
  const int ns = std::max(2, p.klt_samples);
  std::vector<cv::Point2f> a, b;
  for (const LineSegment& s : segs)
    for (int k = 0; k < ns; ++k)
    {
      const Eigen::Vector2d x = s.p + (s.q - s.p) * ((k + 0.5) / ns);
      a.emplace_back(static_cast<float>(x.x()), static_cast<float>(x.y()));
    }
  std::vector<uchar> st;
  std::vector<float> err;
  // Points on a straight edge have a nearly rank-1 structure tensor (the aperture problem): OpenCV's
  // default minimum eigenvalue (1e-4) drops most of them; they still move right across the edge,
  // which is all a line needs (sliding along it does not change the line).
  cv::calcOpticalFlowPyrLK(prev, next, a, b, st, err, cv::Size(15, 15), 3,
                           cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01), 0, 1e-7);
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
}  // namespace assistive_vo
