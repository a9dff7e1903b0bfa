#include <assistive_eval/trajectory.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace assistive_eval
{
namespace
{
std::vector<double> parseNumbers(std::string line, const std::string& path, size_t line_no)
{
  for (char& c : line)
    if (c == ',' || c == '\t' || c == ';')
      c = ' ';
  std::istringstream is(line);
  std::vector<double> v;
  std::string tok;
  while (is >> tok)
  {
    try
    {
      size_t used = 0;
      v.push_back(std::stod(tok, &used));
      if (used != tok.size())
        throw std::invalid_argument(tok);
    }
    catch (const std::exception&)
    {
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": not a number: '" + tok + "'");
    }
  }
  return v;
}

std::ifstream openOrThrow(const std::string& path)
{
  std::ifstream f(path);
  if (!f)
    throw std::runtime_error("cannot open trajectory file '" + path + "'");
  return f;
}

bool skipLine(const std::string& line)
{
  const auto p = line.find_first_not_of(" \t\r");
  return p == std::string::npos || line[p] == '#';
}

// Calls row(values) for every non-comment line of `path`; each must hold exactly `count` numbers
// (`layout` names them in the error).
template <typename Row>
void forEachRow(const std::string& path, size_t count, const std::string& layout, Row row)
{
  std::ifstream f = openOrThrow(path);
  std::string line;
  size_t no = 0;
  while (std::getline(f, line))
  {
    ++no;
    if (skipLine(line))
      continue;
    const auto v = parseNumbers(line, path, no);
    if (v.size() != count)
      throw std::runtime_error(path + ":" + std::to_string(no) + ": expected " + layout + ", got " +
                               std::to_string(v.size()));
    row(v, no);
  }
}
}  // namespace

Trajectory readTum(const std::string& path)
{
  Trajectory out;
  forEachRow(path, 8, "8 values (t tx ty tz qx qy qz qw)", [&](const std::vector<double>& v, size_t no) {
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (!(q.norm() > 1e-9) || !std::isfinite(q.norm()))
      throw std::runtime_error(path + ":" + std::to_string(no) + ": invalid quaternion");
    StampedPose sp;
    sp.t = v[0];
    sp.pose.linear() = q.normalized().toRotationMatrix();
    sp.pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    out.push_back(sp);
  });
  if (out.empty())
    throw std::runtime_error("no poses in '" + path + "'");
  return out;
}

void writeTum(const std::string& path, const Trajectory& traj)
{
  std::ofstream f(path);
  if (!f)
    throw std::runtime_error("cannot write '" + path + "'");
  f << "# timestamp tx ty tz qx qy qz qw\n" << std::setprecision(9) << std::fixed;
  for (const auto& sp : traj)
  {
    const Eigen::Quaterniond q(sp.pose.linear());
    const Eigen::Vector3d t = sp.pose.translation();
    f << sp.t << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z()
      << ' ' << q.w() << '\n';
  }
}

Trajectory readKitti(const std::string& path, const std::string& times_path)
{
  Trajectory out;
  forEachRow(path, 12, "12 values (KITTI 3x4 pose)", [&](const std::vector<double>& v, size_t) {
    StampedPose sp;
    sp.t = static_cast<double>(out.size());
    Eigen::Matrix3d R;
    R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
    sp.pose.linear() = R;
    sp.pose.translation() = Eigen::Vector3d(v[3], v[7], v[11]);
    out.push_back(sp);
  });
  if (out.empty())
    throw std::runtime_error("no poses in '" + path + "'");
  if (!times_path.empty())
  {
    size_t i = 0;
    forEachRow(times_path, 1, "one time stamp", [&](const std::vector<double>& v, size_t) {
      if (i >= out.size())
        throw std::runtime_error(times_path + ": more stamps than poses in " + path);
      out[i++].t = v[0];
    });
    if (i != out.size())
      throw std::runtime_error(times_path + ": " + std::to_string(i) + " stamps for " + std::to_string(out.size()) +
                               " poses in " + path);
  }
  return out;
}

void writeKitti(const std::string& path, const Trajectory& traj)
{
  std::ofstream f(path);
  if (!f)
    throw std::runtime_error("cannot write '" + path + "'");
  f << std::setprecision(9) << std::scientific;
  for (const auto& sp : traj)
  {
    const Eigen::Matrix<double, 3, 4> m = sp.pose.matrix().topRows<3>();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        f << m(r, c) << ((r == 2 && c == 3) ? '\n' : ' ');
  }
}

