#pragma once
// Embree 3 ray-casting stereo renderer. ROS-free. Single-threaded by design (the bag generator
// is measured on one core); one instance per thread.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <assistive_sim/texture.h>
#include <assistive_sim/types.h>
#include <assistive_sim/world.h>

namespace assistive_sim
{
/// The imperfections of a real head-mounted rig (issue 17; README "Camera imperfections" gives the
/// ranges and where they come from). The rendering uses the true (imperfect) rig; the calibration
/// written to the bag (CameraParams::calib) stays the nominal one: what a real pipeline is handed is
/// a calibration with residual errors, while the world is seen through the physical cameras.
/// All zero: the ideal rig.
struct CameraErrors
{
  double baseline_scale = 0.0;  ///< true baseline = calib.baseline * (1 + baseline_scale)
  double focal_scale = 0.0;     ///< true fx, fy = calib.fx, fy * (1 + focal_scale), both cameras
  /// Rotation of the right camera against the nominal (rectified, parallel) rig, rad, about the
  /// left optical frame's x (pitch: vertical misalignment), y (yaw: a disparity offset), z (roll).
  Eigen::Vector3d right_rotation = Eigen::Vector3d::Zero();
  /// Residual radial distortion (normalised image coordinates, both cameras): pixel (x, y) sees the
  /// ray (x, y) * (1 + k1 r^2 + k2 r^4), r^2 = x^2 + y^2 (a barrel residual for k1 > 0).
  double k1 = 0.0, k2 = 0.0;
  /// Rolling shutter: time from the first to the last row (s); row v is exposed at
  /// stamp + (v / (H - 1) - 0.5) * readout (the middle row at the stamp, where the truth is).
  double rolling_shutter_s = 0.0;
  /// Auto-exposure steps: each camera (a side-by-side pair of UVC cameras runs one auto exposure
  /// each) changes its gain by a factor (1 + ae_step)^+-1 at seeded times, on average every
  /// ae_interval_s seconds; the level stays within +-2 steps.
  double ae_step = 0.0, ae_interval_s = 4.0;

  bool any() const;
  /// Values drawn uniformly inside the published ranges (README), deterministic in `seed`; motion
  /// blur (an exposure time) is drawn too and returned in *exposure_time_s when not null.
  static CameraErrors random(uint32_t seed, double* exposure_time_s = nullptr);
  /// One line of JSON: the values applied (for the bag's /sim/camera_errors and the summary).
  std::string json(double exposure_time_s) const;
};

/// An infrared dot-pattern projector beside the left camera, as active stereo cameras have (the
/// RealSense D4xx class, issue 35; README "Pattern projector"). A fixed pattern of dots is cast from
/// the projector's pose: each dot lands on the first surface its ray meets (so what stands in front
/// shadows what lies behind), moves with the head, not with the world, and adds to that surface's
/// radiance in proportion to its albedo and incidence cosine, falling off with distance squared.
/// The scene's own light scales it down (a camera's exposure follows the ambient light): indoors
/// (about 300 lux) the dots stand out to a few metres, in daylight (10,000 lux and more) they are
/// washed out. Only frames rendered with the emitter on (StereoRenderer::setEmitter) show them.
struct ProjectorParams
{
  bool enabled = false;
  /// The projector's centre in the left optical frame (m; x right): between the two imagers, as on
  /// the D4xx, beside the left one. Its axes are the left camera's.
  Eigen::Vector3d offset = Eigen::Vector3d(0.035, 0.0, 0.0);
  double fov_h_deg = 86.0, fov_v_deg = 57.0;  ///< the pattern's field (wider than the cameras' 65 x 51 deg)
  /// Mean spacing of the dots on the projector's image plane at the cameras' focal length (px): a
  /// semi-random (jittered grid) pattern, a few dots in every matching block at half resolution.
  double spacing_px = 5.0;
  double dot_sigma_px = 0.7;  ///< a dot's Gaussian radius in the images (px)
  /// A dot's peak radiance on a white surface facing the projector 1 m away, with the scene lit at
  /// `reference_lux` (the shading's units: a lit white surface is about 1; brighter saturates). A
  /// model choice: a pale wall (albedo 0.75) 3 m away shows its dots about 40 grey levels over it,
  /// 6 m away about 10 (5x the pixel noise).
  double power = 1.8;
  double reference_lux = 300.0;
  double max_range = 8.0;  ///< m; dots further than this are not drawn (well below the noise by then)
  uint32_t pattern_seed = 435;  ///< the pattern is a property of the device: fixed
};

/// The sensor in little light (issue 35): the auto exposure keeps an image's level down to
/// `full_exposure_lux` by exposing longer; below it the exposure is at its longest (a frame's
/// time) and the gain rises as full_exposure_lux / lux, up to `max_gain`; darker still, the image
/// darkens. Gain amplifies the shot noise (a grey level of the base gain is full_well_e / 255
/// electrons) and the read noise: the noise added over the base `noise_sigma` is
/// sqrt((g - 1) S 255 / full_well_e + read_noise_e^2 (g^2 - 1) (255 / full_well_e)^2) grey levels
/// at signal S and gain g. At the shipped worlds' light (300 lux and more) nothing changes.
struct LowLightParams
{
  double full_exposure_lux = 100.0;
  double max_gain = 16.0;      ///< 24 dB
  double full_well_e = 6000.0; ///< a small global-shutter pixel's (3 um class)
  double read_noise_e = 3.0;
  /// The gain (>= 1, before the cap) at an ambient light of `lux`.
  double gainAt(double lux) const { return lux > 0.0 ? std::max(1.0, full_exposure_lux / lux) : max_gain; }
};

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
  CameraErrors errors;               ///< the rig's imperfections (default: none)
  ProjectorParams projector;         ///< the pattern projector (default: none, a passive pair)
  LowLightParams low_light;          ///< gain and noise in little light (the world's `sky.illuminance`)
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
  /// `angular_velocity` (rad/s, left optical frame) drives motion blur when exposure_time > 0 and,
  /// with `linear_velocity` (m/s, world frame), the rolling shutter's per-row poses.
  void render(const Eigen::Isometry3d& T_world_left, double stamp, uint64_t frame_index, RenderOutput& out,
              const Eigen::Vector3d& angular_velocity = Eigen::Vector3d::Zero(),
              const Eigen::Vector3d& linear_velocity = Eigen::Vector3d::Zero());

  /// People (World::people) are rendered where they are at time `t` (s, personAt's clock) in the
  /// following frames; NaN (the default) renders them at each frame's `stamp`. castRay() sees them
  /// where the last render() put them (at construction: t = 0).
  void setPeopleTime(double t);

  /// The projector's emitter for the following frames (ignored without CameraParams::projector).
  void setEmitter(bool on) { emitter_on_ = on; }
  bool emitter() const { return emitter_on_; }
  /// Number of dots in the projector's pattern (0 without a projector).
  size_t dotCount() const;

  /// The auto-exposure gain factor of camera `cam` (0 left, 1 right) at `stamp` (1 without steps).
  double autoExposureGain(int cam, double stamp) const;

  /// Cast a single ray (world frame); returns hit distance or -1 (tests, the nodelet's probes).
  double castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const;

  const CameraParams& params() const { return params_; }
  size_t triangleCount() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  CameraParams params_;
  bool emitter_on_ = false;
};

}  // namespace assistive_sim
