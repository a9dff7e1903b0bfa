#pragma once
// Line segments across a rectified stereo pair and from frame to frame (seed 2.1.3.2: "lines can
// subsequently be tracked one frame to another using the Lucas-Kanade optic flow"). ROS-free.
#include <vector>
#include <opencv2/core.hpp>
#include "assistive_vo/line_detector.h"

namespace assistive_vo
{
struct LineMatchParams
{
  double max_angle_deg = 5.0;      ///< orientation difference
  double min_disparity = 0.5;      ///< px
  double max_disparity = 128.0;    ///< px
  double max_disparity_spread = 1.5; ///< px: disparity at the two shared rows may differ this much
  double min_row_overlap = 0.5;    ///< share of the shorter segment's rows both segments span
  double min_vertical_sin = 0.26;  ///< |dir.y|: near-horizontal segments (within 15 deg) have no stereo
  int klt_samples = 8;             ///< points along the segment tracked by KLT
  int klt_min_tracked = 5;         ///< of them, for the track to count
  double klt_max_residual = 0.7;   ///< px, distance of a tracked sample to the refitted line
};

/// For each left segment the index of its right match, -1 when none (rectified pair: a match
/// covers the same rows, has the same orientation and a positive disparity; the best by
/// disparity consistency, ambiguous candidates within 1 px of each other dropped).
std::vector<int> matchStereoSegments(const LineSegments& left, const LineSegments& right, const LineMatchParams& p);

/// Tracks segments from `prev` to `next` (8-bit images): KLT on `klt_samples` points along each
/// segment, a line refitted through the tracked ones; `ok[i]` false when lost.
LineSegments trackSegments(const cv::Mat& prev, const cv::Mat& next, const LineSegments& segs, const LineMatchParams& p,
                           std::vector<bool>& ok);
}  // namespace assistive_vo
