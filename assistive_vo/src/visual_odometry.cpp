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
InertialCoaster::Options coastOptions(const VoParams& p)
{
  InertialCoaster::Options o;
  o.window_s = p.imu_coast_window_s;
  o.accel_noise_density = p.accel_noise_density;
  o.accel_error_sigma = p.accel_error_sigma;
  o.gyro_noise_density = p.gyro_noise_density;
  return o;
}
GravityAligner::Options gravityOptions(const VoParams& p)
{
  GravityAligner::Options o;
  o.window_s = p.gravity_window_s;
  o.time_constant_s = p.gravity_time_constant_s;
  return o;
}
/// Smaller / larger eigenvalue of the structure tensor over the 7x7 window at c (0 near the
/// border): about 0 on a straight edge, up to 1 on an isotropic corner.
double cornerEigenRatio(const cv::Mat& img, const cv::Point2f& c)
{
  const int x0 = static_cast<int>(std::lround(c.x)), y0 = static_cast<int>(std::lround(c.y));
  if (x0 < 5 || y0 < 5 || x0 >= img.cols - 5 || y0 >= img.rows - 5)
    return 0.0;
  double a = 0, b = 0, d = 0;
  for (int y = y0 - 3; y <= y0 + 3; ++y)
  {
    const uchar* r = img.ptr<uchar>(y);
    const uchar* up = img.ptr<uchar>(y - 1);
    const uchar* dn = img.ptr<uchar>(y + 1);
    for (int x = x0 - 3; x <= x0 + 3; ++x)
    {
      const double gx = 0.5 * (r[x + 1] - r[x - 1]), gy = 0.5 * (dn[x] - up[x]);
      a += gx * gx, b += gx * gy, d += gy * gy;
    }
  }
  const double tr = a + d, det = a * d - b * b, disc = std::sqrt(std::max(0.0, tr * tr / 4 - det));
  const double l1 = tr / 2 + disc, l2 = tr / 2 - disc;
  return l1 > 0 ? std::max(0.0, l2) / l1 : 0.0;
}
bool usesPointLine(const VoParams& p)
{
  return p.motion_solver == "pointline" || p.motion_solver == "points_lines";
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
  : p_(p), cam_(cam), detector_(p), stereo_(p), checks_(p), bias_(p), gravity_(gravityOptions(p)),
    coast_(coastOptions(p))
{
  pointline_ = usesPointLine(p);
}

void VisualOdometry::setParams(const VoParams& p)
{
  p_ = p;
  gravity_.setOptions(gravityOptions(p));
  coast_.setOptions(coastOptions(p));
  detector_.setParams(p);
  stereo_.setParams(p);
  checks_.setParams(p);
  bias_.setParams(p);
  pointline_ = usesPointLine(p);
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
  have_keyframe_ = false;
  tracks_.clear();
  T_w_kf_ = T_w_cur_ = T_kf_prev_ = last_T_prev_cur_ = Eigen::Isometry3d::Identity();
  cov_kf_.setZero();
  cov_cur_.setZero();
  resets_ = 0;
  last_dt_ = 0;
  bias_.reset();
  clearOverlay();
  gravity_.clear();
  coast_.clear();
  untrusted_ = true;
  untrusted_why_.clear();
  have_trusted_ = false;
  prev_thumb_.release();
  level_pending_ = have_up_hint_ = false;
  R_kf_prev_vision_.setIdentity();
  checks_.reset();
}

bool VisualOdometry::mayCoast(double stamp, const FrameContext& fc) const
{
  // Coasting is a guess: only with the gyro bounding the rotation, only briefly, and never once
  // the pose has become untrusted (it stays so until a keyframe is tracked again). With the
  // accelerometer preintegrated and a velocity fitted, longer: while the position's uncertainty
  // stays small.
  if (!(fc.have_gyro && have_trusted_ && !untrusted_))
    return false;
  const double since = stamp - last_trusted_stamp_;
  if (fc.have_imu && coast_.available())
    return since <= p_.imu_coast_max_s + 1e-6 &&
           (!coast_.coasting() ||
            coast_.positionVariance(since) <= p_.imu_coast_max_sigma_m * p_.imu_coast_max_sigma_m);
  return since <= p_.coast_max_s + 1e-6;
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
    o.T_odom_optical = trusted_T_odom_optical_;
    o.T_odom_link = linkPose(trusted_T_odom_optical_);
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
  // Lines: the tracked ones carry on into the new keyframe while at least half of those started
  // (and 8) are left: the line detector (3-8 ms an image) is the dearest step of a keyframe.
  const bool keep_lines = pointline_ && from_current_tracks &&
                          static_cast<int>(lines_.size()) >= std::max(8, lines_started_ / 2);
  if (keep_lines)
  {
    for (LineTrack& t : lines_)
    {
      t.kf_left = t.cur;
      t.kf_right = t.cur_right;
    }
    setPrevRight(right);
  }
  else
  {
    lines_.clear();
    // ... and new lines are looked for at most every kLineDetectFrames frames (keyframes come
    // every 2-3 frames where corners are few)
    // and only while the keyframe's corners are not plenty (twice the 3 x min_inliers below which
    // the lines are used: the span runs down to there before the next keyframe; 10 x detected on
    // 16 % of the corridor's frames for the same drift, bare corridor 1.388 -> 1.279 % at 6 x)
    if (pointline_ && (!from_current_tracks || frames_since_line_detect_ >= kLineDetectFrames) &&
        tracks_started_ < 6 * p_.min_inliers)
    {
      startLines(left, right);
      frames_since_line_detect_ = 0;
    }
    lines_started_ = static_cast<int>(lines_.size());
  }
  st.new_features = added;
  st.keyframe = true;
  T_w_kf_ = T_w_cur_;
  T_kf_prev_ = Eigen::Isometry3d::Identity();
  R_kf_gyro_.setIdentity();
  R_kf_prev_vision_.setIdentity();
  gyro_since_kf_ = true;
  t_kf_ = last_stamp_pending_;
  cov_kf_ = cov_cur_;
  // With lines, a stereo segment counts as a feature (it constrains the motion as much as a point
  // or more: 4 rows of the trifocal system against a point's 3).
  have_keyframe_ = tracks_started_ + static_cast<int>(lines_.size()) >= std::max(4, p_.min_inliers);
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
    if (s != TrackingState::TRACKING && s != TrackingState::INITIALISING)
    {
      // a predicted motion: the variance of the prediction, not the last measured one's
      o.twist_covariance = Eigen::Matrix<double, 6, 6>::Identity() * (1e-2 / (dt * dt));
      if (imu_coasted_)
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
    const Track& t = tracks_[static_cast<size_t>(k)];
    if (t.cur_disp <= 0 || t.kf_obs.ur < 0)
      continue;
    kf.push_back({t.kf_obs.u, t.kf_obs.v, t.kf_obs.u - t.kf_obs.ur});
    cur.push_back({t.cur.x, t.cur.y, t.cur_disp});
  }
  disp_offset_.add(cam_, kf, cur, m.T_kf_cur.linear().transpose(), m.T_kf_cur.translation().norm());
  double delta = 0;
  if (disp_offset_.take(delta))
  {
    // a bounded step (the next round measures what is left)
    const double lim = p_.max_disparity_offset_px;
    stereo_.setOffset(std::clamp(stereo_.offset() + std::clamp(delta, -0.75, 0.75), -lim, lim));
  }
}

void VisualOdometry::growLostCovariance()
{
  // An IMU-coasted frame has grown the covariance by its own uncertainty (lostMotion); any other
  // lost frame (a constant-velocity guess, or the gyro's rotation only) by 0.1 m and 0.1 rad.
  if (!imu_coasted_)
    cov_cur_ += Eigen::Matrix<double, 6, 6>::Identity() * 1e-2;
}

void VisualOdometry::setCoastGyro()
{
  // the gyro's noise and its bias estimate's error tilt the coasted pose (gravity leaks through)
  InertialCoaster::Options o = coastOptions(p_);
  o.gyro_bias_sigma = std::sqrt(std::max(0.0, bias_.variance()));
  if (bias_.variance() < 0)
    o.gyro_bias_sigma = p_.gyro_bias_sigma;
  coast_.setOptions(o);
}

VoOutput VisualOdometry::fail(const std::string& why, const cv::Mat* left, const cv::Mat* right,
                              const Eigen::Isometry3d& T_prev_cur_pred, double stamp, FrameStats& st)
{
  // Keep the pose chain: predicted motion (gyro rotation, damped velocity), then a new keyframe
  // in this frame if it is usable, else wait for a usable frame.
  T_w_cur_ = T_w_cur_ * T_prev_cur_pred;
  last_T_prev_cur_ = T_prev_cur_pred;
  growLostCovariance();
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
  imu_coasted_ = false;
  ++frame_index_;
  const auto t_start = Clock::now();
  FrameStats st;
  st.fast_threshold = detector_.threshold();
  FrameContext fc;
  fc.stamp = stamp;
  const bool have_up_hint = have_up_hint_;  // setGravityHint() holds for this frame only
  have_up_hint_ = false;
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
  if (fc.have_gyro && dv_link && dp_link && p_.imu_coasting && dv_link->allFinite() && dp_link->allFinite())
  {
    fc.have_imu = true;
    fc.imu.dt = fc.dt_real;
    fc.imu.dv = *dv_link;
    fc.imu.dp = *dp_link;
  }
  levelAfterGap(have_up_hint, fc);
  fc.coast_ok = mayCoast(stamp, fc);
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
  const cv::Size win(p_.klt_window, p_.klt_window);
  cv::buildOpticalFlowPyramid(left, cur_pyr_, win, p_.klt_levels, true);
  st.ms_pyramid = msSince(t0);
  if (!have_keyframe_ || fc.gap)
    return finish(restartKeyframe(left, right, fc, st));

  // ---- keyframe tracking, motion estimation ----
  const Eigen::Isometry3d T_kf_pred = T_kf_prev_ * fc.T_pred;
  trackFrame(left, T_kf_pred, st);
  filterEpipolar(st);
  matchStereo(left, right, st);
  if (pointline_)
    trackLines(right, st);
  MotionEstimate m;
  const bool pose_found = estimateMotion(T_kf_pred, fc, st, m);
  last_dt_ = fc.dt;
  if (!pose_found)
    return finish(fail("too few inliers (" + std::to_string(m.rr.inliers.size()) + "): re-initialising", &left,
                       &right, lostMotion(fc), stamp, st));
  refinePose(fc, st, m);

  // ---- plausibility ----
  const std::string bad = judgeMotion(m, gyro_link != nullptr, fc, st);
  if (!bad.empty())
    return finish(fail(bad + ": re-initialising", &left, &right, lostMotion(fc), stamp, st));
  R_kf_prev_vision_ = m.R_vision;

  // ---- accept; gyro bias and a new keyframe at the end of a keyframe span; gravity ----
  accept(m, st);
  if (needKeyframe(m.T_kf_cur))
  {
    updateGyroBias(m);
    startKeyframe(left, right, true, st);
  }
  if (p_.estimate_disparity_offset)
    estimateDisparityOffset(m);
  levelWithGravity(stamp, dv_link);
  coast_.addTracked(stamp, linkPose(T_odom_o0_ * T_w_cur_), fc.have_imu ? &fc.imu : nullptr);

  std::swap(prev_pyr_, cur_pyr_);
  last_stamp_ = stamp;
  return finish(makeOutput(TrackingState::TRACKING, st, m.T_prev_cur, fc.dt));
}

bool VisualOdometry::estimateMotion(const Eigen::Isometry3d& T_kf_pred, const FrameContext& fc, FrameStats& st,
                                    MotionEstimate& m)
{
  // pointline: the point+line RANSAC while stereo line tracks exist; without any it would be
  // the quaternion solver on points alone, slower than P3P and no better (README figures).
  // Where corners are plenty (3 x min_inliers tracks), P3P too: the lines only help where points are few.
  const bool with_lines = pointline_ && static_cast<int>(tracks_.size()) < 3 * p_.min_inliers &&
                          std::any_of(lines_.begin(), lines_.end(), [](const LineTrack& t) { return t.stereo; });
  // With the IMU the points first and the lines only where the points alone fail: a weak frame
  // coasts well on the IMU, and the lines of one wall were no better than the few corners there
  // (shipped worlds and generated ones with the IMU: as many bags worse as better, README).
  if (with_lines && fc.have_imu)
  {
    if (estimatePose(T_kf_pred, st, m))
      return true;
    m = MotionEstimate();
    return estimatePosePointLine(st, m);
  }
  return with_lines ? estimatePosePointLine(st, m) : estimatePose(T_kf_pred, st, m);
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
    T.translation().setZero();
    if (!fc.have_gyro)
      T.linear().setIdentity();
    coast_.clear();
  }
  else if (fc.have_imu && (was_coasting || (setCoastGyro(), coast_.start())))
  {
    if (!was_coasting)
      coast_var_ = coast_rot_var_ = 0.0;
    // IMU coasting: translation from the preintegrated accelerometer and the velocity fitted at
    // the last tracked frame; the rotation stays the bias-corrected gyro's (T_pred).
    const Eigen::Isometry3d T_odom_opt = T_odom_o0_ * T_w_cur_;
    const Eigen::Vector3d dpos = coast_.step(T_odom_opt.linear() * R_link_optical().transpose(), fc.imu);
    if (!(coast_.velocity().norm() <= p_.max_speed_mps))
    {
      // a coasted speed no wearer reaches (an accelerometer spike, a bad fit): no guess, untrusted
      T.translation().setZero();
      coast_.clear();
      fc.coast_ok = false;
      return T;
    }
    T.translation() = T_odom_opt.linear().transpose() * dpos;
    // the covariance grows by what the coast adds (isotropic in position: the same in any axes)
    // (and the rotation by the gyro's, over the whole coast: its bias error grows the angle linearly)
    const double var = coast_.positionVariance(coast_.coastTime());
    const double rvar = bias_.rotationVariance(coast_.coastTime());
    cov_cur_.topLeftCorner<3, 3>() += Eigen::Matrix3d::Identity() * std::max(0.0, var - coast_var_);
    cov_cur_.bottomRightCorner<3, 3>() += Eigen::Matrix3d::Identity() * std::max(0.0, rvar - coast_rot_var_);
    coast_var_ = var;
    coast_rot_var_ = rvar;
    imu_coasted_ = true;
  }
  else
    coast_.clear();  // constant-velocity guess (coast_max_s at most)
  return T;
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
  T_w_cur_ = T_w_kf_ = Eigen::Isometry3d::Identity();
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
  }
  if (fc.gap)
    fc.T_pred.translation().setZero();
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
  std::swap(prev_pyr_, cur_pyr_);
  last_stamp_ = fc.stamp;
  const TrackingState s = have_keyframe_ ? (first ? TrackingState::TRACKING : TrackingState::REINITIALISING)
                                         : (first ? TrackingState::INITIALISING : TrackingState::LOST);
  VoOutput o = makeOutput(s, st, first ? Eigen::Isometry3d::Identity() : lostMotion(fc), fc.dt);
  o.message = fc.why;
  if (!have_keyframe_)
    o.message = "too few features with stereo depth to start tracking";
  return o;
}

