#include <assistive_obstacles/disparity.h>

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace assistive_obstacles
{
namespace
{
void toGrey(const cv::Mat& in, cv::Mat& out)
{
  if (in.channels() == 3)
    cv::cvtColor(in, out, cv::COLOR_BGR2GRAY);
  else if (in.channels() == 4)
    cv::cvtColor(in, out, cv::COLOR_BGRA2GRAY);
  else
    out = in;
}

int sgbmMode(const std::string& m)
{
  if (m == "sgbm") return cv::StereoSGBM::MODE_SGBM;
  if (m == "hh") return cv::StereoSGBM::MODE_HH;
  if (m == "hh4") return cv::StereoSGBM::MODE_HH4;
  return cv::StereoSGBM::MODE_SGBM_3WAY;
}
}  // namespace

DisparityEstimator::DisparityEstimator(const ObstaclesParams& p) { setParams(p); }

int DisparityEstimator::numDisparities() const
{
  const int n = static_cast<int>(std::ceil(params_.max_disparity * params_.disparity_scale / 16.0)) * 16;
  return std::max(16, n);
}

void DisparityEstimator::setParams(const ObstaclesParams& p)
{
  params_ = p;
  const int nd = numDisparities();
  const int bs = params_.block_size | 1;
  if (params_.disparity_method == "bm")
  {
    auto bm = cv::StereoBM::create(nd, std::max(5, bs));
    bm->setUniquenessRatio(params_.uniqueness_ratio);
    bm->setSpeckleWindowSize(params_.speckle_window_size);
    bm->setSpeckleRange(params_.speckle_range);
    bm->setDisp12MaxDiff(params_.disp12_max_diff);
    bm->setTextureThreshold(10);
    bm->setPreFilterCap(31);
    matcher_ = bm;
  }
  else
  {
    auto sg = cv::StereoSGBM::create(0, nd, bs, params_.sgbm_p1 * bs * bs, params_.sgbm_p2 * bs * bs, params_.disp12_max_diff, 63,
                                     params_.uniqueness_ratio, params_.speckle_window_size,
                                     params_.speckle_range, sgbmMode(params_.disparity_method));
    matcher_ = sg;
  }
}

bool DisparityEstimator::compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disp) const
{
  disp.release();
  if (left.empty() || right.empty() || left.size() != right.size() || left.depth() != CV_8U ||
      right.depth() != CV_8U)
    return false;
  toGrey(left, l_grey_);
  toGrey(right, r_grey_);
  const double s = params_.disparity_scale;
  const cv::Mat* l = &l_grey_;
  const cv::Mat* r = &r_grey_;
  if (std::abs(s - 1.0) > 1e-6)
  {
    cv::resize(l_grey_, l_small_, cv::Size(), s, s, cv::INTER_AREA);
    cv::resize(r_grey_, r_small_, cv::Size(), s, s, cv::INTER_AREA);
    l = &l_small_;
    r = &r_small_;
  }
  if (l->cols <= numDisparities() + params_.block_size) return false;
  if (params_.texture_max_depth_sigma > 0.0)
  {
    // Horizontal texture per matching block: what constrains a disparity (toPoints).
    cv::Mat gx;
    cv::Sobel(*l, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);  // grey levels per pixel
    cv::multiply(gx, gx, gx);
    const int bs = params_.block_size | 1;
    cv::boxFilter(gx, texture_, CV_32F, cv::Size(bs, bs), cv::Point(-1, -1), false);
    // The pixel noise has gradient energy of its own, different in the two images: in an active
    // camera's images a patch the dots do not reach (a dark doorway, a wall too far) passed as
    // textured, and the matcher's guess there (the nearest edge's disparity) became obstacles.
    // There only the energy above the noise's expected one constrains a match (the Sobel's
    // squared weights sum to 12/64; area averaging to scale s leaves the noise sigma * s), and
    // only when it stands out of the noise. A passive camera's weak natural textures sit at the
    // noise's level, and SGBM's paths match them better than one block's bound says: raw energy.
    if (params_.projected && params_.texture_min_snr > 0.0)
    {
      const double sigma_s = params_.image_noise_sigma * std::min(s, 1.0);
      const double noise_energy = bs * bs * 12.0 / 64.0 * sigma_s * sigma_s;
      texture_.setTo(0.0f, texture_ < params_.texture_min_snr * noise_energy);
      cv::subtract(texture_, cv::Scalar(noise_energy), texture_);
    }
  }
  else
    texture_.release();
  matcher_->compute(*l, *r, disp16_);
  // 16 * disparity in CV_16S; invalid = (mindisp - 1) * 16 < 0.
  disp16_.convertTo(disp, CV_32F, 1.0 / 16.0);
  cv::threshold(disp, disp, 0.0, 0.0, cv::THRESH_TOZERO);  // invalid (negative) -> 0
  // Mark 0 as invalid (-1): zero disparity means infinite depth, useless here.
  disp.setTo(-1.0f, disp <= 0.0f);
  return true;
}

bool DisparityEstimator::computeFullRes(const cv::Mat& left, const cv::Mat& right, cv::Mat& disp) const
{
  cv::Mat small;
  if (!compute(left, right, small)) return false;
  const double s = params_.disparity_scale;
  if (std::abs(s - 1.0) <= 1e-6)
  {
    disp = small;
    return true;
  }
  // Nearest neighbour keeps invalid pixels invalid at edges instead of blending them in.
  cv::resize(small, disp, left.size(), 0, 0, cv::INTER_NEAREST);
  cv::Mat valid = disp > 0.0f;
  disp.convertTo(disp, CV_32F, 1.0 / s);
  disp.setTo(-1.0f, ~valid);
  return true;
}

