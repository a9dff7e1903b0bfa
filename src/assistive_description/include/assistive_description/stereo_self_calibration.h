#pragma once
// Online self-calibration of a rectified stereo pair (issue 36): the right camera's small rotation
// against the rectified rig, estimated from the running images and undone by a homography.
//
// A worn rig drifts from its checkerboard calibration by shock and heat, about 0.1 deg (Hansen et
// al., "Online continuous stereo extrinsic parameter estimation", CVPR 2012). Rotated by w (rad;
// about the left optical x, y, z: the right camera's pixel p sees the rig's ray R(w) p), a point at
// normalised left coordinates (x, y) and normalised disparity delta appears in the right image
// shifted vertically by
//   dv / fy = (1 + y^2) w_x - x y w_y - x w_z + y delta (x_l + x_r) k1
// (the last term: the rig's residual radial distortion k1, the same in both cameras, which also
// bends rows apart in proportion to the disparity). Matched features' vertical offsets measure
// w_x and w_z directly and w_y (the disparity offset, f w_y px, which scales every far depth)
// through the image's corners. Each used frame gives one robust least-squares solution; the frames'
// solutions are averaged with a forgetting window and their scatter gives the uncertainty (the
// features of one frame share their errors, the frames much less). An axis's correction changes
// only when the estimate differs from it by more than `significance` sigma (before its first
// correction, with a floor per axis: the yaw, seen only through the image's corners, also reads a
// lens's residual distortion) and some pixel moves by at least `min_shift_px`: a perfect rig
// stays untouched.
//
//   StereoSelfCalibration cal;
//   cal.addFrame(left, right, model);          // every frame; it uses every `every_n_frames`-th
//   cal.correctRight(right, right_corrected, model);  // the right image as the rectified rig would see it
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace assistive_description
{
/// The rectified pinhole both images share.
struct RectifiedModel
{
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

class StereoSelfCalibration
{
public:
  struct Options
  {
    int every_n_frames = 5;          ///< the rotation drifts over minutes: one frame in n is enough
    int max_features = 300;          ///< corners per used frame (left image)
    double min_distance_px = 12.0;   ///< between corners
    int max_disparity_px = 128;      ///< row search range
    int max_vertical_px = 3;         ///< rows searched above and below (larger offsets: no match)
    double back_check_px = 0.15;     ///< right -> left must land this close to the corner
    double feature_sigma_px = 0.1;   ///< a matched offset's standard deviation
    bool same_surface = true;        ///< drop corners whose neighbours' disparities disagree (silhouettes)
    double k1_prior = 0.005;         ///< sigma of the residual radial distortion (a calibrated lens's)
    double gate_px = 0.6;            ///< |residual| beyond (or 5 of its sigma): an outlier (mismatch, occlusion)
    int min_inliers = 40;            ///< per frame
    int min_frames = 20;             ///< frame solutions before a correction is considered
    int window_frames = 200;         ///< forgetting window of the frame solutions (used frames)
    double significance = 3.0;       ///< sigma a change must exceed on an axis to be taken
    /// The model's floor per axis (deg, pitch / yaw / roll), added to the estimate's sigma while
    /// the axis is uncorrected: rigs with no rotation but a lens's residual distortion (k1, k2)
    /// read yaws up to 0.017 deg (generated worlds 8101-8104, `render_bag --imperfect` without
    /// the rotation).
    cv::Vec3d sigma_floor_deg = cv::Vec3d(0.002, 0.01, 0.002);
    double min_shift_px = 0.1;       ///< and it must move some pixel at least this much
    double max_rotation_deg = 1.0;   ///< larger estimates are reported, never applied
  };

  /// One matched feature: normalised left coordinates, normalised disparity, vertical offset (px)
  /// and its standard deviation (px).
  struct Observation
  {
    double x = 0, y = 0, delta = 0, dv_px = 0, sigma_px = 0.1;
  };

  StereoSelfCalibration() = default;
  explicit StereoSelfCalibration(const Options& o) : o_(o) {}

  /// A rectified pair as it arrives (with the correction applied, if one is). Returns true when
  /// the frame gave a solution. Counts frames and uses every `every_n_frames`-th.
  bool addFrame(const cv::Mat& left, const cv::Mat& right, const RectifiedModel& model);
  /// One frame's matched features (exposed for tests and other matchers), measured on images of
  /// `size` with the current correction applied: true when it gave a solution.
  bool addObservations(const std::vector<Observation>& obs, const RectifiedModel& model, const cv::Size& size);
  /// The features of one pair: corners in the left image matched along the rows of the right,
  /// refined to sub-pixel in both directions and checked back.
  std::vector<Observation> match(const cv::Mat& left, const cv::Mat& right, const RectifiedModel& model) const;

  /// The estimated rotation of the right camera (rad, about the left optical x, y, z), the
  /// residual distortion k1 and their 1-sigma; valid() once min_frames solutions were averaged.
  bool valid() const { return n_eff_ > 0 && frames_ >= o_.min_frames; }
  cv::Vec3d rotation() const { return cv::Vec3d(mean_[0], mean_[1], mean_[2]); }
  cv::Vec3d rotationSigma() const;
  double k1() const { return mean_[3]; }
  double k1Sigma() const;
  int frameSolutions() const { return frames_; }
  /// The rotation being undone now (rad). Changes only in addFrame / addObservations / setApplied.
  cv::Vec3d applied() const { return applied_; }
  /// Start from a known correction (a persisted one) without waiting for evidence.
  void setApplied(const cv::Vec3d& w) { applied_ = w; }
  /// Why the last estimate was not applied (empty when it was or nothing was due).
  const std::string& status() const { return status_; }
  /// Forget every frame solution (the applied correction stays).
  void reset();

  /// The right image as the rectified rig would see it (a copy when nothing is applied).
  void correctRight(const cv::Mat& right, cv::Mat& out, const RectifiedModel& model) const;
  /// What the driver does to a pair that was rectified without the correction (a bag's): `right`
  /// replaced by its corrected copy, then, when `estimate`, the pair fed to addFrame.
  void correctAndEstimate(const cv::Mat& left, cv::Mat& right, const RectifiedModel& model, bool estimate);
  /// One line: the estimate (deg, pitch / yaw / roll, with its sigma; the residual distortion k1),
  /// the frames, what is applied and why the last estimate was not.
  std::string describe() const;
  /// Homography from a corrected pixel to the pixel of the image as it arrives (for cv::remap or
  /// cv::warpPerspective with WARP_INVERSE_MAP): K R(w)^T K^-1.
  static cv::Matx33d correctionHomography(const cv::Vec3d& w, const RectifiedModel& model);
  /// R(w): folded into the right camera's rectification rotation (R_rect_new = R(w) * R_rect) it
  /// undoes w in the rectification maps themselves (the camera driver does this).
  static cv::Matx33d correctionRotation(const cv::Vec3d& w);
  /// Largest pixel shift over the image between undoing `a` and undoing `b`.
  static double maxShiftPx(const cv::Vec3d& a, const cv::Vec3d& b, const RectifiedModel& model, int width,
                           int height);

private:
  bool solveFrame(const std::vector<Observation>& obs, double fy, cv::Vec4d& w) const;
  /// 1-sigma of the averaged solution's component k (0-2 the rotation, 3 k1); inf before two.
  double meanSigma(int k) const;
  void consider(const RectifiedModel& model, const cv::Size& size);

  Options o_;
  long counter_ = 0;
  int frames_ = 0;
  double n_eff_ = 0;                 // forgetting-weighted count of frame solutions (sum of weights)
  double w2_ = 0;                    // sum of squared weights (the mean's variance)
  cv::Vec4d mean_ = cv::Vec4d::all(0);
  cv::Matx44d scatter_ = cv::Matx44d::zeros();  // weighted sum of squared deviations
  cv::Vec3d applied_ = cv::Vec3d::all(0);
  std::string status_;
};

/// Keeps a correction across runs, per camera (cv::FileStorage YAML: camera, rotation_deg,
/// sigma_deg, frame_solutions). False with a message when the file cannot be written / read, or
/// was written for another camera.
bool saveSelfCalibration(const std::string& path, const std::string& camera, const StereoSelfCalibration& cal,
                         std::string* error = nullptr);
bool loadSelfCalibration(const std::string& path, const std::string& camera, cv::Vec3d& rotation,
                         std::string* error = nullptr);

}  // namespace assistive_description