void VisualOdometry::trackFrame(const cv::Mat& left, const Eigen::Isometry3d& T_kf_pred, FrameStats& st)
{
  const auto t0 = Clock::now();
  const cv::Size win(p_.klt_window, p_.klt_window);
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
  clearOverlay();
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
}

void VisualOdometry::filterEpipolar(FrameStats& st)
{
  const auto t0 = Clock::now();
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
              addOverlay(tracks_[i], false);
          tracks_.swap(keep);
        }
      }
    }
  }
  st.epipolar_kept = static_cast<int>(tracks_.size());
  st.ms_epipolar = msSince(t0);
}

void VisualOdometry::matchStereo(const cv::Mat& left, const cv::Mat& right, FrameStats& st)
{
  const auto t0 = Clock::now();
  std::vector<cv::Point2f> pts(tracks_.size());
  for (size_t i = 0; i < tracks_.size(); ++i)
    pts[i] = tracks_[i].cur;
  const std::vector<float> d = stereo_.match(left, right, pts, maxDisparity());
  for (size_t i = 0; i < tracks_.size(); ++i)
    tracks_[i].cur_disp = d[i];
  st.ms_stereo = msSince(t0);
}

bool VisualOdometry::estimatePose(const Eigen::Isometry3d& T_kf_pred, FrameStats& st, MotionEstimate& m)
{
  const auto t0 = Clock::now();
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
  m.rr = ransac_.estimate(cam_, X, x, ro, &T_kf_pred);
  st.ransac_trials = m.rr.trials;
  st.ms_ransac = msSince(t0);
  if (!m.rr.ok || static_cast<int>(m.rr.inliers.size()) < p_.min_inliers)
  {
    st.inliers = static_cast<int>(m.rr.inliers.size());
    return false;
  }
  return true;
}

