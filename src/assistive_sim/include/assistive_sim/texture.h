#pragma once
// Procedural texture tiles (OpenCV), precomputed once per material with a mip pyramid, looked up
// by surface coordinates in metres. ROS-free.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include <opencv2/core.hpp>

#include <assistive_sim/world.h>

namespace assistive_sim
{
class TextureTile
{
public:
  static constexpr int SIZE = 1024;  ///< texels per tile side (power of two)

  /// Generate the tile of a material (deterministic in material.seed).
  explicit TextureTile(const Material& m);
  TextureTile() = default;

  /// Reflectance 0..1 at surface coordinates (u, v) in metres; `footprint` is the size of one
  /// image pixel on the surface (m), choosing the mip level.
  inline float sample(float u, float v, float footprint) const
  {
    // Mip level = floor(log2(footprint / texel) + 0.25), from the float's exponent bits; below one
    // texel level 0 (std::max(q, 1.0f) as a select: the level boundary crosses the image
    // everywhere and a branch on it mispredicts). The renderer's sampleLanes does the same.
    const float q = footprint * inv_texel_ * 1.189207f;
    uint32_t bits;
    std::memcpy(&bits, &q, sizeof bits);
    int l = static_cast<int>((bits >> 23) & 0xFF) - 127;
    l = q < 1.0f ? 0 : l;  // a NaN keeps its exponent (the last level), as std::max did
    l = l < nlevels_ ? l : nlevels_ - 1;
    const Level& L = levels_[l];
    const float x = u * L.inv_texel - 0.5f, y = v * L.inv_texel - 0.5f;
    // floor() by truncation (x, y are texel coordinates, far inside int's range): the same value
    // as std::floor, without its library sequence.
    int ix = static_cast<int>(x), iy = static_cast<int>(y);
    ix -= x < static_cast<float>(ix);
    iy -= y < static_cast<float>(iy);
    const float ax = x - static_cast<float>(ix), ay = y - static_cast<float>(iy);
    const int mask = L.size - 1;
    const int x0 = ix & mask, y0 = iy & mask;
    const int x1 = (x0 + 1) & mask, y1 = (y0 + 1) & mask;
    const uint8_t* r0 = L.data + (y0 << L.shift);
    const uint8_t* r1 = L.data + (y1 << L.shift);
    const float top = r0[x0] + ax * (r0[x1] - r0[x0]);
    const float bot = r1[x0] + ax * (r1[x1] - r1[x0]);
    return (top + ay * (bot - top)) * (1.0f / 255.0f);
  }

  double texelSize() const { return texel_; }
  const cv::Mat& level(int i) const { return mats_[i]; }

  /// One mip level as sample() reads it (the renderer's packet shading reads them directly).
  struct Level
  {
    const uint8_t* data;
    int size;
    int shift;
    float inv_texel;
  };
  float invTexel() const { return inv_texel_; }
  int levelCount() const { return nlevels_; }
  const Level& mipLevel(int l) const { return levels_[l]; }

private:
  void buildLevels();
  std::vector<cv::Mat> mats_;
  std::vector<Level> levels_;
  double texel_ = 0.005;
  float inv_texel_ = 200.0f;
  int nlevels_ = 0;
};

}  // namespace assistive_sim
