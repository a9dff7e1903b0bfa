// loop_closure_benchmark DIR: the appearance model (learned online) and the geometric check on real
// images, no roscore. DIR is a folder of one of two kinds, or a folder holding such folders:
//  - an image route with a truth matrix (samples/N.jpg + samples_GT.bmp, the rtabmap 84-image set):
//    every image is a keyframe and its own submap; the best candidate of each image is verified with
//    the epipolar constraint; recall at 100 % precision against the truth matrix;
//  - stereo revisit pairs (left_img_N.png, right_img_N.png, sensorLeft/Right.yaml, gt_poses.csv: the
//    EuRoC V1_01 pairs): rectified, stereo 3D, verified with stereo P3P; the relative pose error
//    against the Vicon truth.
// Prints a table, writes PNG plots (--out-dir), and as its last line one JSON object.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "assistive_eval/benchmark.h"
#include "assistive_eval/plots.h"
#include "assistive_slam/appearance_model.h"
#include "assistive_slam/loop_verifier.h"

namespace fs = std::filesystem;
namespace ev = assistive_eval;
using assistive_slam::AppearanceModel;
using assistive_slam::AppearanceParams;
using assistive_slam::LoopKeyframe;
using assistive_slam::LoopVerifier;
using assistive_slam::VerifierParams;

