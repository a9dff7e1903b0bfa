#pragma once
// FastSLAM 2.0 over stereo landmarks with active matching (seed 3.1.4, 3.2.1-3.2.2, eqs. 3.16-3.37):
// the metric layer of a submap when `metric_backend` is `fastslam`. The VO's frame-to-frame motion
// with its covariance Q_t is the proposal, refined per particle by the matched landmarks (an EKF on
// the pose, 3.26-3.29); each particle carries its own landmark EKFs (3.32-3.35) in a persistent
// tree, so particles share every landmark they have not updated differently (copy on write).
#include <cstdint>
#include <memory>
#include <random>
#include <unordered_set>
#include <vector>
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include "assistive_slam/keyframe.h"
#include "assistive_slam/params.h"
#include "assistive_slam/pose_graph.h"

namespace assistive_slam
{
using Matrix23d = Eigen::Matrix<double, 2, 3>;
using Matrix26d = Eigen::Matrix<double, 2, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// A persistent array (a binary trie on the key's bits, balanced by construction for dense keys):
/// copying is O(1) (the root is shared), set() copies only the nodes on the key's path that are
/// shared with another copy, O(log N). Single-threaded.
template <class T>
class PersistentArray
{
public:
  const T* get(uint32_t key) const
  {
    if (!root_ || key >= capacity())
      return nullptr;
    const Node* n = root_.get();
    for (int level = depth_ - 1; level >= 0 && n; --level)
      n = n->kid[(key >> level) & 1u].get();
    return n && n->val ? n->val.get() : nullptr;
  }
  void set(uint32_t key, T value)
  {
    if (!root_)
      root_ = std::make_shared<Node>();
    while (key >= capacity())
    {
      auto r = std::make_shared<Node>();
      r->kid[0] = root_;
      root_ = r;
      ++depth_;
    }
    // Copy on write: a node is mutated in place only when this copy alone reaches it.
    bool unique = root_.use_count() == 1;
    if (!unique)
      root_ = std::make_shared<Node>(*root_);
    Node* n = root_.get();
    for (int level = depth_ - 1; level >= 0; --level)
    {
      std::shared_ptr<Node>& k = n->kid[(key >> level) & 1u];
      if (!k)
        k = std::make_shared<Node>();
      else if (!(unique = unique && k.use_count() == 1))
        k = std::make_shared<Node>(*k);
      n = k.get();
    }
    if (!n->val)
      ++size_;
    n->val = std::make_shared<const T>(std::move(value));
  }
  size_t size() const { return size_; }
  void clear()
  {
    root_.reset();
    depth_ = 0;
    size_ = 0;
  }
  /// Distinct trie nodes (values included) over several arrays: what they cost together.
  static size_t distinctNodes(const std::vector<const PersistentArray*>& arrays);

private:
  struct Node
  {
    std::shared_ptr<Node> kid[2];
    std::shared_ptr<const T> val;
  };
  uint64_t capacity() const { return uint64_t(1) << depth_; }
  std::shared_ptr<Node> root_;
  int depth_ = 0;
  size_t size_ = 0;
};

/// One landmark's EKF in a particle: position in the filter's world and its covariance.
struct LandmarkEstimate
{
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Identity();
};

/// Stereo point and its covariance by first-order propagation of pixel and disparity noise (eqs.
/// 3.18-3.21). `u`, `v`: left pixel, `d`: disparity (px). False when d <= 0.
bool stereoPoint(const StereoModel& cam, double u, double v, double d, double sigma_px, double sigma_d,
                 Eigen::Vector3d* X, Eigen::Matrix3d* cov);

/// Left-image projection h(s, theta) of a world point for camera pose T_w_c (left optical frame in
/// the world) with its Jacobians: the pose is perturbed on the right, T = T_w_c * Exp([rho, omega])
/// (rho, omega in camera axes, the order of Q_t: x y z rotx roty rotz). False behind the camera.
bool projectWithJacobians(const StereoModel& cam, const Eigen::Isometry3d& T_w_c, const Eigen::Vector3d& X,
                          Eigen::Vector2d* z, Matrix26d* H_s, Matrix23d* H_theta);

/// T * Exp(delta) (delta = [rho, omega], the right perturbation above).
Eigen::Isometry3d applyPerturbation(const Eigen::Isometry3d& T, const Vector6d& delta);

/// Landmark EKF update (3.32-3.35) with a left-image measurement z, noise R = sigma^2 I.
LandmarkEstimate updateLandmark(const LandmarkEstimate& prior, const StereoModel& cam, const Eigen::Isometry3d& T_w_c,
                                const Eigen::Vector2d& z, double sigma_px);

/// One matched observation for the proposal: the measurement and the particle's landmark.
struct PoseObservation
{
  Eigen::Vector2d z;
  LandmarkEstimate landmark;
};

/// The FastSLAM 2.0 proposal of one particle (3.26-3.31): the predicted pose's Gaussian N(T_pred, Q)
/// refined by each observation in turn (EKF on the pose, relinearised at the running mean), and the
/// log of the weight 3.31 (sum of log N(z - h; L_i), L_i of 3.30 at the running estimate).
struct ProposalResult
{
  Eigen::Isometry3d mean = Eigen::Isometry3d::Identity();
  Matrix6d cov = Matrix6d::Identity();  ///< of the right perturbation of `mean`
  double log_weight = 0;
  int used = 0;
};
ProposalResult fastslamProposal(const StereoModel& cam, const Eigen::Isometry3d& T_pred, const Matrix6d& Q,
                                const std::vector<PoseObservation>& obs, double sigma_px);

/// Normalised weights from log weights: the maximum is subtracted before exponentiation (seed
/// 3.2.1.4), so log weights of -1e4 do not underflow to 0 / 0.
std::vector<double> normaliseLogWeights(const std::vector<double>& log_w);
/// N_eff = 1 / sum w^2 of normalised weights (3.16).
double effectiveSampleSize(const std::vector<double>& w);
/// Systematic resampling: n indices with one uniform offset u0 in [0, 1/n).
std::vector<int> systematicResample(const std::vector<double>& w, double u0);

/// A search window: a Gaussian in the image (mean, covariance).
struct SearchWindow
{
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov = Eigen::Matrix2d::Identity();
  /// Inside at squared Mahalanobis distance `chi2`.
  bool contains(const Eigen::Vector2d& p, double chi2) const
  {
    const Eigen::Vector2d d = p - mean;
    return d.dot(cov.ldlt().solve(d)) <= chi2;
  }
};
/// The per-particle projections N(mu_j, Lambda_j) (3.36-3.37) fused into one Gaussian: the mean and
/// covariance of their mixture with the given weights (uniform when empty).
SearchWindow fuseProjections(const std::vector<Eigen::Vector2d>& mu, const std::vector<Eigen::Matrix2d>& cov,
                             const std::vector<double>& w = {});
/// Squared Mahalanobis radius of a 2-D Gaussian holding `confidence` of its mass.
inline double chi2Radius2d(double confidence) { return -2.0 * std::log(1.0 - confidence); }

/// Template matching inside a window: the pixel maximising the normalised cross-correlation of
/// `tmpl` (square, odd side, CV_32F) with `image` (mono8) among the pixels inside `win` at `chi2`
/// (subpixel by a parabola through the neighbours). Returns the best NCC (-2 when none searched).
double matchInWindow(const cv::Mat& image, const cv::Mat& tmpl, const SearchWindow& win, double chi2,
                     Eigen::Vector2d* best, int* searched = nullptr);

/// The template as the current camera should see it: `ref` (square CV_32F patch centred on the
/// landmark in its first image) warped by the 2x2 affine map A (current pixel offsets -> reference
/// pixel offsets), `side` x `side`. False when the warp leaves the reference patch.
bool warpTemplate(const cv::Mat& ref, const Eigen::Matrix2d& A, int side, cv::Mat* out);
/// A of warpTemplate from the plane through the landmark with normal n (world): the homography the
/// plane induces between the reference camera and the current one, linearised at the landmark.
Eigen::Matrix2d patchAffine(const StereoModel& cam, const Eigen::Isometry3d& T_w_ref, const Eigen::Isometry3d& T_w_cur,
                            const Eigen::Vector3d& X_w, const Eigen::Vector3d& n_w);

/// What happened on a frame (for the benchmark's truth check and the statistics).
struct FastSlamMatch
{
  uint32_t landmark = 0;
  Eigen::Vector2d z = Eigen::Vector2d::Zero();
  double ncc = 0;
};
struct FastSlamInit
{
  uint32_t landmark = 0;
  Eigen::Vector3d X_cam = Eigen::Vector3d::Zero();  ///< stereo point in the left optical frame
};
struct FastSlamStats
{
  int frames = 0, particles = 0, landmarks = 0, landmarks_total = 0, resamplings = 0, resets = 0;
  int candidates_last = 0, matches_last = 0;
  long matches_total = 0, candidates_total = 0;
  int revisits = 0, refound = 0;  ///< landmarks back in view after >= 30 frames out of it / matched again then
  double neff_last = 0;
};

/// The filter. Its world starts at the first frame's VO pose; it is reset (one pose, empty maps)
/// when the wearer is `submap_max_extent` from where it was last reset, like a submap.
class FastSlam
{
public:
  FastSlam(const SlamParams& p, const StereoModel& cam);
  /// One frame: `T_odom_cam` the VO pose, `Q_rel` the covariance of the VO's motion since the last
  /// frame passed here (right perturbation, camera axes; zero: the floor alone).
  void process(const cv::Mat& left, const cv::Mat& right, const Eigen::Isometry3d& T_odom_cam, const Matrix6d& Q_rel);
  /// The filter's pose of the left optical frame (weighted mean of the particles).
  Eigen::Isometry3d pose() const { return mean_; }
  bool started() const { return started_; }
  const FastSlamStats& stats() const { return stats_; }
  const std::vector<FastSlamMatch>& lastMatches() const { return matches_; }
  const std::vector<FastSlamInit>& lastInits() const { return inits_; }
  /// Distinct landmark-tree nodes over all particles (what copy on write leaves shared), O(nodes).
  size_t mapNodes() const;

private:
  struct Particle
  {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    double log_w = 0;
    PersistentArray<LandmarkEstimate> map;
  };
  struct Info  ///< what particles share about a landmark: its template and patch plane
  {
    cv::Mat ref;  ///< CV_32F patch around the first observation
    Eigen::Isometry3d T_w_ref = Eigen::Isometry3d::Identity();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< world
    int last_candidate = -1000, last_match = -1000;
    bool revisit_pending = false;
  };
  void reset(const Eigen::Isometry3d& T);
  void addLandmarks(const cv::Mat& left, const cv::Mat& right, const std::vector<Eigen::Vector2d>& taken);
  bool stereoMatch(const cv::Mat& left, const cv::Mat& right, double u, double v, double* d) const;
  void updateMean();
  // The steps of process(), in order.
  /// The landmarks to search for this frame, from the most likely particle's map (projected
  /// inside the image): revisits first, then by the size of their search window; at most
  /// fastslam_max_matches.
  std::vector<uint32_t> searchOrder(const cv::Mat& left, const Eigen::Isometry3d& pred_best, size_t best,
                                    const Matrix6d& Q);
  /// The innovation covariance of a landmark's projection (eq. 3.37).
  Eigen::Matrix2d projectionCov(const LandmarkEstimate& l, const Matrix26d& Hs, const Matrix23d& Ht,
                                const Matrix6d& Q) const;
  /// Active matching: each candidate searched in the window the particles' projections fuse into.
  void matchLandmarks(const cv::Mat& left, const std::vector<Eigen::Isometry3d>& pred, size_t best,
                      const Matrix6d& Q, std::vector<uint32_t>& matched_keys, std::vector<Eigen::Vector2d>& matched_z,
                      std::vector<Eigen::Vector2d>& taken);
  void sampleParticles(const std::vector<Eigen::Isometry3d>& pred, const Matrix6d& Q,
                       const std::vector<uint32_t>& matched_keys, const std::vector<Eigen::Vector2d>& matched_z);
  void resampleIfDegenerate();  ///< resampling below fastslam_resample_neff
  void countMap();              ///< the particle and landmark counts of stats_

