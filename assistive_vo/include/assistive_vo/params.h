#pragma once
// Parameters of the visual odometry: ONE table (assistive_common/param_table.h). Each row is the
// field, its ROS parameter name (also vo_benchmark's --set name), default, range, unit and text;
// the nodelet reads every row, clamps by the ranges and README.md lists them (test_params).
#include <string>

#include <assistive_common/param_table.h>

namespace assistive_vo
{
// clang-format off
// X(type, field, ROS name, default, lo, hi, unit, text)
#define ASSISTIVE_VO_PARAMS(X) \
  /* --- FAST detection with adaptive threshold (seed 2.2.1.1) --- */ \
  X(int, fast_threshold_min, "fast_threshold_min", 5, 1, 254, "intensity", "lowest adapted FAST threshold") \
  X(int, fast_threshold_max, "fast_threshold_max", 120, fast_threshold_min, 255, "intensity", "highest adapted FAST threshold") \
  X(int, fast_threshold, "fast_threshold", 40, fast_threshold_min, fast_threshold_max, "intensity", "start FAST threshold (adapted)") \
  X(int, fast_threshold_step, "fast_threshold_step", 4, 1, 50, "intensity", "threshold change per replenishment") \
  /* 400 features: 15 % less rotational drift over 5 seeds x 5 worlds, but 30-50 % more time at p95 (README) */ \
  X(int, target_features, "target_features", 250, 20, 2000, "", "features wanted after replenishment") \
  X(double, grid_cell_px, "grid_cell", 80.0, 10.0, 1000.0, "px", "bucketing grid of round(width / cell) x round(height / cell) cells (8 x 6 at 640x480)") \
  X(int, border_px, "border", 12, 0, 200, "px", "no features this close to the image border") \
  X(double, min_feature_distance_px, "min_feature_distance", 12.0, 0.0, 200.0, "px", "new corners this far from existing tracks") \
  X(double, replenish_ratio, "replenish_ratio", 0.35, 0.05, 0.95, "", "re-detect when tracks alive < ratio x tracks started") \
  X(int, min_tracks, "min_tracks", 40, 8, 1000, "", "... or when fewer tracks are alive") \
  X(double, replenish_coverage_ratio, "replenish_coverage_ratio", 0.8, 0.0, 0.95, "", "... or when the tracks hold fewer than ratio x the bucketing-grid cells held at the keyframe (0 = off)") \
  /* --- sparse stereo along the rectified row --- */ \
  X(int, stereo_half_window, "stereo_half_window", 4, 1, 15, "px", "SAD window half size") \
  X(double, min_disparity_px, "min_disparity", 0.5, 0.0, 64.0, "px", "smallest stereo disparity") \
  X(int, max_disparity_px, "max_disparity", 128, 8, 512, "px", "stereo search range") \
  X(double, stereo_max_mean_sad, "stereo_max_mean_sad", 18.0, 0.0, 255.0, "intensity", "mean absolute difference per pixel of a stereo match at most this") \
  X(double, stereo_uniqueness, "stereo_uniqueness", 0.85, 0.0, 1.0, "", "best cost < uniqueness x second best (outside +-1)") \
  /* Smooth texture (cloudy paint seen up close: its blobs tens of pixels wide) gives FAST and the */ \
  /* 9x9 window nothing: a generated corridor's wall at 1-2 m, 2 stereo corners of 150. A keyframe */ \
  /* short of stereo corners adds corners of the left image halved and smoothed by coarse_sigma, */ \
  /* matched on that pair, tracked by KLT, weighed as noisier. Off by default: fewer VO losses and */ \
  /* fewer unsure cues in the vision trials, but more drift where corners are enough (README "Coarse corners"). */ \
  X(double, coarse_min_ratio, "coarse_min_ratio", 0.0, 0.0, 1.0, "", "a keyframe with fewer stereo corners than ratio x target_features adds coarse corners (0 = never)") \
  X(int, coarse_min_corners, "coarse_min_corners", 36, 0, 2000, "", "coarse corners are added only this many or more with stereo depth") \
  X(double, coarse_sigma_px, "coarse_sigma", 3.0, 1.0, 10.0, "px", "Gaussian smoothing of the coarse corners' pair (at half resolution)") \
  X(double, coarse_sigma_scale, "coarse_sigma_scale", 3.0, 1.0, 100.0, "", "their pixel noise in the bundle adjustment, x pixel_sigma") \
  X(int, coarse_half_window, "coarse_half_window", 8, 2, 15, "px", "their SAD window half size on the half-resolution smoothed pair") \
  X(double, min_depth_m, "min_depth", 0.2, 0.01, 100.0, "m", "nearest feature depth") \
  X(double, max_depth_m, "max_depth", 30.0, min_depth_m, 1000.0, "m", "farthest feature depth ...") \
  X(double, min_triangulation_disparity_px, "min_triangulation_disparity", 5.0, 0.0, 512.0, "px", "... or farther while the disparity stays above this") \
  /* --- KLT tracking --- */ \
  X(int, klt_window, "klt_window", 21, 5, 61, "px", "KLT window") \
  X(int, klt_levels, "klt_levels", 3, 0, 6, "", "KLT pyramid levels") \
  X(int, klt_iterations, "klt_iterations", 20, 1, 200, "", "KLT iterations at most") \
  X(double, klt_epsilon, "klt_epsilon", 0.03, 1e-6, 10.0, "px", "KLT convergence step") \
  X(double, klt_min_eigen, "klt_min_eigen", 1e-4, 0.0, 1.0, "", "KLT minimum eigenvalue (OpenCV's minEigThreshold)") \
  /* Each KLT position is then refined by aligning the track's keyframe patch with an affine warp */ \
  /* (patch_alignment.h): no error accumulates over the keyframe span. */ \
  X(bool, keyframe_alignment, "keyframe_alignment", true, {}, {}, "", "refine KLT positions against the keyframe patch (affine)") \
  X(int, alignment_half_window, "alignment_half_window", 7, 2, 15, "px", "its patch half size") \
  X(int, alignment_iterations, "alignment_iterations", 10, 1, 50, "", "Gauss-Newton iterations at most") \
  X(double, alignment_max_shift_px, "alignment_max_shift", 1.5, 0.1, 10.0, "px", "larger corrections of the KLT position are rejected") \
  X(double, alignment_min_ncc, "alignment_min_ncc", 0.0, -1.0, 1.0, "", "... and so are alignments correlating less than this") \
  /* flat or one-dimensional texture: no patch, KLT only */ \
  X(double, alignment_min_eigen_ratio, "alignment_min_eigen_ratio", 0.01, 0.0, 1.0, "", "smallest / largest eigenvalue of the patch's affine Hessian for a patch to be aligned") \
  /* --- RANSAC on the epipolar constraint (keyframe -> current left image) --- */ \
  X(bool, epipolar_filter, "epipolar_filter", true, {}, {}, "", "fundamental-matrix RANSAC on") \
  X(double, epipolar_threshold_px, "epipolar_threshold", 1.0, 0.1, 10.0, "px", "its inlier distance") \
  X(double, epipolar_min_flow_px, "epipolar_min_flow", 2.0, 0.0, 100.0, "px", "below this mean flow F is degenerate: no epipolar filter") \
  /* --- P3P in RANSAC with LMedS scoring (eq. 2.18) --- */ \
  X(double, ransac_probability, "ransac_probability", 0.99, 0.5, 0.9999, "", "p of eq. 2.18") \
  X(int, ransac_max_trials, "ransac_max_trials", 300, 10, 10000, "", "trial cap") \
  X(int, ransac_min_trials, "ransac_min_trials", 10, 1, ransac_max_trials, "", "trials at least") \
  X(double, inlier_threshold_px, "inlier_threshold", 2.0, 0.3, 20.0, "px", "upper cap on the LMedS inlier threshold") \
  X(double, inlier_threshold_min_px, "inlier_threshold_min", 0.7, 0.01, inlier_threshold_px, "px", "lower cap on the LMedS inlier threshold") \
  X(int, min_inliers, "min_inliers", 12, 6, 1000, "", "fewer = failure") \
  /* Motion hypothesis from points only (P3P above) or from points and lines: the trifocal */ \
  /* quaternion solver (seed 2.2.3, trifocal_solver.h) in RANSAC over the tracked points with a */ \
  /* stereo match in the keyframe and now, and the stereo line segments tracked since the keyframe */ \
  /* (line_tracking.h); inliers = point inliers + line inliers (README "Point+line in the loop"). */ \
  X(std::string, motion_solver, "motion_solver", "points", {}, {}, "", "`points` (P3P RANSAC) or `points_lines` (trifocal point+line RANSAC; `pointline` is the same); other values: `points`") \
  X(double, pointline_min_corner_ratio, "pointline_min_corner_ratio", 0.2, 0.0, 1.0, "", "`points_lines`: point tracks join the point+line RANSAC only when the smaller / larger eigenvalue of their 7x7 structure tensor is at least this (corners on a straight edge slide along it; 0 = all)") \
  X(int, pointline_min_points, "pointline_min_points", 4, 0, 1000, "", "`points_lines`: fewer point inliers than this stay out of a line frame's refinement (with lines of one direction the points alone decide the motion along them: three fix a motion with nothing to check them; a corner sliding down a door jamb)") \
  X(double, pointline_prior_sigma_m, "pointline_prior_sigma", 0.02, 0.0, 1.0, "m", "`points_lines`: the constant-velocity prediction is a prior on a line frame's motion, this standard deviation on its translation (lines of one wall leave directions free: vertical ones the motion along them); 0 = none") \
  X(double, pointline_prior_sigma_deg, "pointline_prior_sigma_rotation", 0.5, 0.0, 90.0, "deg", "`points_lines`, without a gyro: the prior's standard deviation on the rotation (with a gyro its rotation is the prior); 0 = none") \
  X(double, pointline_max_gyro_disagreement_deg, "pointline_max_gyro_disagreement", 0.5, 0.05, 90.0, "deg", "`points_lines`: a point+line motion whose vision rotation differs from the gyro's by more than this on the frame is rejected (the frame coasts on the IMU)") \
  /* --- two-frame sparse bundle adjustment (Levenberg-Marquardt, Schur complement) --- */ \
  X(int, ba_iterations, "ba_iterations", 8, 0, 100, "", "Levenberg-Marquardt iterations") \
  X(double, ba_huber_px, "ba_huber", 1.0, 0.01, 100.0, "px", "Huber loss threshold of the bundle adjustment") \
  X(double, pixel_sigma_px, "pixel_sigma", 0.5, 0.01, 10.0, "px", "feature position noise, for the published covariance") \
  /* --- failure handling and motion limits --- */ \
  X(double, max_speed_mps, "max_speed", 4.0, 0.1, 50.0, "m/s", "larger change of velocity against the constant-velocity prediction = failure (no jumps), unless >= 2 x `min_inliers` and half the tracks support the motion") \
  X(double, max_angular_speed_dps, "max_angular_speed", 400.0, 10.0, 5000.0, "deg/s", "same for rotation") \
  X(bool, untrusted_gyro_orientation, "untrusted_gyro_orientation", true, {}, {}, "", "an untrusted frame reports the last trusted position with the current orientation, which the gyro carries through losses and re-initialisations (off: the last trusted orientation too)") \
  X(double, max_frame_gap_s, "max_frame_gap", 1.0, 0.05, 10.0, "s", "a larger stamp gap (or time going backwards): pose kept, new keyframe, frame untrusted (a gap the IMU covers: see imu_bridge_gaps)") \
  X(bool, imu_bridge_gaps, "imu_bridge_gaps", true, {}, {}, "", "a forward gap the gyro and the accelerometer cover is bridged like lost frames: the gyro's rotation, the position held standing or IMU-coasted under the imu_coast_* rules, the keyframe tracked on; else as above") \
  /* Auto-exposure steps and a gain different in the two cameras: every image is scaled to one */ \
  /* mean brightness before stereo matching and tracking (the input checks see the raw image). */ \
  X(double, brightness_target, "brightness_target", -1.0, -1.0, 250.0, "intensity", "images scaled to this mean before matching and tracking (gain/auto-exposure invariance; -1: the first image's mean; 0: off)") \
  /* A constant disparity offset (the right camera turned about its vertical axis: calibration */ \
  /* residual) scales far depths and so the translation; estimated online (disparity_offset.h). */ \
  X(bool, estimate_disparity_offset, "estimate_disparity_offset", false, {}, {}, "", "estimate a constant stereo disparity offset online and add it to every disparity") \
  X(double, max_disparity_offset_px, "max_disparity_offset", 2.0, 0.0, 10.0, "px", "the offset estimated is kept within +- this") \
  X(double, min_image_stddev, "min_image_stddev", 4.0, 0.0, 128.0, "intensity", "black / saturated / flat frame below this standard deviation") \
  X(double, max_rotation_from_keyframe_deg, "max_rotation_from_keyframe", 25.0, 1.0, 180.0, "deg", "new keyframe beyond this rotation") \
  /* --- fail-safe: when the pose is no longer trusted (VoOutput::pose_trusted; README "Fail-safe") --- */ \
  /* A lost frame coasts on the gyro (rotation) and the damped last velocity for at most coast_max */ \
  /* after the last tracked frame; beyond it, or at once without a gyro, the pose is untrusted and */ \
  /* no longer extrapolated until a new keyframe is tracked. */ \
  X(double, coast_max_s, "coast_max", 0.3, 0.0, 2.0, "s", "a lost frame coasts on the gyro this long after the last tracked frame, then untrusted (at once without gyro)") \
  /* With the accelerometer too (use_imu), a lost frame coasts on IMU preintegration (inertial_coasting.h): */ \
  /* velocity and accelerometer error fitted to the tracked frames of the last imu_coast_window; */ \
  /* trusted while the position's 1-sigma stays within imu_coast_max_sigma, for at most imu_coast_max. */ \
  X(bool, imu_coasting, "imu_coasting", true, {}, {}, "", "lost frames coast on the preintegrated accelerometer (needs use_imu)") \
  X(double, imu_coast_max_s, "imu_coast_max", 2.5, 0.0, 10.0, "s", "an IMU-coasted pose stays trusted at most this long after the last tracked frame ...") \
  X(double, imu_coast_max_sigma_m, "imu_coast_max_sigma", 0.15, 0.0, 10.0, "m", "... and while its position 1-sigma (per axis) stays within this") \
  X(double, imu_coast_window_s, "imu_coast_window", 1.5, 0.2, 10.0, "s", "tracked frames the velocity and the accelerometer error are fitted over") \
  /* The vest's forward ranger aids a coast (range_aid.h): the range's change and rate measure the */ \
  /* walk along its axis (a plain wall the camera cannot see is what it hears best); the trust rule */ \
  /* then reads the coasted position's variance on its worst axis after that correction. */ \
  X(bool, range_aided_coast, "range_aided_coast", true, {}, {}, "", "the forward ranger's range (addRange) corrects an IMU coast along its axis") \
  X(double, range_aid_sigma_m, "range_aid_sigma", 0.02, 0.001, 1.0, "m", "a range's noise (the ranger's)") \
  X(double, range_aid_model_rel, "range_aid_model_rel", 0.08, 0.0, 1.0, "", "error of reading the range's change (rate) as the walk (speed) along the axis, a fraction of it") \
  X(bool, imu_coast_carry, "imu_coast_carry", true, {}, {}, "", "a coast's velocity (with its variance) starts the next window: a few tracked frames between losses can coast again (vision failing on and off at a plain wall) instead of waiting for a full window") \
  /* Standing still known from the IMU (standing_detector.h): no gait in the accelerometer over */ \
  /* standing_window, at a speed known to be low when vision was lost. A lost frame then holds the */ \
  /* position (zero velocity; the camera turns about the neck pivot) and takes the gyro's rotation, */ \
  /* trusted however long vision is blind; gait back: the coast rules above, from the last held frame. */ \
  X(bool, standing_detection, "standing_detection", true, {}, {}, "", "lost frames while the IMU shows no gait hold the position (zero velocity) and turn with the gyro, trusted") \
  X(double, standing_window_s, "standing_window", 0.8, 0.2, 5.0, "s", "the accelerometer's gait test window (longer than one step)") \
  X(double, standing_max_accel_sigma, "standing_max_accel_sigma", 0.25, 0.01, 5.0, "m/s^2", "standing: rms deviation of the specific force (odom axes, per-frame means) from its window mean at most this ...") \
  X(double, standing_max_speed, "standing_max_speed", 0.25, 0.0, 5.0, "m/s", "... and the speed when the hold starts (last tracked or IMU-coasted) at most this") \
  X(bool, standing_on_stop, "standing_on_stop", true, {}, {}, "", "a stop seen on the IMU (speed + its 1-sigma within standing_max_speed, no acceleration on the frame) starts the hold before the gait test's window has cleared the deceleration; it goes on while the samples since show no gait") \
  X(bool, standing_speed_imu, "standing_speed_imu", true, {}, {}, "", "without an IMU coast (too few tracked frames to fit one), the speed a hold may start from is the last tracked frame's velocity carried on by the accelerometer since (else that frame's speed as measured)") \
  X(double, standing_position_sigma, "standing_position_sigma", 0.03, 0.0, 1.0, "m", "position 1-sigma (per axis) added once when a hold starts") \
  X(double, standing_pivot_forward, "standing_pivot_forward", 0.09, -0.5, 0.5, "m", "the camera sits this far in front of the pivot the head turns about (the neck; camera_link x) ...") \
  X(double, standing_pivot_up, "standing_pivot_up", 0.1, -0.5, 0.5, "m", "... and this far above it (camera_link z): a held frame keeps the pivot still") \
  X(double, accel_noise_density, "accel_noise_density", 2.0e-3, 1e-6, 1.0, "m/s^2/sqrt(Hz)", "accelerometer white noise (coasting covariance)") \
  X(double, accel_error_sigma, "accel_error_sigma", 0.15, 1e-3, 10.0, "m/s^2", "prior on the accelerometer bias + gravity leaking through tilt error, in the coasting fit") \
  /* Frozen camera: the left image (every 4th pixel) differs from the previous one by at most */ \
  /* frozen_max_change (mean absolute difference) while the gyro turns at least frozen_min_gyro_rate, */ \
  /* on frozen_frames frames in a row (1: the first repeated frame already; the fault suite saw a */ \
  /* GUIDANCE cue decided on the first frozen frame with 2). Simulated walks: */ \
  /* consecutive frames differ by >= 2.4 (1.3 without pixel noise), the gyro turns >= 1.0 deg/s */ \
  /* (>= 1.5 on 99 % of the frames); gyro bias + noise per frame < 0.6 deg/s. */ \
  X(double, frozen_max_change, "frozen_max_change", 0.5, 0.0, 20.0, "gray levels", "frozen camera: mean absolute difference to the previous left image at most this ...") \
  X(double, frozen_min_gyro_dps, "frozen_min_gyro_rate", 1.5, 0.1, 100.0, "deg/s", "... while the gyro turns at least this ...") \
  X(int, frozen_frames, "frozen_frames", 1, 1, 100, "", "... on this many frames in a row") \
  /* Image motion contradicting the gyro: the vision-only frame-to-frame rotation differs from the */ \
  /* integrated gyro by more than gyro_disagreement on gyro_disagreement_frames tracked frames in a */ \
  /* row (failures in between do not break the run); trust returns after as many agreeing frames. */ \
  /* Clean walks (12 bags): at most 0.73 deg on 3 frames in a row (2.2 on a single frame). */ \
  X(double, gyro_disagreement_deg, "gyro_disagreement", 1.5, 0.05, 90.0, "deg", "vision-only frame-to-frame rotation against the gyro: more than this ...") \
  X(int, gyro_disagreement_frames, "gyro_disagreement_frames", 3, 1, 100, "", "... on this many tracked frames in a row: untrusted (as many agreeing frames to recover)") \
  /* Stereo pair inconsistent with the motion (right image out of sync with the left, a camera */ \
  /* moved on the rig): the inliers' median disparity differs from the one their 3D point predicts */ \
  /* at the estimated pose by more than stereo_max_error, or fewer than stereo_min_matched_ratio */ \
  /* of them find a stereo match, on stereo_inconsistent_frames tracked frames in a row (at once */ \
  /* when the error exceeds 5 x stereo_max_error); trust returns after as many consistent frames. */ \
  /* Clean walks: median error 0.03-0.14 px, at most 0.22 px on 3 frames in a row (1.4 on one), */ \
  /* >= 54 % matched; the real KITTI clip 0.27 px on 3 frames, >= 74 %; a right image 3 frames */ \
  /* late: up to 74 px and down to 0 % matched with the head turning, but only 0.3-1.2 px and */ \
  /* 30-70 % with a slow head (parking), which passes (the scale is then off, see README). */ \
  X(double, stereo_max_error_px, "stereo_max_error", 0.6, 0.05, 50.0, "px", "inliers' median disparity against the pose's prediction: more than this ...") \
  X(double, stereo_min_matched_ratio, "stereo_min_matched_ratio", 0.3, 0.0, 1.0, "", "... or fewer inliers with a stereo match ...") \
  X(int, stereo_inconsistent_frames, "stereo_inconsistent_frames", 3, 1, 100, "", "... on this many tracked frames in a row (at once beyond 5 x `stereo_max_error`): untrusted") \
  /* --- IMU (gyro prior) and odom frame --- */ \
  X(bool, use_imu, "use_imu", true, {}, {}, "", "gyro prior and gravity from `imu/data`") \
  X(bool, gyro_rotation_prior, "gyro_rotation_prior", true, {}, {}, "", "gyro rotation prior in the bundle adjustment") \
  X(double, gyro_noise_density, "gyro_noise_density", 2.0e-4, 1e-6, 1e-1, "rad/s/sqrt(Hz)", "gyro angle random walk") \
  X(double, gyro_bias_sigma, "gyro_bias_sigma", 5.0e-3, 1e-6, 1.0, "rad/s", "initial gyro bias uncertainty (bias estimated online)") \
  X(double, gyro_bias_walk, "gyro_bias_walk", 2.0e-5, 0.0, 1e-1, "rad/s^2/sqrt(Hz)", "gyro bias random walk") \
  X(double, gyro_time_sigma_s, "gyro_time_sigma", 0.0, 0.0, 0.1, "s", "uncertainty of the gyro's timing against the images: the rotation prior (and the bias update) over a keyframe span is off by the rate change since the keyframe times the offset") \
  /* Rolling shutter (rolling_shutter.h): each observation moved to the stamp by the gyro's rate there */ \
  /* (the last frame's vision rate without a gyro) and the last frame's velocity. 0 for a global */ \
  /* shutter (the D4xx's infrared pair); a 640x480 CMOS video sensor reads out in 10-33 ms. */ \
  X(double, rolling_shutter_readout_s, "rolling_shutter_readout", 0.0, 0.0, 0.1, "s", "time from the first image row's exposure to the last's (0: global shutter)") \
  X(double, gyro_bias_min_span_s, "gyro_bias_min_span", 0.3, 0.0, 10.0, "s", "shortest time over which vision's rotation teaches the gyro bias") \
  X(bool, gyro_bias_chain_spans, "gyro_bias_chain_spans", false, {}, {}, "", "keyframe spans shorter than gyro_bias_min_span in a row are chained until they last that long (false: dropped)") \
  X(double, gyro_bias_chain_sigma, "gyro_bias_chain_sigma", 8.7e-4, 0.0, 1.0, "rad/s", "systematic error of a chain of three or more short spans: such a chain teaches the bias only while the estimate's sigma is above this, with this added") \
  X(double, vo_rotation_sigma, "vo_rotation_sigma", 3.0e-4, 1e-6, 1.0, "rad", "floor on the vision rotation error (bias update)") \
  /* Gravity keeps the odom frame level (gravity_alignment.h). */ \
  X(double, gravity_time_constant_s, "gravity_time_constant", 120.0, 0.0, 3600.0, "s", "keeps odom level: the tilt against gravity measured over each window is corrected by window / time constant (0 = off: odom keeps the start's gravity and its tilt drifts with the gyro bias)") \
  X(double, gravity_window_s, "gravity_window", 4.0, 0.5, 60.0, "s", "tracked frames per gravity measurement (a lost frame restarts it)") \
  X(double, camera_height_m, "camera_height", 1.6, 0.0, 5.0, "m", "height of camera_link above the floor at start: the nodelet takes it from the URDF (`footprint_frame`), this value only without one") \
  X(double, initial_roll_deg, "initial_roll", 0.0, -90.0, 90.0, "deg", "camera_link roll at start without IMU") \
  X(double, initial_pitch_deg, "initial_pitch", 0.0, -90.0, 90.0, "deg", "camera_link pitch at start without IMU")

// The nodelet's own parameters (ROS plumbing; vo_benchmark has no use for them).
#define ASSISTIVE_VO_NODE_PARAMS(X) \
  X(double, imu_wait, "imu_wait", 1.0, 0.0, 30.0, "s", "with `use_imu`, the first frames wait this long (image time) for an IMU sample before the odom frame is fixed; after it: `initial_roll` / `initial_pitch` and a warning") \
  X(double, imu_sync_wait, "imu_sync_wait", 0.1, 0.0, 1.0, "s", "a frame whose IMU interval has not fully arrived while the IMU is flowing (its samples behind the images, e.g. from another process) waits up to this long (wall clock) for it; 0 = never: the frame goes without the gyro and the accelerometer") \
  X(int, queue_size, "queue_size", 5, 1, 100, "", "synchroniser queue") \
  X(bool, approximate_sync, "approximate_sync", false, {}, {}, "", "ApproximateTime instead of ExactTime") \
  X(std::string, odom_frame, "odom_frame", "odom", {}, {}, "", "frame of the odometry") \
  X(std::string, base_frame, "base_frame", "camera_link", {}, {}, "", "the camera body, child of the odometry") \
  X(std::string, footprint_frame, "footprint_frame", "base_footprint", {}, {}, "", "URDF frame on the floor under `base_frame`: gives `camera_height`") \
  X(bool, publish_tf, "publish_tf", true, {}, {}, "", "broadcast odom -> camera_link") \
  X(double, expected_rate, "expected_rate", 15.0, 0.1, 200.0, "Hz", "for the frequency diagnostic")
// clang-format on

struct VoParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_VO_PARAMS)
};

struct VoNodeParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_VO_NODE_PARAMS)
};
}  // namespace assistive_vo