namespace
{
double nowMs()
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// a low contrast threshold: the indoor/low-texture images give few features at the default 0.04
double g_sift_contrast = 0.02;
int g_sift_features = 1000;
bool g_orb = false;  // --set features.orb=1: ORB instead of SIFT (what the SLAM keyframes may use)
cv::Ptr<cv::Feature2D> makeSift()
{
  if (g_orb)
    return cv::ORB::create(g_sift_features);
  return cv::SIFT::create(g_sift_features, 3, g_sift_contrast);
}

struct SetResult
{
  bool ran = false;
  double recall = NAN, precision = NAN, recall_appearance_only = NAN, ms_per_image = NAN, ms_model = NAN, ms_check = NAN;
  int queries = 0, accepted = 0, false_accepted = 0;
};

// ------------------------------------------------------------------------------ image route
/// One query image of a route: its best candidate (the first verified, else the most probable).
struct RouteQuery
{
  int i, j;
  double p;
  bool verified, truth;
};

/// The route's truth matrix (samples_GT.bmp) and the model's posterior, the queries so far.
struct RouteRun
{
  cv::Mat gt;    ///< row i, column j: image i revisits image j
  cv::Mat post;  ///< p(submap j | image i)
  std::vector<LoopKeyframe> kfs;
  std::vector<RouteQuery> qs;
  double total_ms = 0.0, model_ms = 0.0, check_ms = 0.0;
};

/// Image i of the route: SIFT, the appearance model, the epipolar check of its candidates; a row
/// of the table on stdout. False when the image cannot be read.
bool runRouteImage(const fs::path& dir, int i, cv::Feature2D& sift, AppearanceModel& model, const VerifierParams& vp,
                   RouteRun& run)
{
  const cv::Mat img = cv::imread((dir / "samples" / (std::to_string(i + 1) + ".jpg")).string(), cv::IMREAD_GRAYSCALE);
  if (img.empty())
  {
    std::cerr << "cannot read image " << i + 1 << "\n";
    return false;
  }
  const double t0 = nowMs();
  std::vector<cv::KeyPoint> kp;
  cv::Mat d;
  sift.detectAndCompute(img, cv::noArray(), kp, d);
  run.kfs[i].descriptors = d;
  for (const auto& k : kp)
    run.kfs[i].keypoints.push_back(k.pt);
  const double t1 = nowMs();
  const auto res = model.process(i, i, d);
  const double t2 = nowMs();
  run.model_ms += t2 - t1;
  for (const auto& p : res.posterior)
    run.post.at<float>(i, p.first) = static_cast<float>(p.second);
  RouteQuery q{i, -1, 0.0, false, false};
  int inliers = 0, matches = 0;
  // the candidates best first; the first that passes the epipolar check is the loop closure
  // no calibration ships with the set: a pinhole guess (focal = image width, ~53 deg)
  const cv::Matx33d K(img.cols, 0, img.cols / 2.0, 0, img.cols, img.rows / 2.0, 0, 0, 1);
  const LoopVerifier verifier(K, vp);
  for (const auto& c : res.candidates)
  {
    const auto v = verifier.verifyEpipolar(run.kfs[i], run.kfs[c.keyframe_id]);
    if (q.j < 0 || v.accepted)
    {
      q.j = c.keyframe_id;
      q.p = c.probability;
      q.verified = v.accepted;
      inliers = v.inliers;
      matches = v.matches;
      q.truth = run.gt.at<std::uint8_t>(i, q.j) > 0;
    }
    if (v.accepted)
      break;
  }
  run.check_ms += nowMs() - t2;
  run.total_ms += nowMs() - t0;
  run.qs.push_back(q);
  std::cout << std::setw(6) << i + 1 << std::setw(7) << kp.size() << std::setw(8)
            << (q.j >= 0 ? std::to_string(q.j + 1) : "-") << std::setw(10) << std::fixed << std::setprecision(3)
            << q.p << std::setw(10) << res.new_place_probability << std::setw(14) << (std::to_string(inliers) + "/" + std::to_string(matches)) << std::setw(10)
            << (q.verified ? "yes" : "no") << std::setw(8) << (q.j < 0 ? "-" : q.truth ? "loop" : "NO") << "\n";
  return true;
}

// recall at 100 % precision: the longest run of true loops from the most probable down, the
// threshold set just above the first false one
double recallAtFullPrecision(const std::vector<RouteQuery>& qs, int positives, bool need_verified)
{
  std::vector<RouteQuery> s;
  for (const auto& q : qs)
    if (q.j >= 0 && (!need_verified || q.verified))
      s.push_back(q);
  std::sort(s.begin(), s.end(), [](const RouteQuery& a, const RouteQuery& b) { return a.p > b.p; });
  int tp = 0;
  double fp_p = -1.0;
  for (const auto& q : s)
    if (!q.truth)
    {
      fp_p = q.p;
      break;
    }
  for (const auto& q : s)
    if (q.truth && q.p > fp_p)
      ++tp;
  return positives > 0 ? static_cast<double>(tp) / positives : NAN;
}

/// The route's figures: recall at 100 % precision (with and without the check), the closures
/// accepted at `threshold`, times per image; a line on stdout.
SetResult scoreRoute(const RouteRun& run, double threshold)
{
  SetResult R;
  const int n = run.gt.rows;
  int positives = 0;
  for (int i = 0; i < n; ++i)
    positives += cv::countNonZero(run.gt.row(i)) > 0 ? 1 : 0;
  R.recall = recallAtFullPrecision(run.qs, positives, true);
  R.recall_appearance_only = recallAtFullPrecision(run.qs, positives, false);
  int tp = 0, fp = 0;
  for (const auto& q : run.qs)
    if (q.j >= 0 && q.verified && q.p >= threshold)
      (q.truth ? tp : fp)++;
  R.accepted = tp + fp;
  R.false_accepted = fp;
  R.precision = tp + fp > 0 ? static_cast<double>(tp) / (tp + fp) : NAN;
  R.queries = positives;
  R.ms_per_image = run.total_ms / n;
  R.ms_model = run.model_ms / n;
  R.ms_check = run.check_ms / n;
  R.ran = true;
  std::cout << "accepted (p >= " << threshold << ", verified): " << tp + fp << ", of them false: " << fp
            << "; recall at this threshold " << static_cast<double>(tp) / std::max(1, positives) << "\n";
  return R;
}

// plot: the posterior matrix beside the truth, accepted closures marked (green true, red false)
void plotPosterior(const fs::path& dir, const RouteRun& run, const SetResult& R, double threshold, const fs::path& out_dir)
{
  const int s = 5;
  cv::Mat a, b;
  run.post.convertTo(a, CV_8U, 255.0);
  cv::applyColorMap(a, a, cv::COLORMAP_VIRIDIS);
  cv::resize(a, a, cv::Size(), s, s, cv::INTER_NEAREST);
  cv::cvtColor(run.gt, b, cv::COLOR_GRAY2BGR);
  cv::resize(b, b, cv::Size(), s, s, cv::INTER_NEAREST);
  for (const auto& q : run.qs)
    if (q.j >= 0 && q.verified && q.p >= threshold)
      cv::circle(a, cv::Point(q.j * s + s / 2, q.i * s + s / 2), s, q.truth ? cv::Scalar(0, 255, 0) : cv::Scalar(0, 0, 255), 1);
  cv::Mat canvas(a.rows + 40, a.cols * 2 + 20, CV_8UC3, cv::Scalar(255, 255, 255));
  a.copyTo(canvas(cv::Rect(0, 40, a.cols, a.rows)));
  b.copyTo(canvas(cv::Rect(a.cols + 20, 40, b.cols, b.rows)));
  cv::putText(canvas, "posterior p(submap j | image i), accepted loops circled", cv::Point(2, 15), cv::FONT_HERSHEY_SIMPLEX,
              0.4, cv::Scalar(0, 0, 0), 1);
  std::ostringstream t2;
  t2 << "truth matrix; recall@100%P " << std::setprecision(3) << R.recall;
  cv::putText(canvas, t2.str(), cv::Point(a.cols + 22, 15), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1);
  cv::putText(canvas, "rows: query image i, columns: stored image j", cv::Point(2, 32), cv::FONT_HERSHEY_SIMPLEX, 0.4,
              cv::Scalar(0, 0, 0), 1);
  const fs::path png = out_dir / (dir.filename().string() + "_posterior.png");
  std::string err;
  if (ev::writePng(png.string(), canvas, &err))
    std::cout << "plot: " << png.string() << "\n";
  else
    std::cerr << "plot not written: " << err << "\n";
}

/// The image route: every image a keyframe and its own submap, run, scored and plotted.
SetResult runImageSet(const fs::path& dir, const AppearanceParams& ap, const VerifierParams& vp, double threshold,
                      const fs::path& out_dir)
{
  RouteRun run;
  run.gt = cv::imread((dir / "samples_GT.bmp").string(), cv::IMREAD_GRAYSCALE);  // imread flips BMP rows
  if (run.gt.empty())
    return SetResult();
  const int n = run.gt.rows;
  auto sift = makeSift();
  AppearanceModel model(ap);
  run.kfs.resize(n);
  run.post = cv::Mat(n, n, CV_32F, cv::Scalar(0));
  std::cout << "image route " << dir.filename().string() << ": " << n << " images\n"
            << std::setw(6) << "image" << std::setw(7) << "feat" << std::setw(8) << "best" << std::setw(10) << "p(loop)"
            << std::setw(10) << "p(new)" << std::setw(14) << "inl/matches" << std::setw(10) << "verified" << std::setw(8)
            << "truth\n";
  for (int i = 0; i < n; ++i)
    if (!runRouteImage(dir, i, *sift, model, vp, run))
      return SetResult();
  const SetResult R = scoreRoute(run, threshold);
  plotPosterior(dir, run, R, threshold, out_dir);
  return R;
}

// ------------------------------------------------------------------------------ stereo pairs
struct EurocCam
{
  cv::Matx33d K;
  cv::Mat dist;
  Eigen::Isometry3d T_BS = Eigen::Isometry3d::Identity();
  cv::Size size;
};

bool readEurocCam(const fs::path& f, EurocCam* c)
{
  cv::FileStorage fsr(f.string(), cv::FileStorage::READ);
  if (!fsr.isOpened())
    return false;
  std::vector<double> in, d, T;
  std::vector<int> res;
  fsr["intrinsics"] >> in;
  fsr["distortion_coefficients"] >> d;
  fsr["resolution"] >> res;
  fsr["T_BS"]["data"] >> T;
  if (in.size() != 4 || d.size() != 4 || res.size() != 2 || T.size() != 16)
    return false;
  c->K = cv::Matx33d(in[0], 0, in[2], 0, in[1], in[3], 0, 0, 1);
  c->dist = (cv::Mat_<double>(1, 4) << d[0], d[1], d[2], d[3]);
  c->size = cv::Size(res[0], res[1]);
  Eigen::Matrix4d M;
  for (int i = 0; i < 16; ++i)
    M(i / 4, i % 4) = T[i];
  c->T_BS.matrix() = M;
  return true;
}

struct Pose
{
  std::string role, left, right;
  Eigen::Isometry3d T_WB_euroc, T_WB_vicon2gt;
};

Eigen::Isometry3d poseFrom(const std::vector<double>& v, std::size_t o)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(v[o + 3], v[o + 4], v[o + 5], v[o + 6]).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(v[o], v[o + 1], v[o + 2]);
  return T;
}

