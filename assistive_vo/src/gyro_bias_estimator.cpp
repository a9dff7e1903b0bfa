#include "assistive_vo/gyro_bias_estimator.h"
#include <algorithm>
#include <cmath>
#include "assistive_vo/frames.h"

namespace assistive_vo
{
void GyroBiasEstimator::reset()
{
  bias_link_ = fixed_ ? fixed_bias_ : Eigen::Vector3d::Zero();
  var_ = fixed_ ? fixed_var_ : -1.0;
}

void GyroBiasEstimator::fix(const Eigen::Vector3d& bias_link, double sigma)
{
  fixed_ = true;
  fixed_bias_ = bias_link_ = bias_link;
  fixed_var_ = var_ = sigma * sigma;
}

void GyroBiasEstimator::initialise()
{
  if (var_ < 0)
    var_ = p_.gyro_bias_sigma * p_.gyro_bias_sigma;
}

Eigen::Matrix3d GyroBiasEstimator::correct(const Eigen::Quaterniond& R_meas_link, double dt) const
{
  const Eigen::Vector3d bdt = bias_link_ * dt;
  return R_meas_link.normalized().toRotationMatrix() *
         (bdt.norm() > 0 ? Eigen::AngleAxisd(-bdt.norm(), bdt.normalized()).toRotationMatrix()
                         : Eigen::Matrix3d::Identity());
}

double GyroBiasEstimator::rotationVariance(double span_s) const
{
  return p_.gyro_noise_density * p_.gyro_noise_density * span_s + var_ * span_s * span_s + 1e-10;
}

void GyroBiasEstimator::update(const Eigen::Matrix3d& R_vision_opt, const Eigen::Matrix3d& R_gyro_opt, double span_s,
                               double vision_rot_var)
{
  if (fixed_)
    return;
  const Eigen::AngleAxisd aa(R_vision_opt.transpose() * R_gyro_opt);
  const Eigen::Vector3d b_err = R_link_optical() * (aa.angle() * aa.axis()) / span_s;
  const double s_vo = std::max(p_.vo_rotation_sigma, std::sqrt(std::max(0.0, vision_rot_var)));
  const double var_m = s_vo * s_vo / (span_s * span_s);
  const double K = var_ / (var_ + var_m);
  if (b_err.allFinite() && b_err.norm() < 0.1)
  {
    bias_link_ += K * b_err;
    var_ = (1 - K) * var_ + p_.gyro_bias_walk * p_.gyro_bias_walk * span_s;
  }
}
}  // namespace assistive_vo
