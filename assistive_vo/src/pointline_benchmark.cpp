// pointline_benchmark [--trials N] [--plot-prefix PREFIX] [--seed S]
// pointline_benchmark --bag FILE.bag [--every K]: the line detector scored against the world's
// geometry instead (see scoreLinesOnBag).
// The seed's simulation study of the point+line trifocal solvers (seed 2.3.1.2): baseline 7.5 cm,
// a random stereo pair (rectified) displaced by a random motion, random 3D points and lines
// projected into the four views, Gaussian noise of sigma px on every image coordinate (focal
// 500 px, 640x480), N trials per noise level:
//   fig 2.9:  rotation and translation error vs noise for the linear, subspace and quaternion
//             solvers on random mixes of points and lines (each on its minimal set size: linear 4
//             features, subspace and quaternion 3, the same three features; the linear's 4th is a
//             point when the three are points and a line after two points, since {3 points + 1 line}
//             has rank 11 < 12);
//   fig 2.10: quaternion-3/4/5 against the three-point algorithm (OpenGV's Kneip P3P on the
//             points triangulated from views 1-2, bearings of view 3) on points only;
//   fig 2.12: RANSAC trials until a hypothesis of quaternion-3/4/5 on random mixed samples from
//             30 points and 15 lines reaches the acceptance threshold of the reprojection error
//             over all four views (RMS over all 45 features at most 1.5 times that of the true
//             motion, which the noise alone gives).
// Errors are those of the solution nearest the truth (the solvers return all real solutions;
// RANSAC chooses among them), reported as the lower quartile (the seed's measure: in RANSAC a
// fraction of good hypotheses is what matters). Prints tables, writes three PNG plots, and as the
// last stdout line one JSON object.
#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opengv/absolute_pose/CentralAbsoluteAdapter.hpp>
#include <opengv/absolute_pose/methods.hpp>
#include <assistive_eval/benchmark.h>
#include <assistive_eval/plots.h>
#include <assistive_eval/stereo_bag.h>
#include "assistive_vo/line_detector.h"
#include "assistive_vo/trifocal_solver.h"
#include "assistive_vo/trifocal_synthetic.h"

using namespace assistive_vo;
namespace ev = assistive_eval;

