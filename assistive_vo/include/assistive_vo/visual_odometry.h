#pragma once
#include <algorithm>
#include <string>
#include <vector>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include "assistive_vo/disparity_offset.h"
#include "assistive_vo/feature_tracker.h"
#include "assistive_vo/frame_stats.h"
#include "assistive_vo/gravity_alignment.h"
#include "assistive_vo/gyro_bias_estimator.h"
#include "assistive_vo/range_aid.h"
#include "assistive_vo/inertial_coasting.h"
#include "assistive_vo/keyframe_manager.h"
#include "assistive_vo/motion_estimator.h"
#include "assistive_vo/motion_refiner.h"
#include "assistive_vo/params.h"
#include "assistive_vo/plausibility.h"
#include "assistive_vo/standing_detector.h"
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
enum class TrackingState
{
  INITIALISING,    ///< no keyframe yet
  TRACKING,
  LOST,            ///< this frame gave no motion estimate (pose predicted)
  REINITIALISING   ///< a new keyframe was started after a failure (pose chain kept)
};
const char* toString(TrackingState s);

struct VoOutput
{
  TrackingState state = TrackingState::INITIALISING;
  bool pose_valid = false;                                 ///< a pose exists (false only before the first frame)
  /// The pose may be guided on. False when lost beyond coast_max_s (or lost without a gyro), on a
  /// frozen camera, while image motion contradicts the gyro or the stereo pair is inconsistent
  /// with the motion (right image out of sync), on the frame after a stamp gap or time
  /// jump and until a new keyframe is tracked again. Untrusted frames carry the last trusted position
  /// (not extrapolated), the orientation the gyro carried on (untrusted_gyro_orientation) and zero
  /// velocities; `untrusted_reason` says why.
  bool pose_trusted = false;
  std::string untrusted_reason;
  Eigen::Isometry3d T_odom_link = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_odom_optical = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> pose_covariance = Eigen::Matrix<double, 6, 6>::Zero();   ///< odom axes
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();   ///< camera_link axes, m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< camera_link axes, rad/s
  Eigen::Matrix<double, 6, 6> twist_covariance = Eigen::Matrix<double, 6, 6>::Identity();
  FrameStats stats;
  std::string message;  ///< why the frame was rejected / lost, empty when fine
};

/// The visual odometry pipeline of seed 2.2.1 (fig. 2.5): FAST corners with stereo depth, KLT
/// frame to frame, RANSAC on the epipolar constraint, P3P-RANSAC (LMedS) against the keyframe's
/// 3D points, two-frame sparse bundle adjustment, replenishment below 35 % of started tracks.
/// Motion is always estimated against the keyframe (the frame the tracks were (re)started in), so
/// drift only accumulates at keyframe changes. On failure the pose is predicted (gyro / constant
/// velocity), a new keyframe is started and the pose chain continues.
/// A coordinator (issue 32): process() runs the parts in order (README "Overview"), each a class
/// of its own: tracking (FeatureTracker: KLT, epipolar RANSAC, stereo, line tracks), keyframes
/// (KeyframeManager: selection and the keyframe's store), pose estimation (MotionEstimator: P3P or
/// point+line RANSAC), refinement (MotionRefiner: two-frame bundle adjustment, point+line
/// refinement), plausibility (checkPlausibility, PlausibilityMonitor), gyro bias
/// (GyroBiasEstimator), gravity (GravityAligner), coasting (InertialCoaster) and the trust of
/// the output, which stay here.
class VisualOdometry
{
public:
  explicit VisualOdometry(const VoParams& p = VoParams(), const StereoCamera& cam = StereoCamera());
  void setParams(const VoParams& p);
  const VoParams& params() const { return p_; }
  /// Changing the camera re-initialises tracking (the pose chain is kept).
  void setCamera(const StereoCamera& cam);
  const StereoCamera& camera() const { return cam_; }
  /// Gravity direction at start ("up", camera_link axes, e.g. the mean accelerometer reading);
  /// used only before the first frame is processed.
  void setInitialUp(const Eigen::Vector3d& up_link);
  /// The accelerometer's "up" (camera_link axes, the mean over a few tenths of a second, e.g.
  /// ImuBuffer::meanAccel) for the next frame only. After a gap or a time jump (bag loop) that
  /// the gyro does not cover, the head's tilt is unknown: once hints have been given, the pose
  /// stays untrusted until the next hint levels it (yaw and position kept; at most
  /// kLevelWaitS), instead of carrying the old tilt, which would make the floor a slope.
  void setGravityHint(const Eigen::Vector3d& up_link);
  /// The gyro's rate (camera_link, rad/s, as measured: the bias is taken out here) around the next
  /// frame's stamp, for its rolling shutter (rolling_shutter_readout); without it the mean rate
  /// since the previous frame. Holds for the next process() only.
  void setGyroRateAtStamp(const Eigen::Vector3d& rate_link);
  static constexpr double kLevelWaitS = 1.0;
  /// Forgets everything, including the pose (next frame is the new origin).
  void reset();

