#include "assistive_vo/visual_odometry.h"
#include <algorithm>
#include <time.h>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include "assistive_vo/frames.h"

namespace assistive_vo
{
namespace
{
/// Stage timers: CPU time of the calling thread (what one core spends on the frame, not
/// inflated by other processes on a shared machine).
struct Clock
{
  using time_point = double;
  static double now()
  {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
  }
};
double msSince(double t0)
{
  return Clock::now() - t0;
}
double angleOf(const Eigen::Matrix3d& R)
{
  return Eigen::AngleAxisd(R).angle();
}
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
  : p_(p), cam_(cam), detector_(p), stereo_(p), gravity_(gravityOptions(p))
{
}

void VisualOdometry::setParams(const VoParams& p)
{
  p_ = p;
  gravity_.setOptions(gravityOptions(p));
  detector_.setParams(p);
  stereo_.setParams(p);
}

void VisualOdometry::setCamera(const StereoCamera& cam)
{
  cam_ = cam;
  have_keyframe_ = false;
  tracks_.clear();
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

void VisualOdometry::levelByGravity(const Eigen::Vector3d& up_link)
{
  const Eigen::Isometry3d T_odom_link = linkPose(T_odom_o0_ * T_w_cur_);
  const Eigen::Vector3d up_odom = T_odom_link.linear() * up_link.normalized();
  // the smallest rotation taking the measured up to odom z: a tilt about a horizontal axis (yaw kept)
  const Eigen::Matrix3d C = Eigen::Quaterniond::FromTwoVectors(up_odom, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d pos = T_odom_link.translation();
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = C;
  M.translation() = pos - C * pos;
  T_odom_o0_ = M * T_odom_o0_;
}

void VisualOdometry::reset()
{
  have_pose_ = false;
  have_keyframe_ = false;
  tracks_.clear();
  T_w_kf_ = T_w_cur_ = T_kf_prev_ = last_T_prev_cur_ = Eigen::Isometry3d::Identity();
  cov_kf_.setZero();
  cov_cur_.setZero();
  resets_ = 0;
  last_dt_ = 0;
  gyro_bias_link_.setZero();
  gyro_bias_var_ = -1.0;
  ov_from_.clear();
  ov_to_.clear();
  ov_inlier_.clear();
  gravity_.clear();
  untrusted_ = true;
  untrusted_why_.clear();
  have_trusted_ = false;
  prev_thumb_.release();
  frozen_run_ = disagree_run_ = agree_needed_ = stereo_bad_run_ = stereo_agree_needed_ = 0;
  level_pending_ = have_up_hint_ = false;
  R_kf_prev_vision_.setIdentity();
  fs_ = FailSafeCounters();
}

bool VisualOdometry::mayCoast(double stamp, bool have_gyro) const
{
  // Coasting is a guess: only with the gyro bounding the rotation, only briefly, and never once
  // the pose has become untrusted (it stays so until a keyframe is tracked again).
  return have_gyro && have_trusted_ && !untrusted_ && stamp - last_trusted_stamp_ <= p_.coast_max_s + 1e-6;
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
    {
      if (agree_needed_ > 0)
        why = "image motion contradicted the gyro: " + std::to_string(agree_needed_) + " agreeing frames to go";
      else if (stereo_agree_needed_ > 0)
        why = "stereo pair was inconsistent: " + std::to_string(stereo_agree_needed_) + " consistent frames to go";
    }
    else if (o.state == TrackingState::INITIALISING)
      why = "no keyframe yet";
    else if (!coast_ok)
      why = untrusted_ && !untrusted_why_.empty()
                ? untrusted_why_
                : std::string(p_.use_imu ? "lost for longer than coast_max_s" : "lost without a gyro to coast on") +
                      (o.message.empty() ? "" : " (" + o.message + ")");
  }
  if (why.empty())
  {
    o.pose_trusted = true;
    untrusted_ = false;
    untrusted_why_.clear();
    if (o.state == TrackingState::TRACKING)
      last_trusted_stamp_ = stamp;  // coasting frames do not extend the coast window
    trusted_T_odom_optical_ = o.T_odom_optical;
    trusted_cov_ = o.pose_covariance;
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
    ++fs_.untrusted_frames;
  }
  if (have_trusted_)
  {
    o.T_odom_optical = trusted_T_odom_optical_;
    o.T_odom_link = linkPose(trusted_T_odom_optical_);
    o.pose_covariance = trusted_cov_;
  }
  o.linear_velocity.setZero();
  o.angular_velocity.setZero();
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

void VisualOdometry::startKeyframe(const cv::Mat& left, const cv::Mat& right, bool from_current_tracks,
                                   FrameStats& st)
{
  const auto t0 = Clock::now();
  std::vector<Track> kept;
  std::vector<cv::Point2f> existing;
  if (from_current_tracks)
  {
    for (auto& tr : tracks_)
    {
      if (tr.cur_disp <= 0)
        continue;
      Track n;
      n.X_kf = cam_.triangulate(tr.cur.x, tr.cur.y, tr.cur_disp);
      n.kf_obs = StereoObservation{tr.cur.x, tr.cur.y, tr.cur.x - tr.cur_disp};
      n.prev = n.cur = tr.cur;
      n.cur_disp = tr.cur_disp;
      if (p_.keyframe_alignment)
        n.patch = KeyframePatch::extract(left, tr.cur, p_.alignment_half_window, p_.alignment_min_eigen_ratio);
      kept.push_back(n);
      existing.push_back(tr.cur);
    }
  }
  const int wanted = std::max(0, p_.target_features - static_cast<int>(kept.size()));
  std::vector<cv::Point2f> fresh = detector_.detect(left, existing, wanted);
  // Low texture: the threshold has just been lowered, try again (at most twice) before giving up.
  for (int retry = 0; retry < 2 && static_cast<int>(fresh.size() + kept.size()) < p_.target_features / 2 &&
                      detector_.threshold() < detector_.lastThresholdUsed();
       ++retry)
    fresh = detector_.detect(left, existing, wanted);
  st.fast_threshold = detector_.threshold();
  st.detected += static_cast<int>(fresh.size());
  const double max_d = maxDisparity();
  std::vector<float> disp = stereo_.match(left, right, fresh, max_d);
  // Farthest useful depth: max_depth_m, or farther when the stereo rig still resolves the point
  // with min_triangulation_disparity_px there (wide baseline / long focal length).
  const double max_depth =
      std::max(p_.max_depth_m, cam_.fx * cam_.baseline / std::max(0.5, p_.min_triangulation_disparity_px));
  int added = 0;
  for (size_t i = 0; i < fresh.size(); ++i)
  {
    if (disp[i] <= 0)
      continue;
    const Eigen::Vector3d X = cam_.triangulate(fresh[i].x, fresh[i].y, disp[i]);
    if (X.z() > max_depth || X.z() < p_.min_depth_m)
      continue;
    Track n;
    n.X_kf = X;
    n.kf_obs = StereoObservation{fresh[i].x, fresh[i].y, fresh[i].x - disp[i]};
    n.prev = n.cur = fresh[i];
    n.cur_disp = disp[i];
    if (p_.keyframe_alignment)
      n.patch = KeyframePatch::extract(left, fresh[i], p_.alignment_half_window, p_.alignment_min_eigen_ratio);
    kept.push_back(n);
    ++added;
  }
  tracks_.swap(kept);
  tracks_started_ = static_cast<int>(tracks_.size());
  cells_started_ = occupiedCells();
  st.new_features = added;
  st.keyframe = true;
  T_w_kf_ = T_w_cur_;
  T_kf_prev_ = Eigen::Isometry3d::Identity();
  R_kf_gyro_.setIdentity();
  R_kf_prev_vision_.setIdentity();
  gyro_since_kf_ = true;
  t_kf_ = last_stamp_pending_;
  cov_kf_ = cov_cur_;
  have_keyframe_ = tracks_started_ >= std::max(4, p_.min_inliers);
  st.ms_detect += msSince(t0);
}

int VisualOdometry::occupiedCells() const
{
  // Image coverage of the tracks on the detector's bucketing grid. Tracks that crowd into part of
  // the image (forward motion: they leave at the edges and the far ones in the centre remain)
  // constrain the motion poorly even while many are left.
  const cv::Size grid = bucketGrid(p_, cam_.width, cam_.height);
  const int gc = grid.width, gr = grid.height;
  std::vector<uint8_t> occ(static_cast<size_t>(gc * gr), 0);
  int n = 0;
  for (const auto& t : tracks_)
  {
    const int x = std::clamp(static_cast<int>(t.cur.x * gc / std::max(1, cam_.width)), 0, gc - 1);
    const int y = std::clamp(static_cast<int>(t.cur.y * gr / std::max(1, cam_.height)), 0, gr - 1);
    uint8_t& o = occ[static_cast<size_t>(y * gc + x)];
    n += o == 0;
    o = 1;
  }
  return n;
}

VoOutput VisualOdometry::makeOutput(TrackingState s, const FrameStats& st, const Eigen::Isometry3d& T_prev_cur,
                                    double dt)
{
  VoOutput o;
  o.state = s;
  o.pose_valid = have_pose_;
  o.stats = st;
  o.stats.tracks = static_cast<int>(tracks_.size());
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
  }
  if (!o.T_odom_link.matrix().allFinite())
  {
    // never publish NaN: fall back to the last keyframe (should not happen)
    o.pose_valid = false;
  }
  last_state_ = s;
  return o;
}

VoOutput VisualOdometry::fail(const std::string& why, const cv::Mat* left, const cv::Mat* right,
                              const Eigen::Isometry3d& T_prev_cur_pred, double stamp, FrameStats& st)
{
  // Keep the pose chain: predicted motion (gyro rotation, damped velocity), then a new keyframe
  // in this frame if it is usable, else wait for a usable frame.
  T_w_cur_ = T_w_cur_ * T_prev_cur_pred;
  last_T_prev_cur_ = T_prev_cur_pred;
  cov_cur_ += Eigen::Matrix<double, 6, 6>::Identity() * 1e-2;
  if (have_keyframe_)  // count the transition tracking -> lost once
  {
    ++resets_;
    st.reset = true;
  }
  have_keyframe_ = false;
  tracks_.clear();
  gravity_.clear();  // a predicted pose: no velocity to compare the accelerometer with
  TrackingState s = TrackingState::LOST;
  if (left && right)
  {
    startKeyframe(*left, *right, false, st);
    if (have_keyframe_)
    {
      s = TrackingState::REINITIALISING;
      std::swap(prev_pyr_, cur_pyr_);
    }
  }
  last_stamp_ = stamp;
  VoOutput o = makeOutput(s, st, T_prev_cur_pred, last_dt_);
  o.message = why;
  return o;
}

VoOutput VisualOdometry::process(const cv::Mat& left, const cv::Mat& right, double stamp,
                                 const Eigen::Quaterniond* gyro_link, const Eigen::Vector3d* dv_link)
{
  const auto t_start = Clock::now();
  FrameStats st;
  st.fast_threshold = detector_.threshold();
  std::string force_untrusted;  // gap / time jump, frozen camera, gyro contradiction, unusable input
  bool coast_ok = false;        // a lost frame may still coast (decided once the gyro is known)
  const bool have_up_hint = have_up_hint_;  // setGravityHint() holds for this frame only
  have_up_hint_ = false;
  auto finish = [&](VoOutput o) {
    applyTrust(o, stamp, coast_ok, force_untrusted);
    o.stats.ms_total = msSince(t_start);
    return o;
  };

  // ---- input checks: nothing here may throw or produce NaN ----
  std::string why;
  if (!cam_.valid())
  {
    VoOutput o = makeOutput(TrackingState::LOST, st, Eigen::Isometry3d::Identity(), 0);
    o.message = "invalid stereo calibration (fx, baseline, size)";
    force_untrusted = o.message;
    return finish(o);
  }
  if (left.empty() || right.empty() || left.type() != CV_8UC1 || right.type() != CV_8UC1 ||
      left.size() != right.size() || left.cols != cam_.width || left.rows != cam_.height)
  {
    VoOutput o = makeOutput(have_pose_ ? TrackingState::LOST : TrackingState::INITIALISING, st,
                            Eigen::Isometry3d::Identity(), 0);
    o.message = "stereo images empty, not mono8, or of a size different from camera_info";
    force_untrusted = o.message;
    return finish(o);
  }

  const bool first_frame = !have_pose_;
  if (!have_pose_)
  {
    const Eigen::Isometry3d T_odom_link0 =
        have_up_ && p_.use_imu ? startPoseFromUp(up_link_, p_.camera_height_m)
                               : startPoseFromRollPitch(p_.initial_roll_deg * M_PI / 180.0,
                                                        p_.initial_pitch_deg * M_PI / 180.0, p_.camera_height_m);
    Eigen::Isometry3d T_link_opt = Eigen::Isometry3d::Identity();
    T_link_opt.linear() = R_link_optical();
    T_odom_o0_ = T_odom_link0 * T_link_opt;
    T_w_cur_ = T_w_kf_ = Eigen::Isometry3d::Identity();
    have_pose_ = true;
    last_stamp_ = stamp;
  }

  // A stamp gap or time going backwards (bag loop), whatever the tracking state: the motion over
  // it is unknown, so the pose is kept (not extrapolated; rotated by the gyro only when it covers
  // the gap), a new keyframe is started and the frame is untrusted.
  double dt = stamp - last_stamp_;
  const double dt_real = dt;
  bool gap = false;
  if (!first_frame && (dt <= 0.0 || dt > p_.max_frame_gap_s))
  {
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
    why = buf;
    force_untrusted = why;
    gap = true;
    dt = last_dt_ > 0 ? last_dt_ : 1.0 / 15.0;
  }

  // Predicted motion prev -> cur in the optical frame.
  Eigen::Isometry3d T_pred = Eigen::Isometry3d::Identity();
  const Eigen::Matrix3d R_lo = R_link_optical();
  if (!gap && last_dt_ > 1e-6)
  {
    const double s = std::clamp(dt / last_dt_, 0.0, 3.0);
    T_pred.translation() = last_T_prev_cur_.translation() * s * 0.9;
    Eigen::AngleAxisd aa(last_T_prev_cur_.linear());
    T_pred.linear() = Eigen::AngleAxisd(aa.angle() * s, aa.axis()).toRotationMatrix();
  }
  last_stamp_pending_ = stamp;
  if (gyro_bias_var_ < 0)
    gyro_bias_var_ = p_.gyro_bias_sigma * p_.gyro_bias_sigma;
  const bool have_gyro = gyro_link && p_.use_imu && gyro_link->coeffs().allFinite() && dt_real > 0;
  Eigen::Matrix3d R_gyro_opt = Eigen::Matrix3d::Identity();
  if (have_gyro)
  {
    // bias-corrected: R = R_meas * exp(-b dt) (body frame), over the real interval (also a gap's)
    const Eigen::Vector3d bdt = gyro_bias_link_ * dt_real;
    const Eigen::Matrix3d Rl = gyro_link->normalized().toRotationMatrix() *
                               (bdt.norm() > 0 ? Eigen::AngleAxisd(-bdt.norm(), bdt.normalized()).toRotationMatrix()
                                               : Eigen::Matrix3d::Identity());
    R_gyro_opt = R_lo.transpose() * Rl * R_lo;
    T_pred.linear() = R_gyro_opt;
    st.gyro_rate_dps = angleOf(Rl) / dt_real * 180.0 / M_PI;
  }
  if (gap)
    T_pred.translation().setZero();
  // Tilt over a gap the gyro does not cover is unknown: level by the accelerometer's next hint.
  if (gap && !have_gyro && hints_seen_ && p_.use_imu)
  {
    level_pending_ = true;
    level_pending_since_ = stamp;
  }
  if (level_pending_ && have_up_hint)
  {
    levelByGravity(up_hint_);
    ++fs_.gravity_relevels;
    level_pending_ = false;
  }
  else if (level_pending_ && stamp - level_pending_since_ > kLevelWaitS)
    level_pending_ = false;  // no accelerometer after all: carry on with the old tilt
  else if (level_pending_ && force_untrusted.empty())
    force_untrusted = "tilt unknown after a gap the gyro did not cover: waiting for the accelerometer";
  coast_ok = mayCoast(stamp, have_gyro);
  // Motion of a lost frame: the prediction while coasting, else none (the gyro's rotation only).
  auto lostMotion = [&]() {
    Eigen::Isometry3d T = T_pred;
    if (!coast_ok || !force_untrusted.empty())
    {
      T.translation().setZero();
      if (!have_gyro)
        T.linear().setIdentity();
    }
    return T;
  };

  st.image_change = imageChange(left);
  if (!imageUsable(left, why) || !imageUsable(right, why))
  {
    last_dt_ = dt;
    VoOutput o = fail(why, nullptr, nullptr, lostMotion(), stamp, st);
    o.state = TrackingState::LOST;
    return finish(o);
  }

  // Frozen camera: the image does not change while the gyro says the head turns. Such a frame
  // carries no motion information (skipped: pose predicted); frozen_frames of them in a row make
  // the pose untrusted until the image changes and a new keyframe is tracked. An unchanged image
  // with a still head is normal (and with a noise-free camera, identical).
  const bool unchanged = st.image_change >= 0 && st.image_change <= p_.frozen_max_change;
  if (!unchanged)
    frozen_run_ = 0;
  else if (have_gyro && st.gyro_rate_dps >= p_.frozen_min_gyro_dps)
    ++frozen_run_;
  if (unchanged && frozen_run_ > 0)
  {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "frozen camera: image unchanged (%.2f) while the gyro turns %.1f deg/s",
                  st.image_change, std::max(0.0, st.gyro_rate_dps));
    if (frozen_run_ >= std::max(1, p_.frozen_frames))
    {
      if (frozen_run_ == std::max(1, p_.frozen_frames))
        ++fs_.frozen;
      if (force_untrusted.empty())
        force_untrusted = buf;
    }
    last_dt_ = dt;
    VoOutput o = fail(buf, nullptr, nullptr, lostMotion(), stamp, st);
    o.state = TrackingState::LOST;
    return finish(o);
  }

  // ---- pyramid of the current left image ----
  auto t0 = Clock::now();
  const cv::Size win(p_.klt_window, p_.klt_window);
  cv::buildOpticalFlowPyramid(left, cur_pyr_, win, p_.klt_levels, true);
  st.ms_pyramid = msSince(t0);

  if (!have_keyframe_ || gap)
  {
    // First frame, a frame after a failure, or a stream gap: start a keyframe here, keeping the
    // pose chain (the pose is predicted over the gap).
    const bool first = last_state_ == TrackingState::INITIALISING;
    if (gap)
    {
      ++resets_;
      st.reset = true;
    }
    if (!first)
    {
      T_w_cur_ = T_w_cur_ * lostMotion();
      last_T_prev_cur_ = lostMotion();
    }
    gravity_.clear();
    last_dt_ = dt;
    startKeyframe(left, right, false, st);
    std::swap(prev_pyr_, cur_pyr_);
    last_stamp_ = stamp;
    const TrackingState s = have_keyframe_ ? (first ? TrackingState::TRACKING : TrackingState::REINITIALISING)
                                           : (first ? TrackingState::INITIALISING : TrackingState::LOST);
    VoOutput o = makeOutput(s, st, first ? Eigen::Isometry3d::Identity() : lostMotion(), dt);
    o.message = why;
    if (!have_keyframe_)
      o.message = "too few features with stereo depth to start tracking";
    return finish(o);
  }

  // ---- KLT from the previous frame, initial guess from the predicted motion ----
  t0 = Clock::now();
  const Eigen::Isometry3d T_kf_pred = T_kf_prev_ * T_pred;
  const Eigen::Isometry3d T_pred_kf = T_kf_pred.inverse();
  std::vector<cv::Point2f> p0(tracks_.size()), p1(tracks_.size());
  for (size_t i = 0; i < tracks_.size(); ++i)
  {
    p0[i] = tracks_[i].cur;
    const Eigen::Vector3d Xc = T_pred_kf * tracks_[i].X_kf;
    if (Xc.z() > 0.05)
    {
      const Eigen::Vector2d q = cam_.projectLeft(Xc);
      p1[i] = cv::Point2f(static_cast<float>(q.x()), static_cast<float>(q.y()));
      if (!(q.allFinite()) || q.x() < 0 || q.y() < 0 || q.x() >= cam_.width || q.y() >= cam_.height)
        p1[i] = p0[i];
    }
    else
      p1[i] = p0[i];
  }
  std::vector<uint8_t> status;
  std::vector<float> err;
  if (!p0.empty())
    cv::calcOpticalFlowPyrLK(prev_pyr_, cur_pyr_, p0, p1, status, err, win, p_.klt_levels,
                             cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, p_.klt_iterations,
                                              p_.klt_epsilon),
                             cv::OPTFLOW_USE_INITIAL_FLOW, p_.klt_min_eigen);
  ov_from_.clear();
  ov_to_.clear();
  ov_inlier_.clear();
  {
    std::vector<Track> alive;
    alive.reserve(tracks_.size());
    const float b = 2.f;
    for (size_t i = 0; i < tracks_.size(); ++i)
    {
      if (!status[i] || !(p1[i].x >= b && p1[i].y >= b && p1[i].x < cam_.width - b && p1[i].y < cam_.height - b))
        continue;
      Track t = tracks_[i];
      t.prev = p0[i];
      t.cur = p1[i];
      alive.push_back(t);
    }
    tracks_.swap(alive);
  }
  // Refine against the keyframe patch (affine): removes the frame-to-frame KLT drift.
  for (auto& t : tracks_)
  {
    if (!t.patch)
      continue;
    cv::Point2f c = t.cur;
    Eigen::Matrix2f A = t.warp;
    float ncc = 0.f;
    if (t.patch->align(left, c, A, p_.alignment_iterations, &ncc) && ncc >= p_.alignment_min_ncc &&
        std::hypot(c.x - t.cur.x, c.y - t.cur.y) <= p_.alignment_max_shift_px)
    {
      t.cur = c;
      t.warp = A;
      ++st.aligned;
    }
  }
  st.klt_tracked = static_cast<int>(tracks_.size());
  st.ms_klt = msSince(t0);