void VisualOdometry::startLines(const cv::Mat& left, const cv::Mat& right)
{
  // Lines detected in the left image only; each one's right segment found by a disparity sweep
  // and KLT (line_tracking.h): detecting the right image too cost as much again.
  const LineSegments L = line_detector_.detect(left);
  line_match_.min_disparity = p_.min_disparity_px;
  line_match_.max_disparity = maxDisparity();
  std::vector<bool> ok;
  // the KLT pyramids: the left one the points use, the right one this frame's line tracking built
  // (else built here and kept for the next frame's)
  const bool pyramids = pointPyramidsServeLines() && !cur_pyr_.empty() && !L.empty();
  if (pyramids && prev_right_pyr_frame_ != frame_index_)
  {
    buildLinePyramid(right, prev_right_pyr_);
    prev_right_pyr_frame_ = frame_index_;
  }
  const LineSegments R = pyramids ? sweepStereoSegments(left, right, L, line_match_, ok, cur_pyr_, prev_right_pyr_)
                                  : sweepStereoSegments(left, right, L, line_match_, ok);
  for (size_t i = 0; i < L.size(); ++i)
  {
    if (!ok[i])
      continue;
    LineTrack t;
    t.kf_left = t.cur = L[i];
    t.kf_right = t.cur_right = R[i];
    t.stereo = true;
    lines_.push_back(t);
  }
  setPrevRight(right);
}