  /// One stereo pair (mono8, rectified, same size). `gyro_link` (optional): rotation of
  /// camera_link from the previous frame to this one (R_prev_cur), integrated from the gyro.
  /// `dv_link` (optional): the accelerometer integrated over the same interval, in camera_link
  /// axes at the previous frame (ImuBuffer::integrate); it keeps the odom frame level.
  /// `dp_link` (optional, with dv_link): the accelerometer integrated twice (ImuBuffer::integrate);
  /// with it a lost frame coasts on the IMU (inertial_coasting.h) instead of a constant-velocity guess.
  VoOutput process(const cv::Mat& left, const cv::Mat& right, double stamp,
                   const Eigen::Quaterniond* gyro_link = nullptr, const Eigen::Vector3d* dv_link = nullptr,
                   const Eigen::Vector3d* dp_link = nullptr);
  /// Inertial coasting (velocity, accelerometer error fitted, coasting time).
  const InertialCoaster& coaster() const { return coast_; }
  /// Standing still from the IMU (no gait): the detector, and whether lost frames hold the position now.
  const StandingDetector& standingDetector() const { return standing_; }
  bool holdingStill() const { return standing_now_; }
  /// Holds started so far (lost frames while standing).
  int standingHolds() const { return standing_holds_; }
  /// Lost frames held standing so far.
  int standingFrames() const { return standing_frames_; }
  /// Stamp gaps (> max_frame_gap_s) bridged on the IMU so far (imu_bridge_gaps): trusted on the coast
  /// rules, or tracked across on the IMU's prediction; the rest re-initialise untrusted.
  int gapsBridged() const { return gaps_bridged_; }
  /// The stereo disparity offset estimated so far (px, added to every disparity).
  double disparityOffset() const { return tracker_.stereo().offset(); }

