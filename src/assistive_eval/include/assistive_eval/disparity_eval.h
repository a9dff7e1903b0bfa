#pragma once
// Dense-stereo scoring on real image pairs with ground truth (assistive_obstacles' disparity_benchmark
// and its real-data gtest), and the full-resolution SGBM peer they compare against:
// KITTI D1 = % of valid GT px with |err| > 3 px and > 5 % of GT; Middlebury bad-2.0 = % of valid
// GT px with |err| > 2 px. Pixels without an estimate count as errors (no interpolation).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace assistive_eval
{
/// One real pair of the real-data folder's stereo_disparity/ (its README's items 3-5).
struct RealPair
{
  std::string name;     ///< "kitti2015_000005", "middlebury3_teddy_half", "middlebury2003_cones_quarter"
  std::string metric;   ///< "d1" (KITTI) or "bad2" (Middlebury)
  cv::Mat left, right;  ///< CV_8UC1
  cv::Mat gt;           ///< CV_32F disparity, NaN = no ground truth
};

/// The pairs found under `dir` (missing or unreadable ones are skipped, with a reason in `skipped`).
std::vector<RealPair> loadRealPairs(const std::string& dir, std::vector<std::string>* skipped = nullptr);
/// Little-endian grey PFM (rows bottom-to-top); empty on error.
cv::Mat readPfm(const std::string& path);

struct DisparityScore
{
  double d1_pct = 0.0, bad2_pct = 0.0;  ///< % of valid GT px
  double density_pct = 0.0;             ///< % of valid GT px with an estimate
  size_t valid = 0;
};
/// `est`: CV_32F, invalid <= 0; `gt`: CV_32F, NaN = unknown; same size.
DisparityScore scoreDisparity(const cv::Mat& est, const cv::Mat& gt);

/// The peer of the disparity benchmark: full-resolution OpenCV SGBM (MODE_SGBM, block 5, P1/P2
/// 8/32 per block pixel, OpenCV's sample settings). Grey or colour input; returns CV_32F
/// disparity in px, invalid < 0.
cv::Mat peerSgbm(const cv::Mat& left, const cv::Mat& right, int num_disparities);
}  // namespace assistive_eval