  // ---- RANSAC on the epipolar constraint (keyframe -> current) ----
  t0 = Clock::now();
  if (p_.epipolar_filter && tracks_.size() >= 15)
  {
    std::vector<cv::Point2f> a(tracks_.size()), c(tracks_.size());
    double flow = 0;
    for (size_t i = 0; i < tracks_.size(); ++i)
    {
      a[i] = cv::Point2f(static_cast<float>(tracks_[i].kf_obs.u), static_cast<float>(tracks_[i].kf_obs.v));
      c[i] = tracks_[i].cur;
      flow += cv::norm(a[i] - c[i]);
    }
    flow /= static_cast<double>(tracks_.size());
    if (flow > p_.epipolar_min_flow_px)
    {
      std::vector<uint8_t> mask;
      cv::Mat F = cv::findFundamentalMat(a, c, cv::FM_RANSAC, p_.epipolar_threshold_px, 0.99, 200, mask);
      if (!F.empty() && mask.size() == tracks_.size())
      {
        size_t nin = 0;
        for (uint8_t m : mask)
          nin += m != 0;
        // Only trust F when it explains most tracks (near-degenerate motion can fit nonsense).
        if (nin >= tracks_.size() / 2)
        {
          std::vector<Track> keep;
          keep.reserve(nin);
          for (size_t i = 0; i < tracks_.size(); ++i)
            if (mask[i])
              keep.push_back(tracks_[i]);
            else
            {
              ov_from_.push_back(tracks_[i].prev);
              ov_to_.push_back(tracks_[i].cur);
              ov_inlier_.push_back(0);
            }
          tracks_.swap(keep);
        }
      }
    }
  }
  st.epipolar_kept = static_cast<int>(tracks_.size());
  st.ms_epipolar = msSince(t0);