bool VisualOdometry::pointPyramidsServeLines() const
{
  return p_.klt_window >= kLineKltWindow && p_.klt_levels >= kLineKltLevels;
}

void VisualOdometry::setPrevRight(const cv::Mat& right)
{
  right.copyTo(prev_right_);
  prev_right_frame_ = frame_index_;
}

void VisualOdometry::trackLines(const cv::Mat& right, FrameStats& st)
{
  const auto t0 = Clock::now();
  ++frames_since_line_detect_;
  if (!lines_.empty() && !prev_pyr_.empty() && !cur_pyr_.empty())
  {
    // Both segments of a line tracked by KLT along them, the left one in the left images, the
    // right one in the right images (detecting the right image's segments again on every frame
    // cost three times as much).
    LineSegments prev_l, prev_r;
    prev_l.reserve(lines_.size());
    prev_r.reserve(lines_.size());
    for (const LineTrack& t : lines_)
    {
      prev_l.push_back(t.cur);
      prev_r.push_back(t.cur_right);
    }
    std::vector<bool> ok_l, ok_r;
    // the KLT pyramids of the left images when built for a window at least the lines':
    // calcOpticalFlowPyrLK would build both again
    const bool pyramids = pointPyramidsServeLines();
    const LineSegments next_l = pyramids ? trackSegments(prev_pyr_, cur_pyr_, prev_l, line_match_, ok_l)
                                         : trackSegments(prev_pyr_[0], cur_pyr_[0], prev_l, line_match_, ok_l);
    // the right images' pyramids: this one's kept for the next frame (one build a frame)
    std::vector<cv::Mat> right_pyr;
    if (pyramids)
    {
      buildLinePyramid(right, right_pyr);
      if (prev_right_pyr_frame_ != prev_right_frame_ || prev_right_pyr_.empty())
        buildLinePyramid(prev_right_, prev_right_pyr_);
    }
    const LineSegments next_r = pyramids ? trackSegments(prev_right_pyr_, right_pyr, prev_r, line_match_, ok_r)
                                         : trackSegments(prev_right_, right, prev_r, line_match_, ok_r);
    if (pyramids)
    {
      prev_right_pyr_.swap(right_pyr);
      prev_right_pyr_frame_ = frame_index_;
    }
    std::vector<LineTrack> alive;
    for (size_t i = 0; i < lines_.size(); ++i)
      if (ok_l[i] && ok_r[i])
      {
        LineTrack t = lines_[i];
        t.cur = next_l[i];
        t.cur_right = next_r[i];
        t.stereo = true;
        alive.push_back(t);
      }
    lines_.swap(alive);
    st.lines = static_cast<int>(lines_.size());
  }
  else
    lines_.clear();
  setPrevRight(right);
  st.ms_lines = msSince(t0);
}

