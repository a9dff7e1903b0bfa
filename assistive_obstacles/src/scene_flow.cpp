#include <assistive_obstacles/scene_flow.h>

#include <algorithm>
#include <cmath>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace assistive_obstacles
{
double disparityAt(const cv::Mat& disp, double s, double u, double v, double max_range)
{
  if (disp.empty() || disp.type() != CV_32F || !(s > 0.0)) return -1.0;
  // Full-resolution pixel centre u -> matcher-scale coordinate (u + 0.5) s - 0.5.
  const double us = (u + 0.5) * s - 0.5, vs = (v + 0.5) * s - 0.5;
  const int cu = static_cast<int>(std::lround(us)), cv_ = static_cast<int>(std::lround(vs));
  if (cu < 1 || cv_ < 1 || cu >= disp.cols - 1 || cv_ >= disp.rows - 1) return -1.0;
  float lo = 1e9f, hi = -1e9f;
  for (int dv = -1; dv <= 1; ++dv)
  {
    const float* row = disp.ptr<float>(cv_ + dv);
    for (int du = -1; du <= 1; ++du)
    {
      const float d = row[cu + du];
      if (!(d > 0.f)) return -1.0;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  }
  if (hi - lo > max_range) return -1.0;
  // Bilinear: the 4 neighbours of (us, vs) lie within the checked 3x3.
  const int u0 = static_cast<int>(std::floor(us)), v0 = static_cast<int>(std::floor(vs));
  const double a = us - u0, b = vs - v0;
  const double d = (1 - a) * (1 - b) * disp.at<float>(v0, u0) + a * (1 - b) * disp.at<float>(v0, u0 + 1) +
                   (1 - a) * b * disp.at<float>(v0 + 1, u0) + a * b * disp.at<float>(v0 + 1, u0 + 1);
  return d / s;
}

namespace
{
bool lift(const cv::Mat& disp, const StereoModel& m, const SceneFlowParams& p, const cv::Point2f& px,
          Eigen::Vector3d& out)
{
  const double s = static_cast<double>(disp.cols) / m.width;
  const double d = disparityAt(disp, s, px.x, px.y, p.max_disparity_range);
  if (!(d > 0.0)) return false;
  const double z = m.fx * m.baseline / d;
  if (z < p.min_depth || z > p.max_depth) return false;
  out = Eigen::Vector3d((px.x - m.cx) * z / m.fx, (px.y - m.cy) * z / m.fy, z);
  return true;
}
}  // namespace

void detectCorners(const cv::Mat& grey, const SceneFlowParams& p, std::vector<cv::KeyPoint>& scratch,
                   std::vector<cv::Point2f>& out, const cv::Mat* disp, const StereoModel* model)
{
  out.clear();
  scratch.clear();
  cv::FAST(grey, scratch, p.fast_threshold, true);
  if (disp && model)
  {
    // Only corners that can be lifted (depth in range, not on a depth edge) compete for the budget.
    Eigen::Vector3d X;
    scratch.erase(std::remove_if(scratch.begin(), scratch.end(),
                                 [&](const cv::KeyPoint& k) { return !lift(*disp, *model, p, k.pt, X); }),
                  scratch.end());
  }
  // The strongest corner per min_distance bucket, then the strongest buckets: spread over the image.
  const int cell = std::max(1, static_cast<int>(std::lround(p.min_distance)));
  const int gw = (grey.cols + cell - 1) / cell, gh = (grey.rows + cell - 1) / cell;
  std::vector<int> best(static_cast<size_t>(gw) * gh, -1);
  for (size_t i = 0; i < scratch.size(); ++i)
  {
    const cv::KeyPoint& k = scratch[i];
    const int gx = std::min(gw - 1, static_cast<int>(k.pt.x) / cell), gy = std::min(gh - 1, static_cast<int>(k.pt.y) / cell);
    int& b = best[static_cast<size_t>(gy) * gw + gx];
    if (b < 0 || k.response > scratch[static_cast<size_t>(b)].response ||
        (k.response == scratch[static_cast<size_t>(b)].response && i < static_cast<size_t>(b)))
      b = static_cast<int>(i);
  }
  std::vector<int> kept;
  for (const int b : best)
    if (b >= 0) kept.push_back(b);
  if (static_cast<int>(kept.size()) > p.max_features)
  {
    std::nth_element(kept.begin(), kept.begin() + p.max_features, kept.end(), [&](int a, int b) {
      return scratch[a].response > scratch[b].response || (scratch[a].response == scratch[b].response && a < b);
    });
    kept.resize(static_cast<size_t>(p.max_features));
  }
  std::sort(kept.begin(), kept.end());
  for (const int i : kept) out.push_back(scratch[static_cast<size_t>(i)].pt);
}

void SceneFlowExtractor::reset()
{
  history_.clear();
  paired_back_ = 0;
  flow_.clear();
  pixels_.clear();
  detected_ = tracked_ = 0;
}

const std::vector<SceneFlowPoint>& SceneFlowExtractor::process(const cv::Mat& grey, const cv::Mat& disp,
                                                               const StereoModel& model,
                                                               const Eigen::Isometry3d* T_world_cam)
{
  flow_.clear();
  pixels_.clear();
  detected_ = tracked_ = 0;
  if (grey.empty() || grey.type() != CV_8UC1 || disp.empty() || disp.type() != CV_32F)
  {
    reset();
    return flow_;
  }
  cv::buildOpticalFlowPyramid(grey, pyr_, cv::Size(params_.lk_window, params_.lk_window), params_.lk_levels);
  // Pair with the oldest kept frame (frames_apart back once that many were seen).
  paired_back_ = 0;
  if (!history_.empty() && (history_.front().grey.size() != grey.size() || history_.front().model.width != model.width ||
                            history_.front().model.height != model.height))
    history_.clear();
  const bool paired = !history_.empty();
  if (paired)
  {
    const Frame& old = history_.front();
    paired_back_ = static_cast<int>(history_.size());
    const cv::Mat& prev_grey_ = old.grey;
    const std::vector<cv::Mat>& prev_pyr_ = old.pyr;
    const cv::Mat& prev_disp_ = old.disp;
    const StereoModel& prev_model_ = old.model;
    detectCorners(prev_grey_, params_, keypoints_, p0_, &prev_disp_, &prev_model_);
    detected_ = static_cast<int>(p0_.size());
    if (!p0_.empty())
    {
      const cv::Size win(params_.lk_window, params_.lk_window);
      const cv::TermCriteria tc(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 10, 0.03);
      // With both poses, each corner starts where the ego-motion puts a static point: on a
      // repeated texture (tiles seen at a grazing angle) Lucas-Kanade from the old pixel can lock
      // onto the next period, the same way at every corner, and a static wall reads as a walker.
      int flags = 0;
      if (T_world_cam && old.has_pose)
      {
        const Eigen::Isometry3d T_cur_prev = T_world_cam->inverse() * old.T_world_cam;
        p1_.resize(p0_.size());
        for (size_t i = 0; i < p0_.size(); ++i)
        {
          Eigen::Vector3d X;
          p1_[i] = p0_[i];
          if (!lift(prev_disp_, prev_model_, params_, p0_[i], X)) continue;
          const Eigen::Vector3d Y = T_cur_prev * X;
          if (!(Y.z() > 1e-3)) continue;
          p1_[i] = cv::Point2f(static_cast<float>(model.fx * Y.x() / Y.z() + model.cx),
                               static_cast<float>(model.fy * Y.y() / Y.z() + model.cy));
        }
        flags = cv::OPTFLOW_USE_INITIAL_FLOW;
      }
      cv::calcOpticalFlowPyrLK(prev_pyr_, pyr_, p0_, p1_, st_, err_, win, params_.lk_levels, tc, flags);
      pb_ = p0_;  // initial guess for the way back
      cv::calcOpticalFlowPyrLK(pyr_, prev_pyr_, p1_, pb_, stb_, err_, win, params_.lk_levels, tc,
                               cv::OPTFLOW_USE_INITIAL_FLOW);
      const double max_fb2 = params_.max_fb_error * params_.max_fb_error;
      for (size_t i = 0; i < p0_.size(); ++i)
      {
        if (!st_[i] || !stb_[i]) continue;
        const cv::Point2f e = pb_[i] - p0_[i];
        if (e.x * e.x + e.y * e.y > max_fb2) continue;
        if (p1_[i].x < 0 || p1_[i].y < 0 || p1_[i].x > grey.cols - 1 || p1_[i].y > grey.rows - 1) continue;
        ++tracked_;
        SceneFlowPoint f;
        if (!lift(prev_disp_, prev_model_, params_, p0_[i], f.prev) || !lift(disp, model, params_, p1_[i], f.cur))
          continue;
        flow_.push_back(f);
        pixels_.push_back(p1_[i]);
      }
    }
  }
  Frame f;
  grey.copyTo(f.grey);
  std::swap(f.pyr, pyr_);
  disp.copyTo(f.disp);
  f.model = model;
  f.has_pose = T_world_cam != nullptr;
  if (T_world_cam) f.T_world_cam = *T_world_cam;
  history_.push_back(std::move(f));
  while (static_cast<int>(history_.size()) > std::max(1, params_.frames_apart)) history_.pop_front();
  return flow_;
}

}  // namespace assistive_obstacles