struct PairResult
{
  std::string name;
  bool accepted = false;
  int matches = 0, inliers = 0;
  double err_m = NAN, err_deg = NAN, err2_m = NAN, err2_deg = NAN, truth_floor_m = NAN, truth_floor_deg = NAN, true_dist_m = NAN, true_rot_deg = NAN;
  std::string reason;
};

/// The pairs' truth (gt_poses.csv): role (matchN, queryN) -> images and the two truths.
std::map<std::string, Pose> readTruthPoses(const fs::path& csv)
{
  std::map<std::string, Pose> poses;
  std::ifstream f(csv);
  for (std::string line; std::getline(f, line);)
  {
    if (line.empty() || line[0] == '#')
      continue;
    std::stringstream ss(line);
    Pose p;
    std::string tok;
    std::getline(ss, p.role, ',');
    std::getline(ss, p.left, ',');
    std::getline(ss, p.right, ',');
    std::vector<double> v;
    while (std::getline(ss, tok, ','))
      v.push_back(std::stod(tok));
    if (v.size() != 15)
      continue;
    p.T_WB_euroc = poseFrom(v, 1);
    p.T_WB_vicon2gt = poseFrom(v, 8);
    poses[p.role] = p;
  }
  return poses;
}

/// The stereo rig rectified: the remap tables, the rectified camera, cam0 -> rectified rotation.
struct Rectified
{
  cv::Mat m0x, m0y, m1x, m1y;
  double fx = 0, cx = 0, cy = 0;
  double fb = 0;  ///< f * baseline
  cv::Matx33d K;
  Eigen::Matrix3d R1e;  ///< x_rect = R1 x_cam0
};

