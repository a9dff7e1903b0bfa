#include <assistive_description/stereo_self_calibration.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace assistive_description
{
namespace
{
constexpr double kDeg = M_PI / 180.0;
constexpr int kSadHalf = 4;     // 9 x 9 row search window
constexpr int kPatchHalf = 7;   // 15 x 15 sub-pixel refinement window
constexpr double kHuberSigmas = 1.5;

/// The model's regressors of one feature: rotation about x, y, z, then k1 (normalised units).
cv::Vec4d regressors(const StereoSelfCalibration::Observation& o)
{
  return cv::Vec4d(1.0 + o.y * o.y, -o.x * o.y, -o.x, o.y * o.delta * (2.0 * o.x - o.delta));
}

/// SAD of the 9 x 9 window at left (u, v) against the right image's at (u - d, v).
int sad(const cv::Mat& left, const cv::Mat& right, int u, int v, int d)
{
  const int h = kSadHalf;
  int c = 0;
  for (int y = -h; y <= h; ++y)
  {
    const uint8_t* l = left.ptr<uint8_t>(v + y) + (u - h);
    const uint8_t* r = right.ptr<uint8_t>(v + y) + (u - h - d);
    for (int x = 0; x < 2 * h + 1; ++x)
      c += std::abs(static_cast<int>(l[x]) - static_cast<int>(r[x]));
  }
  return c;
}

bool windowInside(const cv::Mat& img, int u, int v, int d)
{
  return u - kSadHalf - d >= 0 && v - kSadHalf >= 0 && u + kSadHalf < img.cols && v + kSadHalf < img.rows;
}

/// Integer disparity of the left corner (u, v) by SAD along the same row of the right image;
/// -1 when it is not unique (a repeated texture, a flat patch).
int rowDisparity(const cv::Mat& left, const cv::Mat& right, int u, int v, int max_disparity)
{
  if (!windowInside(left, u, v, 0))
    return -1;
  const int dmax = std::min(max_disparity, u - kSadHalf);
  int best = std::numeric_limits<int>::max(), second = best, best_d = -1;
  std::vector<int> cost(static_cast<size_t>(dmax) + 1);
  for (int d = 0; d <= dmax; ++d)
  {
    const int c = sad(left, right, u, v, d);
    cost[static_cast<size_t>(d)] = c;
    if (c < best)
    {
      best = c;
      best_d = d;
    }
  }
  for (int d = 0; d <= dmax; ++d)
    if (std::abs(d - best_d) > 1)
      second = std::min(second, cost[static_cast<size_t>(d)]);
  if (best_d < 0 || best >= 0.8 * second)
    return -1;
  return best_d;
}

/// Whether the corner at (u, v) of disparity d lies inside one surface: a few pixels to each side
/// the best disparity within d +- 3 is within 1 of d (where the window has texture to tell; at
/// least three sides must). A corner on an object's silhouette sees different backgrounds from the
/// two cameras, and its offset is not the rig's. (The search near d only: a fifth of the cost of a
/// full one, the same corners on the tuning bags.)
bool sameSurface(const cv::Mat& left, const cv::Mat& right, int u, int v, int d)
{
  constexpr int kStep = 6, kNear = 3;
  const int du[4] = {-kStep, kStep, 0, 0}, dv[4] = {0, 0, -kStep, kStep};
  int agree = 0;
  for (int k = 0; k < 4; ++k)
  {
    const int un = u + du[k], vn = v + dv[k];
    if (d - kNear < 0 || !windowInside(left, un, vn, d + kNear))
      continue;
    int best = std::numeric_limits<int>::max(), best_d = 0, worst = 0;
    for (int dd = d - kNear; dd <= d + kNear; ++dd)
    {
      const int c = sad(left, right, un, vn, dd);
      worst = std::max(worst, c);
      if (c < best)
      {
        best = c;
        best_d = dd;
      }
    }
    if (best >= 0.8 * worst)
      continue;  // no texture to tell
    if (std::abs(best_d - d) > 1)
      return false;
    ++agree;
  }
  return agree >= 3;
}

cv::Matx33d cameraMatrix(const RectifiedModel& m)
{
  return cv::Matx33d(m.fx, 0, m.cx, 0, m.fy, m.cy, 0, 0, 1);
}
}  // namespace

std::vector<StereoSelfCalibration::Observation> StereoSelfCalibration::match(const cv::Mat& left,
                                                                           const cv::Mat& right,
                                                                           const RectifiedModel& model) const
{
  std::vector<Observation> out;
  if (left.empty() || right.empty() || left.size() != right.size() || left.type() != CV_8UC1 ||
      right.type() != CV_8UC1 || model.fx <= 0 || model.fy <= 0)
    return out;
  // Corners away from the border by the refinement window and the vertical search.
  const int margin = kPatchHalf + o_.max_vertical_px + 3;
  if (left.cols <= 2 * margin || left.rows <= 2 * margin)
    return out;
  cv::Mat mask(left.size(), CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(margin, margin, left.cols - 2 * margin, left.rows - 2 * margin)).setTo(255);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(left, corners, o_.max_features, 0.01, o_.min_distance_px, mask, 3);
  // The two cameras expose on their own (auto exposure steps): a gain between the images biases a
  // translation fitted across an edge towards its brighter side, so the right image is scaled to
  // the left's mean first.
  // (into a Mat of its own: converting into a header that shares `right` would write the caller's image)
  cv::Mat right_eq;
  const double mean_left = cv::mean(left)[0], mean_right = cv::mean(right)[0];
  if (mean_right > 1.0)
    right.convertTo(right_eq, CV_8U, mean_left / mean_right);
  else
    right_eq = right;
  std::vector<cv::Point2f> from, guess;
  for (const cv::Point2f& c : corners)
  {
    const int u = static_cast<int>(std::lround(c.x)), v = static_cast<int>(std::lround(c.y));
    const int d = rowDisparity(left, right_eq, u, v, o_.max_disparity_px);
    if (d < 0 || (o_.same_surface && !sameSurface(left, right_eq, u, v, d)))
      continue;
    from.push_back(c);
    guess.push_back(cv::Point2f(c.x - d, c.y));
  }
  if (from.empty())
    return out;
  // Sub-pixel in both directions (the vertical offset is what is measured), then back.
  const cv::Size win(2 * kPatchHalf + 1, 2 * kPatchHalf + 1);
  const cv::TermCriteria crit(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.003);
  std::vector<cv::Point2f> to = guess, back = from;
  std::vector<uchar> st1, st2;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(left, right_eq, from, to, st1, err, win, 1, crit, cv::OPTFLOW_USE_INITIAL_FLOW);
  cv::calcOpticalFlowPyrLK(right_eq, left, to, back, st2, err, win, 1, crit, cv::OPTFLOW_USE_INITIAL_FLOW);
  for (size_t i = 0; i < from.size(); ++i)
  {
    const double dv = to[i].y - from[i].y, du = from[i].x - to[i].x;
    if (!st1[i] || !st2[i] || cv::norm(back[i] - from[i]) > o_.back_check_px || std::abs(dv) > o_.max_vertical_px ||
        du < 0 || std::abs(du - (from[i].x - guess[i].x)) > 2.0)
      continue;
    Observation o;
    o.x = (from[i].x - model.cx) / model.fx;
    o.y = (from[i].y - model.cy) / model.fy;
    o.delta = du / model.fx;
    o.dv_px = dv;
    o.sigma_px = o_.feature_sigma_px;
    out.push_back(o);
  }
  return out;
}

bool StereoSelfCalibration::solveFrame(const std::vector<Observation>& obs, double fy, cv::Vec4d& w) const
{
  if (static_cast<int>(obs.size()) < o_.min_inliers)
    return false;
  // Absolute measurements (what was measured on the corrected image plus what the correction took
  // out), in units of each feature's sigma.
  std::vector<cv::Vec4d> a(obs.size());
  std::vector<double> b(obs.size()), sigma(obs.size());
  for (size_t i = 0; i < obs.size(); ++i)
  {
    sigma[i] = std::max(obs[i].sigma_px, 1e-3) / fy;
    a[i] = regressors(obs[i]);
    b[i] = obs[i].dv_px / fy + a[i][0] * applied_[0] + a[i][1] * applied_[1] + a[i][2] * applied_[2];
  }
  // A weak prior keeps a frame whose corners lie in one band solvable (0.5 deg); k1's is the size
  // of a calibrated lens's residual: in a scene at one depth its term and the yaw's are alike.
  const cv::Vec4d prior_sigma(0.5 * kDeg, 0.5 * kDeg, 0.5 * kDeg, o_.k1_prior);
  std::vector<double> weight(obs.size(), 1.0);
  const double gate = o_.gate_px / fy;
  int inliers = 0;
  for (int iter = 0; iter < 5; ++iter)
  {
    cv::Matx44d N = cv::Matx44d::zeros();
    cv::Vec4d r = cv::Vec4d::all(0);
    for (int k = 0; k < 4; ++k)
      N(k, k) = 1.0 / (prior_sigma[k] * prior_sigma[k]);
    for (size_t i = 0; i < obs.size(); ++i)
    {
      if (weight[i] <= 0)
        continue;
      const double wi = weight[i] / (sigma[i] * sigma[i]);
      N += wi * a[i] * a[i].t();
      r += wi * b[i] * a[i];
    }
    cv::Vec4d x;
    if (!cv::solve(N, r, x, cv::DECOMP_CHOLESKY))
      return false;
    w = x;
    inliers = 0;
    for (size_t i = 0; i < obs.size(); ++i)
    {
      const double res = std::abs(b[i] - a[i].dot(x)), z = res / sigma[i];
      // Huber weights while the fit settles, then the gate alone.
      weight[i] = (res > gate || z > 5.0) ? 0.0 : (iter < 3 ? std::min(1.0, kHuberSigmas / std::max(z, 1e-12)) : 1.0);
      inliers += weight[i] > 0;
    }
  }
  return inliers >= o_.min_inliers;
}

bool StereoSelfCalibration::addObservations(const std::vector<Observation>& obs, const RectifiedModel& model,
                                            const cv::Size& size)
{
  cv::Vec4d w;
  if (!solveFrame(obs, model.fy, w))
    return false;
  // Exponentially forgotten weighted mean and scatter of the frames' solutions.
  const double lambda = 1.0 - 1.0 / std::max(2, o_.window_frames);
  const double n_new = lambda * n_eff_ + 1.0;
  const cv::Vec4d dev_old = w - mean_;
  mean_ += dev_old * (1.0 / n_new);
  const cv::Vec4d dev_new = w - mean_;
  scatter_ = lambda * scatter_ + dev_old * dev_new.t();
  n_eff_ = n_new;
  w2_ = lambda * lambda * w2_ + 1.0;
  ++frames_;
  consider(model, size);
  return true;
}

bool StereoSelfCalibration::addFrame(const cv::Mat& left, const cv::Mat& right, const RectifiedModel& model)
{
  if (counter_++ % std::max(1, o_.every_n_frames) != 0)
    return false;
  return addObservations(match(left, right, model), model, left.size());
}

double StereoSelfCalibration::meanSigma(int k) const
{
  if (n_eff_ <= 1.0)
    return std::numeric_limits<double>::infinity();
  // Variance of one frame's solution (scatter / weights), times the weighted mean's factor.
  return std::sqrt(scatter_(k, k) * w2_ / (n_eff_ * n_eff_) / n_eff_);
}

cv::Vec3d StereoSelfCalibration::rotationSigma() const
{
  return cv::Vec3d(meanSigma(0), meanSigma(1), meanSigma(2));
}

double StereoSelfCalibration::k1Sigma() const
{
  return meanSigma(3);
}

void StereoSelfCalibration::consider(const RectifiedModel& model, const cv::Size& size)
{
  if (!valid())
    return;
  const cv::Vec3d est = rotation(), sig = rotationSigma();
  char buf[160];
  if (cv::norm(est) > o_.max_rotation_deg * kDeg)
  {
    std::snprintf(buf, sizeof buf, "estimate %.3f deg beyond max_rotation_deg %.2f: not applied",
                  cv::norm(est) / kDeg, o_.max_rotation_deg);
    status_ = buf;
    return;
  }
  // Axis by axis: a change is taken only beyond `significance` times the estimate's sigma, and
  // while an axis is uncorrected also beyond the model's own floor there (what rigs without any
  // rotation read: whether there is a rotation at all). Once corrected, the axis follows its
  // estimate, which goes on improving: an early correction is not kept for the floor's sake.
  cv::Vec3d candidate = applied_;
  double z_max = 0;
  for (int k = 0; k < 3; ++k)
  {
    const double floor = applied_[k] == 0.0 ? o_.sigma_floor_deg[k] * kDeg : 0.0;
    const double z = std::abs(est[k] - applied_[k]) / std::max(std::hypot(sig[k], floor), 1e-12);
    z_max = std::max(z_max, z);
    if (z >= o_.significance)
      candidate[k] = est[k];
  }
  const double shift = maxShiftPx(applied_, candidate, model, size.width, size.height);
  if (shift < o_.min_shift_px)
  {
    std::snprintf(buf, sizeof buf,
                  "kept: the estimate moves pixels by %.2f px, but its axes beyond %.1f sigma (largest %.1f) by "
                  "%.2f px, under %.2f",
                  maxShiftPx(applied_, est, model, size.width, size.height), o_.significance, z_max, shift,
                  o_.min_shift_px);
    status_ = buf;
    return;
  }
  applied_ = candidate;
  status_.clear();
}

void StereoSelfCalibration::reset()
{
  counter_ = 0;
  frames_ = 0;
  n_eff_ = 0;
  w2_ = 0;
  mean_ = cv::Vec4d::all(0);
  scatter_ = cv::Matx44d::zeros();
  status_.clear();
}

void StereoSelfCalibration::correctAndEstimate(const cv::Mat& left, cv::Mat& right, const RectifiedModel& model,
                                               bool estimate)
{
  cv::Mat corrected;
  correctRight(right, corrected, model);
  right = corrected;
  if (estimate)
    addFrame(left, right, model);
}

std::string StereoSelfCalibration::describe() const
{
  const cv::Vec3d w = rotation() / kDeg, s = rotationSigma() / kDeg, a = applied_ / kDeg;
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "self-calibration: right camera pitch / yaw / roll %.4f / %.4f / %.4f deg (sigma %.4f / %.4f / %.4f) "
                "and k1 %.4f (sigma %.4f) over %d frame solutions, applied %.4f / %.4f / %.4f",
                w[0], w[1], w[2], s[0], s[1], s[2], k1(), k1Sigma(), frames_, a[0], a[1], a[2]);
  std::string line = buf;
  if (!status_.empty())
    line += "; last: " + status_;
  return line;
}

