#pragma once
// Parameters of the visual odometry core. The initializers are the only defaults (STYLE.md 4);
// the nodelet and the benchmark read/override them, README.md lists them.

namespace assistive_vo
{
struct VoParams
{
  // --- FAST detection with adaptive threshold (seed 2.2.1.1) ---
  int fast_threshold = 40;        // start threshold (intensity levels)
  int fast_threshold_min = 5;
  int fast_threshold_max = 120;
  int fast_threshold_step = 4;    // change per replenishment
  int target_features = 250;      // features wanted after a replenishment (400: 15 % less rotational
                                  // drift over 5 seeds x 5 worlds, but 30-50 % more time at p95: README)
  double grid_cell_px = 80.0;     // bucketing grid of about square cells of this side:
                                  // round(width / cell) x round(height / cell) (8 x 6 at 640x480)
  int border_px = 12;             // no features this close to the image border
  double min_feature_distance_px = 12.0;  // new corners this far from existing tracks
  double replenish_ratio = 0.35;  // re-detect when tracks alive < ratio * tracks started
  int min_tracks = 40;            // ... or when fewer than this many tracks are alive
  double replenish_coverage_ratio = 0.8;  // ... or when the tracks hold fewer bucketing-grid cells than
                                          // ratio x the cells held at the keyframe (0 = off)

  // --- sparse stereo along the rectified row ---
  int stereo_half_window = 4;     // SAD window (2h+1)^2
  double min_disparity_px = 0.5;
  int max_disparity_px = 128;
  double stereo_max_mean_sad = 18.0;     // mean absolute difference per pixel
  double stereo_uniqueness = 0.85;       // best cost < uniqueness * second best (outside +-1)
  double min_depth_m = 0.2;
  double max_depth_m = 30.0;             // farthest feature depth ...
  double min_triangulation_disparity_px = 5.0;  // ... or farther while the disparity stays above this

  // --- KLT tracking ---
  int klt_window = 21;
  int klt_levels = 3;
  int klt_iterations = 20;
  double klt_epsilon = 0.03;
  double klt_min_eigen = 1e-4;
  // Each KLT position is then refined by aligning the track's keyframe patch with an affine warp
  // (patch_alignment.h): no error accumulates over the keyframe span.
  bool keyframe_alignment = true;
  int alignment_half_window = 7;         // patch (2h+1)^2
  int alignment_iterations = 10;
  double alignment_max_shift_px = 1.5;   // larger corrections of the KLT position are rejected
  double alignment_min_ncc = 0.0;        // ... and so are alignments correlating less than this
  double alignment_min_eigen_ratio = 0.01;  // patch Hessian: smallest / largest eigenvalue (flat or
                                            // one-dimensional texture: no patch, KLT only)

  // --- RANSAC on the epipolar constraint (keyframe -> current left image) ---
  bool epipolar_filter = true;
  double epipolar_threshold_px = 1.0;
  double epipolar_min_flow_px = 2.0;     // below this mean flow F is degenerate: skip the filter

  // --- P3P in RANSAC with LMedS scoring (eq. 2.18) ---
  double ransac_probability = 0.99;
  int ransac_max_trials = 300;
  int ransac_min_trials = 10;
  double inlier_threshold_px = 2.0;      // upper cap on the LMedS-derived inlier threshold
  double inlier_threshold_min_px = 0.7;  // lower cap
  int min_inliers = 12;

  // --- two-frame sparse bundle adjustment (Levenberg-Marquardt, Schur complement) ---
  int ba_iterations = 8;
  double ba_huber_px = 1.0;
  double pixel_sigma_px = 0.5;           // for the published covariance

  // --- failure handling and motion limits ---
  double max_speed_mps = 4.0;            // larger frame-to-frame translation = failure
  double max_angular_speed_dps = 400.0;  // larger frame-to-frame rotation = failure
  double max_frame_gap_s = 1.0;          // a larger stamp gap (or time going backwards): the pose is
                                         // kept (not extrapolated), a new keyframe, the frame untrusted
  double min_image_stddev = 4.0;         // black / saturated / flat frame detection
  double max_rotation_from_keyframe_deg = 25.0;  // new keyframe beyond this

