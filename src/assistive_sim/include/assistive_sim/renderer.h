#pragma once
// Embree 3 ray-casting stereo renderer. ROS-free. Single-threaded by design (the bag generator
// is measured on one core); one instance per thread.
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <assistive_sim/texture.h>
#include <assistive_sim/types.h>
#include <assistive_sim/world.h>

namespace assistive_sim
{
/// Camera / sensor model options (render_bag and the nodelet read these).
struct CameraParams
{
  StereoCalib calib;                 ///< default 640x480, f 500 px, baseline 0.12 m
  double noise_sigma = 2.0;          ///< gray levels, Gaussian pixel noise (0: off)
  double gain = 1.0;                 ///< radiance -> gray level scale (255 * gain)
  double exposure_variation = 0.12;  ///< relative +- slow exposure (gain) change (0: off)
  double exposure_period = 11.0;     ///< s
  double exposure_time = 0.0;        ///< s, motion blur when > 0 (e.g. 0.01)
  uint32_t seed = 1;
};

/// One rendered stereo pair with per-pixel truth.
struct RenderOutput
{
  cv::Mat left, right;              ///< CV_8UC1
  cv::Mat depth_left, depth_right;  ///< CV_32FC1 true depth Z (m) along the optical axis of the
                                    ///< surface whose texture the pixel shows; 0 for sky
  cv::Mat glass_left;               ///< CV_8UC1 255 where the left ray went through glass
};

class StereoRenderer
{
public:
  StereoRenderer(const World& world, const CameraParams& params);
  ~StereoRenderer();
  StereoRenderer(const StereoRenderer&) = delete;
  StereoRenderer& operator=(const StereoRenderer&) = delete;

  /// Render the pair for the left optical frame's pose in the world (z forward, x right, y down).
  /// `stamp` (s) drives the exposure changes, `frame_index` (with the seed) the noise.
  /// `angular_velocity` (rad/s, left optical frame) drives motion blur when exposure_time > 0.
  void render(const Eigen::Isometry3d& T_world_left, double stamp, uint64_t frame_index, RenderOutput& out,
              const Eigen::Vector3d& angular_velocity = Eigen::Vector3d::Zero());

  /// Cast a single ray (world frame); returns hit distance or -1 (tests, the nodelet's probes).
  double castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const;

  const CameraParams& params() const { return params_; }
  size_t triangleCount() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  CameraParams params_;
};

}  // namespace assistive_sim