  /// Flow vectors of the last frame over the left image (BGR): green = inlier, red = rejected.
  cv::Mat drawOverlay(const cv::Mat& left) const;
  int resets() const { return resets_; }
  const FailSafeCounters& failSafe() const { return checks_.counters(); }
  /// One reading of the forward ranger (range_aided_coast): `range` in m, finite and within the
  /// ranger's limits, at `stamp` (s, the images' clock, stamp order); `axis_link` its axis in
  /// camera_link (the URDF's sonar_front x axis). Readings up to a frame's stamp are added before it.
  void addRange(double stamp, double range, const Eigen::Vector3d& axis_link);
  /// Coasted frames whose position the ranger corrected so far.
  int rangeAidedFrames() const { return range_aided_frames_; }
  /// Current gyro bias estimate (camera_link axes, rad/s).
  const Eigen::Vector3d& gyroBias() const { return bias_.bias(); }
  /// Holds the gyro bias at a known value (camera_link, rad/s) instead of estimating it online
  /// (GyroBiasEstimator::fix).
  void setKnownGyroBias(const Eigen::Vector3d& bias_link, double sigma) { bias_.fix(bias_link, sigma); }
  bool started() const { return have_pose_; }
  /// Gravity alignment: tilt of the odom frame measured in the last window (deg) and the windows
  /// accepted / rejected so far.
  const GravityAligner& gravity() const { return gravity_; }

private:
  /// What one frame knows before it is tracked: its timing, the gyro and the predicted motion,
  /// and the fail-safe verdicts so far.
  struct FrameContext
  {
    double stamp = 0.0;
    double dt = 0.0;        ///< step for the motion model (over a gap: the last regular step)
    double dt_real = 0.0;   ///< stamp step as it came (also a gap's)
    bool first = false;     ///< the first frame: the origin of odom
    bool gap = false;       ///< a stamp gap or time jump before this frame (not bridged)
    bool bridged = false;   ///< a stamp gap bridged on the IMU (bridgeGap): tracked on from its prediction
    bool bridge_within = false;  ///< ... within the coast rules: trusted like lost frames if vision fails on it
    std::string gap_why;          ///< the gap's reason (checkTiming), should it be the plain gap after all
    bool have_gyro = false;
    bool have_rate_at_stamp = false;  ///< setGyroRateAtStamp() before this frame
    Eigen::Matrix3d R_gyro_opt = Eigen::Matrix3d::Identity();  ///< bias-corrected gyro, prev -> cur, optical axes
    Eigen::Isometry3d T_pred = Eigen::Isometry3d::Identity();  ///< predicted motion prev -> cur, optical
    bool coast_ok = false;        ///< a lost frame may still coast (mayCoast)
    std::string force_untrusted;  ///< gap / time jump, frozen camera, gyro contradiction, unusable input
    std::string why;              ///< message of the frame
    bool have_imu = false;        ///< the accelerometer's preintegration `imu` is given
    ImuDelta imu;
    bool standing = false;        ///< the IMU shows no gait, at a low speed: a lost frame holds the position
    bool lost_done = false;       ///< T_lost computed (lostMotion)
    Eigen::Isometry3d T_lost = Eigen::Isometry3d::Identity();
  };
  /// Motion of a lost frame (computed once per frame): IMU coasting when the accelerometer is
  /// there and a velocity is known, else the prediction while coasting, else none (the gyro's
  /// rotation only). Coasting grows the pose covariance.
  const Eigen::Isometry3d& lostMotion(FrameContext& fc);
  /// The accelerometer's specific force over the frame interval (odom axes) to the standing
  /// detector; fc.standing: no gait, and (unless holding already) a low speed.
  void detectStanding(FrameContext& fc);
  /// A lost frame while standing: position held (the neck pivot still), rotation from the gyro.
  Eigen::Isometry3d standingMotion(const FrameContext& fc);
  /// The motion of a held frame about the neck pivot `pivot` (odom): the gyro's rotation, no step.
  Eigen::Isometry3d heldMotion(const FrameContext& fc, const Eigen::Vector3d& pivot) const;
  /// The neck pivot (odom) under the current pose.
  Eigen::Vector3d pivotNow() const;
  /// A forward stamp gap that the gyro and the accelerometer cover, with imu_bridge_gaps: marks the
  /// frame `bridged` (fc.gap off, the real interval as its step) so that the IMU carries the pose
  /// over it instead of an untrusted re-initialisation.
  void markBridgeable(FrameContext& fc);
  /// The bridged gap's motion, for the keyframe tracking's prediction: the position held standing,
  /// else IMU-coasted; the gyro's rotation. Within the coast rules (imu_coast_max_s,
  /// imu_coast_max_sigma_m at the gap's end, max_speed_mps) a frame vision loses stays trusted;
  /// beyond them only a tracked frame is (lost: the plain gap, pose kept, untrusted, new keyframe);
  /// without a coast the plain gap at once. Changes no state but fc.
  void bridgeGap(FrameContext& fc);
  /// The standing decision over a bridged gap: its one interval hides any gait, so the stand goes
  /// on only when the test was quiet up to the gap and its velocity change is small.
  void standingOverGap(FrameContext& fc);
  /// Grows the pose covariance over a lost frame whose motion was predicted, not measured.
  void growLostCovariance();
  /// `in` scaled to one mean brightness for the run (out = in when it is off or black).
  void normaliseBrightness(const cv::Mat& in, cv::Mat& out);
  double brightness_ref_ = 0.0;  ///< the mean every image is scaled to (set by the first image)
  /// Sets the coaster's gyro noise and bias error (before a coast starts).
  void setCoastGyro();
  /// The coaster's options with the gyro's noise and bias error (setCoastGyro()).
  InertialCoaster::Options coastGyroOptions() const;
  // ---- frame set-up (process() in order) ----
  /// Camera and image checks; false: `o` is the frame's (untrusted) output.
  bool checkInput(const cv::Mat& left, const cv::Mat& right, FrameStats& st, FrameContext& fc, VoOutput& o);
  /// The first frame: odom's origin from gravity (or initial_roll / initial_pitch).
  void startPose(double stamp);
  /// Stamp gap / time jump (the motion over it is unknown: pose kept, new keyframe, untrusted).
  void checkTiming(FrameContext& fc);
  /// Predicted motion prev -> cur (constant velocity, gyro rotation) and the bias-corrected gyro.
  void predictMotion(const Eigen::Quaterniond* gyro_link, FrameContext& fc, FrameStats& st);
  /// The frame's rolling shutter for the tracker: the gyro's rate at the stamp (or the mean since
  /// the previous frame, or the last frame's vision rate without a gyro) and the last frame's velocity.
  void setRollingShutter(const FrameContext& fc);
  /// Tilt over a gap the gyro does not cover is unknown: level by the accelerometer's next hint
  /// (`have_up_hint`: this frame's setGravityHint()), untrusted until then (at most kLevelWaitS).
  void levelAfterGap(bool have_up_hint, FrameContext& fc);
  /// Turns odom about the current position so that `up_link` points along odom z.
  void levelByGravity(const Eigen::Vector3d& up_link);
  /// Rotates the odom frame by C about `pos` (odom coordinates): the pose there does not jump.
  void turnOdomAbout(const Eigen::Vector3d& pos, const Eigen::Matrix3d& C);
  /// Unusable or frozen images: the frame is lost; true with its output in `o`.
  bool rejectImages(const cv::Mat& left, const cv::Mat& right, FrameContext& fc, FrameStats& st, VoOutput& o);
  /// First frame, a frame after a failure, or a stream gap: a new keyframe here.
  VoOutput restartKeyframe(const cv::Mat& left, const cv::Mat& right, FrameContext& fc, FrameStats& st);

