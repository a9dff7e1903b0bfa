#pragma once
// "The tracker recovers within 3 frames once the image is usable again" (issue #5), made
// measurable: an objective, tracker-independent test of whether a frame is usable, and a counter
// of the usable frames spent without tracking. Used by vo_benchmark (key recovery_frames_max).
#include <algorithm>
#include <vector>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

namespace assistive_eval
{
/// Fixed thresholds of the usability test (deliberately not the tracker's parameters).
struct UsableImageCriteria
{
  int fast_threshold = 10;   ///< FAST-9 intensity threshold, non-maximum suppression on
  int min_corners = 20;      ///< corners needed ...
  int grid_cols = 8;         ///< ... spread over at least min_cells cells of this grid
  int grid_rows = 6;
  int min_cells = 4;
  double min_stddev = 4.0;   ///< intensity standard deviation of each image (black / saturated / flat)
};

/// A stereo pair is usable when both images have some contrast and the left image shows at least
/// `min_corners` FAST corners (fixed threshold) in at least `min_cells` grid cells: fewer than
/// that cannot give the dozen well-spread correspondences any pose estimate needs. It depends
/// only on the images, not on the tracker's state, adaptive thresholds or stereo matching.
inline bool stereoPairUsable(const cv::Mat& left, const cv::Mat& right,
                             const UsableImageCriteria& c = UsableImageCriteria())
{
  if (left.empty() || right.empty() || left.type() != CV_8UC1 || right.type() != CV_8UC1)
    return false;
  for (const cv::Mat* m : {&left, &right})
  {
    cv::Scalar mean, sd;
    cv::meanStdDev(*m, mean, sd);
    if (sd[0] < c.min_stddev)
      return false;
  }
  std::vector<cv::KeyPoint> kps;
  cv::FAST(left, kps, c.fast_threshold, true);
  if (static_cast<int>(kps.size()) < c.min_corners)
    return false;
  std::vector<uint8_t> occupied(static_cast<size_t>(c.grid_cols * c.grid_rows), 0);
  for (const auto& k : kps)
  {
    const int gx = std::clamp(static_cast<int>(k.pt.x * c.grid_cols / left.cols), 0, c.grid_cols - 1);
    const int gy = std::clamp(static_cast<int>(k.pt.y * c.grid_rows / left.rows), 0, c.grid_rows - 1);
    occupied[static_cast<size_t>(gy * c.grid_cols + gx)] = 1;
  }
  return std::count(occupied.begin(), occupied.end(), 1) >= c.min_cells;
}

/// Counts, for every run of frames without tracking, the frames of the run that were usable; a
/// run ends at the next tracked frame (or at the end of the sequence). maxUsableInRun() is the
/// recovery figure: how many usable frames the tracker needed to track again (1 = the failing
/// frame itself, tracking again on the next one).
class RecoveryCounter
{
public:
  void add(bool tracking, bool usable)
  {
    if (tracking)
    {
      run_ = 0;
      return;
    }
    if (usable)
      max_ = std::max(max_, ++run_);
  }
  int maxUsableInRun() const { return max_; }

private:
  int run_ = 0, max_ = 0;
};
}  // namespace assistive_eval