  // ---- sparse stereo for the tracked points ----
  t0 = Clock::now();
  {
    std::vector<cv::Point2f> pts(tracks_.size());
    for (size_t i = 0; i < tracks_.size(); ++i)
      pts[i] = tracks_[i].cur;
    const std::vector<float> d = stereo_.match(left, right, pts, maxDisparity());
    for (size_t i = 0; i < tracks_.size(); ++i)
      tracks_[i].cur_disp = d[i];
  }
  st.ms_stereo = msSince(t0);

  // ---- P3P RANSAC (LMedS) against the keyframe's 3D points ----
  t0 = Clock::now();
  Vec3List X(tracks_.size());
  Vec2List x(tracks_.size());
  for (size_t i = 0; i < tracks_.size(); ++i)
  {
    X[i] = tracks_[i].X_kf;
    x[i] = Eigen::Vector2d(tracks_[i].cur.x, tracks_[i].cur.y);
  }
  RansacOptions ro;
  ro.probability = p_.ransac_probability;
  ro.max_trials = p_.ransac_max_trials;
  ro.min_trials = p_.ransac_min_trials;
  ro.threshold_max_px = p_.inlier_threshold_px;
  ro.threshold_min_px = p_.inlier_threshold_min_px;
  const RansacResult rr = ransac_.estimate(cam_, X, x, ro, &T_kf_pred);
  st.ransac_trials = rr.trials;
  st.ms_ransac = msSince(t0);
  last_dt_ = dt;
  if (!rr.ok || static_cast<int>(rr.inliers.size()) < p_.min_inliers)
  {
    st.inliers = static_cast<int>(rr.inliers.size());
    return finish(fail("too few inliers (" + std::to_string(rr.inliers.size()) + "): re-initialising", &left,
                       &right, lostMotion(), stamp, st));
  }

