#pragma once
// What one frame of the visual odometry measured: stage timings and counters (VoOutput::stats).
// ROS-free.

namespace assistive_vo
{
/// Per-frame timings (ms of CPU time of the calling thread) and counters.
struct FrameStats
{
  double ms_total = 0, ms_pyramid = 0, ms_klt = 0, ms_epipolar = 0, ms_stereo = 0, ms_ransac = 0,
         ms_ba = 0, ms_detect = 0, ms_lines = 0;
  int tracks = 0, inliers = 0, ransac_trials = 0, new_features = 0, fast_threshold = 0;
  // per-stage counts of this frame (diagnosis): corners detected, KLT tracks kept, tracks kept
  // by the epipolar RANSAC (new_features = detected corners with stereo depth, inliers = P3P)
  int detected = 0, klt_tracked = 0, epipolar_kept = 0;
  int aligned = 0;  ///< tracks refined against their keyframe patch
  int coarse_features = 0;  ///< coarse corners with stereo depth a keyframe added (coarse_min_ratio)
  // motion_solver pointline: stereo line segments tracked since the keyframe with a stereo
  // match in this frame, and the RANSAC's line inliers among them
  int lines = 0, line_inliers = 0;
  bool keyframe = false, reset = false;
  // fail-safe detector inputs of this frame (-1: not measured)
  double image_change = -1;     ///< mean absolute difference to the previous left image (every 4th pixel)
  double gyro_rate_dps = -1;    ///< bias-corrected gyro rate over the frame interval
  double gyro_disagreement_deg = -1;  ///< vision-only frame-to-frame rotation against the gyro's
  double stereo_error_px = -1;  ///< median |disparity - disparity predicted by the pose| of the inliers
  double stereo_matched_ratio = -1;  ///< inliers with a stereo match in this frame
};
}  // namespace assistive_vo
