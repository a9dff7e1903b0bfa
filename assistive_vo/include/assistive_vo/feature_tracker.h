#pragma once
// VisualOdometry's tracking (issue 32): the corners and stereo line segments followed from frame
// to frame since their keyframe: the KLT pyramids, KLT from the previous frame refined against
// each corner's keyframe patch, the epipolar RANSAC, the stereo disparity of the tracked corners,
// the line tracks (detected at keyframes, KLT along the segments in both images) and the flow
// overlay. Which corners a keyframe starts with is KeyframeManager's. ROS-free.
#include <algorithm>
#include <memory>
#include <vector>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include "assistive_vo/bundle_adjustment.h"
#include "assistive_vo/frame_stats.h"
#include "assistive_vo/line_detector.h"
#include "assistive_vo/line_tracking.h"
#include "assistive_vo/p3p_ransac.h"
#include "assistive_vo/params.h"
#include "assistive_vo/patch_alignment.h"
#include "assistive_vo/rolling_shutter.h"
#include "assistive_vo/sparse_stereo.h"
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
/// Stereo search range: disparity of the nearest useful depth (fx * baseline / min_depth_m),
/// capped by max_disparity_px.
inline double maxDisparity(const VoParams& p, const StereoCamera& cam)
{
  return std::min<double>(p.max_disparity_px, cam.fx * cam.baseline / p.min_depth_m);
}

/// motion_solver uses the stereo line tracks (pointline / points_lines).
inline bool usesPointLine(const VoParams& p)
{
  return p.motion_solver == "pointline" || p.motion_solver == "points_lines";
}

/// A corner tracked since its keyframe.
struct PointTrack
{
  Eigen::Vector3d X_kf;       ///< 3D point in the keyframe's optical frame
  StereoObservation kf_obs;   ///< its stereo observation in the keyframe
  cv::Point2f prev, cur;       ///< in the images (KLT, the patches, the stereo match)
  float cur_disp = -1.f;
  /// `cur` and `cur_disp` with the rolling shutter undone (RollingShutter; the same for a global
  /// shutter): what the geometry uses.
  cv::Point2f cur_geo;
  float cur_geo_disp = -1.f;
  bool coarse = false;  ///< a coarse corner (coarse_min_ratio): no patch, stereo on the smoothed pair
  bool inlier = true;
  std::shared_ptr<const KeyframePatch> patch;  ///< keyframe appearance (null: KLT only)
  Eigen::Matrix2f warp = Eigen::Matrix2f::Identity();  ///< keyframe patch axes in the current image
};

/// A stereo line segment tracked since its keyframe (motion_solver pointline).
struct LineTrack
{
  LineSegment kf_left, kf_right;  ///< in the keyframe
  LineSegment cur, cur_right;     ///< in the current frame (cur_right valid when `stereo`)
  bool stereo = false;
};

class FeatureTracker
{
public:
  explicit FeatureTracker(const VoParams& p = VoParams(), const StereoCamera& cam = StereoCamera());
  void setParams(const VoParams& p);
  void setCamera(const StereoCamera& cam) { cam_ = cam; }
  /// Forgets the corner tracks and the overlay (the line tracks and images stay).
  void reset();

  std::vector<PointTrack>& points() { return points_; }
  const std::vector<PointTrack>& points() const { return points_; }
  std::vector<LineTrack>& lines() { return lines_; }
  const std::vector<LineTrack>& lines() const { return lines_; }
  /// motion_solver uses the line tracks.
  bool usesLines() const { return pointline_; }
  /// The corners' stereo matcher (its disparity offset is estimated by VisualOdometry).
  SparseStereo& stereo() { return stereo_; }
  const SparseStereo& stereo() const { return stereo_; }
  /// Level 0 of the current left image's pyramid (built by buildPyramid this frame).
  const cv::Mat& currentImage() const { return cur_pyr_[0]; }

  /// A new stereo frame begins (the right images' pyramids are kept per frame).
  void beginFrame() { ++frame_index_; }
  /// KLT pyramid of the current left image.
  void buildPyramid(const cv::Mat& left);
  /// The current pyramid becomes the previous one (the frame is done with tracking).
  void endFrame() { std::swap(prev_pyr_, cur_pyr_); }