  // ---- two-frame sparse bundle adjustment over the inliers ----
  t0 = Clock::now();
  Vec3List Xin;
  std::vector<StereoObservation> oref, ocur;
  Xin.reserve(rr.inliers.size());
  for (int i : rr.inliers)
  {
    const Track& t = tracks_[static_cast<size_t>(i)];
    Xin.push_back(t.X_kf);
    oref.push_back(t.kf_obs);
    ocur.push_back(StereoObservation{t.cur.x, t.cur.y, t.cur_disp > 0 ? t.cur.x - t.cur_disp : -1.0});
  }
  TwoFrameBundleAdjuster::Options bo;
  bo.iterations = p_.ba_iterations;
  bo.huber_px = p_.ba_huber_px;
  bo.pixel_sigma_px = p_.pixel_sigma_px;
  BundleAdjustmentResult br = ba_.optimize(cam_, rr.T_ref_cur, Xin, oref, ocur, bo);
  // Vision-only rotation (kept for the online gyro bias estimate).
  const Eigen::Matrix3d R_vision = br.ok ? Eigen::Matrix3d(br.T_ref_cur.linear()) : Eigen::Matrix3d(rr.T_ref_cur.linear());
  const Eigen::Matrix<double, 6, 6> cov_vision = br.covariance;
  if (have_gyro)
    R_kf_gyro_ = R_kf_gyro_ * R_gyro_opt;
  else
    gyro_since_kf_ = false;
  const double dt_kf = stamp - t_kf_;
  if (br.ok && gyro_since_kf_ && p_.gyro_rotation_prior && dt_kf > 0)
  {
    // Second pass with the integrated (bias-corrected) gyro as a rotation prior: angle random
    // walk + bias uncertainty over the keyframe span.
    const double var_g = p_.gyro_noise_density * p_.gyro_noise_density * dt_kf + gyro_bias_var_ * dt_kf * dt_kf + 1e-10;
    bo.use_rotation_prior = true;
    bo.rotation_prior = R_kf_gyro_;
    bo.rotation_prior_weight = p_.pixel_sigma_px * p_.pixel_sigma_px / var_g;
    bo.iterations = std::max(2, p_.ba_iterations / 2);
    const BundleAdjustmentResult b2 = ba_.optimize(cam_, br.T_ref_cur, Xin, oref, ocur, bo);
    if (b2.ok)
      br = b2;
  }
  st.ms_ba = msSince(t0);
  const Eigen::Isometry3d T_kf_cur = br.ok ? br.T_ref_cur : rr.T_ref_cur;
  {
    // Stereo consistency: the current disparity of the inliers against the one their refined 3D
    // point predicts at the estimated pose (median). A right image out of sync with the left (or a
    // moved camera) gives pixels of error; a good pair, a tenth of a pixel.
    std::vector<double> res;
    res.reserve(rr.inliers.size());
    const Eigen::Isometry3d T_cur_kf = T_kf_cur.inverse();
    int matched = 0;
    for (size_t k = 0; k < rr.inliers.size(); ++k)
    {
      const Track& t = tracks_[static_cast<size_t>(rr.inliers[k])];
      const Eigen::Vector3d Xc = T_cur_kf * Xin[k];
      matched += t.cur_disp > 0;
      if (t.cur_disp > 0 && Xc.z() > 0.1)
        res.push_back(std::abs(t.cur_disp - cam_.fx * cam_.baseline / Xc.z()));
    }
    st.stereo_matched_ratio = rr.inliers.empty() ? -1.0 : matched / static_cast<double>(rr.inliers.size());
    if (res.size() >= 5)
    {
      std::nth_element(res.begin(), res.begin() + res.size() / 2, res.end());
      st.stereo_error_px = res[res.size() / 2];
    }
  }
  // ---- plausibility: no jumps ----
  const Eigen::Isometry3d T_prev_cur = T_kf_prev_.inverse() * T_kf_cur;
  // Translation: the change against the constant-velocity prediction is bounded by max_speed
  // (a walking head cannot jump; a vehicle moving fast but steadily is fine). A solution that a
  // clear majority of the tracks supports (>= 2 x min_inliers and >= half the tracks) is accepted
  // even when it exceeds the bound: that is the start of tracking on a fast platform, not a jump.
  const double max_t = p_.max_speed_mps * dt + 0.02;
  const double max_r = p_.max_angular_speed_dps * M_PI / 180.0 * dt + 0.02;
  const int n_in = static_cast<int>(rr.inliers.size());
  const bool strong = n_in >= 2 * p_.min_inliers && 2 * n_in >= static_cast<int>(tracks_.size());
  std::string bad;
  if (!T_kf_cur.matrix().allFinite())
    bad = "non-finite motion";
  else if ((T_prev_cur.translation() - T_pred.translation()).norm() > max_t && !strong)
    bad = "implausible translation";
  else if (angleOf(T_prev_cur.linear()) > max_r)
    bad = "implausible rotation";
  else if (gyro_link && p_.use_imu &&
           angleOf(T_prev_cur.linear().transpose() * T_pred.linear()) > 0.05 + 0.5 * angleOf(T_pred.linear()))
    bad = "rotation disagrees with the gyro";
  // Image motion contradicting the gyro (camera loose on the head, the view filled by something
  // moving): the vision-only rotation of this frame against the gyro's, over several frames.
  if (have_gyro && bad.empty())
  {
    const Eigen::Matrix3d R_vis_prev_cur = R_kf_prev_vision_.transpose() * R_vision;
    st.gyro_disagreement_deg = angleOf(R_vis_prev_cur.transpose() * R_gyro_opt) * 180.0 / M_PI;
    if (st.gyro_disagreement_deg > p_.gyro_disagreement_deg)
      ++disagree_run_;
    else
    {
      disagree_run_ = 0;
      agree_needed_ = std::max(0, agree_needed_ - 1);
    }
    const int n = std::max(1, p_.gyro_disagreement_frames);
    if (disagree_run_ >= n)
    {
      if (disagree_run_ == n)
        ++fs_.gyro_disagreement;
      agree_needed_ = n;
      char buf[160];
      std::snprintf(buf, sizeof(buf), "image motion contradicts the gyro (%.1f deg on %d frames)",
                    st.gyro_disagreement_deg, disagree_run_);
      bad = buf;
      force_untrusted = bad;
    }
  }
  else if (!have_gyro)
  {
    disagree_run_ = 0;
    agree_needed_ = std::max(0, agree_needed_ - 1);  // nothing to check against
  }
  // Stereo pair inconsistent with the motion (right image out of sync, camera moved): over
  // stereo_inconsistent_frames tracked frames in a row, or at once when 5 x the threshold.
  if (bad.empty() && st.stereo_matched_ratio >= 0)
  {
    const int n = std::max(1, p_.stereo_inconsistent_frames);
    if (st.stereo_error_px > p_.stereo_max_error_px || st.stereo_matched_ratio < p_.stereo_min_matched_ratio)
      stereo_bad_run_ = st.stereo_error_px > 5 * p_.stereo_max_error_px ? std::max(n, stereo_bad_run_ + 1)
                                                                        : stereo_bad_run_ + 1;
    else
    {
      stereo_bad_run_ = 0;
      stereo_agree_needed_ = std::max(0, stereo_agree_needed_ - 1);
    }
    if (stereo_bad_run_ >= n)
    {
      if (stereo_agree_needed_ == 0)
        ++fs_.stereo_inconsistent;
      stereo_agree_needed_ = n;
      char buf[160];
      std::snprintf(buf, sizeof(buf),
                    "stereo pair inconsistent: disparity off by %.1f px, %.0f %% matched (right image out of sync?)",
                    st.stereo_error_px, 100.0 * st.stereo_matched_ratio);
      bad = buf;
      force_untrusted = bad;
    }
  }
  if (!bad.empty())
    return finish(fail(bad + ": re-initialising", &left, &right, lostMotion(), stamp, st));
  R_kf_prev_vision_ = R_vision;