bool VisualOdometry::estimatePosePointLine(FrameStats& st, MotionEstimate& m)
{
  const auto t0 = Clock::now();
  const auto norm = [this](double u, double v) { return Eigen::Vector2d((u - cam_.cx) / cam_.fx, (v - cam_.cy) / cam_.fy); };
  StereoRig rig;
  rig.t0 = Eigen::Vector3d(-cam_.baseline, 0.0, 0.0);
  PointQuads pq;
  std::vector<int> pq_track;
  // Corners on a straight edge slide along it (the aperture problem): with the lines they add
  // nothing across the edge and mislead along it (the corridor's end: all the corners on the
  // door jambs, 12-28 px off in v at the true motion). Only clear corners join the lines.
  std::vector<uint8_t> edge_like(tracks_.size(), 0);
  for (size_t i = 0; i < tracks_.size(); ++i)
    edge_like[i] = p_.pointline_min_corner_ratio > 0 &&
                   cornerEigenRatio(cur_pyr_[0], tracks_[i].cur) < p_.pointline_min_corner_ratio;
  for (size_t i = 0; i < tracks_.size(); ++i)
  {
    const Track& t = tracks_[i];
    if (t.cur_disp <= 0 || t.kf_obs.ur < 0 || edge_like[i])
      continue;
    PointQuad q;
    q.x[0] = norm(t.kf_obs.u, t.kf_obs.v);
    q.x[1] = norm(t.kf_obs.ur, t.kf_obs.v);
    q.x[2] = norm(t.cur.x, t.cur.y);
    q.x[3] = norm(t.cur.x - t.cur_disp, t.cur.y);
    pq.push_back(q);
    pq_track.push_back(static_cast<int>(i));
  }
  LineQuads lq;
  std::vector<int> lq_track;
  for (size_t i = 0; i < lines_.size(); ++i)
  {
    const LineTrack& t = lines_[i];
    if (!t.stereo)
      continue;
    LineQuad q;
    const LineSegment* v[4] = {&t.kf_left, &t.kf_right, &t.cur, &t.cur_right};
    for (int k = 0; k < 4; ++k)
    {
      q.p[k] = norm(v[k]->p.x(), v[k]->p.y());
      q.q[k] = norm(v[k]->q.x(), v[k]->q.y());
    }
    lq.push_back(q);
    lq_track.push_back(static_cast<int>(i));
  }
  PointLineRansacOptions ro;
  ro.sample_size = 5;  // quaternion-5, as the seed's real-data runs
  ro.threshold_px = p_.inlier_threshold_px;
  ro.focal_px = cam_.fx;
  ro.probability = p_.ransac_probability;
  ro.max_trials = p_.ransac_max_trials;
  const PointLineRansacResult r = pl_ransac_.estimate(rig, pq, lq, ro);
  m.rr = RansacResult();
  m.with_lines = true;
  m.rr.trials = r.trials;
  st.ransac_trials = r.trials;
  int line_in = 0;
  if (r.ok)
  {
    Eigen::Isometry3d T_cur_kf = Eigen::Isometry3d::Identity();
    T_cur_kf.linear() = r.motion.R;
    T_cur_kf.translation() = r.motion.t;
    m.rr.ok = true;
    m.rr.T_ref_cur = T_cur_kf.inverse();
    m.rr.threshold_px = ro.threshold_px;
    std::vector<uint8_t> is_in(tracks_.size(), 0);
    for (int k : r.point_inliers)
      is_in[static_cast<size_t>(pq_track[static_cast<size_t>(k)])] = 1;
    // tracks without a stereo match now: inliers by their left reprojection at this motion
    for (size_t i = 0; i < tracks_.size(); ++i)
    {
      const Track& t = tracks_[i];
      if ((t.cur_disp > 0 && t.kf_obs.ur >= 0) || edge_like[i])
        continue;
      const Eigen::Vector3d Xc = T_cur_kf * t.X_kf;
      if (Xc.z() > 0.05 && (cam_.projectLeft(Xc) - Eigen::Vector2d(t.cur.x, t.cur.y)).norm() < ro.threshold_px)
        is_in[i] = 1;
    }
    for (size_t i = 0; i < tracks_.size(); ++i)
      if (is_in[i])
        m.rr.inliers.push_back(static_cast<int>(i));
    // the line tracks kept: the inliers (outliers and lines without a stereo match now dropped)
    std::vector<LineTrack> keep;
    for (int k : r.line_inliers)
      keep.push_back(lines_[static_cast<size_t>(lq_track[static_cast<size_t>(k)])]);
    lines_.swap(keep);
    line_in = static_cast<int>(lines_.size());
  }
  st.line_inliers = line_in;
  st.ms_ransac = msSince(t0);
  // Enough constraints: a stereo line gives 4 rows against a stereo point's 3, counted as such
  // (the corridor's end wall: a point or two and 8-10 door-frame lines, re-initialised every
  // other frame when each line counted as one point).
  if (!m.rr.ok || 3 * static_cast<int>(m.rr.inliers.size()) + 4 * line_in < 3 * p_.min_inliers)
  {
    st.inliers = static_cast<int>(m.rr.inliers.size());
    return false;
  }
  return true;
}

