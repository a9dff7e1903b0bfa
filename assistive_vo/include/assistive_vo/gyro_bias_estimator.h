#pragma once
// Online gyro bias (seed 2.2.1, gyro prior): the vision rotation over a keyframe span against
// the integrated gyro, a scalar Kalman update per span (R_vision^T R_gyro ~ exp((b - b_est) dt)).
#include <Eigen/Geometry>
#include "assistive_vo/params.h"

namespace assistive_vo
{
class GyroBiasEstimator
{
public:
  explicit GyroBiasEstimator(const VoParams& p = VoParams()) : p_(p) {}
  void setParams(const VoParams& p) { p_ = p; }
  /// Forgets the estimate (bias 0, variance not initialised).
  void reset();
  /// Starts the variance at gyro_bias_sigma^2 unless it runs already.
  void initialise();
  /// A bias known beforehand (camera_link, rad/s; `sigma` its uncertainty): held from now on, no
  /// update changes it, reset() keeps it. An analysis of what the online estimate costs
  /// (`vo_benchmark --bias-known`, issue 34), or a bias calibrated elsewhere.
  void fix(const Eigen::Vector3d& bias_link, double sigma);
  bool fixed() const { return fixed_; }

  /// The gyro's rotation of camera_link over `dt` s (R_prev_cur, as integrated) with the bias
  /// taken out: R_meas * exp(-b dt) (body frame).
  Eigen::Matrix3d correct(const Eigen::Quaterniond& R_meas_link, double dt) const;
  /// Variance (rad^2) of the bias-corrected gyro rotation integrated over `span_s`: angle random
  /// walk plus the bias uncertainty (the weight of the gyro prior).
  double rotationVariance(double span_s) const;
  /// Update from one keyframe span of `span_s` s: `R_vision_opt` and `R_gyro_opt` are the vision
  /// and the (bias-corrected) gyro rotation keyframe -> current (optical axes), `vision_rot_var`
  /// the vision rotation's variance per axis (rad^2; floored by vo_rotation_sigma). An error
  /// above 0.1 rad/s is no bias and is ignored.
  void update(const Eigen::Matrix3d& R_vision_opt, const Eigen::Matrix3d& R_gyro_opt, double span_s,
              double vision_rot_var);

  /// One keyframe span, as update() takes it, for spans of any length: a span over
  /// gyro_bias_min_span is one update; a shorter one is chained with the short spans that follow
  /// it (rotations composed, variances added) until the chain lasts that long, then the chain is
  /// one update (a long span drops the chain before it); a chain of three spans
  /// or more counts only while the estimate is less sure than gyro_bias_chain_sigma, with that
  /// sigma added (gyro_bias_chain_spans false: short spans are dropped). `continues`: this span
  /// starts where the last one given ended (no loss, no restart between); else the chain so far is
  /// dropped. Why: in a plain room keyframes come every 1-3 frames, no single span lasts long enough
  /// for the bias to show, and without the chain the estimate never moves (issue 34).
  void addSpan(const Eigen::Matrix3d& R_vision_opt, const Eigen::Matrix3d& R_gyro_opt, double span_s,
               double vision_rot_var, bool continues);
  /// Drops a chain of short spans (a loss: the next span does not continue it).
  void breakChain() { chain_spans_ = 0; }

  /// Bias estimate (camera_link axes, rad/s) and its variance (< 0: not initialised).
  const Eigen::Vector3d& bias() const { return bias_link_; }
  double variance() const { return var_; }

private:
  VoParams p_;
  Eigen::Vector3d bias_link_ = Eigen::Vector3d::Zero();
  double var_ = -1.0;
  bool fixed_ = false;
  Eigen::Vector3d fixed_bias_ = Eigen::Vector3d::Zero();
  double fixed_var_ = 0.0;
  // short spans chained (addSpan): keyframe of the chain's start -> the last span's end
  Eigen::Matrix3d chain_R_vision_ = Eigen::Matrix3d::Identity(), chain_R_gyro_ = Eigen::Matrix3d::Identity();
  static constexpr int kSpansOfASystematicChain = 3;
  double chain_s_ = 0.0, chain_var_ = 0.0;
  int chain_spans_ = 0;  ///< 0: no chain
};
}  // namespace assistive_vo
