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

bool depthEdgeNear(const cv::Mat& disp, double s, double u, double v, int window, double max_range)
{
  if (disp.empty() || disp.type() != CV_32F || !(s > 0.0) || window <= 1) return false;
  const double us = (u + 0.5) * s - 0.5, vs = (v + 0.5) * s - 0.5;
  const int cu = static_cast<int>(std::lround(us)), cv_ = static_cast<int>(std::lround(vs));
  // The full-resolution half window at the matcher's scale, rounded up.
  const int r = std::max(1, static_cast<int>(std::ceil(0.5 * (window - 1) * s)));
  float lo = 1e9f, hi = -1e9f;
  for (int y = std::max(0, cv_ - r); y <= std::min(disp.rows - 1, cv_ + r); ++y)
  {
    const float* row = disp.ptr<float>(y);
    for (int x = std::max(0, cu - r); x <= std::min(disp.cols - 1, cu + r); ++x)
    {
      const float d = row[x];
      if (!(d > 0.f)) continue;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  }
  return hi - lo > max_range;
}

namespace
{
/// Bilinear samples of `img` (CV_8UC1) on a cols x rows grid of unit steps from (x0, y0) into `out`
/// (row-major); the caller keeps the grid inside the image.
void sampleGrid(const cv::Mat& img, double x0, double y0, int cols, int rows, float* out)
{
  const int ix = static_cast<int>(std::floor(x0)), iy = static_cast<int>(std::floor(y0));
  const float ax = static_cast<float>(x0 - ix), ay = static_cast<float>(y0 - iy);
  const float w00 = (1 - ax) * (1 - ay), w01 = ax * (1 - ay), w10 = (1 - ax) * ay, w11 = ax * ay;
  for (int r = 0; r < rows; ++r)
  {
    const uint8_t* p0 = img.ptr<uint8_t>(iy + r) + ix;
    const uint8_t* p1 = img.ptr<uint8_t>(std::min(img.rows - 1, iy + r + 1)) + ix;
    for (int c = 0; c < cols; ++c)
      out[r * cols + c] = w00 * p0[c] + w01 * p0[c + 1] + w10 * p1[c] + w11 * p1[c + 1];
  }
}
}  // namespace

namespace
{
/// matchDisparity's sub-pixel step from the best integer disparity `d_int`: `a` the zero-mean left
/// window (2h+1 square), `first` the right image's samples at d_int (w + 2 columns, a pixel more
/// each side for the gradient; row stride `stride`): the strip's own columns for the first step.
double refineDisparity(const cv::Mat& right, double u, double v, double d_int, int h, const float* a, const float* first,
                       int stride)
{
  // Sub-pixel: Gauss-Newton on the disparity (one-dimensional Lucas-Kanade on zero-mean windows)
  // from the best integer offset; a parabola through the NCC scores is biased by up to a quarter
  // pixel on an edge.
  const int w = 2 * h + 1, N = w * w;
  double d = d_int;
  float wide[64 * 66];
  const int ww = w + 2;
  for (int it = 0; it < 5; ++it)
  {
    if (it == 0)
    {
      for (int r = 0; r < w; ++r)
        for (int c = 0; c < ww; ++c) wide[r * ww + c] = first[r * stride + c];
    }
    else
      sampleGrid(right, u - d - h - 1, v - h, ww, w, wide);
    // Per-column accumulators (independent lanes: vectorised); float holds 121 terms of grey levels.
    float col_b[66] = {0.f};
    for (int r = 0; r < w; ++r)
      for (int c = 0; c < w; ++c) col_b[c] += wide[r * ww + c + 1];
    double mb = 0.0;
    for (int c = 0; c < w; ++c) mb += col_b[c];
    const float mbf = static_cast<float>(mb / N);
    float col_gb[64] = {0.f}, col_gg[64] = {0.f};
    for (int r = 0; r < w; ++r)
    {
      const float* wr = wide + r * ww;
      const float* ar = a + r * w;
      for (int c = 0; c < w; ++c)
      {
        const float gx = 0.5f * (wr[c + 2] - wr[c]);
        col_gb[c] += gx * (wr[c + 1] - mbf - ar[c]);
        col_gg[c] += gx * gx;
      }
    }
    double gb = 0.0, gg = 0.0;
    for (int c = 0; c < w; ++c)
    {
      gb += col_gb[c];
      gg += col_gg[c];
    }
    if (!(gg > 0.0)) break;
    // b(x) = R(u - d + x): raising d by D moves it to b - D gx.
    const double step = std::clamp(gb / gg, -0.5, 0.5);
    d += step;
    if (std::abs(d - d_int) > 1.0) return -1.0;
    if (std::abs(step) < 0.005) break;
  }
  return d;
}
}  // namespace

double matchDisparity(const cv::Mat& left, const cv::Mat& right, double u, double v, double d0, int window,
                      double search, double min_ncc)
{
  if (left.empty() || right.empty() || left.size() != right.size() || left.type() != CV_8UC1 ||
      right.type() != CV_8UC1 || window < 3)
    return -1.0;
  const int h = window / 2, w = 2 * h + 1, n = static_cast<int>(std::floor(search));
  // The window and every shifted one (a pixel more for the gradient and the sub-pixel steps) inside the images.
  if (u - h < 0 || v - h < 0 || u + h + 1 > left.cols - 1 || v + h + 1 > left.rows - 1 || u - d0 - n - h - 3 < 0 ||
      u - d0 + n + h + 3 > right.cols - 1)
    return -1.0;
  const int N = w * w;
  // One strip of the right image holds every integer offset o = -n..n (disparity d0 + o): the
  // window centred at u - d0 - o starts at strip column 1 + n - o. One column more each side for the gradient.
  const int sw = w + 2 * n + 2;
  float a[64 * 64], strip[64 * 96];
  if (w > 64 || sw > 96) return -1.0;
  sampleGrid(left, u - h, v - h, w, w, a);
  double ma = 0.0;
  for (int i = 0; i < N; ++i) ma += a[i];
  ma /= N;
  double na = 0.0;
  for (int i = 0; i < N; ++i)
  {
    a[i] -= static_cast<float>(ma);
    na += static_cast<double>(a[i]) * a[i];
  }
  na = std::sqrt(na);
  // Texture: at least a grey level of RMS contrast across the window.
  if (!(na > w)) return -1.0;
  sampleGrid(right, u - d0 - n - h - 1, v - h, sw, w, strip);
  // Per strip column its sum and sum of squares (double: the variance is their difference).
  double col_sum[96], col_sq[96];
  for (int c = 0; c < sw; ++c) col_sum[c] = col_sq[c] = 0.0;
  for (int r = 0; r < w; ++r)
    for (int c = 0; c < sw; ++c)
    {
      const double b = strip[r * sw + c];
      col_sum[c] += b;
      col_sq[c] += b * b;
    }
  auto ncc = [&](int col0) {
    double sb = 0.0, sbb = 0.0;
    for (int c = 0; c < w; ++c)
    {
      sb += col_sum[col0 + c];
      sbb += col_sq[col0 + c];
    }
    // The cross term per column, accumulated over the rows (independent lanes: vectorised).
    float acc[64] = {0.f};
    for (int r = 0; r < w; ++r)
    {
      const float* ar = a + r * w;
      const float* br = strip + r * sw + col0;
      for (int c = 0; c < w; ++c) acc[c] += ar[c] * br[c];
    }
    double sab = 0.0;
    for (int c = 0; c < w; ++c) sab += acc[c];
    const double vb = sbb - sb * sb / N;
    return vb > 0.0 ? sab / (na * std::sqrt(vb)) : -1.0;
  };
  int best = 0;
  double best_score = -2.0;
  for (int o = -n; o <= n; ++o)
  {
    const double score = ncc(1 + n - o);
    if (score > best_score)
    {
      best_score = score;
      best = o;
    }
  }
  if (best_score < min_ncc || best == -n || best == n) return -1.0;
  return refineDisparity(right, u, v, d0 + best, h, a, strip + n - best, sw);
}

namespace
{
bool lift(const cv::Mat& disp, const StereoModel& m, const SceneFlowParams& p, const cv::Point2f& px,
          Eigen::Vector3d& out, const cv::Mat* left = nullptr, const cv::Mat* right = nullptr)
{
  const double s = static_cast<double>(disp.cols) / m.width;
  double d = disparityAt(disp, s, px.x, px.y, p.max_disparity_range);
  if (!(d > 0.0)) return false;
  if (p.edge_window > 3 && depthEdgeNear(disp, s, px.x, px.y, p.edge_window, p.max_disparity_range)) return false;
  if (left && right && !right->empty() && p.stereo_search >= 1.0)
  {
    d = matchDisparity(*left, *right, px.x, px.y, d, p.lk_window, p.stereo_search, p.stereo_min_ncc);
    if (!(d > 0.0)) return false;
  }
  const double z = m.fx * m.baseline / d;
  if (z < p.min_depth || z > p.max_depth) return false;
  out = Eigen::Vector3d((px.x - m.cx) * z / m.fx, (px.y - m.cy) * z / m.fy, z);
  return true;
}
}  // namespace

namespace
{
/// The min_distance buckets of a cols x rows image: at most one corner, or one kept track, each.
struct BucketGrid
{
  int cell, gw, gh;
  BucketGrid(int cols, int rows, double min_distance)
    : cell(std::max(1, static_cast<int>(std::lround(min_distance)))), gw((cols + cell - 1) / cell), gh((rows + cell - 1) / cell)
  {
  }
  size_t size() const { return static_cast<size_t>(gw) * gh; }
  cv::Point at(const cv::Point2f& pt) const
  {
    return cv::Point(std::clamp(static_cast<int>(pt.x) / cell, 0, gw - 1), std::clamp(static_cast<int>(pt.y) / cell, 0, gh - 1));
  }
  size_t index(const cv::Point2f& pt) const
  {
    const cv::Point g = at(pt);
    return static_cast<size_t>(g.y) * gw + g.x;
  }
};
}  // namespace

void detectCorners(const cv::Mat& grey, const SceneFlowParams& p, std::vector<cv::KeyPoint>& scratch,
                   std::vector<cv::Point2f>& out, const cv::Mat* disp, const StereoModel* model, const cv::Mat* half,
                   const std::vector<cv::Point2f>* taken)
{
  out.clear();
  scratch.clear();
  const int budget = p.max_features - (taken ? static_cast<int>(taken->size()) : 0);
  if (budget <= 0) return;
  cv::FAST(grey, scratch, p.fast_threshold, true);
  if (p.half_resolution_corners)
  {
    // Close up, a smooth texture is magnified past FAST's 3 px circle (the renderer's and a
    // lens's blur): its corners show at half the resolution.
    cv::Mat own_half;
    if (!half) cv::pyrDown(grey, own_half);
    std::vector<cv::KeyPoint> coarse;
    cv::FAST(half ? *half : own_half, coarse, p.fast_threshold, true);
    for (cv::KeyPoint& k : coarse)
    {
      k.pt = cv::Point2f(2.f * k.pt.x + 0.5f, 2.f * k.pt.y + 0.5f);  // (x + 0.5) 2 - 0.5
      scratch.push_back(k);
    }
  }
  // The strongest corner per min_distance bucket, then the strongest buckets: spread over the image.
  const BucketGrid grid(grey.cols, grey.rows, p.min_distance);
  std::vector<char> bucket_taken(grid.size(), 0);
  if (taken)
    for (const cv::Point2f& pt : *taken) bucket_taken[grid.index(pt)] = 1;
  // Corners in a taken bucket go first (cheap; a textured outdoor scene has thousands); then only
  // corners that can be lifted (depth in range, not on a depth edge) compete for the budget.
  Eigen::Vector3d X;
  scratch.erase(std::remove_if(scratch.begin(), scratch.end(),
                               [&](const cv::KeyPoint& k) {
                                 return bucket_taken[grid.index(k.pt)] ||
                                        (disp && model && !lift(*disp, *model, p, k.pt, X));
                               }),
                scratch.end());
  // Stronger response first, the earlier detection on a tie.
  const auto stronger = [&](int a, int b) {
    return scratch[a].response > scratch[b].response || (scratch[a].response == scratch[b].response && a < b);
  };
  std::vector<int> best(grid.size(), -1);
  for (int i = 0; i < static_cast<int>(scratch.size()); ++i)
  {
    int& b = best[grid.index(scratch[static_cast<size_t>(i)].pt)];
    if (b < 0 || stronger(i, b)) b = i;
  }
  std::vector<int> kept;
  for (const int b : best)
    if (b >= 0) kept.push_back(b);
  if (static_cast<int>(kept.size()) > budget)
  {
    std::sort(kept.begin(), kept.end(), stronger);
    // The budget spread first: the strongest corner of each block of spread_blocks x spread_blocks
    // buckets, then the strongest of the rest. Ranked over the whole image, a textured wall's
    // strong corners took the whole budget from a person's weak ones.
    const int sb = std::max(1, p.spread_blocks);
    const int bw = (grid.gw + sb - 1) / sb;
    std::vector<char> block_used(static_cast<size_t>(bw) * ((grid.gh + sb - 1) / sb), 0);
    const auto blockOf = [&](const cv::Point2f& pt) {
      const cv::Point g = grid.at(pt);
      return static_cast<size_t>(g.y / sb) * bw + g.x / sb;
    };
    if (taken)
      for (const cv::Point2f& pt : *taken) block_used[blockOf(pt)] = 1;
    std::vector<int> first, rest;
    for (const int i : kept)
    {
      char& used = block_used[blockOf(scratch[static_cast<size_t>(i)].pt)];
      (used ? rest : first).push_back(i);
      used = 1;
    }
    first.insert(first.end(), rest.begin(), rest.end());
    first.resize(static_cast<size_t>(budget));
    kept.swap(first);
  }
  std::sort(kept.begin(), kept.end());
  for (const int i : kept) out.push_back(scratch[static_cast<size_t>(i)].pt);
}

void SceneFlowExtractor::trackBack(const std::vector<cv::Mat>& prev_pyr, const cv::Size& win, const cv::TermCriteria& tc)
{
  stb_.assign(p1_.size(), 0);
  // A track that ended within backward_base_px of the prediction starts its way back as near to
  // where it should end (p0): the pyramid's base suffices, and most tracks are on static surfaces.
  // The others (movers, or a way forward that slid) go back through every level.
  for (const bool near : {true, false})
  {
    back_idx_.clear();
    for (size_t i = 0; i < p1_.size(); ++i)
    {
      const cv::Point2f d = p1_[i] - pred_[i];
      const bool base_only = params_.backward_base_px > 0.0 &&
                             d.x * d.x + d.y * d.y <= params_.backward_base_px * params_.backward_base_px;
      if (base_only == near)
        back_idx_.push_back(static_cast<int>(i));
    }
    if (back_idx_.empty()) continue;
    back_from_.clear();
    back_to_.clear();
    for (const int i : back_idx_)
    {
      back_from_.push_back(p1_[static_cast<size_t>(i)]);
      back_to_.push_back(pb_[static_cast<size_t>(i)]);
    }
    cv::calcOpticalFlowPyrLK(pyr_, prev_pyr, back_from_, back_to_, back_st_, err_, win, near ? 0 : params_.lk_levels,
                             tc, cv::OPTFLOW_USE_INITIAL_FLOW);
    for (size_t k = 0; k < back_idx_.size(); ++k)
    {
      const size_t i = static_cast<size_t>(back_idx_[k]);
      pb_[i] = back_to_[k];
      stb_[i] = back_st_[k];
    }
  }
}

void SceneFlowExtractor::reset()
{
  history_.clear();
  kept_px_.clear();
  kept_X_.clear();
  kept_ = 0;
  paired_back_ = 0;
  flow_.clear();
  pixels_.clear();
  detected_ = tracked_ = 0;
}

bool SceneFlowExtractor::predictStarts(const Frame& old, const StereoModel& model, const Eigen::Isometry3d* T_world_cam)
{
  if (!T_world_cam || !old.has_pose) return false;
  const Eigen::Isometry3d T_cur_prev = T_world_cam->inverse() * old.T_world_cam;
  p1_.resize(p0_.size());
  for (size_t i = 0; i < p0_.size(); ++i)
  {
    Eigen::Vector3d X;
    p1_[i] = p0_[i];
    if (static_cast<int>(i) < kept_)
      X = kept_X_[i];
    else if (!lift(old.disp, old.model, params_, p0_[i], X))
      continue;
    const Eigen::Vector3d Y = T_cur_prev * X;
    if (!(Y.z() > 1e-3)) continue;
    p1_[i] = cv::Point2f(static_cast<float>(model.fx * Y.x() / Y.z() + model.cx),
                         static_cast<float>(model.fy * Y.y() / Y.z() + model.cy));
  }
  return true;
}

void SceneFlowExtractor::keepTracked(bool keep, int cols, int rows)
{
  kept_px_.clear();
  kept_X_.clear();
  if (!keep) return;
  // At most one kept track per bucket (tracks converge where the view recedes), the older first.
  const BucketGrid grid(cols, rows, params_.min_distance);
  std::vector<char> used(grid.size(), 0);
  for (size_t i = 0; i < next_px_.size(); ++i)
  {
    char& u = used[grid.index(next_px_[i])];
    if (u) continue;
    u = 1;
    kept_px_.push_back(next_px_[i]);
    kept_X_.push_back(next_X_[i]);
  }
}

const std::vector<SceneFlowPoint>& SceneFlowExtractor::process(const cv::Mat& grey, const cv::Mat& disp,
                                                               const StereoModel& model,
                                                               const Eigen::Isometry3d* T_world_cam,
                                                               const cv::Mat* right)
{
  if (right && (right->empty() || right->size() != grey.size() || right->type() != CV_8UC1)) right = nullptr;
  flow_.clear();
  pixels_.clear();
  detected_ = tracked_ = kept_ = 0;
  next_px_.clear();
  next_X_.clear();
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
  // Tracks kept from the newest frame go on only when it is the one paired with.
  const bool keep = params_.keep_tracks && params_.frames_apart <= 1;
  if (!keep || history_.size() != 1)
  {
    kept_px_.clear();
    kept_X_.clear();
  }
  const bool paired = !history_.empty();
  if (paired)
  {
    const Frame& old = history_.front();
    paired_back_ = static_cast<int>(history_.size());
    const cv::Mat& prev_grey_ = old.grey;
    const std::vector<cv::Mat>& prev_pyr_ = old.pyr;
    const cv::Mat& prev_disp_ = old.disp;
    const StereoModel& prev_model_ = old.model;
    // The pyramid holds the half-resolution image already (levels at even indices, derivatives between).
    // The kept tracks first (their depth there is known), new corners where they left room.
    detectCorners(prev_grey_, params_, keypoints_, fresh_, &prev_disp_, &prev_model_,
                  prev_pyr_.size() > 2 ? &prev_pyr_[2] : nullptr, &kept_px_);
    kept_ = static_cast<int>(kept_px_.size());
    p0_ = kept_px_;
    p0_.insert(p0_.end(), fresh_.begin(), fresh_.end());
    detected_ = static_cast<int>(p0_.size());
    if (!p0_.empty())
    {
      const cv::Size win(params_.lk_window, params_.lk_window);
      const cv::TermCriteria tc(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 10, 0.03);
      // With both poses, each corner starts where the ego-motion puts a static point: on a
      // repeated texture (tiles seen at a grazing angle) Lucas-Kanade from the old pixel can lock
      // onto the next period, the same way at every corner, and a static wall reads as a walker.
      const int flags = predictStarts(old, model, T_world_cam) ? cv::OPTFLOW_USE_INITIAL_FLOW : 0;
      if (flags == 0) p1_ = p0_;  // no poses: no prediction, each track starts at its corner
      pred_ = p1_;               // where the ego-motion puts each corner
      cv::calcOpticalFlowPyrLK(prev_pyr_, pyr_, p0_, p1_, st_, err_, win, params_.lk_levels, tc, flags);
      // The way back starts where the way forward left the prediction: p0 + (p1 - predicted).
      // Started at p0 itself, a track that slid along an edge on the way forward (a direction the
      // window's texture does not pin down: a door jamb over a plain wall, a silhouette) stays
      // at p0 on the way back and passes the check whatever it did forward.
      pb_ = p0_;
      if (params_.fair_backward)
        for (size_t i = 0; i < p0_.size(); ++i) pb_[i] = p0_[i] + (p1_[i] - pred_[i]);
      trackBack(prev_pyr_, win, tc);
      const double max_fb2 = params_.max_fb_error * params_.max_fb_error;
      for (size_t i = 0; i < p0_.size(); ++i)
      {
        if (!st_[i] || !stb_[i]) continue;
        const cv::Point2f e = pb_[i] - p0_[i];
        if (e.x * e.x + e.y * e.y > max_fb2) continue;
        if (p1_[i].x < 0 || p1_[i].y < 0 || p1_[i].x > grey.cols - 1 || p1_[i].y > grey.rows - 1) continue;
        ++tracked_;
        SceneFlowPoint f;
        // Each end's depth: the feature's own stereo match when both right images are there.
        const bool own = right && !old.right.empty();
        if (static_cast<int>(i) < kept_)
          f.prev = kept_X_[i];
        else if (!lift(prev_disp_, prev_model_, params_, p0_[i], f.prev, own ? &prev_grey_ : nullptr,
                       own ? &old.right : nullptr))
          continue;
        if (!lift(disp, model, params_, p1_[i], f.cur, own ? &grey : nullptr, right)) continue;
        flow_.push_back(f);
        pixels_.push_back(p1_[i]);
        next_px_.push_back(p1_[i]);
        next_X_.push_back(f.cur);
      }
    }
  }
  keepTracked(keep, grey.cols, grey.rows);
  Frame f;
  grey.copyTo(f.grey);
  std::swap(f.pyr, pyr_);
  disp.copyTo(f.disp);
  if (right) right->copyTo(f.right);
  f.model = model;
  f.has_pose = T_world_cam != nullptr;
  if (T_world_cam) f.T_world_cam = *T_world_cam;
  history_.push_back(std::move(f));
  while (static_cast<int>(history_.size()) > std::max(1, params_.frames_apart)) history_.pop_front();
  return flow_;
}

}  // namespace assistive_obstacles