Rectified rectify(const EurocCam& c0, const EurocCam& c1)
{
  Rectified r;
  // rectification: x_cam1 = R x_cam0 + T
  const Eigen::Isometry3d T_c1c0 = c1.T_BS.inverse() * c0.T_BS;
  cv::Mat Rcv, Tcv, R1, R2, P1, P2, Qm;
  Eigen::Matrix3d Rl = T_c1c0.linear();
  Eigen::Vector3d tl = T_c1c0.translation();
  cv::eigen2cv(Rl, Rcv);
  cv::eigen2cv(tl, Tcv);
  cv::stereoRectify(cv::Mat(c0.K), c0.dist, cv::Mat(c1.K), c1.dist, c0.size, Rcv, Tcv, R1, R2, P1, P2, Qm,
                    cv::CALIB_ZERO_DISPARITY, 0);
  cv::initUndistortRectifyMap(cv::Mat(c0.K), c0.dist, R1, P1, c0.size, CV_32F, r.m0x, r.m0y);
  cv::initUndistortRectifyMap(cv::Mat(c1.K), c1.dist, R2, P2, c1.size, CV_32F, r.m1x, r.m1y);
  r.fx = P1.at<double>(0, 0);
  r.cx = P1.at<double>(0, 2);
  r.cy = P1.at<double>(1, 2);
  r.fb = -P2.at<double>(0, 3);  // f * baseline
  r.K = cv::Matx33d(r.fx, 0, r.cx, 0, r.fx, r.cy, 0, 0, 1);
  cv::cv2eigen(R1, r.R1e);
  return r;
}

