#include "assistive_vo/plausibility.h"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace assistive_vo
{
namespace
{
double angleOf(const Eigen::Matrix3d& R)
{
  return Eigen::AngleAxisd(R).angle();
}
}  // namespace

void PlausibilityMonitor::reset()
{
  frozen_run_ = disagree_run_ = agree_needed_ = stereo_bad_run_ = stereo_agree_needed_ = 0;
  fs_ = FailSafeCounters();
}

std::string PlausibilityMonitor::checkTiming(double dt)
{
  if (!(dt <= 0.0 || dt > p_.max_frame_gap_s))
    return std::string();
  char buf[160];
  if (dt <= 0.0)
  {
    std::snprintf(buf, sizeof(buf), "time went backwards or repeated stamp (%.3f s): pose kept, re-initialising", dt);
    ++fs_.time_jumps;
  }
  else
  {
    std::snprintf(buf, sizeof(buf), "gap of %.2f s in the image stream (> max_frame_gap_s): pose kept, re-initialising",
                  dt);
    ++fs_.gaps;
  }
  return buf;
}

bool PlausibilityMonitor::frozen(double image_change, bool have_gyro, double gyro_rate_dps, std::string& why,
                                 bool& untrusted)
{
  // An unchanged image with a still head is normal (and with a noise-free camera, identical).
  untrusted = false;
  const bool unchanged = image_change >= 0 && image_change <= p_.frozen_max_change;
  if (!unchanged)
    frozen_run_ = 0;
  else if (have_gyro && gyro_rate_dps >= p_.frozen_min_gyro_dps)
    ++frozen_run_;
  if (!(unchanged && frozen_run_ > 0))
    return false;
  char buf[160];
  std::snprintf(buf, sizeof(buf), "frozen camera: image unchanged (%.2f) while the gyro turns %.1f deg/s",
                image_change, std::max(0.0, gyro_rate_dps));
  why = buf;
  if (frozen_run_ >= std::max(1, p_.frozen_frames))
  {
    if (frozen_run_ == std::max(1, p_.frozen_frames))
      ++fs_.frozen;
    untrusted = true;
  }
  return true;
}

std::string PlausibilityMonitor::checkMotion(const Eigen::Isometry3d& T_kf_cur, const Eigen::Isometry3d& T_prev_cur,
                                             const Eigen::Isometry3d& T_pred, double dt, bool strong,
                                             bool gyro_check) const
{
  // Translation: the change against the constant-velocity prediction is bounded by max_speed
  // (a walking head cannot jump; a vehicle moving fast but steadily is fine).
  const double max_t = p_.max_speed_mps * dt + 0.02;
  const double max_r = p_.max_angular_speed_dps * M_PI / 180.0 * dt + 0.02;
  if (!T_kf_cur.matrix().allFinite())
    return "non-finite motion";
  if ((T_prev_cur.translation() - T_pred.translation()).norm() > max_t && !strong)
    return "implausible translation";
  if (angleOf(T_prev_cur.linear()) > max_r)
    return "implausible rotation";
  if (gyro_check && angleOf(T_prev_cur.linear().transpose() * T_pred.linear()) > 0.05 + 0.5 * angleOf(T_pred.linear()))
    return "rotation disagrees with the gyro";
  return std::string();
}

std::string PlausibilityMonitor::checkGyroAgreement(double disagreement_deg)
{
  // A camera loose on the head, the view filled by something moving.
  if (disagreement_deg > p_.gyro_disagreement_deg)
    ++disagree_run_;
  else
  {
    disagree_run_ = 0;
    agree_needed_ = std::max(0, agree_needed_ - 1);
  }
  const int n = std::max(1, p_.gyro_disagreement_frames);
  if (disagree_run_ < n)
    return std::string();
  if (disagree_run_ == n)
    ++fs_.gyro_disagreement;
  agree_needed_ = n;
  char buf[160];
  std::snprintf(buf, sizeof(buf), "image motion contradicts the gyro (%.1f deg on %d frames)", disagreement_deg,
                disagree_run_);
  return buf;
}

void PlausibilityMonitor::noGyro()
{
  disagree_run_ = 0;
  agree_needed_ = std::max(0, agree_needed_ - 1);
}

std::string PlausibilityMonitor::checkStereo(double error_px, double matched_ratio)
{
  // Right image out of sync, camera moved: over stereo_inconsistent_frames tracked frames in a
  // row, or at once when 5 x the threshold.
  const int n = std::max(1, p_.stereo_inconsistent_frames);
  if (error_px > p_.stereo_max_error_px || matched_ratio < p_.stereo_min_matched_ratio)
    stereo_bad_run_ = error_px > 5 * p_.stereo_max_error_px ? std::max(n, stereo_bad_run_ + 1) : stereo_bad_run_ + 1;
  else
  {
    stereo_bad_run_ = 0;
    stereo_agree_needed_ = std::max(0, stereo_agree_needed_ - 1);
  }
  if (stereo_bad_run_ < n)
    return std::string();
  if (stereo_agree_needed_ == 0)
    ++fs_.stereo_inconsistent;
  stereo_agree_needed_ = n;
  char buf[160];
  std::snprintf(buf, sizeof(buf),
                "stereo pair inconsistent: disparity off by %.1f px, %.0f %% matched (right image out of sync?)",
                error_px, 100.0 * matched_ratio);
  return buf;
}

std::string PlausibilityMonitor::pendingReason() const
{
  if (agree_needed_ > 0)
    return "image motion contradicted the gyro: " + std::to_string(agree_needed_) + " agreeing frames to go";
  if (stereo_agree_needed_ > 0)
    return "stereo pair was inconsistent: " + std::to_string(stereo_agree_needed_) + " consistent frames to go";
  return std::string();
}
}  // namespace assistive_vo
