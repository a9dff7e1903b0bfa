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
  int sweep_half_width = 4;        ///< sweepStereoSegments: px either side of the edge compared
  int sweep_rows = 8;              ///< sweepStereoSegments: rows compared (half in each half of the segment)
  double sweep_max_cost = 25.0;    ///< sweepStereoSegments: mean absolute difference (gray levels) of a match at most
  double sweep_min_margin = 4.0;   ///< sweepStereoSegments: another disparity (3 px or more away) costs at least this more
};

/// The line tracks' KLT window (px) and pyramid levels (trackSegments). A pyramid built with a
/// window at least this and at least these levels serves them (buildLinePyramid, or the points').
constexpr int kLineKltWindow = 15;
constexpr int kLineKltLevels = 3;
/// The KLT pyramid of an 8-bit image for trackSegments / sweepStereoSegments.
void buildLinePyramid(const cv::Mat& image, std::vector<cv::Mat>& pyramid);

/// For each left segment the index of its right match, -1 when none (rectified pair: a match
/// covers the same rows, has the same orientation and a positive disparity; the best by
/// disparity consistency, ambiguous candidates within 1 px of each other dropped).
std::vector<int> matchStereoSegments(const LineSegments& left, const LineSegments& right, const LineMatchParams& p);

/// The right-image segment of each left one without detecting lines in the right image (half the
/// line detector's time): the disparity of each half of the segment by a sweep of the intensity
/// difference across it (nearest pixel, `sweep_*`: unique by `sweep_min_margin`), then KLT along
/// the segment from the left image into the right one from that shift (sub-pixel). `ok[i]` false
/// when near-horizontal, ambiguous, or inconsistent (angle, disparity range and spread).
/// `left_pyr` / `right_pyr`: the images' KLT pyramids when already built (as for trackSegments).
LineSegments sweepStereoSegments(const cv::Mat& left, const cv::Mat& right, const LineSegments& segs,
                                 const LineMatchParams& p, std::vector<bool>& ok,
                                 cv::InputArray left_pyr = cv::noArray(), cv::InputArray right_pyr = cv::noArray());
/// Tracks segments from `prev` to `next` (8-bit images, or their cv::buildOpticalFlowPyramid
/// pyramids built with a window of 15 px or more and 3 levels: not built again): KLT on `klt_samples` points along each
/// segment, a line refitted through the tracked ones; `ok[i]` false when lost.
LineSegments trackSegments(cv::InputArray prev, cv::InputArray next, const LineSegments& segs, const LineMatchParams& p,
                           std::vector<bool>& ok);
}  // namespace assistive_vo
