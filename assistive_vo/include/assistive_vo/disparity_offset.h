#pragma once
// Online estimate of a constant disparity offset of the stereo rig: a small rotation of the right
// camera about its vertical axis (published calibration residuals: a few hundredths of a degree)
// shifts every disparity by f * angle, 0.5-1 px at 640 px. Near points barely notice it; far ones
// get their depth scaled by d / (d + offset): the VO's translation comes out several percent too
// long or short, and no motion model can tell. What does tell: one motion must move every tracked
// point from its keyframe 3D position to its current one, near and far alike; with the wrong
// offset the near and far points disagree on the translation.
#include <vector>
#include <Eigen/Dense>
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
class DisparityOffsetEstimator
{
public:
  struct Options
  {
    double range_px = 2.0;        ///< offsets searched, +- (relative to the one applied)
    double step_px = 0.05;        ///< grid step
    int frames_per_update = 25;   ///< frames accumulated before an estimate is given
    double min_translation_m = 0.15;  ///< a frame whose keyframe is nearer carries too little depth change
    int min_points = 15;
    double min_disparity_px = 1.0;  ///< points (after the offset) nearer to infinity are skipped
  };
  /// One stereo observation: pixel in the left image and disparity (as the VO uses it).
  struct Obs
  {
    double u, v, d;
  };
  DisparityOffsetEstimator() = default;
  explicit DisparityOffsetEstimator(const Options& o) : o_(o) {}
  void clear();
  /// One tracked frame: the same points in the keyframe and in the current frame, the rotation
  /// from keyframe to current optical axes (X_cur = R X_kf + t), and the translation's length.
  /// Returns whether the frame was used.
  bool add(const StereoCamera& cam, const std::vector<Obs>& kf, const std::vector<Obs>& cur,
           const Eigen::Matrix3d& R_cur_kf, double translation_m);
  /// After frames_per_update frames: the offset (px) that, added to the disparities, makes the
  /// points agree best (a minimum inside the range, else false); the accumulator starts again.
  bool take(double& offset_px);
  int frames() const { return frames_; }

private:
  Options o_;
  std::vector<double> cost_;
  int frames_ = 0;
};
}  // namespace assistive_vo
