#pragma once
#include <vector>
#include <opencv2/core.hpp>
#include "assistive_vo/params.h"

namespace assistive_vo
{
/// Sparse stereo: for each left feature, a SAD search along the same row of the rectified right
/// image, a uniqueness test, then a 1-D Lucas-Kanade refinement of the disparity to sub-pixel.
/// No dense disparity is computed (seed 2.2.1: only features need 3D).
class SparseStereo
{
public:
  explicit SparseStereo(const VoParams& p = VoParams()) : p_(p) {}
  void setParams(const VoParams& p) { p_ = p; }
  /// Added to every disparity found (a right camera turned about its vertical axis shifts them
  /// all; disparity_offset.h estimates it).
  void setOffset(double px) { offset_ = px; }
  double offset() const { return offset_; }

  /// Disparity (pixels, > 0) for each point, or a negative value where no reliable match exists.
  /// `max_disparity` bounds the search (pixels).
  std::vector<float> match(const cv::Mat& left, const cv::Mat& right,
                           const std::vector<cv::Point2f>& pts, double max_disparity) const;
  /// One point; negative when not matched.
  float matchOne(const cv::Mat& left, const cv::Mat& right, const cv::Point2f& pt,
                 int max_disparity) const;

private:
  VoParams p_;
  double offset_ = 0.0;
};
}  // namespace assistive_vo
