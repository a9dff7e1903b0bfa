#include "assistive_vo/visual_odometry.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include "assistive_vo/frames.h"
#include "cpu_clock.h"

namespace assistive_vo
{
using internal::Clock;
using internal::angleOf;
using internal::msSince;

namespace
{
Eigen::Matrix<double, 6, 6> rotateCov(const Eigen::Matrix<double, 6, 6>& c, const Eigen::Matrix3d& R)
{
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  A.topLeftCorner<3, 3>() = R;
  A.bottomRightCorner<3, 3>() = R;
  return A * c * A.transpose();
}
/// The same pose for camera_link instead of the optical frame.
Eigen::Isometry3d linkPose(const Eigen::Isometry3d& T_x_optical)
{
  Eigen::Isometry3d T = T_x_optical;
  T.linear() = T_x_optical.linear() * R_link_optical().transpose();
  return T;
}
/// The speed a standing hold may start from: the IMU-coasted velocity while coasting, else the
/// last frame's motion over its interval (0 before any).
double knownSpeed(const InertialCoaster& coast, const Eigen::Isometry3d& T_prev_cur, double dt, const Eigen::Vector3d* v_imu)
{
  if (coast.coasting())
    return coast.velocity().norm();
  if (v_imu)
    return v_imu->norm();
  return dt > 1e-6 ? T_prev_cur.translation().norm() / dt : 0.0;
}

InertialCoaster::Options coastOptions(const VoParams& p)
{
  InertialCoaster::Options o;
  o.window_s = p.imu_coast_window_s;
  o.accel_noise_density = p.accel_noise_density;
  o.accel_error_sigma = p.accel_error_sigma;
  o.gyro_noise_density = p.gyro_noise_density;
  o.carry_velocity = p.imu_coast_carry;
  return o;
}
RangeAid::Options rangeAidOptions(const VoParams& p)
{
  RangeAid::Options o;
  o.sigma_m = p.range_aid_sigma_m;
  o.model_rel = p.range_aid_model_rel;
  return o;
}
StandingDetector::Options standingOptions(const VoParams& p)
{
  StandingDetector::Options o;
  o.window_s = p.standing_window_s;
  o.max_accel_sigma = p.standing_max_accel_sigma;
  return o;
}
GravityAligner::Options gravityOptions(const VoParams& p)
{
  GravityAligner::Options o;
  o.window_s = p.gravity_window_s;
  o.time_constant_s = p.gravity_time_constant_s;
  return o;
}
}  // namespace

const char* toString(TrackingState s)
{
  switch (s)
  {
    case TrackingState::INITIALISING: return "initialising";
    case TrackingState::TRACKING: return "tracking";
    case TrackingState::LOST: return "lost";
    case TrackingState::REINITIALISING: return "re-initialising";
  }
  return "?";
}

VisualOdometry::VisualOdometry(const VoParams& p, const StereoCamera& cam)
  : p_(p), cam_(cam), tracker_(p, cam), keyframes_(p, cam), estimator_(p, cam), refiner_(p, cam), checks_(p),
    bias_(p), gravity_(gravityOptions(p)), coast_(coastOptions(p)), standing_(standingOptions(p)),
    range_aid_(rangeAidOptions(p))
{
}

void VisualOdometry::setParams(const VoParams& p)
{
  p_ = p;
  gravity_.setOptions(gravityOptions(p));
  coast_.setOptions(coastOptions(p));
  range_aid_.setOptions(rangeAidOptions(p));
  standing_.setOptions(standingOptions(p));
  tracker_.setParams(p);
  keyframes_.setParams(p);
  estimator_.setParams(p);
  refiner_.setParams(p);
  checks_.setParams(p);
  bias_.setParams(p);
}

void VisualOdometry::setCamera(const StereoCamera& cam)
{
  cam_ = cam;
  tracker_.setCamera(cam);
  keyframes_.setCamera(cam);
  estimator_.setCamera(cam);
  refiner_.setCamera(cam);
  keyframes_.invalidate();
  tracker_.points().clear();
}

void VisualOdometry::setInitialUp(const Eigen::Vector3d& up_link)
{
  if (up_link.allFinite() && up_link.norm() > 1e-6)
  {
    up_link_ = up_link;
    have_up_ = true;
  }
}

void VisualOdometry::setGravityHint(const Eigen::Vector3d& up_link)
{
  have_up_hint_ = up_link.allFinite() && up_link.norm() > 1e-6;
  if (have_up_hint_)
    up_hint_ = up_link;
  hints_seen_ = hints_seen_ || have_up_hint_;
}

void VisualOdometry::setGyroRateAtStamp(const Eigen::Vector3d& rate_link)
{
  have_rate_at_stamp_ = rate_link.allFinite();
  if (have_rate_at_stamp_)
    rate_at_stamp_link_ = rate_link;
}

void VisualOdometry::levelByGravity(const Eigen::Vector3d& up_link)
{
  const Eigen::Isometry3d T_odom_link = linkPose(T_odom_o0_ * T_w_cur_);
  const Eigen::Vector3d up_odom = T_odom_link.linear() * up_link.normalized();
  // the smallest rotation taking the measured up to odom z: a tilt about a horizontal axis (yaw kept)
  turnOdomAbout(T_odom_link.translation(),
                Eigen::Quaterniond::FromTwoVectors(up_odom, Eigen::Vector3d::UnitZ()).toRotationMatrix());
}

void VisualOdometry::turnOdomAbout(const Eigen::Vector3d& pos, const Eigen::Matrix3d& C)
{
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = C;
  M.translation() = pos - C * pos;
  T_odom_o0_ = M * T_odom_o0_;
}

void VisualOdometry::reset()
{
  have_pose_ = false;
  keyframes_.reset();
  tracker_.reset();
  T_w_cur_ = last_T_prev_cur_ = Eigen::Isometry3d::Identity();
  cov_cur_.setZero();
  resets_ = 0;
  last_dt_ = 0;
  bias_.reset();
  gravity_.clear();
  coast_.clear();
  standing_.clear();
  standing_now_ = v_imu_valid_ = false;
  standing_holds_ = standing_frames_ = 0;
  gaps_bridged_ = 0;
  untrusted_ = true;
  untrusted_why_.clear();
  have_trusted_ = false;
  prev_thumb_.release();
  level_pending_ = have_up_hint_ = false;
  checks_.reset();
}

bool VisualOdometry::mayCoast(double stamp, const FrameContext& fc, std::string& why) const
{
  // Coasting is a guess: only with the gyro bounding the rotation, only briefly, and never once
  // the pose has become untrusted (it stays so until a keyframe is tracked again). With the
  // accelerometer preintegrated and a velocity fitted, longer: while the position's uncertainty
  // stays small.
  why.clear();
  if (!fc.have_gyro)
  {
    why = p_.use_imu ? "lost without the gyro on this frame (no IMU samples over it)" : "lost without a gyro to coast on";
    return false;
  }
  if (!(have_trusted_ && !untrusted_))
  {
    why = "lost while not trusted";
    return false;
  }
  if (fc.standing)
    return true;  // standing (no gait, slow): the position is held, however long vision is blind
  const double since = stamp - last_trusted_stamp_;
  if (fc.have_imu && coast_.available())
  {
    if (since > p_.imu_coast_max_s + 1e-6)
      why = "lost for longer than imu_coast_max_s";
    else if (coast_.coasting() && (range_aided_ ? range_gate_var_ : coast_.positionVariance(since)) >
                                      p_.imu_coast_max_sigma_m * p_.imu_coast_max_sigma_m)
      why = "IMU-coasted position 1-sigma beyond imu_coast_max_sigma";
    return why.empty();
  }
  if (since > p_.coast_max_s + 1e-6)
    why = std::string("lost for longer than coast_max_s") +
          (fc.have_imu ? " (no IMU coast: too few tracked frames to fit its velocity)" : " (no accelerometer)");
  return why.empty();
}

bool VisualOdometry::stopSeen(const FrameContext& fc, const Eigen::Vector3d& f_odom) const
{
  if (!(p_.standing_on_stop && fc.have_imu))
    return false;
  double speed = 0.0, sigma = 0.0;
  if (coast_.coasting())
  {
    speed = coast_.velocity().norm();
    sigma = std::sqrt(std::max(0.0, coast_.velocityVariance(coast_.coastTime())));
  }
  else if (imuSpeed())
    speed = imuSpeed()->norm();  // the last tracked frame's velocity, carried on by the accelerometer
  else if (last_state_ == TrackingState::TRACKING && last_dt_ > 1e-6)
    speed = last_T_prev_cur_.translation().norm() / last_dt_;  // measured on the last frame (not a lost frame's guess)
  else
    return false;
  const Eigen::Vector3d accel = f_odom - Eigen::Vector3d(0.0, 0.0, coastOptions(p_).gravity);
  return speed + sigma <= p_.standing_max_speed && accel.norm() <= p_.standing_max_accel_sigma;
}

double VisualOdometry::imageChange(const cv::Mat& left)
{
  cv::Mat thumb((left.rows + 3) / 4, (left.cols + 3) / 4, CV_8UC1);
  for (int y = 0; y < thumb.rows; ++y)
  {
    const uint8_t* src = left.ptr<uint8_t>(4 * y);
    uint8_t* dst = thumb.ptr<uint8_t>(y);
    for (int x = 0; x < thumb.cols; ++x)
      dst[x] = src[4 * x];
  }
  double change = -1;
  if (!prev_thumb_.empty() && prev_thumb_.size() == thumb.size())
    change = cv::norm(thumb, prev_thumb_, cv::NORM_L1) / static_cast<double>(thumb.total());
  prev_thumb_ = thumb;
  return change;
}

void VisualOdometry::applyTrust(VoOutput& o, double stamp, bool coast_ok, const std::string& force_why)
{
  std::string why = force_why;
  if (!o.pose_valid)
    why = "no pose yet";
  else if (why.empty())
  {
    if (o.state == TrackingState::TRACKING)
      why = checks_.pendingReason();
    else if (o.state == TrackingState::INITIALISING)
      why = "no keyframe yet";
    else if (!coast_ok)
      why = untrusted_ && !untrusted_why_.empty()
                ? untrusted_why_
                : (coast_why_.empty() ? std::string(p_.use_imu ? "lost for longer than coast_max_s"
                                                               : "lost without a gyro to coast on")
                                      : coast_why_) +
                      (o.message.empty() ? "" : " (" + o.message + ")");
  }
  if (why.empty())
  {
    o.pose_trusted = true;
    untrusted_ = false;
    untrusted_why_.clear();
    if (o.state == TrackingState::TRACKING || standing_held_)
      last_trusted_stamp_ = stamp;  // coasting frames do not extend the coast window; held ones do (v = 0 known)
    trusted_T_odom_optical_ = o.T_odom_optical;
    trusted_cov_ = o.pose_covariance;
    trusted_stamp_ = stamp;
    have_trusted_ = true;
    return;
  }
  // Untrusted: the last trusted pose, not a guess; no velocity.
  o.pose_trusted = false;
  o.untrusted_reason = why;
  if (o.pose_valid)
  {
    untrusted_ = true;
    untrusted_why_ = why;
    checks_.countUntrusted();
  }
  if (have_trusted_)
  {
    // The position is the last trusted one; with untrusted_gyro_orientation the orientation is
    // the current one: lost frames carry it on the gyro (lostMotion), so it never restarts at a
    // loss, a re-initialisation or a hold. Holding the old one while the head turned on made every
    // untrusted frame of a turn a rotation error of the whole turn (issue 34: generated home 45,
    // 96 % of its 0.91 deg/m rotational drift, 41x the gyro's floor).
    const Eigen::Matrix3d R_now = o.T_odom_optical.linear();
    const bool keep_rotation = p_.untrusted_gyro_orientation && o.pose_valid && R_now.allFinite();
    o.T_odom_optical = trusted_T_odom_optical_;
    if (keep_rotation)
      o.T_odom_optical.linear() = R_now;
    o.T_odom_link = linkPose(o.T_odom_optical);
    // The held pose is where the wearer was: where they are now is known only to within how far
    // they can have walked (max_speed) and turned (max_angular_speed, up to any heading) since.
    const double since = std::max(0.0, stamp - trusted_stamp_);
    const double reach = p_.max_speed_mps * since, turn = std::min(M_PI, p_.max_angular_speed_dps * M_PI / 180.0 * since);
    o.pose_covariance = trusted_cov_;
    o.pose_covariance.topLeftCorner<3, 3>() += Eigen::Matrix3d::Identity() * reach * reach;
    o.pose_covariance.bottomRightCorner<3, 3>() += Eigen::Matrix3d::Identity() * turn * turn;
  }
  // no velocity: zero, with the variance of any speed the wearer may have
  o.linear_velocity.setZero();
  o.angular_velocity.setZero();
  o.twist_covariance.setZero();
  o.twist_covariance.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() * p_.max_speed_mps * p_.max_speed_mps;
  const double w_max = p_.max_angular_speed_dps * M_PI / 180.0;
  o.twist_covariance.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * w_max * w_max;
}

bool VisualOdometry::imageUsable(const cv::Mat& img, std::string& why) const
{
  // Subsampled mean / stddev: black, saturated or flat frames carry no motion information.
  double s = 0, s2 = 0;
  int n = 0;
  for (int y = 0; y < img.rows; y += 8)
  {
    const uint8_t* r = img.ptr<uint8_t>(y);
    for (int x = 0; x < img.cols; x += 8)
    {
      s += r[x];
      s2 += r[x] * r[x];
      ++n;
    }
  }
  if (n == 0)
  {
    why = "empty image";
    return false;
  }
  const double mean = s / n, sd = std::sqrt(std::max(0.0, s2 / n - mean * mean));
  if (sd < p_.min_image_stddev)
  {
    why = mean < 20 ? "image black" : (mean > 235 ? "image saturated" : "image without texture");
    return false;
  }
  return true;
}

VoOutput VisualOdometry::makeOutput(TrackingState s, const FrameStats& st, const Eigen::Isometry3d& T_prev_cur,
                                    double dt)
{
  VoOutput o;
  o.state = s;
  o.pose_valid = have_pose_;
  o.stats = st;
  o.stats.tracks = static_cast<int>(tracker_.points().size());
  const Eigen::Matrix3d R_lo = R_link_optical();
  o.T_odom_optical = T_odom_o0_ * T_w_cur_;
  o.T_odom_link = linkPose(o.T_odom_optical);
  o.pose_covariance = rotateCov(cov_cur_, o.T_odom_optical.linear());
  if (dt > 1e-6)
  {
    o.linear_velocity = R_lo * T_prev_cur.translation() / dt;
    o.angular_velocity = R_lo * (Eigen::AngleAxisd(T_prev_cur.linear()).angle() *
                                 Eigen::AngleAxisd(T_prev_cur.linear()).axis()) / dt;
    o.twist_covariance = rotateCov(cov_rel_, R_lo) / (dt * dt);
    if (s != TrackingState::TRACKING && s != TrackingState::INITIALISING)
    {
      // a predicted motion: the variance of the prediction, not the last measured one's
      o.twist_covariance = Eigen::Matrix<double, 6, 6>::Identity() * (1e-2 / (dt * dt));
      if (standing_held_)
      {
        // held: zero velocity, within the speed a hold may start at; the gyro's rotation
        o.linear_velocity.setZero();
        o.twist_covariance.topLeftCorner<3, 3>() =
            Eigen::Matrix3d::Identity() * std::max(1e-4, p_.standing_max_speed * p_.standing_max_speed);
        o.twist_covariance.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * bias_.rotationVariance(dt) / (dt * dt);
      }
      else if (imu_coasted_)
      {
        o.twist_covariance.topLeftCorner<3, 3>() =
            Eigen::Matrix3d::Identity() * coast_.velocityVariance(coast_.coastTime());
        o.twist_covariance.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * bias_.rotationVariance(dt) / (dt * dt);
      }
    }
  }
  if (!o.T_odom_link.matrix().allFinite())
  {
    // never publish NaN: fall back to the last keyframe (should not happen)
    o.pose_valid = false;
  }
  last_state_ = s;
  return o;
}

void VisualOdometry::estimateDisparityOffset(const MotionEstimate& m)
{
  std::vector<DisparityOffsetEstimator::Obs> kf, cur;
  for (const int k : m.rr.inliers)
  {
    const PointTrack& t = tracker_.points()[static_cast<size_t>(k)];
    if (t.cur_geo_disp <= 0 || t.kf_obs.ur < 0)
      continue;
    kf.push_back({t.kf_obs.u, t.kf_obs.v, t.kf_obs.u - t.kf_obs.ur});
    cur.push_back({t.cur_geo.x, t.cur_geo.y, t.cur_geo_disp});
  }
  disp_offset_.add(cam_, kf, cur, m.T_kf_cur.linear().transpose(), m.T_kf_cur.translation().norm());
  double delta = 0;
  if (disp_offset_.take(delta))
  {
    // a bounded step (the next round measures what is left)
    const double lim = p_.max_disparity_offset_px;
    tracker_.stereo().setOffset(std::clamp(tracker_.stereo().offset() + std::clamp(delta, -0.75, 0.75), -lim, lim));
  }
}

void VisualOdometry::growLostCovariance()
{
  // An IMU-coasted frame has grown the covariance by its own uncertainty (lostMotion); any other
  // lost frame (a constant-velocity guess, or the gyro's rotation only) by 0.1 m and 0.1 rad.
  if (!imu_coasted_)
    cov_cur_ += Eigen::Matrix<double, 6, 6>::Identity() * 1e-2;
}

InertialCoaster::Options VisualOdometry::coastGyroOptions() const
{
  // the gyro's noise and its bias estimate's error tilt the coasted pose (gravity leaks through)
  InertialCoaster::Options o = coastOptions(p_);
  o.gyro_bias_sigma = std::sqrt(std::max(0.0, bias_.variance()));
  if (bias_.variance() < 0)
    o.gyro_bias_sigma = p_.gyro_bias_sigma;
  return o;
}

void VisualOdometry::setCoastGyro()
{
  coast_.setOptions(coastGyroOptions());
}

VoOutput VisualOdometry::fail(const std::string& why, const cv::Mat* left, const cv::Mat* right,
                              const Eigen::Isometry3d& T_prev_cur_pred, double stamp, FrameStats& st)
{
  // Keep the pose chain: predicted motion (gyro rotation, damped velocity), then a new keyframe
  // in this frame if it is usable, else wait for a usable frame.
  T_w_cur_ = T_w_cur_ * T_prev_cur_pred;
  last_T_prev_cur_ = T_prev_cur_pred;
  growLostCovariance();
  if (keyframes_.valid())  // count the transition tracking -> lost once
  {
    ++resets_;
    st.reset = true;
  }
  keyframes_.invalidate();
  tracker_.points().clear();
  gravity_.clear();  // a predicted pose: no velocity to compare the accelerometer with
  TrackingState s = TrackingState::LOST;
  if (left && right)
  {
    startKeyframe(*left, *right, false, st);
    if (keyframes_.valid())
    {
      s = TrackingState::REINITIALISING;
      tracker_.endFrame();
    }
  }
  last_stamp_ = stamp;
  VoOutput o = makeOutput(s, st, T_prev_cur_pred, last_dt_);
  o.message = why;
  return o;
}

// ---- the frame, in order: input checks, prediction, keyframe tracking, motion estimation,
// plausibility, acceptance (gyro bias, new keyframe, gravity) ----
void VisualOdometry::normaliseBrightness(const cv::Mat& in, cv::Mat& out)
{
  // One gain per image, to one mean (subsampled) for the whole run: a camera's gain (exposure,
  // auto-exposure) multiplies every intensity, so it cancels; saturated pixels stay saturated.
  // The mean is the first image's (brightness_target < 0), so a rig without gain steps sees its
  // images nearly unchanged, or brightness_target; 0: off.
  if (p_.brightness_target == 0)
  {
    out = in;
    return;
  }
  double s = 0;
  int n = 0;
  for (int y = 0; y < in.rows; y += 4)
  {
    const uint8_t* r = in.ptr<uint8_t>(y);
    for (int x = 0; x < in.cols; x += 4, ++n)
      s += r[x];
  }
  const double mean = n > 0 ? s / n : 0.0;
  if (mean < 1.0)
  {
    out = in;
    return;
  }
  if (brightness_ref_ <= 0)
    brightness_ref_ = p_.brightness_target > 0 ? p_.brightness_target : mean;
  in.convertTo(out, CV_8U, brightness_ref_ / mean);
}

VoOutput VisualOdometry::process(const cv::Mat& left_raw, const cv::Mat& right_raw, double stamp,
                                 const Eigen::Quaterniond* gyro_link, const Eigen::Vector3d* dv_link,
                                 const Eigen::Vector3d* dp_link)
{
  imu_coasted_ = standing_held_ = false;
  coast_why_.clear();
  tracker_.beginFrame();
  const auto t_start = Clock::now();
  FrameStats st;
  st.fast_threshold = keyframes_.detectorThreshold();
  FrameContext fc;
  fc.stamp = stamp;
  const bool have_up_hint = have_up_hint_;  // setGravityHint() holds for this frame only
  have_up_hint_ = false;
  const bool have_rate_at_stamp = have_rate_at_stamp_;  // setGyroRateAtStamp() too
  have_rate_at_stamp_ = false;
  auto finish = [&](VoOutput o) {
    applyTrust(o, stamp, fc.coast_ok, fc.force_untrusted);
    o.stats.ms_total = msSince(t_start);
    return o;
  };

  VoOutput o;
  if (!checkInput(left_raw, right_raw, st, fc, o))
  {
    coast_.clear();  // the next frame's IMU interval no longer joins two tracked frames
    return finish(o);
  }
  fc.first = !have_pose_;
  if (fc.first)
    startPose(stamp);
  checkTiming(fc);
  predictMotion(gyro_link, fc, st);
  fc.have_rate_at_stamp = have_rate_at_stamp;
  setRollingShutter(fc);
  if (fc.have_gyro && dv_link && dp_link && p_.imu_coasting && dv_link->allFinite() && dp_link->allFinite())
  {
    fc.have_imu = true;
    fc.imu.dt = fc.dt_real;
    fc.imu.dv = *dv_link;
    fc.imu.dp = *dp_link;
  }
  markBridgeable(fc);
  levelAfterGap(have_up_hint, fc);
  detectStanding(fc);
  fc.coast_ok = mayCoast(stamp, fc, coast_why_);
  if (fc.bridged)
    bridgeGap(fc);
  if (rejectImages(left_raw, right_raw, fc, st, o))
    return finish(o);
  // Everything after works on images of the same global brightness (auto-exposure steps, a gain
  // different in the two cameras): the SAD stereo match and the KLT tracking compare intensities.
  cv::Mat left_n, right_n;
  normaliseBrightness(left_raw, left_n);
  normaliseBrightness(right_raw, right_n);
  const cv::Mat& left = left_n;
  const cv::Mat& right = right_n;

  // ---- pyramid of the current left image ----
  auto t0 = Clock::now();
  tracker_.buildPyramid(left);
  st.ms_pyramid = msSince(t0);
  if (!keyframes_.valid() || fc.gap)
    return finish(restartKeyframe(left, right, fc, st));

  // ---- keyframe tracking, motion estimation ----
  const Eigen::Isometry3d T_kf_pred = keyframes_.current().T_kf_prev * fc.T_pred;
  tracker_.trackPoints(left, T_kf_pred, st);
  tracker_.filterEpipolar(st);
  tracker_.matchStereo(left, right, st);
  if (tracker_.usesLines())
    tracker_.trackLines(right, st);
  MotionEstimate m;
  const bool pose_found = estimator_.estimate(T_kf_pred, fc.have_imu, tracker_, st, m);
  last_dt_ = fc.dt;
  if (!pose_found)
    return finish(fail("too few inliers (" + std::to_string(m.rr.inliers.size()) + "): re-initialising", &left,
                       &right, lostMotion(fc), stamp, st));
  refinePose(fc, T_kf_pred, st, m);

  // ---- plausibility ----
  const std::string bad = judgeMotion(m, gyro_link != nullptr, fc, st);
  if (!bad.empty())
    return finish(fail(bad + ": re-initialising", &left, &right, lostMotion(fc), stamp, st));
  keyframes_.setPreviousVisionRotation(m.R_vision);

  // ---- accept; gyro bias and a new keyframe at the end of a keyframe span; gravity ----
  accept(m, st);
  standing_now_ = false;  // vision measures again
  gaps_bridged_ += fc.bridged && !fc.bridge_within;  // tracked across on the coast's prediction alone
  if (keyframes_.needed(m.T_kf_cur, tracker_))
  {
    updateGyroBias(m, stamp);
    startKeyframe(left, right, true, st);
  }
  if (p_.estimate_disparity_offset)
    estimateDisparityOffset(m);
  levelWithGravity(stamp, dv_link);
  coast_.addTracked(stamp, linkPose(T_odom_o0_ * T_w_cur_), fc.have_imu ? &fc.imu : nullptr);

  tracker_.endFrame();
  last_stamp_ = stamp;
  return finish(makeOutput(TrackingState::TRACKING, st, m.T_prev_cur, fc.dt));
}

std::string VisualOdometry::judgeMotion(const MotionEstimate& m, bool gyro_given, FrameContext& fc, FrameStats& st)
{
  measureStereoConsistency(m, st);
  std::string bad = checkPlausibility(m, gyro_given, fc, st);
  // A point+line motion (few corners: the weakest estimates) is accepted only while its vision
  // rotation agrees with the gyro on the frame; else the frame is lost and coasts on the IMU
  // (corridor's end wall: 0.5-1.3 deg a frame against the gyro, 2-5 cm off; README).
  if (bad.empty() && m.with_lines && fc.have_gyro && st.gyro_disagreement_deg > p_.pointline_max_gyro_disagreement_deg)
    bad = "point+line rotation " + std::to_string(st.gyro_disagreement_deg) + " deg off the gyro";
  // With the IMU a line frame without checked points coasts: the motion along the lines would be
  // the constant-velocity prior's, which the accelerometer knows better (corridor with the IMU:
  // 0.303 -> 0.587 % drift when accepted, its y error carried on into the coast's velocity).
  if (bad.empty() && m.lines_only && fc.have_imu && fc.coast_ok)
    bad = "point+line motion without checked points (the IMU coasts)";
  return bad;
}

const Eigen::Isometry3d& VisualOdometry::lostMotion(FrameContext& fc)
{
  if (fc.lost_done)
    return fc.T_lost;
  fc.lost_done = true;
  Eigen::Isometry3d& T = fc.T_lost;
  T = fc.T_pred;
  const bool was_coasting = coast_.coasting();
  if (!fc.coast_ok || !fc.force_untrusted.empty())
  {
    if (fc.bridged && fc.force_untrusted.empty())
      fc.force_untrusted = fc.gap_why;  // beyond the coast rules, and vision lost it: the plain gap's reason
    T.translation().setZero();
    if (!fc.have_gyro)
      T.linear().setIdentity();
    coast_.clear();
    standing_now_ = false;
  }
  else if (fc.standing)
    T = standingMotion(fc);
  else if (fc.have_imu && (was_coasting || (setCoastGyro(), coast_.start())))
  {
    if (!was_coasting)
      coast_var_ = coast_rot_var_ = 0.0;
    // IMU coasting: translation from the preintegrated accelerometer and the velocity fitted at
    // the last tracked frame; the rotation stays the bias-corrected gyro's (T_pred).
    const Eigen::Isometry3d T_odom_opt = T_odom_o0_ * T_w_cur_;
    const Eigen::Matrix3d R_odom_link = T_odom_opt.linear() * R_link_optical().transpose();
    if (!was_coasting)
      range_aid_.resetAnchor();
    Eigen::Vector3d dpos = coast_.step(R_odom_link, fc.imu);
    const double var = aidCoast(fc.stamp, R_odom_link, dpos);
    if (!(coast_.velocity().norm() <= p_.max_speed_mps))
    {
      // a coasted speed no wearer reaches (an accelerometer spike, a bad fit): no guess, untrusted
      T.translation().setZero();
      coast_.clear();
      fc.coast_ok = false;
      coast_why_ = "IMU-coasted speed beyond max_speed";
      return T;
    }
    T.translation() = T_odom_opt.linear().transpose() * dpos;
    // the covariance grows by what the coast adds (isotropic in position: the same in any axes;
    // with the ranger's aid its worst axis) (and the rotation by the gyro's, over the whole coast:
    // its bias error grows the angle linearly)
    const double rvar = bias_.rotationVariance(coast_.coastTime());
    cov_cur_.topLeftCorner<3, 3>() += Eigen::Matrix3d::Identity() * std::max(0.0, var - coast_var_);
    cov_cur_.bottomRightCorner<3, 3>() += Eigen::Matrix3d::Identity() * std::max(0.0, rvar - coast_rot_var_);
    coast_var_ = var;
    coast_rot_var_ = rvar;
    imu_coasted_ = true;
  }
  else
    coast_.clear();  // constant-velocity guess (coast_max_s at most)
  if (!fc.standing)
    standing_now_ = false;  // gait back (or no IMU): the coast rules, from the last held frame
  return T;
}

double VisualOdometry::aidCoast(double stamp, const Eigen::Matrix3d& R_odom_link, Eigen::Vector3d& dpos)
{
  range_aided_ = false;
  if (!(p_.range_aided_coast && have_range_axis_))
    return coast_.positionVariance(coast_.coastTime());
  const RangeAid::Step a = range_aid_.step(stamp, R_odom_link * range_axis_link_, dpos, coast_);
  if (!a.aided)
    return a.gate_var;  // the unaided rule's
  dpos += a.dpos;
  coast_.correctVelocity(a.dv);
  range_aided_ = true;
  range_gate_var_ = a.gate_var;
  ++range_aided_frames_;
  return a.gate_var;
}

void VisualOdometry::addRange(double stamp, double range, const Eigen::Vector3d& axis_link)
{
  range_aid_.addRange(stamp, range);
  range_axis_link_ = axis_link.normalized();
  have_range_axis_ = range_axis_link_.allFinite();
}

void VisualOdometry::detectStanding(FrameContext& fc)
{
  // The specific force over the interval, in odom axes (the orientation at its start, as the
  // preintegration's dv is expressed): gravity stays put while the head only turns.
  if (fc.bridged)
  {
    standingOverGap(fc);
    return;
  }
  if (!(p_.standing_detection && fc.have_imu && !fc.gap && fc.imu.dt > 1e-6))
  {
    standing_.clear();
    standing_now_ = v_imu_valid_ = false;
    return;
  }
  const Eigen::Matrix3d R_odom_link = linkPose(T_odom_o0_ * T_w_cur_).linear();
  const Eigen::Vector3d f_odom = R_odom_link * fc.imu.dv / fc.imu.dt;
  // carried on to this frame (a tracked frame replaces it with its own measure: accept())
  v_imu_ += (f_odom - Eigen::Vector3d(0.0, 0.0, coastOptions(p_).gravity)) * fc.imu.dt;
  standing_.add(fc.stamp, fc.imu.dt, f_odom);
  if (!standing_.quiet())
  {
    if (p_.standing_on_stop)
    {
      // A hold goes on while the samples since it started (within the window) show no gait: one
      // started at a stop (the window still holds the deceleration) or carried over a bridged gap
      // (standingOverGap: the window refills). Else a stop seen now starts one (standingMotion).
      if (standing_now_)
      {
        const double since = standing_.statisticSince(standing_t0_);
        fc.standing = since >= 0 && since <= p_.standing_max_accel_sigma;
      }
      else
        fc.standing = stopSeen(fc, f_odom);
      return;
    }
    // a hold carried over a bridged gap (standingOverGap) goes on while the window refills, as long
    // as what it has shows no gait
    const double partial = standing_.partialStatistic();
    fc.standing = standing_now_ && standing_.statistic() < 0 && partial >= 0 && partial <= p_.standing_max_accel_sigma;
    return;
  }
  // No gait. A walk at constant speed without a bob would look the same (the accelerometer cannot
  // see a constant velocity), so a hold starts only at a speed known to be low: the IMU-coasted
  // velocity, or the last tracked frame's.
  const double speed = knownSpeed(coast_, last_T_prev_cur_, last_dt_, imuSpeed());
  fc.standing = standing_now_ || speed <= p_.standing_max_speed;
}

Eigen::Isometry3d VisualOdometry::standingMotion(const FrameContext& fc)
{
  // Zero velocity: the neck stays where it was when the hold started; the camera turns about it
  // with the gyro's rotation (bias-corrected). The position variance grows once, by
  // standing_position_sigma; the rotation's by the gyro's over the hold.
  if (!standing_now_)
  {
    standing_now_ = true;
    ++standing_holds_;
    standing_pivot_ = pivotNow();
    standing_t0_ = fc.stamp - fc.dt_real;
    standing_rot_var_ = 0.0;
    const double s2 = p_.standing_position_sigma * p_.standing_position_sigma;
    cov_cur_.topLeftCorner<3, 3>() += Eigen::Matrix3d::Identity() * s2;
  }
  const Eigen::Isometry3d T = heldMotion(fc, standing_pivot_);
  const double rvar = bias_.rotationVariance(fc.stamp - standing_t0_);
  cov_cur_.bottomRightCorner<3, 3>() += Eigen::Matrix3d::Identity() * std::max(0.0, rvar - standing_rot_var_);
  standing_rot_var_ = rvar;
  standing_held_ = true;
  ++standing_frames_;
  imu_coasted_ = true;  // the covariance is grown here (not by growLostCovariance)
  // a zero-velocity measurement: the coaster's window goes on with it, so a walk on with vision
  // still lost coasts from the hold (v = 0) under the coast rules
  coast_.addTracked(fc.stamp, linkPose(T_odom_o0_ * T_w_cur_ * T), &fc.imu);
  return T;
}

Eigen::Vector3d VisualOdometry::pivotNow() const
{
  const Eigen::Isometry3d T_odom_opt = T_odom_o0_ * T_w_cur_;
  const Eigen::Vector3d r_link(p_.standing_pivot_forward, 0.0, p_.standing_pivot_up);
  return T_odom_opt.translation() - T_odom_opt.linear() * R_link_optical().transpose() * r_link;
}

Eigen::Isometry3d VisualOdometry::heldMotion(const FrameContext& fc, const Eigen::Vector3d& pivot) const
{
  // Zero velocity: the neck stays at `pivot`; the camera turns about it with the gyro's rotation.
  const Eigen::Matrix3d R_lo = R_link_optical();
  const Eigen::Isometry3d T_odom_opt = T_odom_o0_ * T_w_cur_;
  const Eigen::Vector3d r_link(p_.standing_pivot_forward, 0.0, p_.standing_pivot_up);
  const Eigen::Matrix3d R1_opt = T_odom_opt.linear() * fc.T_pred.linear();
  const Eigen::Vector3d p1 = pivot + R1_opt * R_lo.transpose() * r_link;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = fc.T_pred.linear();
  T.translation() = T_odom_opt.linear().transpose() * (p1 - T_odom_opt.translation());
  return T;
}

void VisualOdometry::markBridgeable(FrameContext& fc)
{
  // Frames dropped (an overloaded computer, a camera hiccup) while the IMU ran: the motion over
  // the gap was measured by the gyro and the accelerometer, it is not unknown.
  if (!(fc.gap && fc.dt_real > 0 && fc.have_imu && p_.imu_bridge_gaps))
    return;
  fc.gap = false;
  fc.bridged = true;
  fc.gap_why = fc.force_untrusted;  // the gap's own (checkTiming sets it first)
  fc.force_untrusted.clear();
  fc.dt = fc.dt_real;
}

void VisualOdometry::standingOverGap(FrameContext& fc)
{
  v_imu_valid_ = false;  // the gap's one interval: no frame velocity to carry on
  // One interval over the whole gap: its mean specific force hides any gait, so it is no sample
  // of the test (the window restarts after it). The stand goes on through the gap when the test
  // was quiet up to it (at a low speed, as detectStanding asks) and the velocity change over the
  // gap (odom axes, gravity removed) stays within standing_max_speed: no walk started in it.
  const bool quiet_before = standing_.quiet();
  standing_.clear();
  if (!(p_.standing_detection && (standing_now_ || quiet_before)))
    return;
  const double speed = knownSpeed(coast_, last_T_prev_cur_, last_dt_, imuSpeed());
  const Eigen::Matrix3d R_odom_link = linkPose(T_odom_o0_ * T_w_cur_).linear();
  const Eigen::Vector3d dv = R_odom_link * fc.imu.dv - Eigen::Vector3d(0, 0, coastOptions(p_).gravity * fc.imu.dt);
  fc.standing = (standing_now_ || speed <= p_.standing_max_speed) && dv.norm() <= p_.standing_max_speed;
}

void VisualOdometry::bridgeGap(FrameContext& fc)
{
  // The keyframe tracking's prediction over the gap: the position held standing, else the IMU
  // coast (a copy of the coaster: the numbers lostMotion() would use). Within the coast rules the
  // bridged pose is trusted even when vision fails on the frame (lostMotion() takes this motion, a
  // new keyframe starts there). Beyond them (a long gap at walking speed: the coast's sigma) the
  // coast is the tracking's prediction only: tracked, the frame is measured again; lost, it is the
  // plain gap (lostMotion(): pose kept, untrusted, new keyframe).
  Eigen::Isometry3d T = fc.T_pred;  // the gyro's rotation over the gap
  bool predicted = false;
  fc.bridge_within = false;
  if (fc.coast_ok && fc.standing)
  {
    T = heldMotion(fc, standing_now_ ? standing_pivot_ : pivotNow());
    predicted = fc.bridge_within = true;
  }
  else
  {
    InertialCoaster c = coast_;
    if (!c.coasting())
      c.setOptions(coastGyroOptions());
    if (c.coasting() || c.start())
    {
      const Eigen::Isometry3d T_odom_opt = T_odom_o0_ * T_w_cur_;
      const Eigen::Vector3d dpos = c.step(T_odom_opt.linear() * R_link_optical().transpose(), fc.imu);
      const double since = fc.stamp - last_trusted_stamp_, smax = p_.imu_coast_max_sigma_m;
      predicted = c.velocity().norm() <= p_.max_speed_mps;
      fc.bridge_within = predicted && fc.coast_ok && c.positionVariance(since) <= smax * smax;
      T.translation() = T_odom_opt.linear().transpose() * dpos;
    }
  }
  if (!predicted)
  {
    // no velocity to coast from: the plain gap (pose kept, untrusted, new keyframe)
    fc.bridged = fc.standing = false;
    fc.gap = true;
    fc.force_untrusted = fc.gap_why;
    fc.dt = last_dt_ > 0 ? last_dt_ : 1.0 / 15.0;
    fc.T_pred.translation().setZero();
    standing_now_ = false;
    return;
  }
  fc.T_pred = T;
  if (!fc.bridge_within)
  {
    fc.coast_ok = fc.standing = false;  // lost on this frame: the plain gap (lostMotion())
    return;
  }
  ++gaps_bridged_;
  char buf[96];
  std::snprintf(buf, sizeof(buf), "gap of %.2f s in the image stream: bridged on the IMU", fc.dt_real);
  fc.why = buf;
}

bool VisualOdometry::checkInput(const cv::Mat& left, const cv::Mat& right, FrameStats& st, FrameContext& fc,
                                VoOutput& o)
{
  // Nothing here may throw or produce NaN.
  if (!cam_.valid())
  {
    o = makeOutput(TrackingState::LOST, st, Eigen::Isometry3d::Identity(), 0);
    o.message = "invalid stereo calibration (fx, baseline, size)";
    fc.force_untrusted = o.message;
    return false;
  }
  if (left.empty() || right.empty() || left.type() != CV_8UC1 || right.type() != CV_8UC1 ||
      left.size() != right.size() || left.cols != cam_.width || left.rows != cam_.height)
  {
    o = makeOutput(have_pose_ ? TrackingState::LOST : TrackingState::INITIALISING, st, Eigen::Isometry3d::Identity(),
                   0);
    o.message = "stereo images empty, not mono8, or of a size different from camera_info";
    fc.force_untrusted = o.message;
    return false;
  }
  return true;
}

void VisualOdometry::startPose(double stamp)
{
  const Eigen::Isometry3d T_odom_link0 =
      have_up_ && p_.use_imu ? startPoseFromUp(up_link_, p_.camera_height_m)
                             : startPoseFromRollPitch(p_.initial_roll_deg * M_PI / 180.0,
                                                      p_.initial_pitch_deg * M_PI / 180.0, p_.camera_height_m);
  Eigen::Isometry3d T_link_opt = Eigen::Isometry3d::Identity();
  T_link_opt.linear() = R_link_optical();
  T_odom_o0_ = T_odom_link0 * T_link_opt;
  T_w_cur_ = Eigen::Isometry3d::Identity();  // (the keyframe store is empty: reset or new)
  have_pose_ = true;
  last_stamp_ = stamp;
}

void VisualOdometry::checkTiming(FrameContext& fc)
{
  // A stamp gap or time going backwards (bag loop), whatever the tracking state: the motion over
  // it is unknown, so the pose is kept (not extrapolated; rotated by the gyro only when it covers
  // the gap), a new keyframe is started and the frame is untrusted.
  fc.dt = fc.stamp - last_stamp_;
  fc.dt_real = fc.dt;
  if (fc.first)
    return;
  const std::string why = checks_.checkTiming(fc.dt);
  if (why.empty())
    return;
  fc.why = why;
  fc.force_untrusted = why;
  fc.gap = true;
  fc.dt = last_dt_ > 0 ? last_dt_ : 1.0 / 15.0;
}

void VisualOdometry::predictMotion(const Eigen::Quaterniond* gyro_link, FrameContext& fc, FrameStats& st)
{
  // Predicted motion prev -> cur in the optical frame: constant velocity (translation damped),
  // the gyro's rotation when there is one.
  const Eigen::Matrix3d R_lo = R_link_optical();
  if (!fc.gap && last_dt_ > 1e-6)
  {
    const double s = std::clamp(fc.dt / last_dt_, 0.0, 3.0);
    fc.T_pred.translation() = last_T_prev_cur_.translation() * s * 0.9;
    Eigen::AngleAxisd aa(last_T_prev_cur_.linear());
    fc.T_pred.linear() = Eigen::AngleAxisd(aa.angle() * s, aa.axis()).toRotationMatrix();
  }
  last_stamp_pending_ = fc.stamp;
  bias_.initialise();
  fc.have_gyro = gyro_link && p_.use_imu && gyro_link->coeffs().allFinite() && fc.dt_real > 0;
  if (fc.have_gyro)
  {
    // bias-corrected over the real interval (also a gap's)
    const Eigen::Matrix3d Rl = bias_.correct(*gyro_link, fc.dt_real);
    fc.R_gyro_opt = R_lo.transpose() * Rl * R_lo;
    fc.T_pred.linear() = fc.R_gyro_opt;
    st.gyro_rate_dps = angleOf(Rl) / fc.dt_real * 180.0 / M_PI;
    const Eigen::AngleAxisd aa(fc.R_gyro_opt);
    gyro_rate_opt_ = aa.angle() * aa.axis() / fc.dt_real;
  }
  else
    gyro_rate_opt_.setZero();
  if (fc.gap)
    fc.T_pred.translation().setZero();
}

void VisualOdometry::setRollingShutter(const FrameContext& fc)
{
  if (p_.rolling_shutter_readout_s <= 0)
  {
    tracker_.setRollingShutter(RollingShutter());
    return;
  }
  const Eigen::Matrix3d R_lo = R_link_optical();
  Eigen::Vector3d omega = Eigen::Vector3d::Zero(), velocity = Eigen::Vector3d::Zero();
  const bool last_known = !fc.first && !fc.gap && last_dt_ > 1e-6;
  if (fc.have_rate_at_stamp && p_.use_imu)
    omega = R_lo.transpose() * (rate_at_stamp_link_ - bias_.bias());
  else if (fc.have_gyro)
    omega = gyro_rate_opt_;
  else if (last_known)
  {
    const Eigen::AngleAxisd aa(last_T_prev_cur_.linear());
    omega = aa.angle() * aa.axis() / last_dt_;
  }
  if (last_known)
    velocity = last_T_prev_cur_.translation() / last_dt_;
  tracker_.setRollingShutter(RollingShutter(cam_, p_.rolling_shutter_readout_s, omega, velocity));
}

void VisualOdometry::levelAfterGap(bool have_up_hint, FrameContext& fc)
{
  if (fc.gap && !fc.have_gyro && hints_seen_ && p_.use_imu)
  {
    level_pending_ = true;
    level_pending_since_ = fc.stamp;
  }
  if (level_pending_ && have_up_hint)
  {
    levelByGravity(up_hint_);
    checks_.countGravityRelevel();
    level_pending_ = false;
  }
  else if (level_pending_ && fc.stamp - level_pending_since_ > kLevelWaitS)
    level_pending_ = false;  // no accelerometer after all: carry on with the old tilt
  else if (level_pending_ && fc.force_untrusted.empty())
    fc.force_untrusted = "tilt unknown after a gap the gyro did not cover: waiting for the accelerometer";
}

bool VisualOdometry::rejectImages(const cv::Mat& left, const cv::Mat& right, FrameContext& fc, FrameStats& st,
                                  VoOutput& o)
{
  st.image_change = imageChange(left);
  if (!imageUsable(left, fc.why) || !imageUsable(right, fc.why))
  {
    last_dt_ = fc.dt;
    o = fail(fc.why, nullptr, nullptr, lostMotion(fc), fc.stamp, st);
    o.state = TrackingState::LOST;
    return true;
  }
  // Frozen camera: the image does not change while the gyro says the head turns. Such a frame
  // carries no motion information (skipped: pose predicted); frozen_frames of them in a row make
  // the pose untrusted until the image changes and a new keyframe is tracked.
  std::string frozen_why;
  bool untrusted = false;
  if (!checks_.frozen(st.image_change, fc.have_gyro, st.gyro_rate_dps, frozen_why, untrusted))
    return false;
  if (untrusted && fc.force_untrusted.empty())
    fc.force_untrusted = frozen_why;
  last_dt_ = fc.dt;
  o = fail(frozen_why, nullptr, nullptr, lostMotion(fc), fc.stamp, st);
  o.state = TrackingState::LOST;
  return true;
}

VoOutput VisualOdometry::restartKeyframe(const cv::Mat& left, const cv::Mat& right, FrameContext& fc,
                                         FrameStats& st)
{
  // Keeps the pose chain (the pose is predicted over the gap).
  const bool first = last_state_ == TrackingState::INITIALISING;
  if (fc.gap)
  {
    ++resets_;
    st.reset = true;
  }
  if (!first)
  {
    T_w_cur_ = T_w_cur_ * lostMotion(fc);
    last_T_prev_cur_ = lostMotion(fc);
    growLostCovariance();  // (the pose over the gap is predicted, not measured)
  }
  gravity_.clear();
  last_dt_ = fc.dt;
  startKeyframe(left, right, false, st);
  tracker_.endFrame();
  last_stamp_ = fc.stamp;
  const TrackingState s = keyframes_.valid() ? (first ? TrackingState::TRACKING : TrackingState::REINITIALISING)
                                         : (first ? TrackingState::INITIALISING : TrackingState::LOST);
  VoOutput o = makeOutput(s, st, first ? Eigen::Isometry3d::Identity() : lostMotion(fc), fc.dt);
  o.message = fc.why;
  if (!keyframes_.valid())
    o.message = "too few features with stereo depth to start tracking";
  return o;
}

void VisualOdometry::measureStereoConsistency(const MotionEstimate& m, FrameStats& st) const
{
  // The current disparity of the inliers against the one their refined 3D point predicts at the
  // estimated pose (median). A right image out of sync with the left (or a moved camera) gives
  // pixels of error; a good pair, a tenth of a pixel.
  std::vector<double> res;
  res.reserve(m.rr.inliers.size());
  const Eigen::Isometry3d T_cur_kf = m.T_kf_cur.inverse();
  int matched = 0;
  for (size_t k = 0; k < m.rr.inliers.size(); ++k)
  {
    const PointTrack& t = tracker_.points()[static_cast<size_t>(m.rr.inliers[k])];
    const Eigen::Vector3d Xc = T_cur_kf * m.X_in[k];
    matched += t.cur_geo_disp > 0;
    if (t.cur_geo_disp > 0 && Xc.z() > 0.1)
      res.push_back(std::abs(t.cur_geo_disp - cam_.fx * cam_.baseline / Xc.z()));
  }
  st.stereo_matched_ratio = m.rr.inliers.empty() ? -1.0 : matched / static_cast<double>(m.rr.inliers.size());
  if (res.size() >= 5)
  {
    std::nth_element(res.begin(), res.begin() + res.size() / 2, res.end());
    st.stereo_error_px = res[res.size() / 2];
  }
}

std::string VisualOdometry::checkPlausibility(const MotionEstimate& m, bool gyro_given, FrameContext& fc,
                                              FrameStats& st)
{
  // No jumps. A solution that a clear majority of the tracks supports (>= 2 x min_inliers and
  // >= half the tracks) is accepted even when it exceeds the speed bound: that is the start of
  // tracking on a fast platform, not a jump.
  const int n_in = static_cast<int>(m.rr.inliers.size());
  const bool strong = n_in >= 2 * p_.min_inliers && 2 * n_in >= static_cast<int>(tracker_.points().size());
  std::string bad = checks_.checkMotion(m.T_kf_cur, m.T_prev_cur, fc.T_pred, fc.dt, strong, gyro_given && p_.use_imu);
  // Image motion contradicting the gyro: the vision-only rotation of this frame against the
  // gyro's, over several frames.
  if (fc.have_gyro && bad.empty())
  {
    const Eigen::Matrix3d R_vis_prev_cur = keyframes_.current().R_prev_vision.transpose() * m.R_vision;
    st.gyro_disagreement_deg = angleOf(R_vis_prev_cur.transpose() * fc.R_gyro_opt) * 180.0 / M_PI;
    const std::string why = checks_.checkGyroAgreement(st.gyro_disagreement_deg);
    if (!why.empty())
      bad = fc.force_untrusted = why;
  }
  else if (!fc.have_gyro)
    checks_.noGyro();
  // Stereo pair inconsistent with the motion (right image out of sync, camera moved).
  if (bad.empty() && st.stereo_matched_ratio >= 0)
  {
    const std::string why = checks_.checkStereo(st.stereo_error_px, st.stereo_matched_ratio);
    if (!why.empty())
      bad = fc.force_untrusted = why;
  }
  return bad;
}

void VisualOdometry::startKeyframe(const cv::Mat& left, const cv::Mat& right, bool from_current_tracks,
                                   FrameStats& st)
{
  keyframes_.start(left, right, from_current_tracks, tracker_, T_w_cur_, cov_cur_, last_stamp_pending_, st);
  keyframes_.setGyroRate(gyro_rate_opt_);
}

double VisualOdometry::gyroTimingVariance() const
{
  // the keyframe's rate in the current axes (R_gyro: keyframe -> current)
  const VoKeyframe& kf = keyframes_.current();
  const Eigen::Vector3d dw = gyro_rate_opt_ - kf.R_gyro.transpose() * kf.gyro_rate;
  return dw.squaredNorm() * p_.gyro_time_sigma_s * p_.gyro_time_sigma_s;
}

void VisualOdometry::refinePose(const FrameContext& fc, const Eigen::Isometry3d& T_kf_pred, FrameStats& st,
                                MotionEstimate& m)
{
  // The gyro since the keyframe (bias-corrected): a rotation prior for the second pass.
  keyframes_.addGyro(fc.have_gyro, fc.R_gyro_opt);
  const VoKeyframe& kf = keyframes_.current();
  m.dt_kf = fc.stamp - kf.stamp;
  MotionPrior prior;
  prior.T_kf_pred = T_kf_pred;
  prior.T_kf_prev = kf.T_kf_prev;
  prior.gyro = kf.gyro_since && p_.gyro_rotation_prior && m.dt_kf > 0;
  prior.R_kf_gyro = kf.R_gyro;
  // The gyro's noise and bias over the span, and its timing against the images: a gyro a few ms
  // late (the closed loop's: 60 Hz rates by backward differences, 8 ms) pulled the pose 1-2 deg
  // and 0.1-0.2 m off at the end of turns on the spot, the points with it (issue 34).
  m.gyro_timing_var = prior.gyro ? gyroTimingVariance() : 0.0;
  prior.gyro_variance = prior.gyro ? bias_.rotationVariance(m.dt_kf) + m.gyro_timing_var : 1.0;
  refiner_.refine(tracker_, prior, st, m);
}

void VisualOdometry::accept(const MotionEstimate& m, FrameStats& st)
{
  tracker_.keepInliers(m.rr.inliers, m.X_in);
  st.inliers = static_cast<int>(m.rr.inliers.size());
  T_w_cur_ = keyframes_.current().T_w_kf * m.T_kf_cur;
  keyframes_.setPrevious(m.T_kf_cur);
  last_T_prev_cur_ = m.T_prev_cur;
  // the velocity over the frame, in odom axes (the optical frame's origin is camera_link's)
  const Eigen::Matrix3d R_odom_prev = (T_odom_o0_ * T_w_cur_).linear() * m.T_prev_cur.linear().transpose();
  v_imu_valid_ = last_dt_ > 1e-6;
  v_imu_ = v_imu_valid_ ? Eigen::Vector3d(R_odom_prev * m.T_prev_cur.translation() / last_dt_) : Eigen::Vector3d::Zero();
  // BA covariance is of the current frame relative to the keyframe (current-frame axes).
  cov_rel_ = m.br.ok ? m.br.covariance : Eigen::Matrix<double, 6, 6>::Identity() * 1e-2;
  cov_cur_ = keyframes_.current().covariance + rotateCov(cov_rel_, m.T_kf_cur.linear());
}

void VisualOdometry::updateGyroBias(const MotionEstimate& m, double stamp)
{
  // Vision rotation over the keyframe span vs the integrated gyro; a short span is dropped, or,
  // with gyro_bias_chain_spans, chained with the short spans after it (GyroBiasEstimator::addSpan).
  const VoKeyframe& kf = keyframes_.current();
  const double vision_rot_var = m.cov_vision.bottomRightCorner<3, 3>().trace() / 3 + m.gyro_timing_var;
  if (kf.gyro_since && m.br.ok)
    bias_.addSpan(m.R_vision, kf.R_gyro, m.dt_kf, vision_rot_var, kf.stamp == bias_span_end_stamp_);
  else
    bias_.breakChain();
  bias_span_end_stamp_ = stamp;
}

void VisualOdometry::levelWithGravity(double stamp, const Eigen::Vector3d* dv_link)
{
  if (!(dv_link && p_.use_imu))
  {
    gravity_.clear();
    return;
  }
  const Eigen::Isometry3d T_odom_link = linkPose(T_odom_o0_ * T_w_cur_);
  Eigen::Matrix3d C;
  if (gravity_.add(stamp, T_odom_link, *dv_link, C))
    turnOdomAbout(T_odom_link.translation(), C);
}

cv::Mat VisualOdometry::drawOverlay(const cv::Mat& left) const
{
  cv::Mat out;
  if (left.empty())
    return out;
  if (left.channels() == 1)
    cv::cvtColor(left, out, cv::COLOR_GRAY2BGR);
  else
    out = left.clone();
  tracker_.drawOverlay(out);
  cv::putText(out, std::string(toString(last_state_)) + "  tracks " + std::to_string(tracker_.points().size()),
              cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
  return out;
}
}  // namespace assistive_vo
