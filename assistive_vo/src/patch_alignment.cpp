#include "assistive_vo/patch_alignment.h"
#include <cmath>
#include <vector>
#include <Eigen/Dense>

namespace assistive_vo
{
namespace
{
inline float bilinear(const cv::Mat& img, float x, float y)
{
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float ax = x - x0, ay = y - y0;
  const uint8_t* r0 = img.ptr<uint8_t>(y0) + x0;
  const uint8_t* r1 = r0 + img.step[0];
  const float top = r0[0] + ax * (r0[1] - r0[0]);
  const float bot = r1[0] + ax * (r1[1] - r1[0]);
  return top + ay * (bot - top);
}
}  // namespace

std::shared_ptr<const KeyframePatch> KeyframePatch::extract(const cv::Mat& img, const cv::Point2f& p, int half,
                                                            float min_eigen_ratio)
{
  const float m = static_cast<float>(half + 2);
  if (img.empty() || img.type() != CV_8UC1 || !(p.x >= m && p.y >= m && p.x < img.cols - m - 1 && p.y < img.rows - m - 1))
    return nullptr;
  auto k = std::make_shared<KeyframePatch>();
  k->half_ = half;
  const int n = 2 * half + 1;
  k->t_.resize(static_cast<size_t>(n * n));
  k->sd_.resize(k->t_.size());
  // the patch with a one-pixel border, sampled once (the central differences below read it: one
  // bilinear sample per pixel instead of five); where p + x + 1 rounds differently from
  // p + (x + 1) in float (a patch across 64, 128, 256, 512 px) the samples are taken as before,
  // so that the result stays the same to the bit
  const int g = n + 2;
  bool exact = true;
  for (int x = -half; x <= half && exact; ++x)
    exact = p.x + x + 1 == p.x + (x + 1) && p.x + x - 1 == p.x + (x - 1) && p.y + x + 1 == p.y + (x + 1) &&
            p.y + x - 1 == p.y + (x - 1);
  std::vector<float> grid(static_cast<size_t>(g * g));
  for (int y = -half - 1, i = 0; y <= half + 1; ++y)
    for (int x = -half - 1; x <= half + 1; ++x, ++i)
      grid[static_cast<size_t>(i)] = bilinear(img, p.x + x, p.y + y);
  const auto at = [&](int x, int y) { return grid[static_cast<size_t>((y + half + 1) * g + x + half + 1)]; };
  const auto dx = [&](int x, int y) {
    return exact ? at(x + 1, y) - at(x - 1, y)
                 : bilinear(img, p.x + x + 1, p.y + y) - bilinear(img, p.x + x - 1, p.y + y);
  };
  const auto dy = [&](int x, int y) {
    return exact ? at(x, y + 1) - at(x, y - 1)
                 : bilinear(img, p.x + x, p.y + y + 1) - bilinear(img, p.x + x, p.y + y - 1);
  };
  double mean = 0;
  for (int y = -half, i = 0; y <= half; ++y)
    for (int x = -half; x <= half; ++x, ++i)
    {
      k->t_[i] = at(x, y);
      mean += k->t_[i];
    }
  mean /= static_cast<double>(k->t_.size());
  Eigen::Matrix<float, 6, 6> H = Eigen::Matrix<float, 6, 6>::Zero();
  double norm2 = 0;
  for (int y = -half, i = 0; y <= half; ++y)
    for (int x = -half; x <= half; ++x, ++i)
    {
      const float gx = 0.5f * dx(x, y);
      const float gy = 0.5f * dy(x, y);
      // parameters: D11 D12 D21 D22 (affine part) d1 d2 (shift), warp x' = (I + D) x + d
      Eigen::Matrix<float, 6, 1> s;
      s << gx * x, gx * y, gy * x, gy * y, gx, gy;
      k->sd_[i] = s;
      for (int a = 0; a < 6; ++a)  // the upper triangle (H is symmetric)
        for (int b = a; b < 6; ++b)
          H(a, b) += s(a) * s(b);
      k->t_[i] -= static_cast<float>(mean);
      norm2 += k->t_[i] * k->t_[i];
    }
  H.triangularView<Eigen::StrictlyLower>() = H.transpose();
  // Flat or one-dimensional texture: the affine warp is not constrained.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<float, 6, 6>> es(H);
  if (!(es.eigenvalues()(0) > min_eigen_ratio * es.eigenvalues()(5)) || norm2 < 1.0)
    return nullptr;
  k->h_inv_ = H.inverse();
  k->t_norm_ = static_cast<float>(std::sqrt(norm2));
  return k;
}

bool KeyframePatch::align(const cv::Mat& img, cv::Point2f& c_io, Eigen::Matrix2f& A_io, int iterations, float* ncc) const
{
  Eigen::Vector2f c(c_io.x, c_io.y);
  Eigen::Matrix2f A = A_io;
  const size_t n = t_.size();
  std::vector<float> w(n);
  for (int it = 0; it < iterations; ++it)
  {
    // Keep 1.5 patch radii from the border (near it the track is about to leave anyway), and never
    // less than the farthest sample from c (+2: bilinear neighbour and margin).
    const float ext = std::max((1.5f * static_cast<float>(half_) + 2.f) * std::max(1.f, A.cwiseAbs().maxCoeff()),
                               static_cast<float>(half_) * A.cwiseAbs().rowwise().sum().maxCoeff() + 2.f);
    if (!(c.x() > ext && c.y() > ext && c.x() < img.cols - ext - 1 && c.y() < img.rows - ext - 1))
      return false;
    double mean = 0;
    for (int y = -half_, i = 0; y <= half_; ++y)
      for (int x = -half_; x <= half_; ++x, ++i)
      {
        const Eigen::Vector2f q = c + A * Eigen::Vector2f(static_cast<float>(x), static_cast<float>(y));
        w[i] = bilinear(img, q.x(), q.y());
        mean += w[i];
      }
    mean /= static_cast<double>(n);
    // Gain/offset normalisation (exposure changes between keyframe and current frame).
    double norm2 = 0;
    for (auto& v : w)
    {
      v -= static_cast<float>(mean);
      norm2 += v * v;
    }
    if (norm2 < 1e-6)
      return false;
    const float g = t_norm_ / static_cast<float>(std::sqrt(norm2));
    Eigen::Matrix<float, 6, 1> b = Eigen::Matrix<float, 6, 1>::Zero();
    double wt = 0;
    for (size_t i = 0; i < n; ++i)
    {
      b += sd_[i] * (g * w[i] - t_[i]);
      wt += w[i] * t_[i];
    }
    const Eigen::Matrix<float, 6, 1> dp = h_inv_ * b;
    // Inverse composition: W <- W o W(dp)^-1, W(dp)(x) = (I + D) x + d.
    Eigen::Matrix2f D;
    D << 1.f + dp(0), dp(1), dp(2), 1.f + dp(3);
    if (std::abs(D.determinant()) < 1e-3f)
      return false;
    const Eigen::Matrix2f A_new = A * D.inverse();
    const Eigen::Vector2f step = A_new * dp.tail<2>();
    c -= step;
    A = A_new;
    if (!c.allFinite() || !A.allFinite())
      return false;
    const float det = A.determinant();
    if (det < 0.25f || det > 4.f)
      return false;
    if (step.norm() < 0.002f)
    {
      if (ncc)
        *ncc = static_cast<float>(wt * g / (t_norm_ * t_norm_));
      c_io = cv::Point2f(c.x(), c.y());
      A_io = A;
      return true;
    }
  }
  return false;
}
}  // namespace assistive_vo