/// A stereo keyframe of a pair's image: rectified, SIFT on both, stereo 3D of the left features
/// (NaN where none). Empty when an image cannot be read.
LoopKeyframe stereoKeyframe(const fs::path& dir, const Pose& p, const Rectified& rc, cv::Feature2D& sift)
{
  LoopKeyframe kf;
  cv::Mat l = cv::imread((dir / p.left).string(), cv::IMREAD_GRAYSCALE);
  cv::Mat r = cv::imread((dir / p.right).string(), cv::IMREAD_GRAYSCALE);
  if (l.empty() || r.empty())
    return kf;
  cv::remap(l, l, rc.m0x, rc.m0y, cv::INTER_LINEAR);
  cv::remap(r, r, rc.m1x, rc.m1y, cv::INTER_LINEAR);
  std::vector<cv::KeyPoint> kl, kr;
  cv::Mat dl, dr;
  sift.detectAndCompute(l, cv::noArray(), kl, dl);
  sift.detectAndCompute(r, cv::noArray(), kr, dr);
  // stereo: the best right descriptor on the same row (1 px), positive disparity, ratio 0.8
  kf.descriptors = dl;
  for (std::size_t i = 0; i < kl.size(); ++i)
  {
    kf.keypoints.push_back(kl[i].pt);
    double b1 = 1e30, b2 = 1e30;
    int bj = -1;
    for (std::size_t j = 0; j < kr.size(); ++j)
    {
      const double disp = kl[i].pt.x - kr[j].pt.x;
      if (std::abs(kl[i].pt.y - kr[j].pt.y) > 1.0 || disp <= 0.5 || disp > 200)
        continue;
      const double dd = cv::norm(dl.row(static_cast<int>(i)), dr.row(static_cast<int>(j)),
                                 dl.depth() == CV_8U ? cv::NORM_HAMMING : cv::NORM_L2);
      if (dd < b1)
      {
        b2 = b1;
        b1 = dd;
        bj = static_cast<int>(j);
      }
      else if (dd < b2)
        b2 = dd;
    }
    cv::Point3f X(NAN, NAN, NAN);
    if (bj >= 0 && b1 < 0.8 * b2)
    {
      const double disp = kl[i].pt.x - kr[bj].pt.x;
      const double z = rc.fb / disp;
      X = cv::Point3f(static_cast<float>((kl[i].pt.x - rc.cx) * z / rc.fx), static_cast<float>((kl[i].pt.y - rc.cy) * z / rc.fx),
                      static_cast<float>(z));
    }
    kf.points.push_back(X);
  }
  return kf;
}

/// A pair's verified relative pose against both truths (a line on stdout).
PairResult scorePair(const std::string& mn, const std::string& qn, const Pose& pm, const Pose& pq, const EurocCam& c0,
                     const Eigen::Matrix3d& R1e, const assistive_slam::LoopVerification& v)
{
  PairResult pr;
  pr.name = mn + "/" + qn;
  pr.accepted = v.accepted;
  pr.matches = v.matches;
  pr.inliers = v.inliers;
  pr.reason = v.reason;
  // the estimate in the (unrectified) cam0 frame: x_rect = R1 x_cam0
  Eigen::Isometry3d Rr = Eigen::Isometry3d::Identity();
  Rr.linear() = R1e;
  const Eigen::Isometry3d est = Rr.inverse() * v.T_match_query * Rr;
  auto truth = [&](bool vicon2gt) {
    const Eigen::Isometry3d& Wm = vicon2gt ? pm.T_WB_vicon2gt : pm.T_WB_euroc;
    const Eigen::Isometry3d& Wq = vicon2gt ? pq.T_WB_vicon2gt : pq.T_WB_euroc;
    return Eigen::Isometry3d((Wm * c0.T_BS).inverse() * (Wq * c0.T_BS));
  };
  const Eigen::Isometry3d T = truth(false), T2 = truth(true);
  const Eigen::Isometry3d E = T.inverse() * est, F = T.inverse() * T2;
  pr.err_m = E.translation().norm();
  pr.err_deg = Eigen::AngleAxisd(E.linear()).angle() * 180.0 / M_PI;
  const Eigen::Isometry3d E2 = T2.inverse() * est;
  pr.err2_m = E2.translation().norm();
  pr.err2_deg = Eigen::AngleAxisd(E2.linear()).angle() * 180.0 / M_PI;
  pr.truth_floor_m = F.translation().norm();
  pr.truth_floor_deg = Eigen::AngleAxisd(F.linear()).angle() * 180.0 / M_PI;
  pr.true_dist_m = T.translation().norm();
  pr.true_rot_deg = Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI;
  std::cout << std::fixed << std::setprecision(4) << "  " << pr.name << ": truth t " << T.translation().transpose()
            << " (|t| " << pr.true_dist_m << " m, " << pr.true_rot_deg << " deg); estimate t "
            << est.translation().transpose() << "\n";
  return pr;
}