  // ---- keyframe tracking, motion estimation (the parts' glue) ----
  /// A new keyframe at the current pose (KeyframeManager::start).
  void startKeyframe(const cv::Mat& left, const cv::Mat& right, bool from_current_tracks, FrameStats& st);
  /// The gyro since the keyframe joins it; the motion refined with it as a prior (MotionRefiner).
  void refinePose(const FrameContext& fc, const Eigen::Isometry3d& T_kf_pred, FrameStats& st, MotionEstimate& m);
  /// Variance (rad^2 per axis) of the gyro's rotation since the keyframe that a timing offset of
  /// the gyro against the images (gyro_time_sigma) gives: the rate change since the keyframe
  /// times the offset (a lagging gyro is off by 0.7 deg at the end of an 80 deg/s turn whose
  /// keyframe was made at full rate, and exact while the rate holds).
  double gyroTimingVariance() const;
  /// Accepts the estimate: inliers kept (points refined), pose and covariance updated.
  void accept(const MotionEstimate& m, FrameStats& st);

  // ---- plausibility (fail-safe) ----
  /// Median disparity error of the inliers at the estimated pose, share matched.
  void measureStereoConsistency(const MotionEstimate& m, FrameStats& st) const;
  /// Jumps, gyro contradiction, stereo inconsistency: the reason to reject the frame (empty: fine).
  std::string checkPlausibility(const MotionEstimate& m, bool gyro_given, FrameContext& fc, FrameStats& st);
  /// The stereo consistency measured, then checkPlausibility() and the point+line motion's own
  /// checks (against the gyro; none without checked points while the IMU coasts): the reason to
  /// reject the frame (empty: fine).
  std::string judgeMotion(const MotionEstimate& m, bool gyro_given, FrameContext& fc, FrameStats& st);
  VoOutput fail(const std::string& why, const cv::Mat* left, const cv::Mat* right,
                const Eigen::Isometry3d& T_prev_cur_pred, double stamp, FrameStats& st);
  VoOutput makeOutput(TrackingState s, const FrameStats& st, const Eigen::Isometry3d& T_prev_cur, double dt);
  /// Decides pose_trusted for an output (README "Fail-safe"); `force_why`: a reason that makes
  /// the frame untrusted whatever the state (gap, frozen camera, gyro contradiction).
  void applyTrust(VoOutput& o, double stamp, bool coast_ok, const std::string& force_why);
  /// Lost frame: may it still coast (pose predicted and trusted)? When not, `why` says which rule
  /// refused it (the untrusted reason).
  bool mayCoast(double stamp, const FrameContext& fc, std::string& why) const;
  /// A stop seen on the IMU (standing_on_stop): the speed (IMU-coasted, or the last frame's) plus its
  /// 1-sigma within standing_max_speed and no acceleration over this frame (`f_odom`: its specific
  /// force, odom axes): the hold may start before the gait test's window clears the deceleration.
  bool stopSeen(const FrameContext& fc, const Eigen::Vector3d& f_odom) const;
  /// v_imu_ when standing_speed_imu uses it, else null
  const Eigen::Vector3d* imuSpeed() const { return p_.standing_speed_imu && v_imu_valid_ ? &v_imu_ : nullptr; }
  /// Mean absolute difference of the left image to the previous one (every 4th pixel); -1 when
  /// there is no previous image of the same size. Keeps this image for the next frame.
  double imageChange(const cv::Mat& left);
  bool imageUsable(const cv::Mat& img, std::string& why) const;