  // ---- accept ----
  std::vector<uint8_t> is_in(tracks_.size(), 0);
  for (size_t k = 0; k < rr.inliers.size(); ++k)
  {
    const size_t i = static_cast<size_t>(rr.inliers[k]);
    is_in[i] = 1;
    tracks_[i].X_kf = Xin[k];  // refined by the bundle adjustment
  }
  {
    std::vector<Track> keep;
    keep.reserve(rr.inliers.size());
    for (size_t i = 0; i < tracks_.size(); ++i)
    {
      ov_from_.push_back(tracks_[i].prev);
      ov_to_.push_back(tracks_[i].cur);
      ov_inlier_.push_back(is_in[i]);
      if (is_in[i])
        keep.push_back(tracks_[i]);
    }
    tracks_.swap(keep);
  }
  st.inliers = static_cast<int>(rr.inliers.size());
  T_w_cur_ = T_w_kf_ * T_kf_cur;
  T_kf_prev_ = T_kf_cur;
  last_T_prev_cur_ = T_prev_cur;
  // BA covariance is of the current frame relative to the keyframe (current-frame axes).
  cov_rel_ = br.ok ? br.covariance : Eigen::Matrix<double, 6, 6>::Identity() * 1e-2;
  cov_cur_ = cov_kf_ + rotateCov(cov_rel_, T_kf_cur.linear());