/// The stereo revisit pairs (match1/query1 ... match9/query9): each verified with stereo P3P and
/// scored against the truth; `ms_per_pair` the time per pair.
std::vector<PairResult> runStereoPairs(const fs::path& dir, const VerifierParams& vp, double* ms_per_pair)
{
  std::vector<PairResult> out;
  EurocCam c0, c1;
  if (!readEurocCam(dir / "sensorLeft.yaml", &c0) || !readEurocCam(dir / "sensorRight.yaml", &c1))
  {
    std::cerr << dir.string() << ": cannot read sensorLeft/Right.yaml\n";
    return out;
  }
  std::map<std::string, Pose> poses = readTruthPoses(dir / "gt_poses.csv");
  const Rectified rc = rectify(c0, c1);
  auto sift = makeSift();

  const double t0 = nowMs();
  int pairs = 0;
  for (int k = 1; k <= 9; ++k)
  {
    const std::string mn = "match" + std::to_string(k), qn = "query" + std::to_string(k);
    if (!poses.count(mn) || !poses.count(qn))
      continue;
    ++pairs;
    const LoopKeyframe m = stereoKeyframe(dir, poses[mn], rc, *sift), q = stereoKeyframe(dir, poses[qn], rc, *sift);
    const auto v = LoopVerifier(rc.K, vp).verifyStereo(q, m);
    out.push_back(scorePair(mn, qn, poses[mn], poses[qn], c0, rc.R1e, v));
  }
  *ms_per_pair = pairs > 0 ? (nowMs() - t0) / pairs : NAN;
  return out;
}

/// --set name=value: the appearance model's, the features' and the verifier's settings; -1 when
/// all applied, else the exit code of the usage error.
int applySets(const ev::CommandLine& cl, const ev::CommandLine::Sets& sets, AppearanceParams& ap, VerifierParams& vp)
{
  for (const auto& [k, v] : sets)
  {
    double x = 0;
    try
    {
      x = std::stod(v);
    }
    catch (...)
    {
      return cl.usageError("--set " + k + ": not a number");
    }
    if (k == "appearance.likelihood_exponent") ap.likelihood_exponent = x;
    else if (k == "appearance.new_place_prior") ap.new_place_prior = x;
    else if (k == "appearance.prior_memory") ap.prior_memory = x;
    else if (k == "appearance.word_probability_min") ap.word_probability_min = x;
    else if (k == "appearance.recent_submaps_excluded") ap.recent_submaps_excluded = static_cast<int>(x);
    else if (k == "appearance.projection_dims") ap.projection_dims = static_cast<int>(x);
    else if (k == "appearance.projection_tables") ap.projection_tables = static_cast<int>(x);
    else if (k == "appearance.projection_scale") ap.projection_scale = x;
    else if (k == "appearance.distinctiveness_min") ap.distinctiveness_min = x;
    else if (k == "sift.contrast") g_sift_contrast = x;
    else if (k == "features.orb") g_orb = x != 0.0;
    else if (k == "sift.features") g_sift_features = static_cast<int>(x);
    else if (k == "verifier.min_inliers") vp.min_inliers = static_cast<int>(x);
    else if (k == "verifier.min_inliers_epipolar") vp.min_inliers_epipolar = static_cast<int>(x);
    else if (k == "verifier.min_inlier_ratio") vp.min_inlier_ratio = x;
    else if (k == "verifier.ratio") vp.ratio = x;
    else if (k == "verifier.reprojection_px") vp.reprojection_px = x;
    else if (k == "verifier.epipolar_px") vp.epipolar_px = x;
    else
      return cl.usageError("--set: unknown name " + k);
  }
  return -1;
}