  // ---- gyro bias, gravity ----
  /// Gyro bias from the keyframe span that ends here at `stamp` (before a new keyframe).
  void updateGyroBias(const MotionEstimate& m, double stamp);
  /// Keeps the odom frame level (about the current position: no jump).
  void levelWithGravity(double stamp, const Eigen::Vector3d* dv_link);

  VoParams p_;
  StereoCamera cam_;
  FeatureTracker tracker_;
  KeyframeManager keyframes_;
  MotionEstimator estimator_;
  MotionRefiner refiner_;
  PlausibilityMonitor checks_;
  GyroBiasEstimator bias_;
  double bias_span_end_stamp_ = -1.0;  ///< where the last span given to bias_ ended (the keyframe it started)

  bool have_pose_ = false;       ///< T_w_cur_ is meaningful
  Eigen::Isometry3d T_odom_o0_ = Eigen::Isometry3d::Identity();  ///< first optical frame in odom
  Eigen::Vector3d up_link_ = Eigen::Vector3d::UnitZ();
  bool have_up_ = false;
  Eigen::Vector3d up_hint_ = Eigen::Vector3d::UnitZ();  ///< setGravityHint(), for one frame
  bool have_up_hint_ = false, hints_seen_ = false;
  bool level_pending_ = false;  ///< tilt unknown since an uncovered gap at level_pending_since_
  double level_pending_since_ = 0.0;
  Eigen::Isometry3d T_w_cur_ = Eigen::Isometry3d::Identity();  ///< w = first optical frame
  Eigen::Isometry3d last_T_prev_cur_ = Eigen::Isometry3d::Identity();
  Eigen::Vector3d gyro_rate_opt_ = Eigen::Vector3d::Zero();  ///< this frame's gyro rate (bias-corrected, optical, rad/s)
  Eigen::Vector3d rate_at_stamp_link_ = Eigen::Vector3d::Zero();  ///< setGyroRateAtStamp(), for one frame
  bool have_rate_at_stamp_ = false;
  double last_dt_ = 0.0;
  Eigen::Matrix<double, 6, 6> cov_cur_ = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 6> cov_rel_ = Eigen::Matrix<double, 6, 6>::Identity();
  double last_stamp_ = 0.0;
  int resets_ = 0;
  TrackingState last_state_ = TrackingState::INITIALISING;
  double last_stamp_pending_ = 0.0;
  GravityAligner gravity_;
  InertialCoaster coast_;
  DisparityOffsetEstimator disp_offset_;
  /// Feeds the disparity offset estimator with the inliers of a tracked frame; applies an estimate.
  void estimateDisparityOffset(const MotionEstimate& m);
  StandingDetector standing_;
  bool standing_now_ = false;       ///< lost frames hold the position (since the hold started)
  /// camera_link's velocity (odom): the last tracked frame's, carried on by the accelerometer over
  /// the frames since (standing_speed_imu: the speed a hold may start from without a coast)
  Eigen::Vector3d v_imu_ = Eigen::Vector3d::Zero();
  bool v_imu_valid_ = false;
  bool standing_held_ = false;      ///< this frame was held standing
  Eigen::Vector3d standing_pivot_ = Eigen::Vector3d::Zero();  ///< odom, the still neck
  double standing_t0_ = 0.0, standing_rot_var_ = 0.0;
  int standing_holds_ = 0, standing_frames_ = 0;
  int gaps_bridged_ = 0;
  std::string coast_why_;     ///< this frame: why a lost frame may not coast (mayCoast, lostMotion)
  bool imu_coasted_ = false;  ///< this frame's pose was coasted on the IMU (covariance already grown)
  /// The ranger's aid to a coast (range_aided_coast): corrects this coasted frame's `dpos` (odom)
  /// along the ranger's axis; returns the position variance the trust rule and the covariance use.
  double aidCoast(double stamp, const Eigen::Matrix3d& R_odom_link, Eigen::Vector3d& dpos);
  RangeAid range_aid_;
  Eigen::Vector3d range_axis_link_ = Eigen::Vector3d::UnitX();
  bool have_range_axis_ = false;
  bool range_aided_ = false;     ///< the last coasted frame was corrected by the ranger
  double range_gate_var_ = 0.0;  ///< ... and its position variance on the worst axis
  int range_aided_frames_ = 0;
  double coast_var_ = 0.0;    ///< position variance the coast has added so far (per axis)
  double coast_rot_var_ = 0.0;  ///< rotation variance the coast has added so far (per axis)
  double trusted_stamp_ = 0.0;  ///< stamp of the last trusted pose (held while untrusted)
  // fail-safe state
  bool untrusted_ = true;             ///< latched until a keyframe is tracked again
  std::string untrusted_why_;
  double last_trusted_stamp_ = 0.0;   ///< stamp of the last tracked (or trusted coasting) frame
  Eigen::Isometry3d trusted_T_odom_optical_ = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> trusted_cov_ = Eigen::Matrix<double, 6, 6>::Zero();
  bool have_trusted_ = false;
  cv::Mat prev_thumb_;                ///< left image of the previous frame, every 4th pixel
};
}  // namespace assistive_vo
