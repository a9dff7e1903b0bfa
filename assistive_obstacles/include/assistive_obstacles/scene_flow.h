#pragma once
// Sparse scene flow for the mover segmentation (issue 22), from the obstacle stage's own inputs:
// corners of the previous left image (FAST, the strongest per bucket) tracked into the current one by
// pyramidal Lucas-Kanade (cv::calcOpticalFlowPyrLK), kept only when tracking back lands within
// `max_fb_error` of the start (occlusions, repeated texture), each end lifted to 3D by the dense
// disparity of its own frame. The VO has tracks too, but keeps them private. Each image's pyramid
// is built once (it serves as the previous one at the next frame). ROS-free.
//
// Depth at a feature: the disparity at the matcher's scale, bilinear between the 4 neighbours,
// only where the 3x3 disparity range around it is at most `max_disparity_range` (px at the
// matcher's scale): corners lie on silhouettes more often than anywhere else, and a corner formed
// by a foreground edge over the background moves with neither (its depth is one of them, its
// image motion a mix), which reads as motion against the ego-motion in a static scene. With the
// right image given, that disparity only starts the feature's own stereo match (matchDisparity()):
// the dense matcher aggregates over a neighbourhood, and a corner next to a plain area takes the
// area's fill (a door jamb over the sky: a depth that stays put while the wearer walks up to it).
#include <deque>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <assistive_obstacles/disparity.h>
#include <assistive_obstacles/mover_segmentation.h>

namespace assistive_obstacles
{
struct SceneFlowParams
{
  int max_features = 600;            ///< corners detected per frame
  int fast_threshold = 8;            ///< FAST corner threshold (grey levels)
  double min_distance = 8.0;         ///< px, bucket size: at most one corner (the strongest) per bucket
  /// the budget goes first to the strongest corner of each block of this many x this many buckets (1: by strength alone)
  int spread_blocks = 3;
  bool half_resolution_corners = true;  ///< FAST also on the half-resolution image (a smooth texture seen close up)
  int lk_window = 11;                ///< px, Lucas-Kanade window
  int lk_levels = 3;                 ///< pyramid levels above the base (11 px window: ~40 px motion per frame)
  double max_fb_error = 0.5;         ///< px, forward-backward tracking error beyond which a track is dropped
  double max_disparity_range = 1.0;  ///< px at the matcher's scale: larger 3x3 range = depth edge, no depth
  /// px at full resolution: no depth edge (valid disparities spanning more than max_disparity_range)
  /// within this window around a feature, at either end of its track (0: the 3x3 check alone).
  /// Lucas-Kanade tracks the whole window: one that holds two surfaces moves with neither.
  int edge_window = 0;
  /// Whether the way back starts where the way forward left the ego-motion's prediction
  /// (p0 + (p1 - predicted)); false: at p0 itself (see process()).
  bool fair_backward = true;
  /// With the right image given: each end's disparity is the feature's own match, found by
  /// normalised cross-correlation of its `lk_window` window along the rectified row within
  /// +-`stereo_search` px (full resolution) of the matcher's value (parabola peak); a feature whose
  /// best score is below `stereo_min_ncc`, or lies at the end of the search, has no depth. The dense
  /// matcher's disparity at a corner comes from its aggregation over the neighbourhood: next to a
  /// plain surface (the sky through a doorway) the edge takes the plain area's fill, which does not
  /// change as the wearer walks up to it, and the corner seems to recede at walking speed.
  double stereo_search = 3.0;
  double stereo_min_ncc = 0.8;
  double min_depth = 0.3, max_depth = 6.0;  ///< m, points outside are dropped
  /// The flow spans this many frames (the current one against the one k frames back; fewer
  /// right after a start): walking along the viewing ray moves a point by only ~0.1 m per frame
  /// at 15 Hz, within the stereo depth noise of two frames; k frames move it k times as far
  /// with the same noise.
  int frames_apart = 1;
  /// With frames_apart 1: each feature tracked with depth at its new end is tracked on from there
  /// at the next frame, where that end's depth is already known; new corners only fill the
  /// buckets the kept tracks leave empty (issue 37: each stereo match once, not at both ends).
  bool keep_tracks = true;
  /// px: a track that ended within this of the ego-motion's prediction is tracked back on the
  /// pyramid's base alone (its way back starts that near its corner); 0: every track through
  /// every level.
  double backward_base_px = 2.0;
};

/// Disparity (full-resolution px) at full-resolution pixel (u, v) from a disparity image at the
/// matcher's scale `s` (= disp.cols / width): bilinear over the 4 neighbours when every pixel of
/// the 3x3 around the nearest one is valid (> 0) and their range is at most `max_range`; else -1.
double disparityAt(const cv::Mat& disp, double s, double u, double v, double max_range);

/// Whether the valid disparities (matcher scale `s` = disp.cols / width) within the full-resolution
/// window `window` x `window` px centred on (u, v) span more than `max_range` px (a depth edge the
/// window straddles). Invalid pixels are not counted; a window reaching out of the image is clipped.
bool depthEdgeNear(const cv::Mat& disp, double s, double u, double v, int window, double max_range);

/// The disparity (full-resolution px) of the window around (u, v) of `left` in `right` by
/// normalised cross-correlation at integer offsets within +-search px of `d0`, refined by a parabola
/// through the best score and its neighbours; -1 when the window has no texture, the best score is
/// below `min_ncc`, or the best offset lies at the end of the search.
double matchDisparity(const cv::Mat& left, const cv::Mat& right, double u, double v, double d0, int window,
                      double search, double min_ncc);

/// FAST corners of `grey`, the strongest per min_distance bucket, at most max_features (the
/// strongest), in raster order of detection. With `disp` and `model` (the image's disparity at the
/// matcher's scale) only corners with a usable depth (in [min_depth, max_depth], off depth edges)
/// compete: the far background and the sky would otherwise take half the budget. `half`: `grey`
/// at half resolution when the caller has it (its pyramid), for half_resolution_corners.
/// `taken`: features the caller already has (tracks kept from the frame before): their buckets
/// get no corner, their blocks count as served in the spread, and they use up the budget.
void detectCorners(const cv::Mat& grey, const SceneFlowParams& p, std::vector<cv::KeyPoint>& scratch,
                   std::vector<cv::Point2f>& out, const cv::Mat* disp = nullptr, const StereoModel* model = nullptr,
                   const cv::Mat* half = nullptr, const std::vector<cv::Point2f>* taken = nullptr);

class SceneFlowExtractor
{
public:
  explicit SceneFlowExtractor(const SceneFlowParams& p = SceneFlowParams()) : params_(p) {}
  void setParams(const SceneFlowParams& p) { params_ = p; }
  const SceneFlowParams& params() const { return params_; }

