#include "assistive_vo/line_detector.h"

#include <algorithm>
#include <cmath>
#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

namespace assistive_vo
{
namespace
{
/// A group of edgels being linked.
struct Blob
{
  std::vector<Eigen::Vector2d> pts;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  Eigen::Vector2d dir = Eigen::Vector2d::UnitX();  ///< principal direction
  double lo = 0, hi = 0;                           ///< extent along dir (from mean)
  double thickness = 0;                            ///< extent across dir
};

void fit(Blob& b)
{
  const double n = static_cast<double>(b.pts.size());
  b.mean.setZero();
  for (const auto& x : b.pts)
    b.mean += x;
  b.mean /= n;
  b.cov.setZero();
  for (const auto& x : b.pts)
    b.cov += (x - b.mean) * (x - b.mean).transpose();
  b.cov /= n;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(b.cov);
  b.dir = es.eigenvectors().col(1);
  const Eigen::Vector2d nrm = es.eigenvectors().col(0);
  double a0 = 1e300, a1 = -1e300, c0 = 1e300, c1 = -1e300;
  for (const auto& x : b.pts)
  {
    const double a = (x - b.mean).dot(b.dir), c = (x - b.mean).dot(nrm);
    a0 = std::min(a0, a), a1 = std::max(a1, a);
    c0 = std::min(c0, c), c1 = std::max(c1, c);
  }
  b.lo = a0, b.hi = a1;
  // width of the points across the line: the convex hull's thickness in that direction
  b.thickness = c1 - c0;
}

/// True when the union of two blobs is surely thicker than `max_thickness`, from their moments
/// alone (no copy, no fit): points spread across a direction with standard deviation sd span at
/// least 2 sd, so 2 sqrt(smallest eigenvalue of the union's covariance) bounds the thickness
/// from below (1 % margin for rounding: the fit decides the cases near the limit, as before).
bool tooThickToMerge(const Blob& a, const Blob& b, double max_thickness)
{
  const double na = static_cast<double>(a.pts.size()), nb = static_cast<double>(b.pts.size()), n = na + nb;
  const Eigen::Vector2d m = (na * a.mean + nb * b.mean) / n;
  const Eigen::Matrix2d M = (na * (a.cov + a.mean * a.mean.transpose()) + nb * (b.cov + b.mean * b.mean.transpose())) / n;
  const Eigen::Matrix2d C = M - m * m.transpose();
  const double tr = C(0, 0) + C(1, 1), det = C(0, 0) * C(1, 1) - C(0, 1) * C(1, 0);
  const double lmin = 0.5 * (tr - std::sqrt(std::max(0.0, tr * tr - 4 * det)));
  return 2.0 * std::sqrt(std::max(0.0, lmin)) > 1.01 * max_thickness + 1e-6;
}

/// Gap along the line between two blobs (0 when they overlap).
double gapAlong(const Blob& a, const Blob& b)
{
  const double b0 = (b.mean - a.mean).dot(a.dir) + std::min(b.lo * b.dir.dot(a.dir), b.hi * b.dir.dot(a.dir));
  const double b1 = (b.mean - a.mean).dot(a.dir) + std::max(b.lo * b.dir.dot(a.dir), b.hi * b.dir.dot(a.dir));
  return std::max({0.0, b0 - a.hi, a.lo - b1});
}
}  // namespace

cv::Mat LineDetector::edges(const cv::Mat& gray) const
{
  cv::Mat gx, gy, S;
  cv::Sobel(gray, gx, CV_32F, 1, 0, 3);
  cv::Sobel(gray, gy, CV_32F, 0, 1, 3);
  cv::magnitude(gx, gy, S);
  return edgesOf(S);
}

cv::Mat LineDetector::edgesOf(const cv::Mat& S) const
{
  cv::Mat E(S.size(), CV_8U, cv::Scalar(0));
  const double theta = p_.edge_threshold;
  const float theta_f = static_cast<float>(theta), m = static_cast<float>(p_.sigmoid_m);
  for (int y = 1; y + 1 < S.rows; ++y)
  {
    // row pointers (the per-pixel at<> of the first version cost a third of the detector)
    const float* up = S.ptr<float>(y - 1);
    const float* row = S.ptr<float>(y);
    const float* dn = S.ptr<float>(y + 1);
    uchar* e = E.ptr<uchar>(y);
    for (int x = 1; x + 1 < S.cols; ++x)
    {
      const float s = row[x];
      if (s < theta_f)
        continue;  // too weak to be an edge at all
      // eq. 2.16: I = max over the four directions of sigma((S - avg) / max(avg, theta); s, m),
      // an edgel where I > 0.5; the sigmoid is monotonic (s > 0) and 0.5 at m: I > 0.5 exactly
      // when some direction's ratio exceeds m (no exp per pixel: the detector's main cost).
      // Directions: (1, 0), (0, 1), (1, 1), (1, -1), in this order.
      const float pairs[4][2] = {{row[x + 1], row[x - 1]}, {dn[x], up[x]}, {dn[x + 1], up[x - 1]}, {up[x + 1], dn[x - 1]}};
      // (s - avg) / max(avg, theta) > m, without the division (the denominator is positive)
      for (const auto& pr : pairs)
      {
        const float avg = 0.5f * (pr[0] + pr[1]);
        if (s - avg > m * std::max(avg, theta_f))
        {
          e[x] = 255;
          break;
        }
      }
    }
  }
  return E;
}

LineSegments LineDetector::detect(const cv::Mat& gray) const
{
  LineSegments out;
  if (gray.empty() || gray.type() != CV_8UC1 || gray.rows < 3 || gray.cols < 3)
    return out;
  // the gradients once, for the edge map and the segments' polarity
  cv::Mat gx, gy, S;
  cv::Sobel(gray, gx, CV_32F, 1, 0, 3);
  cv::Sobel(gray, gy, CV_32F, 0, 1, 3);
  cv::magnitude(gx, gy, S);
  const cv::Mat E = edgesOf(S);
  const int c = std::max(2, p_.cell);
  int nx = (E.cols + c - 1) / c, ny = (E.rows + c - 1) / c;
  // level 0: one blob per 8x8 cell, kept when thin
  std::vector<std::vector<Blob>> cells(static_cast<size_t>(nx * ny));
  {
    // one pass over the edge map, rows in order: each cell's edgels in the same (row-major) order
    // as a scan cell by cell
    std::vector<Blob> blob(static_cast<size_t>(nx * ny));
    for (int y = 0; y < E.rows; ++y)
    {
      const uchar* e = E.ptr<uchar>(y);
      Blob* brow = &blob[static_cast<size_t>((y / c) * nx)];
      for (int x = 0; x < E.cols; ++x)
        if (e[x])
          brow[x / c].pts.emplace_back(x, y);
    }
    for (size_t k = 0; k < blob.size(); ++k)
    {
      Blob& b = blob[k];
      if (static_cast<int>(b.pts.size()) < p_.min_cell_points)
        continue;
      fit(b);
      if (b.thickness <= p_.max_thickness)
        cells[k].push_back(std::move(b));
    }
  }
  const double cos_merge = std::cos(10.0 * M_PI / 180.0);
  // next levels: 2x2 cells joined, segments merged pairwise while thin and close along the line
  while (nx > 1 || ny > 1)
  {
    const int mx = (nx + 1) / 2, my = (ny + 1) / 2;
    std::vector<std::vector<Blob>> up(static_cast<size_t>(mx * my));
    for (int cy = 0; cy < ny; ++cy)
      for (int cx = 0; cx < nx; ++cx)
      {
        auto& dst = up[static_cast<size_t>((cy / 2) * mx + cx / 2)];
        for (Blob& b : cells[static_cast<size_t>(cy * nx + cx)])
          dst.push_back(std::move(b));
      }
    for (auto& blobs : up)
    {
      bool merged = true;
      while (merged)
      {
        merged = false;
        for (size_t i = 0; i < blobs.size() && !merged; ++i)
          for (size_t j = i + 1; j < blobs.size() && !merged; ++j)
          {
            if (std::abs(blobs[i].dir.dot(blobs[j].dir)) < cos_merge ||
                gapAlong(blobs[i], blobs[j]) > p_.max_gap || tooThickToMerge(blobs[i], blobs[j], p_.max_thickness))
              continue;
            Blob m;
            m.pts = blobs[i].pts;
            m.pts.insert(m.pts.end(), blobs[j].pts.begin(), blobs[j].pts.end());
            fit(m);
            if (m.thickness <= p_.max_thickness)
            {
              blobs[i] = std::move(m);
              blobs.erase(blobs.begin() + static_cast<long>(j));
              merged = true;
            }
          }
      }
    }
    cells.swap(up);
    nx = mx, ny = my;
  }
  for (const auto& blobs : cells)
    for (const Blob& b : blobs)
    {
      LineSegment s;
      s.p = b.mean + b.lo * b.dir;
      s.q = b.mean + b.hi * b.dir;
      s.mean = b.mean;
      s.covariance = b.cov;
      s.thickness = b.thickness;
      s.points = static_cast<int>(b.pts.size());
      for (const auto& x : b.pts)
        s.gradient += Eigen::Vector2d(gx.at<float>(static_cast<int>(x.y()), static_cast<int>(x.x())),
                                      gy.at<float>(static_cast<int>(x.y()), static_cast<int>(x.x())));
      s.gradient /= static_cast<double>(b.pts.size());
      if (s.length() >= p_.min_length)
        out.push_back(s);
    }
  return out;
}
}  // namespace assistive_vo
