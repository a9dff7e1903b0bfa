#pragma once
// Which height bands of a cell's column one frame saw clear (issue 17). Floor returns prove only
// that the floor band is clear: a shelf or a sign at 1.4-1.9 m, out of view once the wearer is
// close and the head pitched down, was freed by the floor under it. A column may be freed only when
// every band of it was seen clear (bits gathered over frames in the TemporalFilter).
// A band is tested at one height above the feet on the cell's centre: it is seen clear when the
// pixel it projects to has depth BEYOND it (the ray passed through), by at least
// max(column_clear_margin, 2 sigma_Z). Out of view, no depth, or depth at / in front of it: not
// clear this frame. A band whose depth ends just in front of it (within column_block_depth) is
// blocked: where the floor below it is seen in the same frame, something overhangs that floor
// (vertical things hide floor and band alike, their edges being vertical). ROS-free.
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <assistive_obstacles/disparity.h>
#include <assistive_obstacles/params.h>

namespace assistive_obstacles
{
/// Test heights above the feet of the `column_bands` bands (evenly spaced from
/// column_band_low to column_band_high); empty when column_bands is 0 (rule off).
std::vector<float> columnBandHeights(const ObstaclesParams& p);

/// Bit i set when at least `min_points` of the sorted heights `h` (n of them, world z) lie in band
/// i: within half the band spacing of its test height (the lowest band reaching down to
/// feet + step_height, the highest up to the top of the heights). An obstacle seen in a band
/// withdraws that band's clearance only: the depth-noise spill of a wall near the floor leaves
/// the head-height band of a cell cleared.
uint8_t columnOccupiedBits(const ObstaclesParams& p, float feet_z, const float* h, int n);

/// All bands' bits (column_bands bits set).
inline uint8_t allBands(int bands) { return bands <= 0 ? 0 : static_cast<uint8_t>((1u << bands) - 1u); }

class ColumnClearance
{
public:
  /// `disp`: the matcher-scale CV_32F disparity of the frame; `m` the full-resolution camera.
  ColumnClearance(const ObstaclesParams& p, const StereoModel& m, const cv::Mat& disp,
                  const Eigen::Isometry3f& T_world_cam, float feet_z);
  /// Bit i set when band i of the column at (x, y) was seen clear this frame.
  uint8_t clearBits(float x, float y) const { return bits(x, y).clear; }
  struct Bits
  {
    uint8_t clear = 0;    ///< the band's pixel has depth beyond it
    uint8_t blocked = 0;  ///< ... in front of it, by more than the clear margin and at most column_block_depth
  };
  /// Both: a band neither clear nor blocked was out of view, without depth, or hidden from afar.
  Bits bits(float x, float y) const;

private:
  const StereoModel& m_;
  const cv::Mat& disp_;
  Eigen::Isometry3f T_cam_world_;
  std::vector<float> z_;  ///< world heights of the bands
  float sx_, sy_, fb_, margin_, k_sigma_, min_z_, max_z_, block_depth_;
};

}  // namespace assistive_obstacles
