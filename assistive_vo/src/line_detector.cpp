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
  cv::Mat E(gray.size(), CV_8U, cv::Scalar(0));
  const int dx[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  const double theta = p_.edge_threshold;
  for (int y = 1; y + 1 < S.rows; ++y)
    for (int x = 1; x + 1 < S.cols; ++x)
    {
      const double s = S.at<float>(y, x);
      if (s < theta)
        continue;  // too weak to be an edge at all
      // eq. 2.16: I = max over the four directions of sigma((S - avg) / max(avg, theta); s, m),
      // an edgel where I > 0.5; the sigmoid is monotonic (s > 0) and 0.5 at m: I > 0.5 exactly
      // when some direction's ratio exceeds m (no exp per pixel: the detector's main cost).
      for (const auto& d : dx)
      {
        const double avg = 0.5 * (S.at<float>(y + d[1], x + d[0]) + S.at<float>(y - d[1], x - d[0]));
        const double r = (s - avg) / std::max(avg, theta);
        if (r > p_.sigmoid_m)
        {
          E.at<uchar>(y, x) = 255;
          break;
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
  const cv::Mat E = edges(gray);
  cv::Mat gx, gy;
  cv::Sobel(gray, gx, CV_32F, 1, 0, 3);
  cv::Sobel(gray, gy, CV_32F, 0, 1, 3);
  const int c = std::max(2, p_.cell);
  int nx = (E.cols + c - 1) / c, ny = (E.rows + c - 1) / c;
  // level 0: one blob per 8x8 cell, kept when thin
  std::vector<std::vector<Blob>> cells(static_cast<size_t>(nx * ny));
  for (int cy = 0; cy < ny; ++cy)
    for (int cx = 0; cx < nx; ++cx)
    {
      Blob b;
      for (int y = cy * c; y < std::min(E.rows, (cy + 1) * c); ++y)
        for (int x = cx * c; x < std::min(E.cols, (cx + 1) * c); ++x)
          if (E.at<uchar>(y, x))
            b.pts.emplace_back(x, y);
      if (static_cast<int>(b.pts.size()) < p_.min_cell_points)
        continue;
      fit(b);
      if (b.thickness <= p_.max_thickness)
        cells[static_cast<size_t>(cy * nx + cx)].push_back(std::move(b));
    }
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
            if (std::abs(blobs[i].dir.dot(blobs[j].dir)) < std::cos(10.0 * M_PI / 180.0) ||
                gapAlong(blobs[i], blobs[j]) > p_.max_gap)
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