  /// KLT from the previous frame (initial guess from the predicted motion keyframe -> current),
  /// then each track refined against its keyframe patch.
  void trackPoints(const cv::Mat& left, const Eigen::Isometry3d& T_kf_pred, FrameStats& st);
  /// RANSAC on the epipolar constraint keyframe -> current: drops tracks off the epipolar lines.
  void filterEpipolar(FrameStats& st);
  /// The current frame's rolling shutter (a global shutter by default).
  void setRollingShutter(const RollingShutter& rs) { rs_ = rs; }
  const RollingShutter& rollingShutter() const { return rs_; }
  /// `cur_geo` / `cur_geo_disp` of an observation (u, v) with disparity d in the current frame.
  void undoRollingShutter(const cv::Point2f& c, float d, cv::Point2f& geo, float& geo_disp) const;
  /// The current left image at half resolution smoothed by coarse_sigma (built once a frame, on
  /// first use).
  const cv::Mat& smoothedLeft(const cv::Mat& left);
  /// Disparities of coarse corners (full resolution): matched on the half-resolution smoothed pair
  /// (negative: no match).
  std::vector<float> matchCoarse(const cv::Mat& left, const cv::Mat& right, const std::vector<cv::Point2f>& pts);
  /// Stereo disparity of the tracked points in the current pair (and their `cur_geo`).
  void matchStereo(const cv::Mat& left, const cv::Mat& right, FrameStats& st);
  /// Line tracks: KLT along the segments from the previous left and right images.
  void trackLines(const cv::Mat& right, FrameStats& st);
  /// The line tracks of a new keyframe whose corners are `points_started`: the tracked ones carry
  /// on while enough are left, else new lines are detected (at most every kLineDetectFrames
  /// frames, and only while corners are not plenty).
  void startKeyframeLines(const cv::Mat& left, const cv::Mat& right, bool from_current_tracks, int points_started);
  /// Cells of the detector's bucketing grid (bucketGrid) that hold a track.
  int occupiedCells() const;
  /// Keeps the inliers of an accepted motion (their keyframe points refined: `X_refined[k]` for
  /// `inliers[k]`); the overlay shows the inliers and the dropped tracks.
  void keepInliers(const std::vector<int>& inliers, const Vec3List& X_refined);

  /// Draws the last frame's flow (green = inlier, red = rejected), the fresh corners of a new
  /// keyframe and the line tracks onto `out` (BGR).
  void drawOverlay(cv::Mat& out) const;

private:
  static constexpr int kLineDetectFrames = 5;  ///< tracked frames between two line detections at most
  /// Stereo line segments of a new keyframe (left segments with a right match).
  void startLines(const cv::Mat& left, const cv::Mat& right);
  /// The points' KLT pyramids (klt_window, klt_levels) serve the line tracks too.
  bool pointPyramidsServeLines() const;
  /// prev_right_ = right (this frame's; a pyramid built of it this frame stays valid).
  void setPrevRight(const cv::Mat& right);
  void clearOverlay();
  void addOverlay(const PointTrack& t, bool inlier);

  VoParams p_;
  StereoCamera cam_;
  SparseStereo stereo_;
  SparseStereo coarse_stereo_;  ///< coarse_half_window
  cv::Mat smooth_left_, smooth_right_;
  unsigned long smooth_frame_ = ~0ul, smooth_right_frame_ = ~0ul;  ///< frame_index_ of each
  RollingShutter rs_;
  bool pointline_ = false;  ///< motion_solver is pointline
  std::vector<cv::Mat> prev_pyr_, cur_pyr_;
  std::vector<PointTrack> points_;

  // ---- line tracks
  int frames_since_line_detect_ = 0;
  int lines_started_ = 0;
  LineDetector line_detector_;
  LineMatchParams line_match_;
  std::vector<LineTrack> lines_;
  cv::Mat prev_right_;  ///< the previous right image (line tracks)
  std::vector<cv::Mat> prev_right_pyr_;  ///< its KLT pyramid when built (frame_index_ of both below)
  unsigned long frame_index_ = 0, prev_right_frame_ = 0, prev_right_pyr_frame_ = ~0ul;

  // ---- last frame's flow for the overlay
  std::vector<cv::Point2f> ov_from_, ov_to_;
  std::vector<uint8_t> ov_inlier_;
};
}  // namespace assistive_vo