  /// One frame: `grey` the rectified left image (CV_8UC1, full resolution), `disp` its disparity
  /// at the matcher's scale (CV_32F, invalid < 0, DisparityEstimator::compute()). Returns the scene
  /// flow from the previous frame given (empty at the first frame or after reset()), each point in
  /// the previous and the current left optical frame.
  /// With `T_world_cam` (the left optical frame's pose, for this and the paired frame) each
  /// corner's track starts at the pixel the ego-motion predicts for a static point.
  /// With `right` (the rectified right image, CV_8UC1) each end's depth is the feature's own
  /// stereo match (see stereo_search).
  const std::vector<SceneFlowPoint>& process(const cv::Mat& grey, const cv::Mat& disp, const StereoModel& model,
                                             const Eigen::Isometry3d* T_world_cam = nullptr,
                                             const cv::Mat* right = nullptr);
  const std::vector<SceneFlowPoint>& flow() const { return flow_; }
  /// Per flow point: its pixel in the current image.
  const std::vector<cv::Point2f>& pixels() const { return pixels_; }
  /// Features tracked from the previous image (kept tracks and new corners) / tracked both ways /
  /// with depth at both ends.
  int detected() const { return detected_; }
  /// Of detected(), the tracks kept from the frame before (keep_tracks).
  int kept() const { return kept_; }
  int tracked() const { return tracked_; }
  /// How many frames back the last process() paired with (0: none).
  int pairedBack() const { return paired_back_; }
  /// Forgets the previous frames (after a gap or a map clear).
  void reset();

private:
  SceneFlowParams params_;
  struct Frame
  {
    cv::Mat grey, disp, right;
    std::vector<cv::Mat> pyr;
    StereoModel model;
    bool has_pose = false;
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  };
  std::deque<Frame> history_;  ///< the last frames_apart frames, oldest first
  /// keep_tracks: the newest frame's tracked features and their points (its left optical frame)
  std::vector<cv::Point2f> kept_px_;
  std::vector<Eigen::Vector3d> kept_X_;
  int paired_back_ = 0;
  std::vector<SceneFlowPoint> flow_;
  std::vector<cv::Point2f> pixels_;
  std::vector<cv::Mat> pyr_;
  std::vector<cv::KeyPoint> keypoints_;
  std::vector<cv::Point2f> p0_, p1_, pb_, pred_, fresh_, next_px_;
  std::vector<Eigen::Vector3d> next_X_;
  std::vector<int> back_idx_;
  std::vector<cv::Point2f> back_from_, back_to_;
  std::vector<uint8_t> back_st_;
  /// Each feature's start in the current image where the ego-motion puts a static point (into
  /// p1_); false without both poses.
  bool predictStarts(const Frame& old, const StereoModel& model, const Eigen::Isometry3d* T_world_cam);
  /// The tracked features with depth (next_px_, next_X_) kept for the next frame, one per bucket.
  void keepTracked(bool keep, int cols, int rows);
  /// The forward-backward check's way back (pb_ from p1_), into stb_.
  void trackBack(const std::vector<cv::Mat>& prev_pyr, const cv::Size& win, const cv::TermCriteria& tc);
  std::vector<uint8_t> st_, stb_;
  std::vector<float> err_;
  int detected_ = 0, tracked_ = 0, kept_ = 0;
};

}  // namespace assistive_obstacles