void VisualOdometry::refinePose(const FrameContext& fc, FrameStats& st, MotionEstimate& m)
{
  const auto t0 = Clock::now();
  std::vector<StereoObservation> oref, ocur;
  m.X_in.reserve(m.rr.inliers.size());
  for (int i : m.rr.inliers)
  {
    const Track& t = tracks_[static_cast<size_t>(i)];
    m.X_in.push_back(t.X_kf);
    oref.push_back(t.kf_obs);
    ocur.push_back(StereoObservation{t.cur.x, t.cur.y, t.cur_disp > 0 ? t.cur.x - t.cur_disp : -1.0});
  }
  TwoFrameBundleAdjuster::Options bo;
  bo.iterations = p_.ba_iterations;
  bo.huber_px = p_.ba_huber_px;
  bo.pixel_sigma_px = p_.pixel_sigma_px;
  // The gyro since the keyframe (bias-corrected): a rotation prior for the second pass.
  if (fc.have_gyro)
    R_kf_gyro_ = R_kf_gyro_ * fc.R_gyro_opt;
  else
    gyro_since_kf_ = false;
  m.dt_kf = fc.stamp - t_kf_;
  const bool gyro_prior = gyro_since_kf_ && p_.gyro_rotation_prior && m.dt_kf > 0;
  const double var_g = gyro_prior ? bias_.rotationVariance(m.dt_kf) : 1.0;
  if (m.with_lines)
  {
    // points_lines: the motion refined on the point and the line inliers together (structure
    // fixed): with the points alone it was the few points that decided (README figures).
    StereoLineObservations lo;
    for (const LineTrack& t : lines_)
    {
      StereoLineObservation l;
      if (!t.stereo || !triangulateStereoSegment(cam_, t.kf_left, t.kf_right, p_.min_disparity_px, l.P, l.Q))
        continue;
      l.left_p = t.cur.p, l.left_q = t.cur.q, l.right_p = t.cur_right.p, l.right_q = t.cur_right.q;
      lo.push_back(l);
    }
    PointLineRefineOptions ro;
    ro.iterations = std::max(1, p_.ba_iterations);
    ro.huber_px = p_.ba_huber_px;
    ro.pixel_sigma_px = p_.pixel_sigma_px;
    // The constant-velocity prediction as a prior: the corridor's end wall leaves only its
    // vertical door jambs, which say nothing of the motion along them (without it 6-11 cm a frame
    // off in v there, README "Point+line in the loop").
    const Eigen::Isometry3d T_kf_pred = T_kf_prev_ * fc.T_pred;
    const double sig_t = p_.pointline_prior_sigma_m, sig_r = p_.pointline_prior_sigma_deg * M_PI / 180.0;
    ro.use_translation_prior = sig_t > 0;
    ro.translation_prior = T_kf_pred.translation();
    ro.translation_prior_weight = sig_t > 0 ? p_.pixel_sigma_px * p_.pixel_sigma_px / (sig_t * sig_t) : 0.0;
    // vision-only rotation first (the gyro bias estimate needs it), then with the gyro prior;
    // without a gyro the predicted rotation is the prior
    ro.use_rotation_prior = !gyro_prior && sig_r > 0;
    if (ro.use_rotation_prior)
    {
      ro.rotation_prior = T_kf_pred.linear();
      ro.rotation_prior_weight = p_.pixel_sigma_px * p_.pixel_sigma_px / (sig_r * sig_r);
    }
    // a point or two only where they are checked by others
    const bool points_checked = static_cast<int>(m.X_in.size()) >= p_.pointline_min_points;
    m.lines_only = !points_checked;
    const Vec3List no_points;
    const std::vector<StereoObservation> no_obs;
    const Vec3List& X_ref = points_checked ? m.X_in : no_points;
    const std::vector<StereoObservation>& X_obs = points_checked ? ocur : no_obs;
    m.br = refineMotionPointsLines(cam_, m.rr.T_ref_cur, X_ref, X_obs, lo, ro);
    m.R_vision = m.br.ok ? Eigen::Matrix3d(m.br.T_ref_cur.linear()) : Eigen::Matrix3d(m.rr.T_ref_cur.linear());
    m.cov_vision = m.br.covariance;
    if (m.br.ok && gyro_prior)
    {
      ro.use_rotation_prior = true;
      ro.rotation_prior = R_kf_gyro_;
      ro.rotation_prior_weight = p_.pixel_sigma_px * p_.pixel_sigma_px / var_g;
      const BundleAdjustmentResult b2 = refineMotionPointsLines(cam_, m.br.T_ref_cur, X_ref, X_obs, lo, ro);
      if (b2.ok)
        m.br = b2;
    }
  }
  else
  {
    m.br = ba_.optimize(cam_, m.rr.T_ref_cur, m.X_in, oref, ocur, bo);
    // Vision-only rotation (kept for the online gyro bias estimate).
    m.R_vision = m.br.ok ? Eigen::Matrix3d(m.br.T_ref_cur.linear()) : Eigen::Matrix3d(m.rr.T_ref_cur.linear());
    m.cov_vision = m.br.covariance;
    if (m.br.ok && gyro_prior)
    {
      // Second pass with the integrated (bias-corrected) gyro as a rotation prior: angle random
      // walk + bias uncertainty over the keyframe span.
      bo.use_rotation_prior = true;
      bo.rotation_prior = R_kf_gyro_;
      bo.rotation_prior_weight = p_.pixel_sigma_px * p_.pixel_sigma_px / var_g;
      bo.iterations = std::max(2, p_.ba_iterations / 2);
      const BundleAdjustmentResult b2 = ba_.optimize(cam_, m.br.T_ref_cur, m.X_in, oref, ocur, bo);
      if (b2.ok)
        m.br = b2;
    }
  }
  st.ms_ba = msSince(t0);
  m.T_kf_cur = m.br.ok ? m.br.T_ref_cur : m.rr.T_ref_cur;
  m.T_prev_cur = T_kf_prev_.inverse() * m.T_kf_cur;
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
    const Track& t = tracks_[static_cast<size_t>(m.rr.inliers[k])];
    const Eigen::Vector3d Xc = T_cur_kf * m.X_in[k];
    matched += t.cur_disp > 0;
    if (t.cur_disp > 0 && Xc.z() > 0.1)
      res.push_back(std::abs(t.cur_disp - cam_.fx * cam_.baseline / Xc.z()));
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
  const bool strong = n_in >= 2 * p_.min_inliers && 2 * n_in >= static_cast<int>(tracks_.size());
  std::string bad = checks_.checkMotion(m.T_kf_cur, m.T_prev_cur, fc.T_pred, fc.dt, strong, gyro_given && p_.use_imu);
  // Image motion contradicting the gyro: the vision-only rotation of this frame against the
  // gyro's, over several frames.
  if (fc.have_gyro && bad.empty())
  {
    const Eigen::Matrix3d R_vis_prev_cur = R_kf_prev_vision_.transpose() * m.R_vision;
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

void VisualOdometry::accept(const MotionEstimate& m, FrameStats& st)
{
  std::vector<uint8_t> is_in(tracks_.size(), 0);
  for (size_t k = 0; k < m.rr.inliers.size(); ++k)
  {
    const size_t i = static_cast<size_t>(m.rr.inliers[k]);
    is_in[i] = 1;
    tracks_[i].X_kf = m.X_in[k];  // refined by the bundle adjustment
  }
  std::vector<Track> keep;
  keep.reserve(m.rr.inliers.size());
  for (size_t i = 0; i < tracks_.size(); ++i)
  {
    addOverlay(tracks_[i], is_in[i] != 0);
    if (is_in[i])
      keep.push_back(tracks_[i]);
  }
  tracks_.swap(keep);
  st.inliers = static_cast<int>(m.rr.inliers.size());
  T_w_cur_ = T_w_kf_ * m.T_kf_cur;
  T_kf_prev_ = m.T_kf_cur;
  last_T_prev_cur_ = m.T_prev_cur;
  // BA covariance is of the current frame relative to the keyframe (current-frame axes).
  cov_rel_ = m.br.ok ? m.br.covariance : Eigen::Matrix<double, 6, 6>::Identity() * 1e-2;
  cov_cur_ = cov_kf_ + rotateCov(cov_rel_, m.T_kf_cur.linear());
}

bool VisualOdometry::needKeyframe(const Eigen::Isometry3d& T_kf_cur) const
{
  return static_cast<int>(tracks_.size()) < p_.replenish_ratio * tracks_started_ ||
         occupiedCells() < p_.replenish_coverage_ratio * cells_started_ ||
         static_cast<int>(tracks_.size()) < p_.min_tracks ||
         angleOf(T_kf_cur.linear()) > p_.max_rotation_from_keyframe_deg * M_PI / 180.0;
}

void VisualOdometry::updateGyroBias(const MotionEstimate& m)
{
  // Vision rotation over the keyframe span vs the integrated gyro; only over spans long enough
  // for the bias to show.
  if (gyro_since_kf_ && m.br.ok && m.dt_kf > 0.3)
    bias_.update(m.R_vision, R_kf_gyro_, m.dt_kf, m.cov_vision.bottomRightCorner<3, 3>().trace() / 3);
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

void VisualOdometry::clearOverlay()
{
  ov_from_.clear();
  ov_to_.clear();
  ov_inlier_.clear();
}

void VisualOdometry::addOverlay(const Track& t, bool inlier)
{
  ov_from_.push_back(t.prev);
  ov_to_.push_back(t.cur);
  ov_inlier_.push_back(inlier ? 1 : 0);
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
  // line tracks (motion_solver pointline): magenta
  for (const auto& l : lines_)
    cv::line(out, cv::Point2d(l.cur.p.x(), l.cur.p.y()), cv::Point2d(l.cur.q.x(), l.cur.q.y()),
             cv::Scalar(255, 0, 255), 2, cv::LINE_AA);
  cv::putText(out, std::string(toString(last_state_)) + "  tracks " + std::to_string(tracks_.size()),
              cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
  return out;
}
}  // namespace assistive_vo
