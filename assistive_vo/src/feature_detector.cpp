#include "assistive_vo/feature_detector.h"
#include <algorithm>
#include <opencv2/features2d.hpp>

namespace assistive_vo
{
FeatureDetector::FeatureDetector(const VoParams& p) : p_(p), threshold_(p.fast_threshold) {}

void FeatureDetector::setParams(const VoParams& p)
{
  p_ = p;
  threshold_ = std::clamp(p.fast_threshold, p.fast_threshold_min, p.fast_threshold_max);
}

std::vector<cv::Point2f> FeatureDetector::detect(const cv::Mat& img,
                                                 const std::vector<cv::Point2f>& existing,
                                                 int wanted)
{
  std::vector<cv::Point2f> out;
  if (img.empty() || img.type() != CV_8UC1)
    return out;
  kps_.clear();
  last_threshold_ = threshold_;
  cv::FAST(img, kps_, threshold_, true, cv::FastFeatureDetector::TYPE_9_16);
  last_raw_ = static_cast<int>(kps_.size());

  // Occupancy grid of existing tracks (cell = min distance) to keep new corners apart.
  const double md = std::max(1.0, p_.min_feature_distance_px);
  const int ocw = static_cast<int>(std::ceil(img.cols / md)), och = static_cast<int>(std::ceil(img.rows / md));
  std::vector<uint8_t> occ(static_cast<size_t>(ocw * och), 0);
  auto mark = [&](const cv::Point2f& q) {
    const int cx = static_cast<int>(q.x / md), cy = static_cast<int>(q.y / md);
    for (int y = std::max(0, cy - 1); y <= std::min(och - 1, cy + 1); ++y)
      for (int x = std::max(0, cx - 1); x <= std::min(ocw - 1, cx + 1); ++x)
        occ[static_cast<size_t>(y * ocw + x)] = 1;
  };
  auto occupied = [&](const cv::Point2f& q) {
    const int cx = static_cast<int>(q.x / md), cy = static_cast<int>(q.y / md);
    return occ[static_cast<size_t>(cy * ocw + cx)] != 0;
  };
  for (const auto& q : existing)
    if (q.x >= 0 && q.y >= 0 && q.x < img.cols && q.y < img.rows)
      mark(q);

  // Strongest first, bucketed: at most `per_cell` per grid cell.
  std::sort(kps_.begin(), kps_.end(),
            [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  const cv::Size grid = bucketGrid(p_, img.cols, img.rows);
  const int cells = grid.width * grid.height;
  const int per_cell = std::max(1, (wanted + static_cast<int>(existing.size())) / cells + 1);
  std::vector<int> count(static_cast<size_t>(cells), 0);
  for (const auto& q : existing)
  {
    if (q.x < 0 || q.y < 0 || q.x >= img.cols || q.y >= img.rows)
      continue;
    const int gx = std::min(grid.width - 1, static_cast<int>(q.x * grid.width / img.cols));
    const int gy = std::min(grid.height - 1, static_cast<int>(q.y * grid.height / img.rows));
    ++count[static_cast<size_t>(gy * grid.width + gx)];
  }
  const float b = static_cast<float>(p_.border_px);
  for (const auto& k : kps_)
  {
    if (static_cast<int>(out.size()) >= wanted)
      break;
    const cv::Point2f& q = k.pt;
    if (q.x < b || q.y < b || q.x >= img.cols - b || q.y >= img.rows - b)
      continue;
    const int gx = std::min(grid.width - 1, static_cast<int>(q.x * grid.width / img.cols));
    const int gy = std::min(grid.height - 1, static_cast<int>(q.y * grid.height / img.rows));
    int& c = count[static_cast<size_t>(gy * grid.width + gx)];
    if (c >= per_cell || occupied(q))
      continue;
    ++c;
    mark(q);
    out.push_back(q);
  }

  // Adapt the threshold: too few raw corners -> lower it, far too many -> raise it.
  const int target = std::max(1, p_.target_features);
  if (last_raw_ < target)
    threshold_ -= 2 * p_.fast_threshold_step;
  else if (last_raw_ < target * 2)
    threshold_ -= p_.fast_threshold_step;
  else if (last_raw_ > target * 6)
    threshold_ += p_.fast_threshold_step;
  threshold_ = std::clamp(threshold_, p_.fast_threshold_min, p_.fast_threshold_max);
  return out;
}
}  // namespace assistive_vo