  // ---- replenish (new keyframe) ----
  if (static_cast<int>(tracks_.size()) < p_.replenish_ratio * tracks_started_ ||
      occupiedCells() < p_.replenish_coverage_ratio * cells_started_ ||
      static_cast<int>(tracks_.size()) < p_.min_tracks ||
      angleOf(T_kf_cur.linear()) > p_.max_rotation_from_keyframe_deg * M_PI / 180.0)
  {
    // Online gyro bias: vision rotation over the keyframe span vs the integrated gyro,
    // scalar Kalman update (R_vision^T R_gyro ~ exp((b - b_est) dt)).
    if (gyro_since_kf_ && br.ok && dt_kf > 0.3)
    {
      const Eigen::AngleAxisd aa(R_vision.transpose() * R_kf_gyro_);
      const Eigen::Vector3d b_err = R_lo * (aa.angle() * aa.axis()) / dt_kf;
      const double s_vo = std::max(p_.vo_rotation_sigma, std::sqrt(std::max(0.0, cov_vision.bottomRightCorner<3, 3>().trace() / 3)));
      const double var_m = s_vo * s_vo / (dt_kf * dt_kf);
      const double K = gyro_bias_var_ / (gyro_bias_var_ + var_m);
      if (b_err.allFinite() && b_err.norm() < 0.1)
      {
        gyro_bias_link_ += K * b_err;
        gyro_bias_var_ = (1 - K) * gyro_bias_var_ + p_.gyro_bias_walk * p_.gyro_bias_walk * dt_kf;
      }
    }
    startKeyframe(left, right, true, st);
  }