std::vector<std::pair<size_t, size_t>> associate(const Trajectory& first, const Trajectory& second, double max_diff,
                                                 AssociationMethod method, double offset_second)
{
  std::vector<std::pair<size_t, size_t>> out;
  if (method == AssociationMethod::INDEX)
  {
    for (size_t i = 0; i < std::min(first.size(), second.size()); ++i)
      out.emplace_back(i, i);
    return out;
  }
  // Indices of `second` sorted by (shifted) stamp, for window searches.
  std::vector<size_t> order(second.size());
  for (size_t j = 0; j < order.size(); ++j)
    order[j] = j;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return second[a].t < second[b].t; });
  std::vector<double> st(order.size());
  for (size_t k = 0; k < order.size(); ++k)
    st[k] = second[order[k]].t + offset_second;

  if (method == AssociationMethod::TUM_GREEDY)
  {
    // All candidate pairs with |a - (b + offset)| < max_diff, sorted as python sorts
    // (diff, a, b) tuples, then greedily taken if both stamps are still free.
    std::vector<std::tuple<double, double, double, size_t, size_t>> cand;
    for (size_t i = 0; i < first.size(); ++i)
    {
      const double a = first[i].t;
      auto lo = std::lower_bound(st.begin(), st.end(), a - max_diff);
      for (auto it = lo; it != st.end() && *it <= a + max_diff; ++it)
      {
        const size_t k = static_cast<size_t>(it - st.begin());
        const double diff = std::abs(a - st[k]);
        if (diff < max_diff)
          cand.emplace_back(diff, a, second[order[k]].t, i, order[k]);
      }
    }
    std::sort(cand.begin(), cand.end());
    std::vector<char> used1(first.size(), 0), used2(second.size(), 0);
    for (const auto& c : cand)
    {
      const size_t i = std::get<3>(c), j = std::get<4>(c);
      if (used1[i] || used2[j])
        continue;
      used1[i] = used2[j] = 1;
      out.emplace_back(i, j);
    }
    std::sort(out.begin(), out.end());
    return out;
  }

  // EVO_NEAREST: iterate the shorter trajectory, nearest stamp in the longer one (first on ties).
  const bool second_longer = second.size() > first.size();
  const Trajectory& shorter = second_longer ? first : second;
  const Trajectory& longer = second_longer ? second : first;
  const double off = second_longer ? offset_second : -offset_second;
  std::vector<double> lt(longer.size());
  for (size_t k = 0; k < longer.size(); ++k)
    lt[k] = longer[k].t + off;
  for (size_t i = 0; i < shorter.size(); ++i)
  {
    const double a = shorter[i].t;
    size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < lt.size(); ++k)  // argmin over the unsorted stamps, as numpy does
    {
      const double d = std::abs(lt[k] - a);
      if (d < best_d)
      {
        best_d = d;
        best = k;
      }
    }
    if (best_d <= max_diff)
    {
      if (second_longer)
        out.emplace_back(i, best);
      else
        out.emplace_back(best, i);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

MatchedTrajectories match(const Trajectory& gt, const Trajectory& est, double max_diff, AssociationMethod method)
{
  MatchedTrajectories m;
  for (const auto& ij : associate(gt, est, max_diff, method))
  {
    m.gt.push_back(gt[ij.first]);
    m.est.push_back(est[ij.second]);
  }
  return m;
}

Alignment computeAlignment(const Trajectory& gt, const Trajectory& est, AlignMode mode)
{
  Alignment a;
  const size_t n = std::min(gt.size(), est.size());
  if (mode == AlignMode::NONE || n == 0)
    return a;
  if (mode == AlignMode::FIRST_POSE)
  {
    a.transform = gt[0].pose * est[0].pose.inverse();
    return a;
  }
  if (n < 3)
    return a;
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (size_t i = 0; i < n; ++i)
  {
    src.col(static_cast<Eigen::Index>(i)) = est[i].pose.translation();
    dst.col(static_cast<Eigen::Index>(i)) = gt[i].pose.translation();
  }
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, mode == AlignMode::SIM3);
  const Eigen::Matrix3d sR = T.topLeftCorner<3, 3>();
  a.scale = (mode == AlignMode::SIM3) ? std::cbrt(sR.determinant()) : 1.0;
  a.transform.linear() = sR / a.scale;
  a.transform.translation() = T.topRightCorner<3, 1>();
  return a;
}

Trajectory applyAlignment(const Trajectory& est, const Alignment& a)
{
  Trajectory out = est;
  const Eigen::Matrix3d R = a.transform.linear();
  for (auto& sp : out)
  {
    const Eigen::Vector3d p = sp.pose.translation();
    sp.pose.linear() = R * sp.pose.linear();
    sp.pose.translation() = a.scale * (R * p) + a.transform.translation();
  }
  return out;
}

std::vector<double> pathDistances(const Trajectory& traj)
{
  std::vector<double> d(traj.size(), 0.0);
  for (size_t i = 1; i < traj.size(); ++i)
    d[i] = d[i - 1] + (traj[i].pose.translation() - traj[i - 1].pose.translation()).norm();
  return d;
}

double pathLength(const Trajectory& traj)
{
  const auto d = pathDistances(traj);
  return d.empty() ? 0.0 : d.back();
}

Eigen::Isometry3d linkToOptical()
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // optical axes expressed in camera_link: x_opt = -y_link, y_opt = -z_link, z_opt = x_link
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return T;
}

}  // namespace assistive_eval