  SlamParams p_;
  StereoModel cam_;
  std::mt19937_64 rng_;
  std::vector<Particle> particles_;
  std::vector<Info> infos_;  ///< by landmark id - id_base_
  uint32_t id_base_ = 0;
  bool started_ = false;
  Eigen::Isometry3d last_odom_ = Eigen::Isometry3d::Identity(), mean_ = Eigen::Isometry3d::Identity(),
                    origin_ = Eigen::Isometry3d::Identity();
  FastSlamStats stats_;
  std::vector<FastSlamMatch> matches_;
  std::vector<FastSlamInit> inits_;
};

template <class T>
size_t PersistentArray<T>::distinctNodes(const std::vector<const PersistentArray*>& arrays)
{
  std::unordered_set<const void*> seen;
  std::vector<const Node*> stack;
  for (const PersistentArray* a : arrays)
    if (a && a->root_)
      stack.push_back(a->root_.get());
  while (!stack.empty())
  {
    const Node* n = stack.back();
    stack.pop_back();
    if (!seen.insert(n).second)
      continue;  // shared: its subtree is counted already
    if (n->val)
      seen.insert(n->val.get());
    for (const auto& k : n->kid)
      if (k)
        stack.push_back(k.get());
  }
  return seen.size();
}

}  // namespace assistive_slam
