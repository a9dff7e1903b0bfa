#pragma once
#include <algorithm>
#include <cmath>
#include <vector>
#include <opencv2/core.hpp>
#include "assistive_vo/params.h"

namespace assistive_vo
{
/// Bucketing grid (cols, rows) for an image: cells of about grid_cell_px square, so a wide image
/// (KITTI 1242x375: 16 x 5) is not cut into long flat cells.
inline cv::Size bucketGrid(const VoParams& p, int width, int height)
{
  const double c = p.grid_cell_px > 1.0 ? p.grid_cell_px : 1.0;
  return cv::Size(std::max(1, static_cast<int>(std::lround(width / c))),
                  std::max(1, static_cast<int>(std::lround(height / c))));
}

/// FAST corners with an adaptive threshold (seed 2.2.1.1): each call to detect() moves the
/// threshold one step towards the value that yields VoParams::target_features corners. Corners
/// are bucketed on a grid so they cover the image, and kept away from existing tracks.
class FeatureDetector
{
public:
  explicit FeatureDetector(const VoParams& p = VoParams());
  void setParams(const VoParams& p);

  /// Detects up to `wanted` new corners in `img` (mono8), at least min_feature_distance_px away
  /// from every point in `existing`. Adapts the threshold for the next call.
  std::vector<cv::Point2f> detect(const cv::Mat& img, const std::vector<cv::Point2f>& existing,
                                  int wanted);
  int threshold() const { return threshold_; }
  int lastRawCount() const { return last_raw_; }
  int lastThresholdUsed() const { return last_threshold_; }

private:
  VoParams p_;
  int threshold_;
  int last_raw_ = 0;
  int last_threshold_ = 0;
  std::vector<cv::KeyPoint> kps_;
};
}  // namespace assistive_vo