void DisparityEstimator::toPoints(const cv::Mat& disp, const StereoModel& m, std::vector<Eigen::Vector3f>& points,
                                  std::vector<Eigen::Vector3f>* normals) const
{
  points.clear();
  if (normals) normals->clear();
  if (disp.empty() || disp.type() != CV_32F) return;
  const double sx = static_cast<double>(disp.cols) / m.width;
  const double sy = static_cast<double>(disp.rows) / m.height;
  const float fx = static_cast<float>(m.fx * sx), fy = static_cast<float>(m.fy * sy);
  const float cx = static_cast<float>((m.cx + 0.5) * sx - 0.5), cy = static_cast<float>((m.cy + 0.5) * sy - 0.5);
  const float fb = static_cast<float>(fx * m.baseline);
  if (!(fb > 0.f) || !std::isfinite(fb)) return;
  const float dmin = fb / static_cast<float>(params_.max_depth);
  const float dmax = fb / static_cast<float>(params_.min_depth);
  const int st = std::max(1, params_.point_stride);
  const bool edges = params_.edge_filter > 0.0;
  if (edges)
  {
    const cv::Mat k = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
    cv::dilate(disp, dmax_, k);
    cv::erode(disp, dmin_, k);  // invalid (-1) neighbours make the range large: dropped too
  }
  const float jump = static_cast<float>(params_.edge_filter);
  // Cramer-Rao bound of the disparity from the block's horizontal texture (both images noisy):
  // sigma_d^2 >= 2 sigma_n^2 / sum(g_x^2); its depth error Z^2 sigma_d / fb must stay below the limit.
  const bool texture_check = params_.texture_max_depth_sigma > 0.0 && texture_.size() == disp.size();
  const float tex_limit = static_cast<float>(params_.texture_max_depth_sigma);
  const float two_noise2 = static_cast<float>(2.0 * params_.image_noise_sigma * params_.image_noise_sigma);
  // second difference over the normal's stencil: beyond this the pixel is on an edge
  const float normal_max_curvature = static_cast<float>(edges ? params_.edge_filter : 0.5);
  points.reserve(static_cast<size_t>(disp.rows / st) * static_cast<size_t>(disp.cols / st));
  for (int v = 0; v < disp.rows; v += st)
  {
    const float* row = disp.ptr<float>(v);
    const float* hi = edges ? dmax_.ptr<float>(v) : nullptr;
    const float* lo = edges ? dmin_.ptr<float>(v) : nullptr;
    const float yn = (v - cy) / fy;
    for (int u = 0; u < disp.cols; u += st)
    {
      const float d = row[u];
      if (!(d >= dmin && d <= dmax)) continue;
      if (edges && hi[u] - lo[u] > jump) continue;
      const float z = fb / d;
      if (texture_check)
      {
        const float sigma_d = std::sqrt(two_noise2 / std::max(texture_.at<float>(v, u), 1e-6f));
        if (z * z * sigma_d > tex_limit * fb) continue;
      }
      points.emplace_back((u - cx) / fx * z, yn * z, z);
      if (normals) normals->push_back(surfaceNormal(disp, u, v, fx, fy, cx, cy, points.back(), normal_max_curvature));
    }
  }
}

Eigen::Vector3f DisparityEstimator::surfaceNormal(const cv::Mat& disp, int u, int v, float fx, float fy, float cx,
                                                  float cy, const Eigen::Vector3f& X, float max_curvature)
{
  // On a plane n.X = k the disparity is d = (fx B / k) (nx (u - cx) / fx + ny (v - cy) / fy + nz), so
  // n ~ (dd/du, dd/dv fy / fx, (d - dd/du (u - cx) - dd/dv (v - cy)) / fx). Central differences
  // over +-4 px (+-2, +-1 near invalid pixels; a wider stencil averages the matcher's noise).
  const Eigen::Vector3f back = -X.normalized();
  auto at = [&](int x, int y) { return disp.at<float>(y, x); };
  auto diff = [&](int du, int dv, float& g) {
    for (int h = 4; h >= 1; h /= 2)
    {
      const int x0 = u - h * du, y0 = v - h * dv, x1 = u + h * du, y1 = v + h * dv;
      if (x0 < 0 || y0 < 0 || x1 >= disp.cols || y1 >= disp.rows) continue;
      const float a = at(x0, y0), b = at(x1, y1), c = at(u, v);
      if (!(a > 0.f && b > 0.f)) continue;
      // Not planar across the stencil (an object's edge): no normal.
      if (std::abs(a + b - 2.f * c) > max_curvature) return false;
      g = (b - a) / (2.f * h);
      return true;
    }
    return false;
  };
  float gu = 0.f, gv = 0.f;
  if (!diff(1, 0, gu) || !diff(0, 1, gv)) return back;
  const float d = at(u, v);
  Eigen::Vector3f n(gu, gv * fy / fx, (d - gu * (u - cx) - gv * (v - cy)) / fx);
  const float len = n.norm();
  if (!(len > 0.f) || !std::isfinite(len)) return back;
  n /= len;
  return n.dot(X) > 0.f ? Eigen::Vector3f(-n) : n;
}

}  // namespace assistive_obstacles
