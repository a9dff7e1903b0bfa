#include <assistive_sim/texture.h>

#include <algorithm>
#include <random>

#include <opencv2/imgproc.hpp>

namespace assistive_sim
{
namespace
{
/// Tileable value noise: `cells` random values per side, bicubically upsampled to `size`.
cv::Mat tileNoise(int size, int cells, std::mt19937& rng)
{
  cells = std::max(2, std::min(cells, size));
  cv::Mat small(cells, cells, CV_32F);
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  for (int r = 0; r < cells; ++r)
    for (int c = 0; c < cells; ++c) small.at<float>(r, c) = U(rng);
  cv::Mat padded;
  cv::copyMakeBorder(small, padded, 2, 2, 2, 2, cv::BORDER_WRAP);
  const double s = static_cast<double>(size) / cells;
  cv::Mat big;
  cv::resize(padded, big, cv::Size(), s, s, cv::INTER_CUBIC);
  const int off = static_cast<int>(std::round(2 * s));
  return big(cv::Rect(off, off, size, size)).clone();
}

/// Multi-octave noise, zero mean, unit standard deviation.
cv::Mat fractalNoise(int size, int base_cells, int octaves, std::mt19937& rng)
{
  cv::Mat acc = cv::Mat::zeros(size, size, CV_32F);
  float amp = 1.f;
  for (int o = 0; o < octaves; ++o)
  {
    const int cells = base_cells << o;
    if (cells > size) break;
    acc += amp * tileNoise(size, cells, rng);
    amp *= 0.55f;
  }
  cv::Scalar mean, sd;
  cv::meanStdDev(acc, mean, sd);
  acc = (acc - mean[0]) / std::max(sd[0], 1e-6);
  return acc;
}

int cellsFor(double tile_m, double feature_m, int size)
{
  return std::max(2, std::min(size, static_cast<int>(std::round(tile_m / std::max(feature_m, 1e-3)))));
}

void drawPoster(cv::Mat& img, cv::Rect r, std::mt19937& rng, float albedo)
{
  std::uniform_real_distribution<float> U(0.f, 1.f);
  cv::Mat roi = img(r);
  const float bg = std::clamp(albedo + (U(rng) - 0.5f) * 0.5f, 0.1f, 0.95f);
  roi.setTo(bg);
  cv::rectangle(roi, cv::Rect(0, 0, r.width, r.height), cv::Scalar(0.1), std::max(2, r.width / 60));
  const int shapes = 6 + static_cast<int>(U(rng) * 10);
  for (int i = 0; i < shapes; ++i)
  {
    const cv::Point p(static_cast<int>(U(rng) * r.width), static_cast<int>(U(rng) * r.height));
    const float val = U(rng) < 0.5f ? U(rng) * 0.3f : 0.6f + U(rng) * 0.4f;
    const int sz = static_cast<int>((0.05f + 0.25f * U(rng)) * std::min(r.width, r.height));
    switch (i % 4)
    {
      case 0: cv::circle(roi, p, sz, cv::Scalar(val), cv::FILLED, cv::LINE_AA); break;
      case 1: cv::rectangle(roi, cv::Rect(p.x, p.y, sz, sz / 2 + 1), cv::Scalar(val), cv::FILLED); break;
      case 2: cv::line(roi, p, p + cv::Point(sz, sz / 3), cv::Scalar(val), std::max(2, sz / 6), cv::LINE_AA); break;
      default:
      {
        std::string txt;
        for (int k = 0; k < 4; ++k) txt += static_cast<char>('A' + static_cast<int>(U(rng) * 26));
        cv::putText(roi, txt, p, cv::FONT_HERSHEY_DUPLEX, std::max(0.5, r.width / 250.0), cv::Scalar(val),
                    std::max(1, r.width / 120), cv::LINE_AA);
      }
    }
  }
}
}  // namespace

TextureTile::TextureTile(const Material& m)
{
  std::mt19937 rng(m.seed * 2654435761u + 17u);
  const int N = SIZE;
  const float A = static_cast<float>(m.albedo);
  const float C = static_cast<float>(m.contrast);
  cv::Mat img(N, N, CV_32F);
  switch (m.pattern)
  {
    case Pattern::PLAIN:
    {
      texel_ = 0.01;
      const double tile_m = N * texel_;
      cv::Mat n = fractalNoise(N, cellsFor(tile_m, std::max(m.scale, 0.05), N), 4, rng);
      img = A * (1.f + 0.5f * C * n);
      break;
    }
    case Pattern::NOISE:
    {
      texel_ = std::clamp(m.scale / 24.0, 0.002, 0.02);
      const double tile_m = N * texel_;
      cv::Mat n = fractalNoise(N, cellsFor(tile_m, m.scale * 2.0, N), 5, rng);
      img = A * (1.f + 0.6f * C * n);
      break;
    }
    case Pattern::BRICKS:
    {
      texel_ = std::clamp(m.scale / 40.0, 0.002, 0.02);
      const double tile_m = N * texel_;
      const int nb = std::max(1, static_cast<int>(std::round(tile_m / m.scale)));
      const int nr = std::max(2, static_cast<int>(std::round(tile_m / (m.scale * 0.35)))) & ~1;
      const float bw = static_cast<float>(N) / nb, bh = static_cast<float>(N) / nr;
      const float mortar = std::max(1.5f, static_cast<float>(0.01 / texel_));
      std::uniform_real_distribution<float> U(-1.f, 1.f);
      std::vector<float> shade(nb * nr);
      for (auto& s : shade) s = U(rng);
      cv::Mat fine = fractalNoise(N, cellsFor(tile_m, 0.03, N), 3, rng);
      for (int y = 0; y < N; ++y)
      {
        const int row = static_cast<int>(y / bh);
        const float fy = y - row * bh;
        const float shift = (row & 1) ? bw * 0.5f : 0.f;
        for (int x = 0; x < N; ++x)
        {
          float xs = x + shift;
          if (xs >= N) xs -= N;
          const int col = static_cast<int>(xs / bw);
          const float fx = xs - col * bw;
          const bool mort = fy < mortar || fx < mortar;
          const float base = mort ? A * (1.f + 0.5f * C) : A * (1.f + 0.35f * C * shade[row * nb + col]);
          img.at<float>(y, x) = base * (1.f + 0.15f * C * fine.at<float>(y, x));
        }
      }
      break;
    }
    case Pattern::TILES:
    {
      texel_ = std::clamp(m.scale / 60.0, 0.002, 0.02);
      const double tile_m = N * texel_;
      const int nb = std::max(1, static_cast<int>(std::round(tile_m / m.scale)));
      const float bw = static_cast<float>(N) / nb;
      const float grout = std::max(1.5f, static_cast<float>(0.006 / texel_));
      std::uniform_real_distribution<float> U(-1.f, 1.f);
      std::vector<float> shade(nb * nb);
      for (auto& s : shade) s = U(rng);
      cv::Mat fine = fractalNoise(N, cellsFor(tile_m, 0.05, N), 4, rng);
      for (int y = 0; y < N; ++y)
      {
        const int row = static_cast<int>(y / bw);
        const float fy = y - row * bw;
        for (int x = 0; x < N; ++x)
        {
          const int col = static_cast<int>(x / bw);
          const float fx = x - col * bw;
          const bool g = fy < grout || fx < grout;
          const float base = g ? A * (1.f - 0.5f * C) : A * (1.f + 0.2f * C * shade[row * nb + col]);
          img.at<float>(y, x) = base * (1.f + 0.25f * C * fine.at<float>(y, x));
        }
      }
      break;
    }
    case Pattern::POSTERS:
    {
      texel_ = 0.008;
      const double tile_m = N * texel_;
      cv::Mat n = fractalNoise(N, cellsFor(tile_m, 0.3, N), 4, rng);
      img = A * (1.f + 0.03f * n);
      std::uniform_real_distribution<float> U(0.f, 1.f);
      // Number of posters grows with the amount of texture (contrast).
      const int count = static_cast<int>(std::round(1 + C * 10));
      for (int i = 0; i < count; ++i)
      {
        const int w = static_cast<int>((0.35 + 0.5 * U(rng)) / texel_);
        const int h = static_cast<int>((0.4 + 0.5 * U(rng)) / texel_);
        const int x = static_cast<int>(U(rng) * (N - w - 1));
        const int y = static_cast<int>(U(rng) * (N - h - 1));
        drawPoster(img, cv::Rect(x, y, w, h), rng, A);
      }
      break;
    }
  }
  cv::Mat u8;
  img.convertTo(u8, CV_8U, 255.0);
  mats_.push_back(u8);
  buildLevels();
}

void TextureTile::buildLevels()
{
  while (mats_.back().cols > 4)
  {
    cv::Mat half;
    cv::resize(mats_.back(), half, cv::Size(mats_.back().cols / 2, mats_.back().rows / 2), 0, 0, cv::INTER_AREA);
    mats_.push_back(half);
  }
  levels_.clear();
  for (size_t i = 0; i < mats_.size(); ++i)
  {
    Level L;
    L.data = mats_[i].ptr<uint8_t>();
    L.size = mats_[i].cols;
    L.shift = 0;
    while ((1 << L.shift) < L.size) ++L.shift;
    L.inv_texel = static_cast<float>(1.0 / (texel_ * (1 << i)));
    levels_.push_back(L);
  }
  inv_texel_ = static_cast<float>(1.0 / texel_);
  nlevels_ = static_cast<int>(levels_.size());
}

}  // namespace assistive_sim