  // --- fail-safe: when the pose is no longer trusted (VoOutput::pose_trusted; README "Fail-safe") ---
  // A lost frame coasts on the gyro (rotation) and the damped last velocity for at most this long
  // after the last tracked frame; beyond it, or at once without a gyro, the pose is untrusted and
  // no longer extrapolated until a new keyframe is tracked.
  double coast_max_s = 0.3;
  // Frozen camera: the left image (every 4th pixel) differs from the previous one by at most this
  // mean absolute difference (gray levels) while the gyro turns at least frozen_min_gyro_dps, on
  // frozen_frames frames in a row (1: the first repeated frame already; the fault suite saw a
  // GUIDANCE cue decided on the first frozen frame with 2). Simulated walks:
  // consecutive frames differ by >= 2.4 (1.3 without pixel noise), the gyro turns >= 1.0 deg/s
  // (>= 1.5 on 99 % of the frames); gyro bias + noise per frame < 0.6 deg/s.
  double frozen_max_change = 0.5;
  double frozen_min_gyro_dps = 1.5;
  int frozen_frames = 1;
  // Image motion contradicting the gyro: the vision-only frame-to-frame rotation differs from the
  // integrated gyro by more than this on this many tracked frames in a row (failures in between
  // do not break the run); trust returns after as many agreeing frames. Clean walks (12 bags):
  // at most 0.73 deg on 3 frames in a row (2.2 on a single frame), on the corridor's bare end.
  double gyro_disagreement_deg = 1.5;
  int gyro_disagreement_frames = 3;
  // Stereo pair inconsistent with the motion (right image out of sync with the left, a camera
  // moved on the rig): the inliers' median disparity differs from the one their 3D point predicts
  // at the estimated pose by more than stereo_max_error_px, or fewer than stereo_min_matched_ratio
  // of them find a stereo match, on stereo_inconsistent_frames tracked frames in a row (at once
  // when the error exceeds 5 x stereo_max_error_px); trust returns after as many consistent
  // frames. Clean walks: median error 0.03-0.14 px, at most 0.22 px on 3 frames in a row (1.4 on
  // one), >= 54 % matched; the real KITTI clip 0.27 px on 3 frames, >= 74 %; a right image 3
  // frames late: up to 74 px and down to 0 % matched with the head turning, but only 0.3-1.2 px
  // and 30-70 % with a slow head (parking), which passes (the scale is then off, see README).
  double stereo_max_error_px = 0.6;
  double stereo_min_matched_ratio = 0.3;
  int stereo_inconsistent_frames = 3;

  // --- IMU (gyro prior) and odom frame ---
  bool use_imu = true;
  bool gyro_rotation_prior = true;       // fuse the integrated gyro into the bundle adjustment
  double gyro_noise_density = 2.0e-4;    // rad/s/sqrt(Hz)
  double gyro_bias_sigma = 5.0e-3;       // rad/s, initial bias uncertainty (bias estimated online)
  double gyro_bias_walk = 2.0e-5;        // rad/s^2/sqrt(Hz)
  double vo_rotation_sigma = 3.0e-4;     // rad, floor on the vision rotation error (bias update)
  // Gravity keeps the odom frame level (gravity_alignment.h): the tilt measured over each window
  // is corrected by window / time constant (0 = off; the odom frame then keeps the start's gravity).
  double gravity_time_constant_s = 120.0;
  double gravity_window_s = 4.0;
  double camera_height_m = 1.6;          // origin of odom on the floor under the camera start
  double initial_roll_deg = 0.0;         // camera_link roll/pitch at start when no IMU
  double initial_pitch_deg = 0.0;
};
}  // namespace assistive_vo
