#pragma once
#include <vector>
#include <opencv2/core.hpp>
#include "assistive_vo/params.h"

namespace assistive_vo
{
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
