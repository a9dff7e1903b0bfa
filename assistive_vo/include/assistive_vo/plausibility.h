#pragma once
// The VO's fail-safe checks (README "Fail-safe"): stamp gaps and time jumps, a frozen camera, a
// frame-to-frame motion that cannot be, image motion contradicting the gyro and a stereo pair
// inconsistent with the motion. Each check keeps its own run counter, so one bad frame is only
// skipped while a run of them makes the pose untrusted until enough good frames came back.
#include <string>
#include <Eigen/Geometry>
#include "assistive_vo/params.h"

namespace assistive_vo
{
/// Fail-safe event counters (since construction / reset()).
struct FailSafeCounters
{
  int frozen = 0;             ///< frozen-camera episodes detected
  int gyro_disagreement = 0;  ///< episodes of image motion contradicting the gyro
  int gaps = 0;               ///< frames after a stamp gap > max_frame_gap_s
  int time_jumps = 0;         ///< frames whose stamp went backwards (or repeated)
  int stereo_inconsistent = 0;  ///< episodes of a stereo pair inconsistent with the motion (desync)
  int gravity_relevels = 0;   ///< gaps / time jumps the gyro did not cover, levelled by the accelerometer
  int untrusted_frames = 0;   ///< frames output with pose_trusted = false
};

/// Run counters and thresholds of the fail-safe checks. Every check returns the reason that
/// makes the frame untrusted, empty when it passes.
class PlausibilityMonitor
{
public:
  explicit PlausibilityMonitor(const VoParams& p = VoParams()) : p_(p) {}
  void setParams(const VoParams& p) { p_ = p; }
  /// Forgets the runs and the counters.
  void reset();

  /// Stamp step `dt` (s) to the previous frame: a gap longer than max_frame_gap_s or time going
  /// backwards (or repeating). Counted.
  std::string checkTiming(double dt);

  /// Frozen camera: the image does not change (`image_change`, -1 = unknown) while the gyro says
  /// the head turns. True: skip the frame (`why` says so); `untrusted` is set once
  /// frozen_frames such frames came in a row (counted once per episode).
  bool frozen(double image_change, bool have_gyro, double gyro_rate_dps, std::string& why, bool& untrusted);

  /// Frame-to-frame motion `T_prev_cur` (optical) against the prediction `T_pred` over `dt`:
  /// a jump in translation (unless `strong`: a clear majority of the tracks supports it), in
  /// rotation, a non-finite motion (`T_kf_cur` of the estimate) or, with `gyro_check`, a rotation
  /// far from the gyro's. Stateless.
  std::string checkMotion(const Eigen::Isometry3d& T_kf_cur, const Eigen::Isometry3d& T_prev_cur,
                          const Eigen::Isometry3d& T_pred, double dt, bool strong, bool gyro_check) const;

  /// Vision-only frame-to-frame rotation against the gyro's (deg) on a tracked frame: untrusted
  /// on gyro_disagreement_frames in a row; trust returns after as many agreeing frames.
  std::string checkGyroAgreement(double disagreement_deg);
  /// A tracked frame without a gyro: nothing to check against (the pending count runs down).
  void noGyro();

  /// Stereo consistency of a tracked frame: median disparity error of the inliers (px, -1 =
  /// unknown) and the share of them matched in the right image.
  std::string checkStereo(double error_px, double matched_ratio);

  /// Why a tracked frame is still untrusted after a contradiction (empty: trusted).
  std::string pendingReason() const;
  void countUntrusted() { ++fs_.untrusted_frames; }
  void countGravityRelevel() { ++fs_.gravity_relevels; }
  const FailSafeCounters& counters() const { return fs_; }

private:
  VoParams p_;
  FailSafeCounters fs_;
  int frozen_run_ = 0;           ///< unchanged frames while the gyro turned
  int disagree_run_ = 0;         ///< consecutive tracked frames contradicting the gyro
  int agree_needed_ = 0;         ///< agreeing tracked frames still needed after a contradiction
  int stereo_bad_run_ = 0;       ///< consecutive tracked frames with an inconsistent stereo pair
  int stereo_agree_needed_ = 0;  ///< consistent tracked frames still needed after that
};
}  // namespace assistive_vo
