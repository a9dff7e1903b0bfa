#pragma once
// Dense disparity from a rectified pair with OpenCV's semi-global or block matcher run at a
// configurable scale, and back-projection of the disparity to 3D points in the left optical frame.
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <opencv2/calib3d.hpp>

#include <assistive_obstacles/params.h>

namespace assistive_obstacles
{
/// Rectified pinhole model of the left camera at full resolution.
struct StereoModel
{
  int width = 640;
  int height = 480;
  double fx = 500.0, fy = 500.0, cx = 319.5, cy = 239.5;  ///< px
  double baseline = 0.12;                                ///< m
};

class DisparityEstimator
{
public:
  explicit DisparityEstimator(const ObstaclesParams& p = ObstaclesParams());
  void setParams(const ObstaclesParams& p);
  const ObstaclesParams& params() const { return params_; }

  /// Disparity of `left` (CV_8UC1 or CV_8UC3; converted to grey) at the matcher's scale:
  /// CV_32F, in px AT THAT SCALE, invalid pixels < 0. Returns false on bad input (empty,
  /// size mismatch); `disp` is then empty.
  bool compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disp) const;
  /// Same, resized back to the input resolution and scaled to full-resolution pixels.
  bool computeFullRes(const cv::Mat& left, const cv::Mat& right, cv::Mat& disp) const;

  /// Scale actually used for a given input width (the matcher needs width >= max disparity).
  double scale() const { return params_.disparity_scale; }
  /// Number of disparities at the matcher's scale (multiple of 16).
  int numDisparities() const;

  /// 3D points (left optical frame: x right, y down, z forward) from a disparity at the
  /// matcher's scale; keeps min_depth <= z <= max_depth and every point_stride-th pixel, and
  /// drops pixels on depth discontinuities (3x3 disparity range > edge_filter).
  /// `normals` (optional): per point, the unit normal of the surface (left optical frame, facing
  /// the camera) from the disparity gradient, which is linear in (u, v) on a plane; the viewing
  /// ray reversed where the gradient is not available.
  /// With texture_max_depth_sigma > 0 and `disp` from the last compute(), pixels whose depth error
  /// by the Cramer-Rao bound of their block's texture, Z^2 sigma_d / (fx B) with
  /// sigma_d = sqrt(2 image_noise_sigma^2 / sum(g_x^2)), exceeds it give no point; sum(g_x^2) is
  /// taken less the pixel noise's expected share, and as none below texture_min_snr times that.
  void toPoints(const cv::Mat& disp, const StereoModel& model, std::vector<Eigen::Vector3f>& points,
                std::vector<Eigen::Vector3f>* normals = nullptr) const;

private:
  static Eigen::Vector3f surfaceNormal(const cv::Mat& disp, int u, int v, float fx, float fy, float cx, float cy,
                                       const Eigen::Vector3f& X, float max_curvature);
  ObstaclesParams params_;
  cv::Ptr<cv::StereoMatcher> matcher_;
  mutable cv::Mat l_small_, r_small_, l_grey_, r_grey_, disp16_, dmax_, dmin_;
  mutable cv::Mat texture_;  // sum of squared horizontal gradients over the block, of the last compute()'s left image
};

}  // namespace assistive_obstacles
