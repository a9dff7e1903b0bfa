#pragma once
// Line segments for the point+line solver (seed 2.1.3.2, after Chandraker et al. 2009): Sobel
// edges, a non-maximal suppression that keeps the ridges of strong and weak edges (eq. 2.16), and
// divide-and-conquer linking: edgels are grouped per 8x8-pixel cell, a cell's blob is a segment
// when the thickness of its points (their extent across the principal direction, the convex
// hull's width) is small; at each next level 2x2 cells are joined and pairs of segments merged
// while the merged thickness stays within the threshold, until one cell covers the image.
// Each segment keeps its points' mean and covariance. ROS-free (OpenCV, Eigen).
#include <vector>
#include <Eigen/Core>
#include <Eigen/StdVector>
#include <opencv2/core.hpp>

namespace assistive_vo
{
struct LineDetectorParams
{
  double edge_threshold = 20.0;   ///< theta_edge of eq. 2.16 (Sobel magnitude units, 3x3 kernel on 8-bit)
  double sigmoid_m = 0.25;        ///< eq. 2.16 sigmoid centre: an edgel's relative excess over its neighbours
  double sigmoid_s = 0.1;         ///< eq. 2.16 sigmoid scale (the edge map thresholds I at 0.5: r > m, whatever the scale)
  int cell = 8;                   ///< px, first level of the linking
  double max_thickness = 2.0;     ///< px, convex-hull width of a segment's edgels (a slanted step edge leaves a 2-px staircase ridge: about 1.6 px wide)
  double max_gap = 6.0;           ///< px, largest gap along the line between two merged segments
  int min_cell_points = 4;        ///< edgels for a cell's blob to count
  double min_length = 20.0;       ///< px, shorter segments are dropped at the end
};

struct LineSegment
{
  Eigen::Vector2d p, q;            ///< end points (px)
  Eigen::Vector2d mean;            ///< of the edgels
  Eigen::Matrix2d covariance;      ///< of the edgels
  double thickness = 0;            ///< px
  int points = 0;                  ///< edgels
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();  ///< mean Sobel gradient over the edgels (polarity)
  double length() const { return (q - p).norm(); }
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
using LineSegments = std::vector<LineSegment, Eigen::aligned_allocator<LineSegment>>;

class LineDetector
{
public:
  explicit LineDetector(const LineDetectorParams& p = LineDetectorParams()) : p_(p) {}
  /// Edge map (eq. 2.16): 255 where the sigmoid of the suppression ratio exceeds 0.5.
  cv::Mat edges(const cv::Mat& gray) const;
  /// Segments of an 8-bit gray image.
  LineSegments detect(const cv::Mat& gray) const;
  const LineDetectorParams& params() const { return p_; }

private:
  /// Edge map of a Sobel magnitude image (CV_32F).
  cv::Mat edgesOf(const cv::Mat& S) const;
  LineDetectorParams p_;
};
}  // namespace assistive_vo