/// What a folder holds: 1 an image route with a truth matrix, 2 stereo revisit pairs, 0 neither.
int folderKind(const fs::path& p)
{
  if (fs::exists(p / "samples_GT.bmp") && fs::is_directory(p / "samples"))
    return 1;
  if (fs::exists(p / "gt_poses.csv") && fs::exists(p / "sensorLeft.yaml"))
    return 2;
  return 0;
}

/// DIR itself when it is a set, else the sets in it (sorted).
std::vector<fs::path> setFolders(const fs::path& dir)
{
  std::vector<fs::path> folders;
  if (folderKind(dir))
    folders.push_back(dir);
  else
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_directory() && folderKind(e.path()))
        folders.push_back(e.path());
  std::sort(folders.begin(), folders.end());
  return folders;
}

/// The figures table of the report.
void printFigures(const SetResult& route, const std::vector<PairResult>& pairs, double ms_pair)
{
  std::cout << "\n" << std::left << std::setw(36) << "figure" << "value\n" << std::string(50, '-') << "\n";
  auto row = [](const std::string& k, double v, int prec = 3) {
    std::cout << std::left << std::setw(36) << k << std::fixed << std::setprecision(prec) << v << "\n";
  };
  if (route.ran)
  {
    row("recall at 100 % precision", route.recall);
    row("  appearance alone (no geometry)", route.recall_appearance_only);
    row("precision (p >= threshold, verified)", route.precision);
    row("accepted / false", route.accepted, 0);
    row("ms per image (SIFT+model+check)", route.ms_per_image, 1);
    row("  of it the appearance model", route.ms_model, 1);
    row("  of it the epipolar checks", route.ms_check, 1);
  }
  for (const auto& p : pairs)
  {
    std::cout << std::left << std::setw(36) << p.name << (p.accepted ? "accepted" : "rejected: " + p.reason) << ", "
              << p.inliers << "/" << p.matches << " inliers\n";
    row("  relative pose error m", p.err_m, 4);
    row("  relative pose error deg", p.err_deg, 3);
    row("  error vs vicon2gt truth m", p.err2_m, 4);
    row("  error vs vicon2gt truth deg", p.err2_deg, 3);
    row("  truth floor (EuRoC vs vicon2gt) m", p.truth_floor_m, 4);
    row("  truth floor deg", p.truth_floor_deg, 3);
  }
  if (!pairs.empty())
    row("ms per pair (rectify+SIFT+stereo+check)", ms_pair, 1);
}

