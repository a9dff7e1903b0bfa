#include "assistive_slam/fastslam.h"
#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>

namespace assistive_slam
{
namespace
{
constexpr double kDeg = M_PI / 180.0;
constexpr int kSide = 13;      ///< template side (seed 3.2.2.1)
constexpr int kRefRadius = 20; ///< reference patch radius: room for the warp up to ~3x scale
constexpr int kRevisitGap = 30; ///< frames out of view before a return counts as a revisit

Eigen::Matrix3d skew(const Eigen::Vector3d& v)
{
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

double logGauss2(const Eigen::Vector2d& e, const Eigen::Matrix2d& L)
{
  return -0.5 * e.dot(L.inverse() * e) - 0.5 * std::log(4.0 * M_PI * M_PI * L.determinant());
}

/// Bilinear sample of a CV_32F image (caller checks bounds).
inline float sample(const cv::Mat& m, double x, double y)
{
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float ax = static_cast<float>(x - x0), ay = static_cast<float>(y - y0);
  const float* r0 = m.ptr<float>(y0);
  const float* r1 = m.ptr<float>(y0 + 1);
  return (1 - ay) * ((1 - ax) * r0[x0] + ax * r0[x0 + 1]) + ay * ((1 - ax) * r1[x0] + ax * r1[x0 + 1]);
}

/// NCC of a zero-mean, unit-norm template (tn) with the mono8 patch centred on (cx, cy).
inline double nccAt(const cv::Mat& img, const float* tn, int side, int cx, int cy)
{
  const int h = side / 2;
  double s = 0, s2 = 0, st = 0;
  for (int r = 0; r < side; ++r)
  {
    const uchar* row = img.ptr<uchar>(cy - h + r) + (cx - h);
    const float* t = tn + r * side;
    for (int c = 0; c < side; ++c)
    {
      const double v = row[c];
      s += v;
      s2 += v * v;
      st += t[c] * v;
    }
  }
  const double n = side * side;
  const double var = s2 - s * s / n;
  return var > 1e-6 ? st / std::sqrt(var) : -1.0;
}

/// Zero-mean, unit-norm copy of a CV_32F template; false when it is flat.
bool normaliseTemplate(const cv::Mat& t, std::vector<float>* out)
{
  const int n = t.rows * t.cols;
  out->resize(n);
  double mean = 0;
  for (int i = 0; i < n; ++i)
    mean += t.ptr<float>()[i];
  mean /= n;
  double ss = 0;
  for (int i = 0; i < n; ++i)
  {
    (*out)[i] = static_cast<float>(t.ptr<float>()[i] - mean);
    ss += (*out)[i] * (*out)[i];
  }
  if (ss < 1e-3)
    return false;
  const float k = static_cast<float>(1.0 / std::sqrt(ss));
  for (float& v : *out)
    v *= k;
  return true;
}

/// Peak offset of a parabola through three samples, in [-0.5, 0.5].
double parabolaPeak(double a, double b, double c)
{
  const double den = a - 2 * b + c;
  return std::abs(den) > 1e-12 ? std::clamp(0.5 * (a - c) / den, -0.5, 0.5) : 0.0;
}
}  // namespace

bool stereoPoint(const StereoModel& cam, double u, double v, double d, double sigma_px, double sigma_d,
                 Eigen::Vector3d* X, Eigen::Matrix3d* cov)
{
  if (d <= 0)
    return false;
  // eq. 3.18 with u, v relative to the principal point (fy may differ from fx)
  const double uc = u - cam.cx, vc = v - cam.cy, B = cam.baseline, f = cam.fx, g = cam.fy;
  const double Z = f * B / d;
  *X = Eigen::Vector3d(uc * B / d, vc * f * B / (g * d), Z);
  Eigen::Matrix3d J;  // d(X, Y, Z) / d(u, v, d)
  J << B / d, 0, -uc * B / (d * d),  //
      0, f * B / (g * d), -vc * f * B / (g * d * d),  //
      0, 0, -f * B / (d * d);
  const Eigen::Vector3d s(sigma_px * sigma_px, sigma_px * sigma_px, sigma_d * sigma_d);
  *cov = J * s.asDiagonal() * J.transpose();  // eq. 3.20
  return true;
}

bool projectWithJacobians(const StereoModel& cam, const Eigen::Isometry3d& T_w_c, const Eigen::Vector3d& X,
                          Eigen::Vector2d* z, Matrix26d* H_s, Matrix23d* H_theta)
{
  const Eigen::Matrix3d Rt = T_w_c.linear().transpose();
  const Eigen::Vector3d p = Rt * (X - T_w_c.translation());
  if (p.z() < 1e-3)
    return false;
  const double iz = 1.0 / p.z();
  *z = Eigen::Vector2d(cam.fx * p.x() * iz + cam.cx, cam.fy * p.y() * iz + cam.cy);
  Matrix23d Jp;
  Jp << cam.fx * iz, 0, -cam.fx * p.x() * iz * iz, 0, cam.fy * iz, -cam.fy * p.y() * iz * iz;
  if (H_s)
  {
    // p(delta) = Exp(delta)^-1 p = p - rho + [p]x omega to first order
    H_s->leftCols<3>() = -Jp;
    H_s->rightCols<3>() = Jp * skew(p);
  }
  if (H_theta)
    *H_theta = Jp * Rt;
  return true;
}

Eigen::Isometry3d applyPerturbation(const Eigen::Isometry3d& T, const Vector6d& delta)
{
  Eigen::Isometry3d E = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d w = delta.tail<3>();
  if (w.norm() > 1e-15)
    E.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  E.translation() = delta.head<3>();
  return T * E;
}

LandmarkEstimate updateLandmark(const LandmarkEstimate& prior, const StereoModel& cam, const Eigen::Isometry3d& T_w_c,
                                const Eigen::Vector2d& z, double sigma_px)
{
  Eigen::Vector2d zh;
  Matrix23d H;
  if (!projectWithJacobians(cam, T_w_c, prior.mean, &zh, nullptr, &H))
    return prior;
  const Eigen::Matrix2d S = H * prior.cov * H.transpose() + Eigen::Matrix2d::Identity() * sigma_px * sigma_px;
  const Eigen::Matrix<double, 3, 2> K = prior.cov * H.transpose() * S.inverse();  // eq. 3.32
  LandmarkEstimate post;
  post.mean = prior.mean + K * (z - zh);                                          // eq. 3.34
  post.cov = (Eigen::Matrix3d::Identity() - K * H) * prior.cov;                   // eq. 3.35
  post.cov = 0.5 * (post.cov + post.cov.transpose());
  return post;
}

ProposalResult fastslamProposal(const StereoModel& cam, const Eigen::Isometry3d& T_pred, const Matrix6d& Q,
                                const std::vector<PoseObservation>& obs, double sigma_px)
{
  ProposalResult r;
  r.mean = T_pred;
  r.cov = Q;
  const Eigen::Matrix2d R = Eigen::Matrix2d::Identity() * sigma_px * sigma_px;
  for (const PoseObservation& o : obs)
  {
    Eigen::Vector2d zh;
    Matrix26d Hs;
    Matrix23d Ht;
    if (!projectWithJacobians(cam, r.mean, o.landmark.mean, &zh, &Hs, &Ht))
      continue;
    const Eigen::Matrix2d Z = R + Ht * o.landmark.cov * Ht.transpose();  // eq. 3.27
    const Eigen::Matrix2d L = Z + Hs * r.cov * Hs.transpose();           // eq. 3.30
    const Eigen::Vector2d e = o.z - zh;
    r.log_weight += logGauss2(e, L);                                     // eq. 3.31 (log)
    const Eigen::Matrix2d Zi = Z.inverse();
    Matrix6d info = Hs.transpose() * Zi * Hs + r.cov.inverse();          // eq. 3.28
    const Matrix6d cov = info.inverse();
    const Vector6d delta = cov * Hs.transpose() * Zi * e;                // eq. 3.29
    r.cov = 0.5 * (cov + cov.transpose());
    r.mean = applyPerturbation(r.mean, delta);
    ++r.used;
  }
  return r;
}

std::vector<double> normaliseLogWeights(const std::vector<double>& log_w)
{
  std::vector<double> w(log_w.size(), 0.0);
  if (log_w.empty())
    return w;
  const double mx = *std::max_element(log_w.begin(), log_w.end());
  double sum = 0;
  for (size_t i = 0; i < w.size(); ++i)
    sum += (w[i] = std::exp(log_w[i] - mx));  // the largest becomes exp(0) = 1: no 0 / 0
  for (double& v : w)
    v /= sum;
  return w;
}

double effectiveSampleSize(const std::vector<double>& w)
{
  double s = 0;
  for (double v : w)
    s += v * v;
  return s > 0 ? 1.0 / s : 0.0;
}

std::vector<int> systematicResample(const std::vector<double>& w, double u0)
{
  const int n = static_cast<int>(w.size());
  std::vector<int> idx(n);
  double c = w.empty() ? 0 : w[0];
  int k = 0;
  for (int i = 0; i < n; ++i)
  {
    const double u = u0 + static_cast<double>(i) / n;
    while (u > c && k + 1 < n)
      c += w[++k];
    idx[i] = k;
  }
  return idx;
}

SearchWindow fuseProjections(const std::vector<Eigen::Vector2d>& mu, const std::vector<Eigen::Matrix2d>& cov,
                             const std::vector<double>& w)
{
  SearchWindow s;
  const size_t n = mu.size();
  if (n == 0)
    return s;
  auto wt = [&](size_t i) { return w.empty() ? 1.0 / n : w[i]; };
  s.mean.setZero();
  for (size_t i = 0; i < n; ++i)
    s.mean += wt(i) * mu[i];
  s.cov.setZero();
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector2d d = mu[i] - s.mean;
    s.cov += wt(i) * (cov[i] + d * d.transpose());
  }
  return s;
}

double matchInWindow(const cv::Mat& image, const cv::Mat& tmpl, const SearchWindow& win, double chi2,
                     Eigen::Vector2d* best, int* searched)
{
  std::vector<float> tn;
  if (searched)
    *searched = 0;
  if (!normaliseTemplate(tmpl, &tn))
    return -2;
  const int side = tmpl.rows, h = side / 2;
  const double ax = std::sqrt(chi2 * win.cov(0, 0)), ay = std::sqrt(chi2 * win.cov(1, 1));
  const int x0 = std::max(h, static_cast<int>(std::floor(win.mean.x() - ax)));
  const int x1 = std::min(image.cols - 1 - h, static_cast<int>(std::ceil(win.mean.x() + ax)));
  const int y0 = std::max(h, static_cast<int>(std::floor(win.mean.y() - ay)));
  const int y1 = std::min(image.rows - 1 - h, static_cast<int>(std::ceil(win.mean.y() + ay)));
  if (x1 < x0 || y1 < y0)
    return -2;
  const int W = x1 - x0 + 1, H = y1 - y0 + 1;
  std::vector<double> score(static_cast<size_t>(W) * H, -2.0);
  const Eigen::Matrix2d info = win.cov.inverse();
  double bs = -2;
  int bx = -1, by = -1, n = 0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
    {
      const Eigen::Vector2d d(x - win.mean.x(), y - win.mean.y());
      if (d.dot(info * d) > chi2)
        continue;  // only inside the window
      const double s = nccAt(image, tn.data(), side, x, y);
      score[static_cast<size_t>(y - y0) * W + (x - x0)] = s;
      ++n;
      if (s > bs)
      {
        bs = s;
        bx = x;
        by = y;
      }
    }
  if (searched)
    *searched = n;
  if (bx < 0)
    return -2;
  auto at = [&](int x, int y) {
    return (x < x0 || x > x1 || y < y0 || y > y1) ? -2.0 : score[static_cast<size_t>(y - y0) * W + (x - x0)];
  };
  double dx = 0, dy = 0;
  if (at(bx - 1, by) > -2 && at(bx + 1, by) > -2)
    dx = parabolaPeak(at(bx - 1, by), bs, at(bx + 1, by));
  if (at(bx, by - 1) > -2 && at(bx, by + 1) > -2)
    dy = parabolaPeak(at(bx, by - 1), bs, at(bx, by + 1));
  *best = Eigen::Vector2d(bx + dx, by + dy);
  return bs;
}

bool warpTemplate(const cv::Mat& ref, const Eigen::Matrix2d& A, int side, cv::Mat* out)
{
  const int h = side / 2;
  const double c = (ref.cols - 1) / 2.0;
  out->create(side, side, CV_32F);
  for (int r = 0; r < side; ++r)
    for (int q = 0; q < side; ++q)
    {
      const Eigen::Vector2d p = Eigen::Vector2d(c, c) + A * Eigen::Vector2d(q - h, r - h);
      if (p.x() < 0 || p.y() < 0 || p.x() >= ref.cols - 1 || p.y() >= ref.rows - 1)
        return false;
      out->at<float>(r, q) = sample(ref, p.x(), p.y());
    }
  return true;
}

Eigen::Matrix2d patchAffine(const StereoModel& cam, const Eigen::Isometry3d& T_w_ref, const Eigen::Isometry3d& T_w_cur,
                            const Eigen::Vector3d& X_w, const Eigen::Vector3d& n_w)
{
  // Current pixel -> its ray -> the patch plane -> the reference image; differentiated at the
  // landmark's projection (the plane-induced homography, linearised).
  const Eigen::Vector3d pc = T_w_cur.inverse() * X_w;
  const Eigen::Vector2d x(cam.fx * pc.x() / pc.z() + cam.cx, cam.fy * pc.y() / pc.z() + cam.cy);
  const Eigen::Isometry3d T_ref_w = T_w_ref.inverse();
  auto toRef = [&](const Eigen::Vector2d& px, Eigen::Vector2d* out) {
    const Eigen::Vector3d dir = T_w_cur.linear() * Eigen::Vector3d((px.x() - cam.cx) / cam.fx, (px.y() - cam.cy) / cam.fy, 1.0);
    const double den = n_w.dot(dir);
    if (std::abs(den) < 1e-9)
      return false;
    const Eigen::Vector3d P = T_w_cur.translation() + dir * (n_w.dot(X_w - T_w_cur.translation()) / den);
    const Eigen::Vector3d pr = T_ref_w * P;
    if (pr.z() < 1e-3)
      return false;
    *out = Eigen::Vector2d(cam.fx * pr.x() / pr.z(), cam.fy * pr.y() / pr.z());
    return true;
  };
  Eigen::Vector2d r0, rx, ry;
  if (!toRef(x, &r0) || !toRef(x + Eigen::Vector2d(1, 0), &rx) || !toRef(x + Eigen::Vector2d(0, 1), &ry))
    return Eigen::Matrix2d::Identity();
  Eigen::Matrix2d A;
  A.col(0) = rx - r0;
  A.col(1) = ry - r0;
  return A;
}

// ------------------------------------------------------------------------------------------------
FastSlam::FastSlam(const SlamParams& p, const StereoModel& cam) : p_(p), cam_(cam), rng_(static_cast<uint64_t>(p.fastslam_seed))
{
}

void FastSlam::reset(const Eigen::Isometry3d& T)
{
  id_base_ += static_cast<uint32_t>(infos_.size());
  infos_.clear();
  particles_.assign(static_cast<size_t>(p_.fastslam_particles), Particle());
  for (Particle& q : particles_)
    q.T = T;
  mean_ = origin_ = T;
}

void FastSlam::updateMean()
{
  std::vector<double> lw(particles_.size());
  for (size_t i = 0; i < particles_.size(); ++i)
    lw[i] = particles_[i].log_w;
  const std::vector<double> w = normaliseLogWeights(lw);
  const size_t best = static_cast<size_t>(std::max_element(w.begin(), w.end()) - w.begin());
  const Eigen::Quaterniond qb(particles_[best].T.linear());
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector4d q = Eigen::Vector4d::Zero();
  for (size_t i = 0; i < particles_.size(); ++i)
  {
    t += w[i] * particles_[i].T.translation();
    Eigen::Quaterniond qi(particles_[i].T.linear());
    if (qi.dot(qb) < 0)
      qi.coeffs() = -qi.coeffs();
    q += w[i] * qi.coeffs();
  }
  mean_.setIdentity();
  mean_.linear() = Eigen::Quaterniond(q.normalized()).toRotationMatrix();
  mean_.translation() = t;
}

bool FastSlam::stereoMatch(const cv::Mat& left, const cv::Mat& right, double u, double v, double* d) const
{
  const int h = kSide / 2, x = static_cast<int>(std::lround(u)), y = static_cast<int>(std::lround(v));
  if (x - h < 0 || y - h < 0 || x + h >= left.cols || y + h >= left.rows)
    return false;
  cv::Mat t;
  left(cv::Rect(x - h, y - h, kSide, kSide)).convertTo(t, CV_32F);
  std::vector<float> tn;
  if (!normaliseTemplate(t, &tn))
    return false;
  const int dmin = std::max(1, static_cast<int>(std::floor(cam_.fx * cam_.baseline / p_.max_depth_m)));
  const int dmax = std::min(x - h, static_cast<int>(std::ceil(cam_.fx * cam_.baseline / p_.min_depth_m)));
  if (dmax < dmin + 2)
    return false;
  std::vector<double> s(static_cast<size_t>(dmax - dmin + 1));
  int bi = -1;
  for (int k = dmin; k <= dmax; ++k)
  {
    s[k - dmin] = nccAt(right, tn.data(), kSide, x - k, y);
    if (bi < 0 || s[k - dmin] > s[bi])
      bi = k - dmin;
  }
  if (s[bi] < p_.fastslam_ncc || bi == 0 || bi == static_cast<int>(s.size()) - 1)
    return false;
  // unique along the row: no other peak within 0.05 of the best (repeated texture)
  for (int i = 0; i < static_cast<int>(s.size()); ++i)
    if (std::abs(i - bi) > 2 && s[i] > s[bi] - 0.05)
      return false;
  *d = dmin + bi + parabolaPeak(s[bi - 1], s[bi], s[bi + 1]);
  return true;
}

void FastSlam::addLandmarks(const cv::Mat& left, const cv::Mat& right, const std::vector<Eigen::Vector2d>& taken)
{
  const int border = kRefRadius + 2;
  if (left.cols <= 2 * border || left.rows <= 2 * border)
    return;
  cv::Mat mask(left.size(), CV_8U, cv::Scalar(0));
  mask(cv::Rect(border, border, left.cols - 2 * border, left.rows - 2 * border)).setTo(255);
  for (const Eigen::Vector2d& t : taken)
    cv::circle(mask, cv::Point(static_cast<int>(t.x()), static_cast<int>(t.y())), 12, cv::Scalar(0), -1);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(left, corners, p_.fastslam_new_landmarks * 2, 0.01, 12, mask, 5);
  int added = 0;
  for (const cv::Point2f& c : corners)
  {
    if (added >= p_.fastslam_new_landmarks)
      break;
    const double u = std::round(c.x), v = std::round(c.y);
    double d = 0;
    if (!stereoMatch(left, right, u, v, &d))
      continue;
    Eigen::Vector3d X;
    Eigen::Matrix3d C;
    if (!stereoPoint(cam_, u, v, d, p_.fastslam_pixel_sigma, p_.fastslam_disparity_sigma, &X, &C) ||
        X.z() < p_.min_depth_m || X.z() > p_.max_depth_m)
      continue;
    // The patch normal from the underlying 3D data (seed 3.2.2.1): the stereo points 8 px to each
    // side; facing the camera when they disagree or the patch would be seen edge-on.
    Eigen::Vector3d n_c = -X.normalized();
    {
      Eigen::Vector3d P[4];
      const double off[4][2] = {{-8, 0}, {8, 0}, {0, -8}, {0, 8}};
      bool ok = true;
      for (int k = 0; k < 4 && ok; ++k)
      {
        double dk = 0;
        Eigen::Matrix3d Ck;
        ok = stereoMatch(left, right, u + off[k][0], v + off[k][1], &dk) && std::abs(dk - d) < 0.3 * d &&
             stereoPoint(cam_, u + off[k][0], v + off[k][1], dk, 1, 1, &P[k], &Ck);
      }
      if (ok)
      {
        Eigen::Vector3d n = (P[1] - P[0]).cross(P[3] - P[2]);
        if (n.norm() > 1e-9)
        {
          n.normalize();
          if (n.dot(X) > 0)
            n = -n;
          if (n.dot(-X.normalized()) > std::cos(75.0 * kDeg))
            n_c = n;
        }
      }
    }
    Info info;
    cv::Mat ref;
    left(cv::Rect(static_cast<int>(u) - kRefRadius, static_cast<int>(v) - kRefRadius, 2 * kRefRadius + 1, 2 * kRefRadius + 1))
        .convertTo(info.ref, CV_32F);
    info.T_w_ref = mean_;
    info.normal = mean_.linear() * n_c;
    info.last_candidate = stats_.frames;
    const uint32_t key = static_cast<uint32_t>(infos_.size());
    infos_.push_back(info);
    for (Particle& q : particles_)
    {
      LandmarkEstimate l;
      l.mean = q.T * X;
      l.cov = q.T.linear() * C * q.T.linear().transpose();
      q.map.set(key, l);
    }
    inits_.push_back({id_base_ + key, X});
    ++added;
  }
}

void FastSlam::process(const cv::Mat& left, const cv::Mat& right, const Eigen::Isometry3d& T_odom_cam,
                       const Matrix6d& Q_rel)
{
  matches_.clear();
  inits_.clear();
  ++stats_.frames;
  if (!started_)
  {
    started_ = true;
    last_odom_ = T_odom_cam;
    reset(T_odom_cam);  // the filter's world is odom at the start
    addLandmarks(left, right, {});
    countMap();
    return;
  }
  // ---- prediction: the VO's motion since the last frame, N(u_t, Q_t)
  const Eigen::Isometry3d u = last_odom_.inverse() * T_odom_cam;
  last_odom_ = T_odom_cam;
  Matrix6d Q = Q_rel;
  const double qt = p_.fastslam_q_floor_m, qr = p_.fastslam_q_floor_deg * kDeg;
  for (int i = 0; i < 3; ++i)
  {
    Q(i, i) += qt * qt;
    Q(i + 3, i + 3) += qr * qr;
  }
  std::vector<Eigen::Isometry3d> pred(particles_.size());
  for (size_t m = 0; m < particles_.size(); ++m)
    pred[m] = particles_[m].T * u;
  size_t best = 0;
  for (size_t m = 1; m < particles_.size(); ++m)
    if (particles_[m].log_w > particles_[best].log_w)
      best = m;

  std::vector<uint32_t> matched_keys;
  std::vector<Eigen::Vector2d> matched_z, taken;
  matchLandmarks(left, pred, best, Q, matched_keys, matched_z, taken);
  sampleParticles(pred, Q, matched_keys, matched_z);
  resampleIfDegenerate();
  updateMean();

  // ---- the filter's map is a submap: restart it beyond the extent
  if ((origin_.inverse() * mean_).translation().norm() > p_.submap_max_extent_m)
  {
    reset(mean_);
    ++stats_.resets;
    taken.clear();
  }
  if (static_cast<int>(matched_keys.size()) < p_.fastslam_min_matches)
    addLandmarks(left, right, taken);
  countMap();
}

void FastSlam::countMap()
{
  stats_.particles = static_cast<int>(particles_.size());
  stats_.landmarks = static_cast<int>(infos_.size());
  stats_.landmarks_total = static_cast<int>(id_base_ + infos_.size());
}

std::vector<uint32_t> FastSlam::searchOrder(const cv::Mat& left, const Eigen::Isometry3d& pred_best, size_t best,
                                            const Matrix6d& Q)
{
  // ---- active matching (3.2.2.2-3.2.2.3): candidates from the most likely particle's map
  const int h = kSide / 2;
  struct Cand
  {
    uint32_t key;
    double size;
    bool revisit;  ///< back in view after kRevisitGap frames: searched first (it is what bounds the error)
  };
  std::vector<Cand> cands;
  for (uint32_t k = 0; k < infos_.size(); ++k)
  {
    const LandmarkEstimate* l = particles_[best].map.get(k);
    Eigen::Vector2d z;
    Matrix26d Hs;
    Matrix23d Ht;
    if (!l || !projectWithJacobians(cam_, pred_best, l->mean, &z, &Hs, &Ht) || z.x() < h || z.y() < h ||
        z.x() > left.cols - 1 - h || z.y() > left.rows - 1 - h)
      continue;
    Info& in = infos_[k];
    if (stats_.frames - in.last_candidate >= kRevisitGap)
    {
      ++stats_.revisits;
      in.revisit_pending = true;
    }
    in.last_candidate = stats_.frames;
    cands.push_back({k, projectionCov(*l, Hs, Ht, Q).trace(), in.revisit_pending});
  }
  std::sort(cands.begin(), cands.end(),
            [](const Cand& a, const Cand& b) { return a.revisit != b.revisit ? a.revisit : a.size < b.size; });
  if (static_cast<int>(cands.size()) > p_.fastslam_max_matches)
    cands.resize(static_cast<size_t>(p_.fastslam_max_matches));
  stats_.candidates_last = static_cast<int>(cands.size());
  stats_.candidates_total += static_cast<long>(cands.size());
  std::vector<uint32_t> keys;
  for (const Cand& c : cands)
    keys.push_back(c.key);
  return keys;
}

Eigen::Matrix2d FastSlam::projectionCov(const LandmarkEstimate& l, const Matrix26d& Hs, const Matrix23d& Ht,
                                        const Matrix6d& Q) const
{
  const double R2 = p_.fastslam_pixel_sigma * p_.fastslam_pixel_sigma;
  return Eigen::Matrix2d::Identity() * R2 + Ht * l.cov * Ht.transpose() + Hs * Q * Hs.transpose();  // 3.37
}

void FastSlam::matchLandmarks(const cv::Mat& left, const std::vector<Eigen::Isometry3d>& pred, size_t best,
                              const Matrix6d& Q, std::vector<uint32_t>& matched_keys,
                              std::vector<Eigen::Vector2d>& matched_z, std::vector<Eigen::Vector2d>& taken)
{
  const double chi2 = chi2Radius2d(p_.fastslam_window_confidence);
  std::vector<Eigen::Vector2d> mu(particles_.size());
  std::vector<Eigen::Matrix2d> lam(particles_.size());
  for (const uint32_t key : searchOrder(left, pred[best], best, Q))
  {
    size_t n = 0;
    for (size_t m = 0; m < particles_.size(); ++m)
    {
      const LandmarkEstimate* l = particles_[m].map.get(key);
      Matrix26d Hs;
      Matrix23d Ht;
      if (!l || !projectWithJacobians(cam_, pred[m], l->mean, &mu[n], &Hs, &Ht))
        continue;
      lam[n++] = projectionCov(*l, Hs, Ht, Q);
    }
    if (n == 0)
      continue;
    const SearchWindow win = fuseProjections(std::vector<Eigen::Vector2d>(mu.begin(), mu.begin() + static_cast<long>(n)),
                                             std::vector<Eigen::Matrix2d>(lam.begin(), lam.begin() + static_cast<long>(n)));
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(win.cov);
    if (std::sqrt(chi2 * es.eigenvalues().maxCoeff()) > p_.fastslam_max_window)
      continue;  // too uncertain to search
    taken.push_back(win.mean);
    Info& in = infos_[key];
    const LandmarkEstimate* lb = particles_[best].map.get(key);
    cv::Mat tmpl;
    if (!warpTemplate(in.ref, patchAffine(cam_, in.T_w_ref, pred[best], lb->mean, in.normal), kSide, &tmpl))
      continue;
    Eigen::Vector2d z;
    const double s = matchInWindow(left, tmpl, win, chi2, &z);
    if (s <= p_.fastslam_ncc)
      continue;
    matched_keys.push_back(key);
    matched_z.push_back(z);
    matches_.push_back({id_base_ + key, z, s});
    in.last_match = stats_.frames;
    if (in.revisit_pending)
    {
      ++stats_.refound;
      in.revisit_pending = false;
    }
  }
  stats_.matches_last = static_cast<int>(matched_keys.size());
  stats_.matches_total += static_cast<long>(matched_keys.size());
}

void FastSlam::sampleParticles(const std::vector<Eigen::Isometry3d>& pred, const Matrix6d& Q,
                               const std::vector<uint32_t>& matched_keys, const std::vector<Eigen::Vector2d>& matched_z)
{
  // ---- per particle: proposal (3.26-3.31), sample, landmark EKFs (3.32-3.35)
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<PoseObservation> obs;
  for (size_t m = 0; m < particles_.size(); ++m)
  {
    Particle& q = particles_[m];
    obs.clear();
    std::vector<size_t> which;
    for (size_t i = 0; i < matched_keys.size(); ++i)
      if (const LandmarkEstimate* l = q.map.get(matched_keys[i]))
      {
        obs.push_back({matched_z[i], *l});
        which.push_back(i);
      }
    const ProposalResult pr = fastslamProposal(cam_, pred[m], Q, obs, p_.fastslam_pixel_sigma);
    Vector6d g;
    for (int i = 0; i < 6; ++i)
      g(i) = gauss(rng_);
    const Eigen::LLT<Matrix6d> llt(pr.cov);
    q.T = applyPerturbation(pr.mean, llt.info() == Eigen::Success ? Vector6d(llt.matrixL() * g) : Vector6d::Zero());
    q.log_w += pr.log_weight;
    for (size_t j = 0; j < obs.size(); ++j)
      q.map.set(matched_keys[which[j]], updateLandmark(obs[j].landmark, cam_, q.T, obs[j].z, p_.fastslam_pixel_sigma));
  }
}

void FastSlam::resampleIfDegenerate()
{
  // ---- importance weights and resampling (3.16, 3.2.1.4)
  std::vector<double> lw(particles_.size());
  for (size_t m = 0; m < particles_.size(); ++m)
    lw[m] = particles_[m].log_w;
  const std::vector<double> w = normaliseLogWeights(lw);
  stats_.neff_last = effectiveSampleSize(w);
  if (stats_.neff_last < p_.fastslam_resample_neff * static_cast<double>(particles_.size()))
  {
    std::uniform_real_distribution<double> uni(0.0, 1.0 / static_cast<double>(particles_.size()));
    const std::vector<int> idx = systematicResample(w, uni(rng_));
    std::vector<Particle> next;
    next.reserve(particles_.size());
    for (int i : idx)
    {
      next.push_back(particles_[static_cast<size_t>(i)]);  // the map is shared, O(1)
      next.back().log_w = 0;
    }
    particles_.swap(next);
    ++stats_.resamplings;
  }
  else
  {
    const double mx = *std::max_element(lw.begin(), lw.end());
    for (Particle& q : particles_)
      q.log_w -= mx;  // keep the log weights near 0
  }
}

size_t FastSlam::mapNodes() const
{
  std::vector<const PersistentArray<LandmarkEstimate>*> a;
  for (const Particle& q : particles_)
    a.push_back(&q.map);
  return PersistentArray<LandmarkEstimate>::distinctNodes(a);
}

}  // namespace assistive_slam
