// Helpers shared by the dataset readers (kitti.cpp, euroc.cpp, pairs.cpp): files, images, YAML.
#include "dataset_io.h"

#include <algorithm>
#include <cmath>
#include <dirent.h>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <sys/stat.h>

namespace assistive_eval
{
namespace dataset_io
{
bool exists(const std::string& p)
{
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}
bool isDir(const std::string& p)
{
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::string join(const std::string& a, const std::string& b) { return (a.empty() || a.back() == '/') ? a + b : a + "/" + b; }

std::string stem(const std::string& f)
{
  const auto p = f.rfind('.');
  return p == std::string::npos ? f : f.substr(0, p);
}

std::string lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// Files in `dir` whose extension is one of `exts`, sorted (numerically when the stems are numbers).
std::vector<std::string> listFiles(const std::string& dir, const std::vector<std::string>& exts)
{
  DIR* d = ::opendir(dir.c_str());
  if (!d)
    fail("cannot open folder '" + dir + "'");
  std::vector<std::string> out;
  while (dirent* e = ::readdir(d))
  {
    const std::string n = e->d_name;
    const auto p = n.rfind('.');
    if (p == std::string::npos)
      continue;
    const std::string ext = lower(n.substr(p + 1));
    if (std::find(exts.begin(), exts.end(), ext) != exts.end())
      out.push_back(n);
  }
  ::closedir(d);
  auto numeric = [](const std::string& s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
  };
  std::sort(out.begin(), out.end(), [&](const std::string& a, const std::string& b) {
    const std::string sa = stem(a), sb = stem(b);
    if (numeric(sa) && numeric(sb) && sa.size() != sb.size())
      return sa.size() < sb.size();
    return a < b;
  });
  return out;
}

cv::Mat readGray(const std::string& path)
{
  cv::Mat m = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (m.empty())
    fail("cannot read image '" + path + "' (missing or not an image)");
  return m;
}

/// Fails naming the image (its file path) whose size is not `expected` (`source` says where the
/// expected size comes from): the left one first, then the right one.
void checkImageSizes(const std::string& dataset, const cv::Mat& left, const std::string& left_path,
                     const cv::Mat& right, const std::string& right_path, const cv::Size& expected,
                     const std::string& source)
{
  auto text = [](const cv::Size& s) { return std::to_string(s.width) + "x" + std::to_string(s.height); };
  if (left.size() != expected)
    fail(dataset + ": left image '" + left_path + "' is " + text(left.size()) + ", " + source + " says " +
         text(expected));
  if (right.size() != expected)
    fail(dataset + ": right image '" + right_path + "' is " + text(right.size()) + ", " + source + " says " +
         text(expected) + " (left image '" + left_path + "')");
}

std::vector<std::string> readLines(const std::string& path)
{
  std::ifstream f(path);
  if (!f)
    fail("cannot open '" + path + "'");
  std::vector<std::string> lines;
  std::string l;
  while (std::getline(f, l))
  {
    if (!l.empty() && l.back() == '\r')
      l.pop_back();
    lines.push_back(l);
  }
  return lines;
}

/// yaml-cpp does not accept OpenCV's "%YAML:1.0" directive: drop it.
YAML::Node loadYaml(const std::string& path)
{
  std::ifstream f(path);
  if (!f)
    fail("cannot open '" + path + "'");
  std::stringstream ss;
  std::string l;
  while (std::getline(f, l))
    if (l.rfind("%YAML", 0) != 0)
      ss << l << "\n";
  try
  {
    return YAML::Load(ss.str());
  }
  catch (const YAML::Exception& e)
  {
    fail(path + ": malformed YAML: " + e.what());
  }
}

std::vector<double> yamlNumbers(const YAML::Node& n, const std::string& path, const std::string& key, size_t count)
{
  YAML::Node v = n;
  if (v.IsMap() && v["data"])
    v = v["data"];
  if (!v || !v.IsSequence())
    fail(path + ": field '" + key + "' missing or not a list");
  std::vector<double> out;
  try
  {
    for (const auto& x : v)
      out.push_back(x.as<double>());
  }
  catch (const YAML::Exception&)
  {
    fail(path + ": field '" + key + "' holds a non-number");
  }
  if (count && out.size() != count)
    fail(path + ": field '" + key + "' has " + std::to_string(out.size()) + " values, expected " +
         std::to_string(count));
  return out;
}

Eigen::Isometry3d fromRt(const std::vector<double>& R, const std::vector<double>& t)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      T.linear()(r, c) = R[static_cast<size_t>(3 * r + c)];
  T.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  return T;
}

const std::vector<double>& need(const std::map<std::string, std::vector<double>>& m, const std::string& key,
                                size_t count, const std::string& path)
{
  const auto it = m.find(key);
  if (it == m.end())
    fail(path + ": key '" + key + "' missing");
  if (it->second.size() != count)
    fail(path + ": key '" + key + "' has " + std::to_string(it->second.size()) + " values, expected " +
         std::to_string(count));
  return it->second;
}

Eigen::Vector3d centralVelocity(const std::vector<Eigen::Isometry3d>& p, const std::vector<double>& t, size_t i)
{
  if (p.size() < 2)
    return Eigen::Vector3d::Zero();
  const size_t a = i == 0 ? 0 : i - 1, b = std::min(p.size() - 1, i + 1);
  const double dt = t[b] - t[a];
  return dt > 0 ? Eigen::Vector3d((p[b].translation() - p[a].translation()) / dt) : Eigen::Vector3d::Zero();
}
}  // namespace dataset_io
}  // namespace assistive_eval
