#pragma once
// All parameters of the obstacle stage: ONE table (assistive_common/param_table.h). Each row is
// the field, its ROS parameter name (also obstacles_benchmark's --set name), default, range,
// unit and text; the nodelet reads every row, clampParams() clamps by the ranges and README.md
// lists them (test_params).
#include <string>
#include <vector>

#include <assistive_common/param_table.h>

namespace assistive_obstacles
{
// clang-format off
// X(type, field, ROS name, default, lo, hi, unit, text)
#define ASSISTIVE_OBSTACLES_PARAMS(X) \
  /* --- dense disparity --- */ \
  /* hh/hh4: fewer errors, but 10x slower than sgbm3way on 450x375 inputs */ \
  X(std::string, disparity_method, "disparity_method", "sgbm3way", {}, {}, "", "`sgbm3way`, `sgbm`, `hh`, `hh4` or `bm` (another: sgbm3way)") \
  X(double, disparity_scale, "disparity_scale", 0.5, 0.125, 1.0, "", "image scale the matcher runs at (1 = full resolution)") \
  X(int, max_disparity, "max_disparity", 128, 16, 512, "px", "at FULL resolution (min depth = fx*B/max_disparity)") \
  X(int, block_size, "block_size", 5, 1, 21, "px", "at the matcher's scale, odd (an even value is made odd)") \
  X(int, uniqueness_ratio, "uniqueness_ratio", 10, 0, 100, "%", "matcher uniqueness margin") \
  X(int, speckle_window_size, "speckle_window_size", 100, 0, 1000, "px^2", "at the matcher's scale (0 disables)") \
  X(int, speckle_range, "speckle_range", 2, 0, 64, "disparity levels", "speckle filter range") \
  X(int, disp12_max_diff, "disp12_max_diff", 1, -1, 64, "px", "left-right check at the matcher's scale (<0 disables)") \
  /* OpenCV's sample uses 8; 4 keeps slanted floors and walls from being pulled onto fronto-parallel planes */ \
  X(int, sgbm_p1, "sgbm_p1", 4, 0, 1000, "", "SGBM P1 (disparity change of 1) = sgbm_p1 * block_size^2") \
  X(int, sgbm_p2, "sgbm_p2", 64, sgbm_p1 + 1, 10000, "", "SGBM P2 (larger disparity jumps) = sgbm_p2 * block_size^2") \
  /* --- points --- */ \
  X(double, min_depth, "min_depth", 0.3, 0.05, 10.0, "m", "closer points are dropped") \
  X(double, max_depth, "max_depth", 6.0, min_depth + 0.1, 50.0, "m", "farther points are dropped (disparity noise grows as z^2)") \
  X(int, point_stride, "point_stride", 1, 1, 16, "", "take every n-th pixel of the scaled disparity in u and v") \
  X(double, edge_filter, "edge_filter", 0.5, 0.0, 1000.0, "px", "at the matcher's scale: pixels whose 3x3 disparity range exceeds this lie on a depth discontinuity and give no point (0 disables)") \
  /* a near-textureless wall matches at +-1-2 px and scatters points in front of it */ \
  X(double, texture_max_depth_sigma, "texture_max_depth_sigma", 0.15, 0.0, 100.0, "m", "pixels whose depth is less precise than this (Cramer-Rao bound of the block's texture) give no point (0 disables)") \
  X(double, image_noise_sigma, "image_noise_sigma", 2.0, 0.01, 100.0, "grey levels", "the camera's pixel noise, for that bound") \
  /* the noise's own energy passes 1 % of flat blocks at 3 (a chi-square of about 8 degrees of freedom); a passive */ \
  /* camera keeps the raw energy: its weak textures sit at the noise's level (recall 0.962 -> 0.925 at 1.5) */ \
  X(double, texture_min_snr, "texture_min_snr", 3.0, 0.0, 100.0, "", "with an active camera's images (`projected`) a block's texture for that bound is its horizontal gradient energy less the pixel noise's expected energy, and none unless the energy is at least this many times the noise's (0: the raw energy, noise and all, as for a passive camera)") \
  X(bool, projected, "projected", false, {}, {}, "", "an active camera (issue 35): `left/image_rect`... are its emitter-on pairs (the projector's dots; the texture bound then takes the pixel noise off, `texture_min_snr`), and the movers track its emitter-off pairs on `track/{left,right}/image_rect` (the dots move with the head)") \
  /* --- elevation map / MLS (wearer-tied, not scene-tied) --- */ \
  X(double, cell_size, "cell_size", 0.2, 0.02, 2.0, "m", "elevation cell edge") \
  X(double, window_radius, "window_radius", 5.0, 2 * cell_size, 50.0, "m", "processed circle around the wearer (scrolls)") \
  X(int, min_points_per_cell, "min_points_per_cell", 10, 1, 100000, "", "cells with fewer points are dropped as noise") \
  X(double, gap_height, "gap_height", 1.9, 0.5, 5.0, "m", "G: intervals split at vertical gaps larger than this (wearer height + margin)") \
  X(double, step_height, "step_height", 0.2, 0.01, 1.0, "m", "T: thicker intervals are vertical (obstacle); also max climbable height difference") \
  X(double, min_step, "min_step", 0.065, 0.0, step_height, "m", "a traversable cell whose neighbour differs by more is a step/curb") \
  X(double, step_sigmas, "step_sigmas", 2.0, 0.0, 10.0, "", "a neighbour's ground differing by more than min_step makes a step only when the difference exceeds min_step by this many standard errors of the two grounds (from their heights' density about the ground quantile); in between the cell takes no vote (0: any difference over min_step)") \
  X(bool, step_se_per_block, "step_se_per_block", false, {}, {}, "", "the heights of one matching block (block_size^2 pixels at the matcher's scale) share its error: a ground's standard error counts n (point_stride / block_size)^2 independent heights (false, the default: all n; on, vision trials on generated worlds stood stuck less but collided more)") \
  X(double, head_clearance, "head_clearance", 0.3, 0.0, 3.0, "m", "above the camera: higher points cannot touch the wearer") \
  X(double, camera_height, "camera_height", 1.6, 0.0, 3.0, "m", "camera above the wearer's feet (feet level = camera z - this): the nodelet takes it from the URDF (`footprint_frame`), this value only without one") \
  X(double, max_surface_rise, "max_surface_rise", 0.45, 0.0, 5.0, "m", "walkable surfaces lie at most this far above the feet ...") \
  X(double, max_surface_drop, "max_surface_drop", 0.6, 0.0, 5.0, "m", "... or this far below them (else obstacle / drop-off)") \
  X(double, cluster_gap, "cluster_gap", 0.1, 0.0, 1.0, "m", "heights closer than this form one sub-cluster (outlier rejection)") \
  X(int, min_cluster_points, "min_cluster_points", 3, 1, 1000, "", "sub-clusters with fewer points are noise") \
  /* A camera sees the front face of a solid, the solid lies behind it, so a face on a cell border */ \
  /* (depth noise splits its points) lands in the solid's cell; keep it below the thinnest obstacle. */ \
  X(double, surface_push, "surface_push", 0.04, 0.0, 0.5, "m", "elevated points are moved this far away from the camera along the horizontal ray (0 disables)") \
  X(bool, surface_push_normal, "surface_push_normal", true, {}, {}, "", "steep surfaces pushed along their horizontal normal (disparity gradient) instead of the viewing ray") \
  /* above the median, so a cell holding a curb edge takes the curb's height as the ground truth */ \
  /* does (highest walkable surface in the cell) */ \
  X(double, ground_quantile, "ground_quantile", 0.7, 0.0, 1.0, "", "quantile of the lowest interval's heights taken as the cell's ground height") \
  X(double, thickness_trim, "thickness_trim", 0.05, 0.0, 0.45, "", "fraction of an interval's heights trimmed at each end for its thickness") \
  X(int, min_traversable_edges, "min_traversable_edges", 5, 0, 8, "", "compatible 8-neighbours needed to be traversable") \
  X(int, closing_radius, "closing_radius", 1, 0, 5, "cells", "morphological closing of the obstacle mask, filling cells without a vote (0 disables)") \
  X(int, closing_weight, "closing_weight", 1, 1, 4, "", "vote weight of a cell the closing filled; such votes never decide a cell on their own") \
  X(int, fine_factor, "fine_factor", 4, 1, 10, "", "elevated points are also counted on a grid this many times finer (5 cm) ...") \
  /* suppresses the depth-noise spill of a wall into the cell in front of it */ \
  X(double, peak_fraction, "peak_fraction", 0.5, 0.0, 1.0, "", "... and a vertical cell stays an obstacle only if one of its fine bins holds at least this fraction of the densest fine bin within 2 fine bins (0 disables)") \
  /* --- temporal filter --- */ \
  X(int, min_observations, "min_observations", 5, 1, 1000, "", "O+S before a cell is decided") \
  X(double, obstacle_ratio, "obstacle_ratio", 0.5, 0.0, 1.0, "", "obstacle if O/(O+S) > this") \
  X(int, permanent_flips, "permanent_flips", 15, 1, 60000, "", "I at which a cell becomes an obstacle for good") \
  X(int, max_count, "max_count", 40, min_observations, 60000, "", "O+S are halved above this many full-weight votes (keeps the filter responsive)") \
  /* depth error grows as Z^2; a cell behind a wall is otherwise only ever voted on from afar (by */ \
  /* noise) and never corrected up close */ \
  X(double, vote_max_range, "vote_max_range", 3.5, 0.0, 50.0, "m", "cells farther than this from the wearer take no vote (0 = whole window)") \
  X(double, full_weight_range, "full_weight_range", 2.5, 0.0, 50.0, "m", "votes of nearer cells weigh 4, farther ones 4*(r0/r)^2 (>= 1) (0: every vote weighs 1)") \
  X(double, disparity_sigma, "disparity_sigma", 0.3, 0.0, 100.0, "px", "at full resolution: stereo disparity noise assumed for the depth error") \
  /* 2.45 m for the 12 cm, 500 px rig; free votes reach vote_max_range */ \
  X(double, obstacle_max_sigma, "obstacle_max_sigma", 0.03, 0.0, 100.0, "m", "obstacle votes only where sigma_Z = Z^2 * disparity_sigma / (fx * B) <= this (0 = no limit)") \
  /* false: floor noise from afar no longer makes steps (a generated corridor's precision 0.19 -> 0.30), */ \
  /* but far FREE labels still vote and curbs then read as free (plaza: cells reported free 9 -> 17) */ \
  X(bool, far_step_votes, "far_step_votes", true, {}, {}, "", "cells labelled step beyond the obstacle evidence range vote (false: no vote from there, as obstacles)") \
  /* --- column clearance (issue 17): floor returns free only the floor band; a shelf or sign at */ \
  /* head height, out of view up close, was freed by the floor under it */ \
  X(int, column_bands, "column_bands", 5, 0, 8, "", "a cell is freed only when each of this many height bands of its column was seen clear (depth beyond it), gathered over frames since its last obstacle evidence (0 disables)") \
  X(double, column_band_low, "column_band_low", 0.3, 0.0, 3.0, "m", "height above the feet of the lowest band's test point ...") \
  /* a sign hanging at 1.56-1.94 m sits above a test point at 1.55 m: the highest is above the eye */ \
  X(double, column_band_high, "column_band_high", 1.75, column_band_low, 3.0, "m", "... and of the highest (test points evenly spaced between)") \
  /* 0 (every band must be seen clear) cut coverage within 3 m on the course 0.506 -> 0.284: a band */ \
  /* above the eye is out of view with the head pitched down */ \
  X(double, column_strict_from, "column_strict_from", 2.0, 0.0, 3.0, "m", "bands whose test point lies this high or higher must be seen clear; lower ones are presumed clear until an obstacle is seen in them") \
  X(double, column_clear_margin, "column_clear_margin", 0.05, 0.0, 1.0, "m", "a band is seen clear when the depth at its pixel lies beyond it by more than this (and than 2 sigma_Z)") \
  /* a vertical thing (wall, jamb, person) hides a cell's floor and its bands alike; a band hidden */ \
  /* just in front while the floor below is seen has something overhanging that floor (issue 36) */ \
  X(double, column_block_depth, "column_block_depth", 0.0, 0.0, 3.0, "m", "a band whose pixel's depth ends in front of it by more than the clear margin but at most this much, in a frame that labels the cell's floor free or step, is withdrawn: a shelf, sign or branch overhangs the seen floor (0, the default, disables it: vision trials did no better with 0.5)") \
  /* --- dropout / glass policy --- */ \
  X(double, dropout_max_range, "dropout_max_range", 4.0, 0.0, 50.0, "m", "obstacle cells in view this close but without depth are reported") \
  /* 0 locks the cell (a false obstacle in front of the floor could then never be cleared), 1 */ \
  /* lets seen-through cells fade after ~4x as many frames as made them obstacles */ \
  X(int, dropout_free_weight, "dropout_free_weight", 1, 0, 4, "", "weight of the free vote such a cell still takes (0 = locked for good)") \
  /* --- forward ultrasonic ranger (sonar_fusion.h): sees glass the camera sees through --- */ \
  X(bool, sonar_enabled, "sonar_enabled", true, {}, {}, "", "fuse `sonar/front` (sensor_msgs/Range) into the map") \
  X(int, sonar_hit_votes, "sonar_hit_votes", 2, 1, 20, "", "full-weight obstacle votes per echo in each cell the cone's arc crosses above the floor") \
  X(int, sonar_release_readings, "sonar_release_readings", 3, 1, 1000, "", "a ranger-hit cell takes no camera free vote until this many echoes came from beyond it") \
  X(double, sonar_release_margin, "sonar_release_margin", 0.3, 0.0, 5.0, "m", "... a cell nearer than the echo by at least this (inner half of the cone)") \
  X(double, sonar_floor_echo_deg, "sonar_floor_echo_deg", 50.0, 0.0, 90.0, "deg", "an echo whose cone holds a ray this steep below the horizontal and whose arc reaches the floor may be the floor: no evidence (shallower, the floor sends the echo away)") \
  /* --- people who move (issue 22, mover_pipeline.h): scene flow against the ego-motion, tracked */ \
  /* movers take no vote in the static map (no ghosts, no locked cells) --- */ \
  X(bool, movers, "movers", true, {}, {}, "", "detect and track movers (scene flow of the left image) and keep their cells out of the map's votes; publishes `movers`") \
  X(int, mover_max_features, "mover_max_features", 600, 10, 5000, "", "corners tracked per frame for the scene flow") \
  X(int, mover_fast_threshold, "mover_fast_threshold", 8, 1, 255, "grey levels", "FAST corner threshold of the scene flow's corners (12 found only silhouettes on the smooth clothes and walls of generated busy worlds)") \
  X(int, mover_spread_blocks, "mover_spread_blocks", 3, 1, 64, "", "the corner budget goes first to the strongest corner of each block of this many x this many 8 px buckets, then to the strongest of the rest (1: by strength alone; a textured wall's corners then took the whole budget from a person in smooth clothes)") \
  X(bool, mover_half_resolution_corners, "mover_half_resolution_corners", true, {}, {}, "", "FAST corners also on the half-resolution image (a person in smooth clothes seen within 2 m: the texture is magnified past FAST's circle)") \
  X(int, mover_frames_apart, "mover_frames_apart", 1, 1, 10, "frames", "the scene flow pairs each frame with the one this many frames back (walking along the viewing ray moves a point farther than the depth noise only over several frames)") \
  X(int, mover_edge_window, "mover_edge_window", 0, 0, 101, "px", "no scene-flow point where valid disparities within this window (full resolution, e.g. 11: the Lucas-Kanade window) span a depth edge, at either end of its track (0: the 3x3 check alone; 11 removed the silhouettes but also most points of distant people)") \
  X(bool, mover_keep_tracks, "mover_keep_tracks", true, {}, {}, "", "with mover_frames_apart 1, a scene-flow feature tracked with depth goes on from its new pixel at the next frame (its depth there already known: one stereo match per feature and frame); new corners fill the buckets the kept tracks leave") \
  X(double, mover_backward_base_px, "mover_backward_base_px", 2.0, 0.0, 100.0, "px", "a scene-flow track that ended within this of the ego-motion's prediction is checked back on the image pyramid's base alone (0: through every level)") \
  X(bool, mover_fair_backward, "mover_fair_backward", true, {}, {}, "", "the forward-backward check's way back starts where the way forward left the ego-motion's prediction (false: at the corner itself)") \
  X(double, mover_stereo_search, "mover_stereo_search", 3.0, 0.0, 32.0, "px", "each scene-flow feature's depth is its own stereo match (normalised cross-correlation of its window) within this many px of the matcher's disparity (full resolution; below 1: the matcher's disparity)") \
  X(double, mover_stereo_min_ncc, "mover_stereo_min_ncc", 0.8, -1.0, 1.0, "", "... a feature whose best correlation is lower has no depth") \
  X(double, mover_max_fb_error, "mover_max_fb_error", 0.5, 0.01, 10.0, "px", "forward-backward Lucas-Kanade error beyond which a corner's track is dropped") \
  X(double, mover_disparity_sigma, "mover_disparity_sigma", 0.3, 0.01, 100.0, "px", "at full resolution: disparity noise of a tracked corner's depth, for the residual along the ray") \
  X(double, mover_sigma_scale, "mover_sigma_scale", 3.0, 0.5, 100.0, "", "a point moves when its residual against the ego-motion exceeds this many sigmas ...") \
  X(double, mover_min_residual, "mover_min_residual", 0.05, 0.0, 5.0, "m", "... and this") \
  X(int, mover_min_cluster_points, "mover_min_cluster_points", 5, 1, 10000, "", "moving points (8-connected 0.2 m ground cells) that make a mover") \
  X(int, mover_death_misses, "mover_death_misses", 8, 1, 1000, "frames", "a confirmed mover track coasts (constant velocity) through this many frames without a detection before it ends (5 dropped walkers the detector missed for a few frames and at the view's edge during the head's scan; 10 coasted past people who turned)") \
  X(double, mover_min_speed, "mover_min_speed", 0.3, 0.0, 5.0, "m/s", "a track at least 0.5 s old that moved less than this since its birth is a static surface (not reported, its cells vote again)") \
  X(double, mover_confirm_sigmas, "mover_confirm_sigmas", 3.0, 0.0, 100.0, "", "a confirmed track is reported only while its points' mean motion against the ego-motion is at least mover_min_speed and this many standard errors, and its centres move the same way (mover_pipeline.h); 0 reports every confirmed track") \
  X(double, mover_flow_sigma, "mover_flow_sigma", 0.3, 0.01, 10.0, "m/s", "floor of the scatter of one detection's flow velocity, for that test") \
  /* --- trust in the input ("never guide on a guess", FrameGate) --- */ \
  X(double, max_frame_gap_s, "max_frame_gap_s", 0.5, 0.05, 60.0, "s", "a longer gap between frames, or time going back, clears the map") \
  X(int, rebuild_frames, "rebuild_frames", 5, 1, 1000, "", "fresh frames after a clear before the grid is published again") \
  /* black, saturated, covered or textureless view */ \
  X(int, min_fresh_points, "min_fresh_points", 500, 0, 10000000, "", "a frame with fewer 3D points yields no depth: it neither updates the map nor refreshes the grid's stamp") \
  /* --- OctoMap of what was seen --- */ \
  X(bool, octomap_enabled, "octomap_enabled", true, {}, {}, "", "build the OctoMap") \
  X(double, octomap_resolution, "octomap_resolution", 0.1, 0.01, 2.0, "m", "OctoMap voxel size") \
  X(double, octomap_max_range, "octomap_max_range", 5.0, 0.1, 50.0, "m", "ray length for insertion") \
  X(int, octomap_point_stride, "octomap_point_stride", 8, 1, 1000, "", "insert every n-th point (ray casting cost)") \
  X(std::string, octomap_save_path, "octomap_save_path", "/tmp/assistive_obstacles.bt", {}, {}, "", "where `save_octomap` writes")

// The nodelet's own parameters (ROS plumbing; obstacles_benchmark has no use for them).
#define ASSISTIVE_OBSTACLES_NODE_PARAMS(X) \
  X(std::string, world_frame, "world_frame", "odom", {}, {}, "", "frame of the grid; each frame waits for its pose on tf (tf2_ros::MessageFilter)") \
  X(std::string, camera_frame, "camera_frame", "camera_link", {}, {}, "", "the head, for `camera_height` from the URDF") \
  X(std::string, footprint_frame, "footprint_frame", "base_footprint", {}, {}, "", "URDF frame on the floor under `camera_frame`: gives `camera_height`") \
  X(int, queue_size, "queue_size", 5, 1, 100, "", "synchroniser and tf-filter queue") \
  X(bool, approximate_sync, "approximate_sync", false, {}, {}, "", "ApproximateTime instead of ExactTime") \
  X(bool, use_odom, "use_odom", true, {}, {}, "", "clear the map when `odom` marks a pose untrusted") \
  X(int, octomap_insert_every, "octomap_insert_every", 5, 1, 1000, "frames", "OctoMap insertion period")
// clang-format on

struct ObstaclesParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_OBSTACLES_PARAMS)
};

struct ObstaclesNodeParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_OBSTACLES_NODE_PARAMS)
};

/// Clamps `p` by the table's ranges, then the rules a range cannot say (a known disparity
/// method, an odd block size); returns one message per changed field (for NODELET_WARN).
std::vector<std::string> clampParams(ObstaclesParams& p);

}  // namespace assistive_obstacles