/// The last stdout line (docs/design.md: its keys are read by others).
ev::JsonLine jsonLine(const SetResult& route, const std::vector<PairResult>& pairs, double ms_pair)
{
  ev::JsonLine js;
  js.add("recall_at_full_precision", ev::jsonNumber(route.recall, 4))
      .add("precision", ev::jsonNumber(route.precision, 4))
      .add("ms_per_image", ev::jsonNumber(route.ms_per_image, 4))
      .add("ms_appearance_per_image", ev::jsonNumber(route.ms_model, 4))
      .add("recall_appearance_only", ev::jsonNumber(route.recall_appearance_only, 4))
      .add("false_loop_closures", route.ran ? ev::jsonNumber(route.false_accepted, 4) : "null");
  const PairResult* revisit = pairs.empty() ? nullptr : &pairs.front();
  const bool ok = revisit && revisit->accepted;
  js.add("relative_pose_err_m", ev::jsonNumber(ok ? revisit->err_m : NAN, 4))
      .add("relative_pose_err_deg", ev::jsonNumber(ok ? revisit->err_deg : NAN, 4));
  if (pairs.size() > 1)
  {
    const bool ok2 = pairs[1].accepted;
    js.add("pair2_relative_pose_err_m", ev::jsonNumber(ok2 ? pairs[1].err_m : NAN, 4))
        .add("pair2_relative_pose_err_deg", ev::jsonNumber(ok2 ? pairs[1].err_deg : NAN, 4));
  }
  if (revisit)
    js.add("relative_pose_err_vicon2gt_m", ev::jsonNumber(ok ? revisit->err2_m : NAN, 4))
        .add("relative_pose_err_vicon2gt_deg", ev::jsonNumber(ok ? revisit->err2_deg : NAN, 4));
  if (revisit)
    js.add("truth_floor_m", ev::jsonNumber(revisit->truth_floor_m, 4))
        .add("truth_floor_deg", ev::jsonNumber(revisit->truth_floor_deg, 4));
  js.add("ms_per_pair", ev::jsonNumber(ms_pair, 4));
  return js;
}
}  // namespace

int main(int argc, char** argv)
{
  std::string dir_arg, out_dir = ".";
  double threshold = -1.0;
  ev::CommandLine::Sets sets;
  const std::string usage =
      "usage: loop_closure_benchmark DIR [--out-dir D] [--threshold P] [--set name=value]...\n"
      "  DIR: an image route with a truth matrix (samples/N.jpg, samples_GT.bmp), stereo revisit pairs\n"
      "  (left_img_N.png, right_img_N.png, sensorLeft/Right.yaml, gt_poses.csv), or a folder of such folders.\n"
      "  --threshold: the loop probability at which a verified candidate is accepted (default: the model's\n"
      "  candidate_min). --set: appearance.<name> or verifier.<name> overrides, e.g. appearance.likelihood_exponent=0.2";
  ev::CommandLine cl("loop_closure_benchmark", usage);
  cl.positional(&dir_arg, "DIR", true).text("--out-dir", &out_dir).number("--threshold", &threshold).sets(&sets);
  if (const int rc = cl.parse(argc, argv); rc >= 0)
    return rc;

  AppearanceParams ap;
  VerifierParams vp;
  // each image of a route is its own submap: the 10 latest are still "in view", not a revisit
  ap.recent_submaps_excluded = 10;
  if (const int rc = applySets(cl, sets, ap, vp); rc >= 0)
    return rc;
  if (threshold < 0.0)
    threshold = ap.candidate_min;
  const fs::path dir(dir_arg);
  if (!fs::is_directory(dir))
  {
    std::cerr << "loop_closure_benchmark: not a folder: " << dir_arg << "\n";
    return 1;
  }
  const std::vector<fs::path> folders = setFolders(dir);
  if (folders.empty())
  {
    std::cerr << "loop_closure_benchmark: no image route or stereo pairs in " << dir_arg << "\n";
    return 1;
  }
  fs::create_directories(out_dir);

  SetResult route;
  std::vector<PairResult> pairs;
  double ms_pair = NAN;
  for (const auto& f : folders)
  {
    if (folderKind(f) == 1)
    {
      const SetResult r = runImageSet(f, ap, vp, threshold, out_dir);
      if (!r.ran)
      {
        std::cerr << "loop_closure_benchmark: could not run on " << f.string() << "\n";
        return 1;
      }
      route = r;
    }
    else
    {
      std::cout << "stereo revisit pairs " << f.filename().string() << "\n";
      pairs = runStereoPairs(f, vp, &ms_pair);
    }
  }
  printFigures(route, pairs, ms_pair);
  std::cout << jsonLine(route, pairs, ms_pair).str() << std::endl;
  return 0;
}
