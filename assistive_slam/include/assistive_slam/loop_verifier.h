#pragma once
// Geometric verification of a loop-closure candidate (seed 3.2.4: a wrong closure is worse than
// none): descriptor matching (ratio test, mutual), then stereo P3P RANSAC both ways (OpenCV
// solvePnPRansac, SOLVEPNP_AP3P) with enough inliers and the two directions agreeing; or, for single
// images, the epipolar constraint (essential matrix RANSAC). ROS-free (OpenCV, Eigen).
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace assistive_slam
{
/// One keyframe as the verifier sees it: rectified left-image keypoints, one descriptor row per
/// keypoint, and the keypoint's 3D point in the keyframe's camera frame (x right, y down, z
/// forward; NaN where there is no stereo depth), all three of the same length (a keyframe that is
/// not is rejected with a reason). `points` may be empty for the epipolar variant.
struct LoopKeyframe
{
  std::vector<cv::Point2f> keypoints;
  cv::Mat descriptors;
  std::vector<cv::Point3f> points;
};

struct VerifierParams
{
  double ratio = 0.8;                ///< Lowe's ratio test on the two nearest descriptors
  int min_inliers = 25;              ///< RANSAC inliers needed to accept
  double min_inlier_ratio = 0.4;     ///< inliers / matches needed to accept
  double reprojection_px = 2.0;      ///< RANSAC inlier threshold (pixels)
  int ransac_iterations = 1000;
  double confidence = 0.999;
  double max_translation_m = 10.0;   ///< a revisit farther apart than this is not plausible
  /// The pose from query->match PnP and the inverse of match->query PnP must agree this well.
  double consistency_m = 0.10;
  double consistency_deg = 2.0;
  double epipolar_px = 1.5;          ///< essential-matrix RANSAC threshold (pixels)
  int min_inliers_epipolar = 10;     ///< inliers the epipolar variant needs (no 3D to check)
};

struct LoopVerification
{
  bool accepted = false;
  int matches = 0;                   ///< descriptor matches after the ratio test
  int inliers = 0;                   ///< RANSAC inliers of the accepted model
  /// Pose of the query camera in the match camera's frame (x_match = T * x_query). For the
  /// epipolar variant the translation has unit length (scale unknown).
  Eigen::Isometry3d T_match_query = Eigen::Isometry3d::Identity();
  std::string reason;                ///< why it was rejected ("" when accepted)
};

class LoopVerifier
{
public:
  /// K: the rectified left camera matrix shared by both keyframes.
  LoopVerifier(const cv::Matx33d& K, const VerifierParams& params = VerifierParams());
  /// Stereo: both keyframes need 3D points.
  LoopVerification verifyStereo(const LoopKeyframe& query, const LoopKeyframe& match) const;
  /// Single images: essential matrix RANSAC + cheirality (recoverPose); no 3D needed.
  LoopVerification verifyEpipolar(const LoopKeyframe& query, const LoopKeyframe& match) const;
  /// Ratio-test + mutual nearest-neighbour matches (queryIdx: query, trainIdx: match).
  std::vector<cv::DMatch> match(const cv::Mat& query, const cv::Mat& match) const;
  const VerifierParams& params() const { return params_; }

private:
  cv::Matx33d K_;
  VerifierParams params_;
};
}  // namespace assistive_slam