cv::Matx33d StereoSelfCalibration::correctionRotation(const cv::Vec3d& w)
{
  cv::Matx33d R;
  cv::Rodrigues(w, R);
  return R;
}

cv::Matx33d StereoSelfCalibration::correctionHomography(const cv::Vec3d& w, const RectifiedModel& model)
{
  const cv::Matx33d K = cameraMatrix(model);
  return K * correctionRotation(w).t() * K.inv();
}

double StereoSelfCalibration::maxShiftPx(const cv::Vec3d& a, const cv::Vec3d& b, const RectifiedModel& model,
                                         int width, int height)
{
  const cv::Matx33d Ha = correctionHomography(a, model), Hb = correctionHomography(b, model);
  double worst = 0;
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 2; ++j)
    {
      const cv::Vec3d p(0.5 * i * (width - 1), 0.5 * j * (height - 1), 1.0);
      const cv::Vec3d pa = Ha * p, pb = Hb * p;
      worst = std::max(worst, std::hypot(pa[0] / pa[2] - pb[0] / pb[2], pa[1] / pa[2] - pb[1] / pb[2]));
    }
  return worst;
}

void StereoSelfCalibration::correctRight(const cv::Mat& right, cv::Mat& out, const RectifiedModel& model) const
{
  if (applied_ == cv::Vec3d::all(0))
  {
    right.copyTo(out);
    return;
  }
  cv::warpPerspective(right, out, correctionHomography(applied_, model), right.size(),
                      cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
}

bool saveSelfCalibration(const std::string& path, const std::string& camera, const StereoSelfCalibration& cal,
                         std::string* error)
{
  try
  {
    cv::FileStorage fs(path, cv::FileStorage::WRITE);
    if (!fs.isOpened())
    {
      if (error) *error = "cannot write " + path;
      return false;
    }
    const cv::Vec3d w = cal.applied() / kDeg, s = cal.rotationSigma() / kDeg;
    fs << "camera" << camera;
    fs << "rotation_deg" << std::vector<double>{w[0], w[1], w[2]};
    fs << "sigma_deg" << std::vector<double>{s[0], s[1], s[2]};
    fs << "frame_solutions" << cal.frameSolutions();
  }
  catch (const cv::Exception& e)
  {
    if (error) *error = "cannot write " + path + ": " + e.what();
    return false;
  }
  return true;
}

bool loadSelfCalibration(const std::string& path, const std::string& camera, cv::Vec3d& rotation, std::string* error)
{
  try
  {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened())
    {
      if (error) *error = "no file " + path;
      return false;
    }
    std::string name;
    std::vector<double> w;
    fs["camera"] >> name;
    fs["rotation_deg"] >> w;
    if (name != camera || w.size() != 3 || !std::isfinite(w[0] + w[1] + w[2]))
    {
      if (error) *error = path + " holds no correction of camera '" + camera + "'";
      return false;
    }
    rotation = cv::Vec3d(w[0], w[1], w[2]) * kDeg;
  }
  catch (const cv::Exception& e)
  {
    if (error) *error = "cannot read " + path + ": " + e.what();
    return false;
  }
  return true;
}

}  // namespace assistive_description