  // ---- gravity: keep the odom frame level (about the current position: no jump) ----
  if (dv_link && p_.use_imu)
  {
    const Eigen::Isometry3d T_odom_link = linkPose(T_odom_o0_ * T_w_cur_);
    Eigen::Matrix3d C;
    if (gravity_.add(stamp, T_odom_link, *dv_link, C))
    {
      const Eigen::Vector3d pos = T_odom_link.translation();
      Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
      M.linear() = C;
      M.translation() = pos - C * pos;
      T_odom_o0_ = M * T_odom_o0_;
    }
  }
  else
    gravity_.clear();

  std::swap(prev_pyr_, cur_pyr_);
  last_stamp_ = stamp;
  return finish(makeOutput(TrackingState::TRACKING, st, T_prev_cur, dt));
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
  for (size_t i = 0; i < ov_from_.size(); ++i)
  {
    const cv::Scalar c = ov_inlier_[i] ? cv::Scalar(0, 220, 0) : cv::Scalar(0, 0, 255);
    cv::line(out, ov_from_[i], ov_to_[i], c, 1, cv::LINE_AA);
    cv::circle(out, ov_to_[i], 2, c, -1, cv::LINE_AA);
  }
  for (const auto& t : tracks_)
    if (t.prev == t.cur)  // fresh corners of a new keyframe
      cv::circle(out, t.cur, 2, cv::Scalar(255, 160, 0), -1, cv::LINE_AA);
  cv::putText(out, std::string(toString(last_state_)) + "  tracks " + std::to_string(tracks_.size()),
              cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
  return out;
}
}  // namespace assistive_vo
