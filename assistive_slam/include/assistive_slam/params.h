#pragma once
// Parameters of the SLAM stage: ONE table (assistive_common/param_table.h). Each row is the field,
// its ROS parameter name (also slam_benchmark's --set name), default, range, unit and text; the
// nodelet reads every row, clamps by the ranges and README.md lists them.
#include <string>

#include <assistive_common/param_table.h>

namespace assistive_slam
{
// clang-format off
// X(type, field, ROS name, default, lo, hi, unit, text)
#define ASSISTIVE_SLAM_PARAMS(X) \
  /* --- keyframes (seed 3.2.3.3): taken when the VO replenishes its tracks, or by distance / angle --- */ \
  X(double, keyframe_min_distance_m, "keyframe_min_distance", 0.3, 0.0, 10.0, "m", "a VO replenishment closer than this to the last keyframe (and turned less than keyframe_min_angle) is no keyframe") \
  X(double, keyframe_min_angle_deg, "keyframe_min_angle", 10.0, 0.0, 180.0, "deg", "... nor turned less than this") \
  X(double, keyframe_max_distance_m, "keyframe_max_distance", 1.0, keyframe_min_distance_m, 100.0, "m", "a keyframe at the latest this far from the last one") \
  X(double, keyframe_max_angle_deg, "keyframe_max_angle", 25.0, keyframe_min_angle_deg, 180.0, "deg", "... or turned this far") \
  /* --- stereo features of a keyframe --- */ \
  X(int, orb_features, "orb_features", 800, 50, 5000, "", "ORB features detected in the left image") \
  X(int, orb_fast_threshold, "orb_fast_threshold", 12, 1, 100, "intensity", "ORB's FAST threshold") \
  X(double, stereo_max_row_diff_px, "stereo_max_row_diff", 1.5, 0.0, 10.0, "px", "left/right match on the same rectified row within this") \
  X(int, stereo_max_hamming, "stereo_max_hamming", 50, 1, 256, "bits", "stereo match descriptor distance at most this") \
  X(bool, stereo_subpixel, "stereo_subpixel", true, {}, {}, "", "refine each stereo match's disparity along the row (9x9 patch at full resolution: SAD search, then Gauss-Newton to a fraction of a pixel): ORB's coarse levels place far points a pixel or more off") \
  X(double, min_depth_m, "min_depth", 0.3, 0.05, 10.0, "m", "nearest keyframe point") \
  X(double, max_depth_m, "max_depth", 15.0, min_depth_m, 200.0, "m", "farthest keyframe point") \
  /* --- bounded submaps (seed 3.2.3.1) --- */ \
  X(int, submap_max_keyframes, "submap_max_keyframes", 8, 1, 1000, "", "a new submap after this many keyframes ...") \
  X(double, submap_max_extent_m, "submap_max_extent", 4.0, 0.5, 1000.0, "m", "... or this far from the submap's origin") \
  /* --- local bundle adjustment over a sliding window of keyframes (Ceres, worker thread) --- */ \
  X(int, ba_window, "ba_window", 8, 2, 50, "", "keyframes in the window (the oldest two are held fixed)") \
  /* Off by default: on the parking walk the ORB-keyframe adjustment made the VO's rotational drift worse */ \
  /* (0.042-0.140 deg/m against 0.029 over 450 frames) and diverged once over four loops (README "Figures"). */ \
  X(int, ba_iterations, "ba_iterations", 0, 0, 200, "", "Levenberg-Marquardt iterations at most (0: no local bundle adjustment)") \
  X(double, ba_huber_px, "ba_huber", 1.5, 0.1, 50.0, "px", "Huber loss of the reprojection residuals") \
  X(double, pixel_sigma_px, "pixel_sigma", 0.7, 0.05, 10.0, "px", "keypoint position noise") \
  X(int, match_max_hamming, "match_max_hamming", 60, 1, 256, "bits", "keyframe-to-keyframe descriptor distance at most this") \
  X(double, match_gate_px, "match_gate", 25.0, 1.0, 500.0, "px", "a match lies this close to where the VO's motion puts the point") \
  X(int, ba_min_observations, "ba_min_observations", 2, 2, 10, "", "landmarks seen in fewer keyframes stay out of the adjustment") \
  /* --- odometry links (VO relative motion): its noise per metre walked and per keyframe --- */ \
  X(double, odom_sigma_per_m, "odom_sigma_per_m", 0.02, 1e-5, 1.0, "m/m", "translation noise of the VO per metre walked") \
  X(double, odom_sigma_deg_per_m, "odom_sigma_deg_per_m", 0.3, 1e-4, 10.0, "deg/m", "rotation noise of the VO per metre walked") \
  X(double, odom_sigma_floor_m, "odom_sigma_floor", 0.01, 1e-5, 1.0, "m", "translation noise floor per link") \
  X(double, odom_sigma_floor_deg, "odom_sigma_floor_deg", 0.2, 1e-4, 10.0, "deg", "rotation noise floor per link") \
  /* --- loop closure: candidates from older submaps, verified geometrically before they touch the graph --- */ \
  X(bool, loop_closure, "loop_closure", true, {}, {}, "", "look for loop closures") \
  X(int, loop_skip_submaps, "loop_skip_submaps", 3, 1, 1000, "", "the newest submaps are no loop candidates (they are linked by odometry)") \
  X(int, loop_min_inliers, "loop_min_inliers", 40, 8, 2000, "", "P3P RANSAC inliers needed to accept a closure") \
  X(double, loop_min_inlier_ratio, "loop_min_inlier_ratio", 0.35, 0.0, 1.0, "", "... and this share of the matches") \
  X(double, loop_inlier_px, "loop_inlier", 2.0, 0.3, 20.0, "px", "reprojection error of a P3P inlier") \
  X(double, loop_max_correction_m, "loop_max_correction", 3.0, 0.1, 1000.0, "m", "a closure that moves the wearer farther than this (+ 5 % of the path since the candidate) is rejected") \
  X(double, loop_max_correction_deg, "loop_max_correction_deg", 30.0, 1.0, 180.0, "deg", "... or turns them more than this") \
  X(double, loop_confirm_m, "loop_confirm", 0.3, 0.0, 10.0, "m", "a verified closure is accepted when the next keyframe's implies the same map correction within this ...") \
  X(double, loop_confirm_deg, "loop_confirm_deg", 3.0, 0.0, 90.0, "deg", "... and this") \
  X(int, loop_candidates, "loop_candidates", 3, 1, 50, "", "candidate keyframes verified per new keyframe") \
  X(int, appearance_candidates, "appearance_candidates", 3, 0, 50, "", "keyframes the appearance model (ORB, its binary path) proposes per keyframe: the only candidates when relocalising after a load (0: no relocalisation)") \
  /* Off by default: on the parking walks it added no closure to the proximity search's (24 and 102 either way) */ \
  /* and the model's grids cost about 0.5 MB per keyframe (peak RSS 106 -> 199 MB on the shipped parking walk). */ \
  /* The model's words barely match between two views of a place on the rendered parking walks (1-5 of 800 */ \
  /* observations per query): its ranking alone left the stored place unverified for 83 keyframes. */ \
  X(int, relocalisation_sweep, "relocalisation_sweep", 3, 0, 50, "", "after a load, stored submaps verified per query besides the appearance model's, in turn (each within submaps / this queries whatever the model ranks; 0: the model's only)") \
  X(bool, appearance_loop, "appearance_loop", false, {}, {}, "", "the model also learns every keyframe and its candidates are verified after the proximity ones for loop closure") \
  X(int, appearance_features, "appearance_features", 200, 10, 5000, "", "descriptors per keyframe the appearance model learns and queries (its memory grows with them)") \
  X(double, loop_sigma_m, "loop_sigma", 0.03, 1e-4, 10.0, "m", "translation noise of a verified closure") \
  X(double, loop_sigma_deg, "loop_sigma_deg", 0.5, 1e-3, 90.0, "deg", "rotation noise of a verified closure") \
  /* --- after a VO loss (issue 34): an untrusted VO pose (held while the wearer moved) unplaces the wearer until found again --- */ \
  X(bool, reset_relocalisation, "reset_relocalisation", true, {}, {}, "", "after a VO loss keyframes are queries until one is verified against the map (and the next agrees); false: the map goes on from the VO's held pose") \
  X(double, reset_bridge_m, "reset_bridge", 0.5, 0.0, 10.0, "m", "a loss so short that the wearer can have walked at most this unseen (from its speed when the loss began, speeding up at reset_max_accel up to reset_max_speed, from the last trusted frame to the next trusted one) is bridged when the search has not placed the wearer within reset_bridge_after: placed on the VO's held pose (map -> odom as before the loss); 0.5 m, the planner's reached_distance (0: never)") \
  X(double, reset_bridge_after_s, "reset_bridge_after", 0.5, 0.0, 60.0, "s", "... that long after the first trusted frame (a search that succeeds does within a few queries; the planner keeps guiding on a map -> odom up to 1 s old)") \
  X(double, reset_max_accel, "reset_max_accel", 2.0, 0.1, 20.0, "m/s^2", "how quickly the wearer may speed up unseen, for reset_bridge (gait initiation: mean accelerations of 0.5-1.2 m/s^2 from standing to the preferred pace)") \
  X(double, reset_search_radius_m, "reset_search_radius", 2.0, 0.1, 100.0, "m", "keyframes this close to the last trusted pose (+ reset_max_speed x the time since it) are verified first ...") \
  X(double, reset_max_speed, "reset_max_speed", 1.5, 0.0, 10.0, "m/s", "... the speed the wearer may have walked at unseen") \
  X(double, reset_max_backward_m, "reset_max_backward", 0.75, 0.0, 100.0, "m", "a relocalised pose farther than this behind the last trusted pose, along the wearer's level view direction, is refused (people walk where they look)") \
  X(int, reset_candidates, "reset_candidates", 6, 1, 50, "", "keyframes near the last trusted pose verified per query (nearest first; then the appearance model's, with appearance_loop)") \
  X(int, reset_min_inliers, "reset_min_inliers", 15, 8, 2000, "", "P3P RANSAC inliers (also in the right image) a relocalisation after a loss needs (the prior and the next query's agreement guard it) ...") \
  X(double, reset_min_inlier_ratio, "reset_min_inlier_ratio", 0.3, 0.0, 1.0, "", "... and this share of the matches") \
  X(double, reset_max_rotation_deg, "reset_max_rotation_deg", 5.0, 0.5, 180.0, "deg", "a relocalisation after a loss turns the predicted pose (the VO's rotation went on with the gyro) at most this") \
  X(double, reset_rotation_sigma_deg, "reset_rotation_sigma_deg", 0.5, 0.01, 90.0, "deg", "the predicted rotation (the VO's, kept by the gyro through the loss) as a prior of the relocalised pose: its noise") \
  X(bool, reset_fixed_rotation, "reset_fixed_rotation", true, {}, {}, "", "a relocalisation after a loss solves the position alone at the predicted rotation (two matches a hypothesis), not P3P's free pose: on a corridor's far points P3P traded 5 deg of yaw for 0.7 m of position") \
  X(int, reset_confirm_queries, "reset_confirm_queries", 3, 2, 30, "", "consecutive queries (each frame while looking) agreeing on map -> odom place the wearer, at their mean ...") \
  X(double, reset_confirm_m, "reset_confirm", 0.15, 0.0, 10.0, "m", "... each within this of the first ...") \
  X(double, reset_confirm_deg, "reset_confirm_deg", 1.5, 0.0, 90.0, "deg", "... and this") \
  X(double, reset_relocalisation_timeout_s, "reset_relocalisation_timeout", 10.0, 0.0, 3600.0, "s", "not found again this long after the last trusted frame: mapping resumes, weakly linked, and the wearer stays unplaced until a loop closure reaches the map before the loss (0: never)") \
  /* --- the metric layer of a submap: keyframe_ba (keyframe chain + optional local BA) or fastslam (seed 3.2.1-3.2.2) --- */ \
  X(std::string, metric_backend, "metric_backend", "keyframe_ba", {}, {}, "", "keyframe_ba: keyframes chained by the VO (local BA if ba_iterations > 0); fastslam: the FastSLAM 2.0 filter with active matching runs on every frame and chains the keyframes") \
  X(int, fastslam_particles, "fastslam_particles", 50, 1, 2000, "", "particles of the filter") \
  X(double, fastslam_pixel_sigma, "fastslam_pixel_sigma", 0.1, 0.01, 10.0, "px", "image measurement noise (seed: 0.1)") \
  X(double, fastslam_disparity_sigma, "fastslam_disparity_sigma", 0.4, 0.01, 10.0, "px", "disparity noise of a new landmark (seed: 0.4)") \
  X(double, fastslam_resample_neff, "fastslam_resample_neff", 0.5, 0.0, 1.0, "", "systematic resampling when N_eff falls below this share of the particles") \
  X(int, fastslam_max_matches, "fastslam_max_matches", 40, 4, 1000, "", "candidate landmarks searched per frame at most (smallest windows first)") \
  X(int, fastslam_min_matches, "fastslam_min_matches", 30, 0, 1000, "", "new landmarks are added while fewer were matched") \
  X(int, fastslam_new_landmarks, "fastslam_new_landmarks", 30, 0, 1000, "", "new landmarks per frame at most") \
  X(double, fastslam_ncc, "fastslam_ncc", 0.8, -1.0, 1.0, "", "normalised cross-correlation a match must exceed (13x13 template)") \
  X(double, fastslam_window_confidence, "fastslam_window_confidence", 0.99, 0.5, 0.999999, "", "probability mass of the fused Gaussian the search window holds") \
  X(double, fastslam_max_window, "fastslam_max_window", 30.0, 2.0, 500.0, "px", "a candidate whose window's half axis is longer is not searched") \
  X(double, fastslam_q_floor_m, "fastslam_q_floor", 0.0005, 1e-6, 1.0, "m", "translation noise of the VO per frame at least") \
  X(double, fastslam_q_floor_deg, "fastslam_q_floor_deg", 0.01, 1e-6, 10.0, "deg", "rotation noise of the VO per frame at least") \
  X(int, fastslam_seed, "fastslam_seed", 1, 0, 1000000000, "", "random seed of the filter (sampling, resampling)") \
  /* --- worker thread --- */ \
  X(int, queue_size, "queue_size", 4, 1, 100, "", "keyframes waiting for the worker at most (the oldest is dropped beyond)") \
  X(bool, loop_closing_thread, "loop_closing_thread", true, {}, {}, "", "loop closing (detection, verification, pose graph) on a thread of its own behind the worker; false: on the worker after each keyframe")

// The nodelet's own parameters (ROS plumbing; slam_benchmark has no use for them).
#define ASSISTIVE_SLAM_NODE_PARAMS(X) \
  X(std::string, map_frame, "map_frame", "map", {}, {}, "", "the map frame (REP-105)") \
  X(std::string, odom_frame, "odom_frame", "odom", {}, {}, "", "the VO's odometry frame") \
  X(std::string, optical_frame, "optical_frame", "camera_left_optical_frame", {}, {}, "", "left camera frame (its pose in camera_link from tf, the URDF)") \
  X(int, sync_queue_size, "sync_queue_size", 10, 1, 100, "", "synchroniser queue (stereo pair + vo/odom, same stamp)") \
  X(double, untrusted_variance, "untrusted_variance", 1000.0, 1.0, 1e9, "m^2", "a vo/odom position variance this large marks the VO pose untrusted (no keyframe)") \
  X(double, tf_rate, "tf_rate", 20.0, 1.0, 200.0, "Hz", "map -> odom is re-broadcast at this rate (future-dated by 1 / rate)") \
  X(double, graph_rate, "graph_rate", 1.0, 0.1, 50.0, "Hz", "path, submap graph and markers are published at this rate") \
  X(double, expected_rate, "expected_rate", 15.0, 0.1, 200.0, "Hz", "for the frequency diagnostic") \
  X(std::string, map_file, "map_file", "assistive_slam.map", {}, {}, "", "slam/save_map and slam/load_map use this file (a relative path is under ROS_HOME, default ~/.ros)") \
  X(bool, load_map_at_start, "load_map_at_start", false, {}, {}, "", "load map_file before the first frame (then not localised until a stored place is recognised)")
// clang-format on

struct SlamNodeParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_SLAM_NODE_PARAMS)
};

struct SlamParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_SLAM_PARAMS)
};

}  // namespace assistive_slam