namespace
{
const std::vector<double> NOISE_PX = {0.0, 0.25, 0.5, 1.0, 1.5, 2.0};
constexpr double FOCAL = 500.0;
const double NaN = std::numeric_limits<double>::quiet_NaN();

struct Errors
{
  std::vector<double> rot_deg, trans_pct;
  int failures = 0;
  double ms = 0;  // total solve time
  int solves = 0;
};

void record(Errors& e, const StereoMotions& sols, const StereoMotion& truth)
{
  double best_r = NaN, best_t = NaN, best = std::numeric_limits<double>::infinity();
  for (const StereoMotion& m : sols)
  {
    const double r = rotationErrorDeg(m.R, truth.R), t = translationErrorPct(m.t, truth.t);
    const double score = r / 1.0 + t / 10.0;  // nearest to the truth (deg and 10 % weighed alike)
    if (score < best)
      best = score, best_r = r, best_t = t;
  }
  if (sols.empty() || !std::isfinite(best_r))
  {
    ++e.failures;
    return;
  }
  e.rot_deg.push_back(best_r);
  e.trans_pct.push_back(best_t);
}

double q25(const std::vector<double>& v) { return v.empty() ? NaN : ev::percentile(v, 0.25); }

/// The three-point algorithm: points triangulated from views 1-2 (DLT), bearings in view 3.
StereoMotions threePoint(const StereoRig& rig, const PointQuads& pts)
{
  opengv::bearingVectors_t bearings;
  opengv::points_t X;
  for (const PointQuad& p : pts)
  {
    Eigen::Matrix<double, 3, 4> P1, P2;
    P1 << Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero();
    P2 << rig.R0, rig.t0;
    Eigen::Matrix4d D;
    D.row(0) = p.x[0].x() * P1.row(2) - P1.row(0);
    D.row(1) = p.x[0].y() * P1.row(2) - P1.row(1);
    D.row(2) = p.x[1].x() * P2.row(2) - P2.row(0);
    D.row(3) = p.x[1].y() * P2.row(2) - P2.row(1);
    const Eigen::Vector4d h = Eigen::JacobiSVD<Eigen::Matrix4d>(D, Eigen::ComputeFullV).matrixV().col(3);
    X.push_back(h.head<3>() / h(3));
    bearings.push_back(Eigen::Vector3d(p.x[2].x(), p.x[2].y(), 1.0).normalized());
  }
  opengv::absolute_pose::CentralAbsoluteAdapter adapter(bearings, X);
  std::vector<int> idx = {0, 1, 2};
  StereoMotions out;
  for (const opengv::transformation_t& T : opengv::absolute_pose::p3p_kneip(adapter, idx))
  {
    // T = [R_wc | t_wc]: view-1 (world) to view-3 coordinates is R = R_wc^T, t = -R_wc^T t_wc
    StereoMotion m;
    m.R = T.leftCols<3>().transpose();
    m.t = -m.R * T.col(3);
    if (m.R.allFinite() && m.t.allFinite())
      out.push_back(m);
  }
  return out;
}

/// A line chart (log y) of several series against noise, PNG-ready.
cv::Mat chart(const std::string& title, const std::string& ylabel, const std::vector<std::string>& names,
              const std::vector<std::vector<double>>& ys, const std::vector<double>& xs, bool log_y)
{
  const int W = 640, H = 420, L = 80, R = 170, T = 40, B = 60;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& s : ys)
    for (double v : s)
      if (std::isfinite(v) && (!log_y || v > 0))
        lo = std::min(lo, v), hi = std::max(hi, v);
  if (!std::isfinite(lo))
    lo = 1e-3, hi = 1.0;
  if (log_y)
  {
    lo = std::pow(10.0, std::floor(std::log10(lo)));
    hi = std::pow(10.0, std::ceil(std::log10(hi)));
    if (hi <= lo)
      hi = lo * 10;
  }
  else
  {
    lo = 0;
    hi = hi > 0 ? hi * 1.1 : 1.0;
  }
  const double x0 = xs.front(), x1 = xs.back() > xs.front() ? xs.back() : xs.front() + 1;
  auto px = [&](double x) { return L + (x - x0) / (x1 - x0) * (W - L - R); };
  auto py = [&](double y) {
    const double f = log_y ? (std::log10(y) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (y - lo) / (hi - lo);
    return H - B - f * (H - T - B);
  };
  cv::rectangle(img, cv::Point(L, T), cv::Point(W - R, H - B), cv::Scalar(0, 0, 0), 1);
  const double fs = 0.42;
  if (log_y)
    for (double d = lo; d <= hi * 1.0001; d *= 10)
    {
      const int y = static_cast<int>(py(d));
      cv::line(img, cv::Point(L, y), cv::Point(W - R, y), cv::Scalar(220, 220, 220), 1);
      std::ostringstream os;
      os << d;
      cv::putText(img, os.str(), cv::Point(5, y + 4), cv::FONT_HERSHEY_SIMPLEX, fs, cv::Scalar(0, 0, 0), 1);
    }
  else
    for (int i = 0; i <= 4; ++i)
    {
      const double d = lo + (hi - lo) * i / 4.0;
      const int y = static_cast<int>(py(d));
      cv::line(img, cv::Point(L, y), cv::Point(W - R, y), cv::Scalar(220, 220, 220), 1);
      std::ostringstream os;
      os << std::setprecision(3) << d;
      cv::putText(img, os.str(), cv::Point(5, y + 4), cv::FONT_HERSHEY_SIMPLEX, fs, cv::Scalar(0, 0, 0), 1);
    }
  for (double x : xs)
  {
    std::ostringstream os;
    os << x;
    cv::putText(img, os.str(), cv::Point(static_cast<int>(px(x)) - 8, H - B + 18), cv::FONT_HERSHEY_SIMPLEX, fs,
                cv::Scalar(0, 0, 0), 1);
  }
  cv::putText(img, "image noise sigma (px)", cv::Point(L + 120, H - 15), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 1);
  cv::putText(img, title, cv::Point(L, 25), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 1);
  cv::putText(img, ylabel, cv::Point(W - R + 8, T + 10), cv::FONT_HERSHEY_SIMPLEX, fs, cv::Scalar(0, 0, 0), 1);
  const cv::Scalar colors[] = {cv::Scalar(0, 0, 220), cv::Scalar(0, 160, 0), cv::Scalar(220, 0, 0),
                               cv::Scalar(0, 0, 0), cv::Scalar(0, 140, 220)};
  for (size_t s = 0; s < ys.size(); ++s)
  {
    const cv::Scalar c = colors[s % 5];
    cv::Point prev(-1, -1);
    for (size_t i = 0; i < xs.size() && i < ys[s].size(); ++i)
    {
      const double v = ys[s][i];
      if (!std::isfinite(v) || (log_y && v <= 0))
      {
        prev = cv::Point(-1, -1);
        continue;
      }
      const cv::Point p(static_cast<int>(px(xs[i])), static_cast<int>(py(std::max(v, lo))));
      cv::circle(img, p, 3, c, -1);
      if (prev.x >= 0)
        cv::line(img, prev, p, c, 2);
      prev = p;
    }
    cv::line(img, cv::Point(W - R + 8, T + 35 + 20 * static_cast<int>(s)),
             cv::Point(W - R + 28, T + 35 + 20 * static_cast<int>(s)), c, 2);
    cv::putText(img, names[s], cv::Point(W - R + 33, T + 39 + 20 * static_cast<int>(s)), cv::FONT_HERSHEY_SIMPLEX, fs,
                cv::Scalar(0, 0, 0), 1);
  }
  return img;
}

cv::Mat sideBySide(const cv::Mat& a, const cv::Mat& b)
{
  cv::Mat out;
  cv::hconcat(a, b, out);
  return out;
}

std::string noiseKey(double n)
{
  std::ostringstream os;
  os << n;
  std::string s = os.str();
  std::replace(s.begin(), s.end(), '.', 'p');
  return "noise_" + s + "px";
}

/// RMS over all features of the four-view reprojection error (px).
double rmsError(const TrifocalScene& s, const StereoMotion& m)
{
  double sq = 0;
  for (const PointQuad& p : s.points)
    sq += std::pow(pointReprojectionError(s.rig, m, p, FOCAL), 2);
  for (const LineQuad& l : s.lines)
    sq += std::pow(lineReprojectionError(s.rig, m, l, FOCAL), 2);
  return std::sqrt(sq / static_cast<double>(s.points.size() + s.lines.size()));
}
/// True edges of the world in the left image from its ground-truth depth (render_bag --depth):
/// pixels where the depth jumps (more than 3 % between neighbours, or to / from nothing) or the
/// surface turns (normals of the two sides more than 20 deg apart): wall corners, door frames,
/// box edges, whatever the texture. 255 = edge.
cv::Mat trueEdges(const cv::Mat& Z, const ev::StereoCalib& c)
{
  cv::Mat E(Z.size(), CV_8U, cv::Scalar(0));
  auto P = [&](int u, int v) {
    const double z = Z.at<float>(v, u);
    return Eigen::Vector3d((u - c.cx) / c.fx * z, (v - c.cy) / c.fy * z, z);
  };
  // normal at (u, v) from the points two pixels apart on each side (zero when undefined)
  auto normal = [&](int u, int v) -> Eigen::Vector3d {
    if (u < 2 || v < 2 || u + 2 >= Z.cols || v + 2 >= Z.rows)
      return Eigen::Vector3d::Zero();
    for (int du = -2; du <= 2; du += 2)
      for (int dv = -2; dv <= 2; dv += 2)
        if (!(Z.at<float>(v + dv, u + du) > 0))
          return Eigen::Vector3d::Zero();
    const Eigen::Vector3d n = (P(u + 2, v) - P(u, v)).cross(P(u, v + 2) - P(u, v));
    return n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
  };
  const double cos_crease = std::cos(20.0 * M_PI / 180.0);
  for (int v = 0; v + 1 < Z.rows; ++v)
    for (int u = 0; u + 1 < Z.cols; ++u)
    {
      const float z = Z.at<float>(v, u);
      for (const auto& d : {std::make_pair(1, 0), std::make_pair(0, 1)})
      {
        const float zn = Z.at<float>(v + d.second, u + d.first);
        const bool a = z > 0, b = zn > 0;
        if (a != b || (a && b && std::abs(z - zn) > 0.03 * std::min(z, zn)))
        {
          E.at<uchar>(v, u) = 255;
          E.at<uchar>(v + d.second, u + d.first) = 255;
        }
      }
    }
  // creases: the normal two pixels before and after differ (no depth jump needed)
  for (int v = 4; v + 4 < Z.rows; ++v)
    for (int u = 4; u + 4 < Z.cols; ++u)
    {
      const Eigen::Vector3d n0 = normal(u, v);
      if (n0.isZero())
        continue;
      for (const auto& d : {std::make_pair(1, 0), std::make_pair(0, 1)})
      {
        const Eigen::Vector3d a = normal(u - 2 * d.first, v - 2 * d.second), b = normal(u + 2 * d.first, v + 2 * d.second);
        if (!a.isZero() && !b.isZero() && std::abs(a.dot(b)) < cos_crease)
          E.at<uchar>(v, u) = 255;
      }
    }
  return E;
}

/// --bag: the line detector (default parameters) on every K-th left image of a bag rendered with
/// `render_bag --depth`; a segment is on a true edge when at least 80 % of its points (one per px
/// along it) are within 1 px of a true-edge pixel (trueEdges). Key line_segments_within_1px.
int scoreLinesOnBag(const std::string& path, long every)
{
  ev::StereoBagReader reader(path);
  ev::StereoFrame f;
  const LineDetector det;
  long k = 0, frames = 0, segments = 0, on_edge = 0;
  double sample_share = 0;
  while (reader.next(f))
  {
    if (k++ % every != 0)
      continue;
    if (f.gt_depth.empty())
    {
      std::cerr << "pointline_benchmark: " << path << " has no ground-truth depth (render_bag --depth)\n";
      return 2;
    }
    const cv::Mat E = trueEdges(f.gt_depth, f.calib);
    cv::Mat dist;
    cv::distanceTransform(255 - E, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    ++frames;
    for (const LineSegment& s : det.detect(f.left))
    {
      const int n = std::max(2, static_cast<int>(std::ceil(s.length())));
      int near = 0;
      for (int i = 0; i <= n; ++i)
      {
        const Eigen::Vector2d x = s.p + (s.q - s.p) * (static_cast<double>(i) / n);
        const int u = static_cast<int>(std::lround(x.x())), v = static_cast<int>(std::lround(x.y()));
        near += u >= 0 && v >= 0 && u < dist.cols && v < dist.rows && dist.at<float>(v, u) <= 1.0f;
      }
      const double share = near / static_cast<double>(n + 1);
      ++segments;
      on_edge += share >= 0.8;
      sample_share += share;
    }
  }
  const double within = segments ? on_edge / static_cast<double>(segments) : NaN;
  std::cout << "frames " << frames << ", segments " << segments << " (" << (frames ? segments / double(frames) : 0.0)
            << " per image), within 1 px of a true edge: " << within * 100 << " % (points along them: "
            << (segments ? sample_share / segments * 100 : NaN) << " %)\n";
  ev::JsonLine js;
  js.add("frames", frames).add("segments", segments)
      .add("line_segments_within_1px", ev::jsonNumber(within, 4))
      .add("line_points_within_1px", ev::jsonNumber(segments ? sample_share / segments : NaN, 4));
  std::cout << js.str() << std::endl;
  return 0;
}
using Coin = std::uniform_int_distribution<int>;
constexpr int RANSAC_CAP = 1000;

/// The study's figures, per solver and noise level (NOISE_PX).
struct Study
{
  explicit Study(size_t nl) : lin(nl), sub(nl), quat(nl), p3p(nl), q3(nl), q4(nl), q5(nl), ransac_capped(3 * nl, 0)
  {
    for (auto& v : ransac_trials)
      v.resize(nl);
  }
  std::vector<Errors> lin, sub, quat;          ///< fig 2.9
  std::vector<Errors> p3p, q3, q4, q5;         ///< fig 2.10
  std::vector<std::vector<double>> ransac_trials[3];  ///< fig 2.12, quaternion-3..5
  std::vector<int> ransac_capped;              ///< [3 * noise + n - 3]
};

StereoMotions timed(Errors& e, const std::function<StereoMotions()>& f)
{
  const double t0 = ev::threadCpuMs();
  StereoMotions s = f();
  e.ms += ev::threadCpuMs() - t0;
  ++e.solves;
  return s;
}

/// fig 2.9: a random mix of points and lines (3 features; the linear solver gets a 4th)
void mixedTrial(std::mt19937& rng, Coin& coin, const TrifocalSceneOptions& so, size_t ni, Study& st)
{
  const TrifocalScene s = makeTrifocalScene(rng, 4, 4, so);
  const int np = coin(rng) % 4;  // 0..3 points, the rest lines
  PointQuads pts(s.points.begin(), s.points.begin() + np);
  LineQuads lns(s.lines.begin(), s.lines.begin() + (3 - np));
  record(st.sub[ni], timed(st.sub[ni], [&] { return solveTrifocalSubspace(s.rig, pts, lns).solutions; }), s.motion);
  record(st.quat[ni], timed(st.quat[ni], [&] { return solveTrifocalQuaternion(s.rig, pts, lns).solutions; }),
         s.motion);
  // a 4th feature for the linear solver, never making {3 points + 1 line} (rank 11 < 12)
  if (np == 3 || (np < 2 && coin(rng) % 2))
    pts.push_back(s.points[static_cast<size_t>(np)]);
  else
    lns.push_back(s.lines[static_cast<size_t>(3 - np)]);
  record(st.lin[ni], timed(st.lin[ni], [&] { return solveTrifocalLinear(s.rig, pts, lns).solutions; }), s.motion);
}

/// fig 2.10: points only
void pointsTrial(std::mt19937& rng, const TrifocalSceneOptions& so, size_t ni, Study& st)
{
  const TrifocalScene s = makeTrifocalScene(rng, 5, 0, so);
  const LineQuads none;
  record(st.p3p[ni],
         timed(st.p3p[ni], [&] { return threePoint(s.rig, PointQuads(s.points.begin(), s.points.begin() + 3)); }),
         s.motion);
  Errors* qs[3] = {&st.q3[ni], &st.q4[ni], &st.q5[ni]};
  for (int n = 3; n <= 5; ++n)
    record(*qs[n - 3],
           timed(*qs[n - 3], [&] {
             return solveTrifocalQuaternion(s.rig, PointQuads(s.points.begin(), s.points.begin() + n), none).solutions;
           }),
           s.motion);
}

/// fig 2.12: RANSAC trials to an acceptable hypothesis, 30 points + 15 lines, n = 3..5 features a sample
void ransacRun(std::mt19937& rng, Coin& coin, const TrifocalSceneOptions& so, size_t ni, Study& st)
{
  const TrifocalScene s = makeTrifocalScene(rng, 30, 15, so);
  const double accept = std::max(1.5 * rmsError(s, s.motion), 1e-6);
  const int total = static_cast<int>(s.points.size() + s.lines.size());
  for (int n = 3; n <= 5; ++n)
  {
    int k = 0;
    bool done = false;
    std::vector<int> idx(static_cast<size_t>(total));
    for (int i = 0; i < total; ++i)
      idx[static_cast<size_t>(i)] = i;
    while (!done && k < RANSAC_CAP)
    {
      ++k;
      for (int i = 0; i < n; ++i)  // partial Fisher-Yates: n distinct features
        std::swap(idx[static_cast<size_t>(i)], idx[static_cast<size_t>(i + coin(rng) % (total - i))]);
      PointQuads pts;
      LineQuads lns;
      for (int i = 0; i < n; ++i)
      {
        const int f = idx[static_cast<size_t>(i)];
        if (f < static_cast<int>(s.points.size()))
          pts.push_back(s.points[static_cast<size_t>(f)]);
        else
          lns.push_back(s.lines[static_cast<size_t>(f) - s.points.size()]);
      }
      for (const StereoMotion& m : solveTrifocalQuaternion(s.rig, pts, lns).solutions)
        if (rmsError(s, m) <= accept)
        {
          done = true;
          break;
        }
    }
    if (!done)
      ++st.ransac_capped[3 * ni + static_cast<size_t>(n - 3)];
    st.ransac_trials[n - 3][ni].push_back(k);
  }
}

double usPerSolve(const std::vector<Errors>& e)
{
  double ms = 0;
  int n = 0;
  for (const Errors& x : e)
    ms += x.ms, n += x.solves;
  return n ? 1000.0 * ms / n : NaN;
}

void printTables(const Study& st, long trials, long ransac_runs, const TrifocalSceneOptions& so)
{
  auto row = [](const std::string& name, const std::vector<Errors>& e, bool rot) {
    std::cout << std::left << std::setw(14) << name << std::right;
    for (const Errors& x : e)
      std::cout << std::setw(11) << std::setprecision(3) << (rot ? q25(x.rot_deg) : q25(x.trans_pct));
    std::cout << "\n";
  };
  auto header = [&](const std::string& what) {
    std::cout << "\n" << what << "\n" << std::left << std::setw(14) << "noise (px)" << std::right;
    for (double n : NOISE_PX)
      std::cout << std::setw(11) << n;
    std::cout << "\n";
  };
  std::cout << "pointline_benchmark: " << trials << " trials per noise level, baseline " << so.baseline
            << " m, f = " << FOCAL << " px, lower-quartile errors\n";
  for (const bool rot : {true, false})
  {
    header(rot ? "fig 2.9 rotation error, deg (random point/line mixes)" : "fig 2.9 translation error, % of |t|");
    row("linear-4", st.lin, rot);
    row("subspace-3", st.sub, rot);
    row("quaternion-3", st.quat, rot);
  }
  for (const bool rot : {true, false})
  {
    header(rot ? "fig 2.10 rotation error, deg (points only)" : "fig 2.10 translation error, % of |t|");
    row("three-point", st.p3p, rot);
    row("quaternion-3", st.q3, rot);
    row("quaternion-4", st.q4, rot);
    row("quaternion-5", st.q5, rot);
  }
  header("fig 2.12 RANSAC trials to success, median (mean) over " + std::to_string(ransac_runs) + " runs");
  for (int n = 3; n <= 5; ++n)
  {
    std::cout << std::left << std::setw(14) << ("quaternion-" + std::to_string(n)) << std::right;
    for (size_t ni = 0; ni < NOISE_PX.size(); ++ni)
    {
      std::ostringstream os;
      os << ev::median(st.ransac_trials[n - 3][ni]) << " (" << std::setprecision(3)
         << ev::mean(st.ransac_trials[n - 3][ni]) << ")";
      std::cout << std::setw(11) << os.str();
    }
    std::cout << "\n";
  }
  header("failures (no solution) per solver, of " + std::to_string(trials));
  for (auto [name, e] : std::vector<std::pair<std::string, const std::vector<Errors>*>>{
           {"linear-4", &st.lin}, {"subspace-3", &st.sub}, {"quaternion-3", &st.quat}, {"three-point", &st.p3p},
           {"quat-3 pts", &st.q3}, {"quat-4 pts", &st.q4}, {"quat-5 pts", &st.q5}})
  {
    std::cout << std::left << std::setw(14) << name << std::right;
    for (const Errors& x : *e)
      std::cout << std::setw(11) << x.failures;
    std::cout << "\n";
  }
  std::cout << "\nCPU us per solve: linear-4 " << usPerSolve(st.lin) << ", subspace-3 " << usPerSolve(st.sub)
            << ", quaternion-3 (mixed) " << usPerSolve(st.quat) << ", three-point " << usPerSolve(st.p3p)
            << ", quaternion-5 " << usPerSolve(st.q5) << "\n";
}

/// The figures as PNGs PREFIX_fig2_9.png, PREFIX_fig2_10.png, PREFIX_fig2_12.png; false when one
/// could not be written.
bool writePlots(const Study& st, const std::string& prefix)
{
  // log-scale error plots over the noisy levels (noise 0 is exact: in the tables)
  const std::vector<double> noisy(NOISE_PX.begin() + 1, NOISE_PX.end());
  auto series = [](const std::vector<Errors>& e, bool rot) {
    std::vector<double> v;
    for (size_t i = 1; i < e.size(); ++i)
      v.push_back(rot ? q25(e[i].rot_deg) : q25(e[i].trans_pct));
    return v;
  };
  bool plots_ok = true;
  std::string err;
  const std::vector<std::string> n29 = {"linear-4", "subspace-3", "quaternion-3"};
  const cv::Mat f29 = sideBySide(
      chart("fig 2.9 (a) translation error, lower quartile", "% of |t|", n29,
            {series(st.lin, false), series(st.sub, false), series(st.quat, false)}, noisy, true),
      chart("fig 2.9 (b) rotation error, lower quartile", "deg", n29,
            {series(st.lin, true), series(st.sub, true), series(st.quat, true)}, noisy, true));
  const std::vector<std::string> n210 = {"three-point", "quaternion-3", "quaternion-4", "quaternion-5"};
  const cv::Mat f210 = sideBySide(
      chart("fig 2.10 (a) translation error, points only", "% of |t|", n210,
            {series(st.p3p, false), series(st.q3, false), series(st.q4, false), series(st.q5, false)}, noisy, true),
      chart("fig 2.10 (b) rotation error, points only", "deg", n210,
            {series(st.p3p, true), series(st.q3, true), series(st.q4, true), series(st.q5, true)}, noisy, true));
  std::vector<std::vector<double>> rt(3);
  for (int n = 0; n < 3; ++n)
    for (size_t ni = 0; ni < NOISE_PX.size(); ++ni)
      rt[static_cast<size_t>(n)].push_back(ev::mean(st.ransac_trials[n][ni]));
  const cv::Mat f212 = chart("fig 2.12 RANSAC trials to success (mean)", "trials",
                             {"quaternion-3", "quaternion-4", "quaternion-5"}, rt, NOISE_PX, false);
  for (auto [name, img] : std::vector<std::pair<std::string, cv::Mat>>{
           {prefix + "_fig2_9.png", f29}, {prefix + "_fig2_10.png", f210}, {prefix + "_fig2_12.png", f212}})
  {
    if (ev::writePng(name, img, &err))
      std::cout << "wrote " << name << "\n";
    else
    {
      std::cerr << "pointline_benchmark: " << err << "\n";
      plots_ok = false;
    }
  }
  return plots_ok;
}

void printJson(const Study& st, long trials, long ransac_runs, const TrifocalSceneOptions& so, bool plots_ok)
{
  ev::JsonLine js;
  js.add("trials", static_cast<long long>(trials)).add("ransac_runs", static_cast<long long>(ransac_runs));
  js.add("baseline_m", ev::jsonNumber(so.baseline, 3)).add("focal_px", ev::jsonNumber(FOCAL, 4));
  auto addErr = [&](const std::string& name, const std::vector<Errors>& e) {
    for (size_t ni = 0; ni < NOISE_PX.size(); ++ni)
    {
      js.add(name + "_rot_err_q25_deg_" + noiseKey(NOISE_PX[ni]), ev::jsonNumber(q25(e[ni].rot_deg), 4));
      js.add(name + "_trans_err_q25_pct_" + noiseKey(NOISE_PX[ni]), ev::jsonNumber(q25(e[ni].trans_pct), 4));
    }
    int fails = 0;
    for (const Errors& x : e)
      fails += x.failures;
    js.add(name + "_failures", fails);
  };
  addErr("linear4", st.lin);
  addErr("subspace3", st.sub);
  addErr("quaternion3_mixed", st.quat);
  addErr("three_point", st.p3p);
  addErr("quaternion3_points", st.q3);
  addErr("quaternion4_points", st.q4);
  addErr("quaternion5_points", st.q5);
  for (int n = 3; n <= 5; ++n)
    for (size_t ni = 0; ni < NOISE_PX.size(); ++ni)
    {
      js.add("ransac_trials_mean_quaternion" + std::to_string(n) + "_" + noiseKey(NOISE_PX[ni]),
             ev::jsonNumber(ev::mean(st.ransac_trials[n - 3][ni]), 4));
      js.add("ransac_capped_quaternion" + std::to_string(n) + "_" + noiseKey(NOISE_PX[ni]),
             st.ransac_capped[3 * ni + static_cast<size_t>(n - 3)]);
    }
  js.add("us_per_solve_quaternion3", ev::jsonNumber(usPerSolve(st.quat), 4))
      .add("us_per_solve_quaternion5", ev::jsonNumber(usPerSolve(st.q5), 4))
      .add("us_per_solve_three_point", ev::jsonNumber(usPerSolve(st.p3p), 4))
      .add("plots_written", plots_ok);
  std::cout << js.str() << std::endl;
}
}  // namespace

int main(int argc, char** argv)
{
  const std::string usage =
      "usage: pointline_benchmark [--trials N] [--plot-prefix PREFIX] [--seed S]\n"
      "  the seed's simulation study of the point+line trifocal solvers (figs 2.9, 2.10, 2.12):\n"
      "  N trials per noise level (default 1000), plots PREFIX_fig2_9.png, PREFIX_fig2_10.png,\n"
      "  PREFIX_fig2_12.png (default prefix: pointline), lower-quartile errors, a JSON last line.\n"
      "  --bag FILE.bag [--every K]: instead, the line detector on every K-th (default 5) left image of a\n"
      "  bag rendered with render_bag --depth, scored against the true edges of its depth\n"
      "  (line_segments_within_1px).\n";
  long trials = 1000;
  long seed = 1;
  std::string prefix = "pointline";
  ev::CommandLine cl("pointline_benchmark", usage);
  std::string bag;
  long every = 5;
  cl.count("--trials", &trials, 1L).count("--seed", &seed, 0L).text("--plot-prefix", &prefix).text("--bag", &bag)
      .count("--every", &every, 1L);
  if (const int rc = cl.parse(argc, argv); rc >= 0)
    return rc;
  if (!bag.empty())
    return scoreLinesOnBag(bag, every);

  std::mt19937 rng(static_cast<unsigned>(seed));
  Coin coin(0, 1 << 30);
  TrifocalSceneOptions so;  // baseline 7.5 cm, rectified, 640x480 at f = 500 px
  Study st(NOISE_PX.size());
  const long ransac_runs = trials;  // fig 2.12: one RANSAC run per trial too
  for (size_t ni = 0; ni < NOISE_PX.size(); ++ni)
  {
    so.noise_px = NOISE_PX[ni];
    for (long tr = 0; tr < trials; ++tr)
    {
      mixedTrial(rng, coin, so, ni, st);
      pointsTrial(rng, so, ni, st);
    }
    for (long run = 0; run < ransac_runs; ++run)
      ransacRun(rng, coin, so, ni, st);
    std::cerr << "pointline_benchmark: noise " << NOISE_PX[ni] << " px done\n";
  }
  printTables(st, trials, ransac_runs, so);
  const bool plots_ok = writePlots(st, prefix);
  printJson(st, trials, ransac_runs, so, plots_ok);
  return 0;
}
