#pragma once
// Affine alignment of a keyframe patch into the current image (inverse compositional
// Lucas-Kanade, Baker & Matthews 2004, with gain/offset normalisation).
//
// Why: frame-to-frame KLT (translation only) is biased when the patch is scaled or sheared, which
// is what walking forward does to every patch (about 0.3 px per frame on the simulated course),
// and chaining frame-to-frame tracks turns that into a random walk (about 1 px after 10 frames)
// whose mean over the image biases the rotation. Aligning the patch as it looked in the keyframe,
// with an affine warp, removes both: the error no longer accumulates over the keyframe span.
#include <memory>
#include <vector>
#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace assistive_vo
{
class KeyframePatch
{
public:
  /// Template of (2 half + 1)^2 pixels around `p` in `img` (mono8), with its precomputed
  /// steepest-descent images and inverse Hessian. Null when `p` is too close to the border or the
  /// patch is too flat to constrain an affine warp.
  static std::shared_ptr<const KeyframePatch> extract(const cv::Mat& img, const cv::Point2f& p, int half,
                                                      float min_eigen_ratio = 1e-3f);

  /// Refines `c` (patch centre in `img`) and `A` (patch axes in `img`: x_img = c + A x_patch) from
  /// their initial values. False when it does not converge within `iterations`, leaves the image,
  /// or the warp degenerates; `c` and `A` are then unchanged. `ncc`: normalised cross-correlation
  /// of the aligned patch with the template (1 = identical up to gain and offset).
  bool align(const cv::Mat& img, cv::Point2f& c, Eigen::Matrix2f& A, int iterations, float* ncc = nullptr) const;

  int half() const { return half_; }

private:
  int half_ = 0;
  std::vector<float> t_;                    // zero-mean template
  float t_norm_ = 0.f;                      // its L2 norm
  std::vector<Eigen::Matrix<float, 6, 1>> sd_;  // steepest-descent rows
  Eigen::Matrix<float, 6, 6> h_inv_;
};
}  // namespace assistive_vo
