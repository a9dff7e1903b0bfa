#include <assistive_sim/eval/datasets.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <ctime>
#include <dirent.h>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>
#include <yaml-cpp/yaml.h>

namespace assistive_sim
{
namespace eval
{
namespace
{
[[noreturn]] void fail(const std::string& msg) { throw std::runtime_error(msg); }

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

// ------------------------------------------------------------------------------------- KITTI
class KittiSource : public DatasetSource
{
public:
  KittiSource(const std::string& dir, KittiTruth truth) : dir_(dir), truth_(truth)
  {
    if (!isDir(dir))
      fail("KITTI folder '" + dir + "' does not exist");
    for (const char* cam : {"image_00", "image_01"})
      if (!isDir(join(dir, std::string(cam) + "/data")))
        fail("KITTI folder '" + dir + "' has no " + cam + "/data (expected a raw 'sync' drive with grey stereo)");
    left_ = listFiles(join(dir, "image_00/data"), {"png"});
    right_ = listFiles(join(dir, "image_01/data"), {"png"});
    if (left_.empty())
      fail(join(dir, "image_00/data") + ": no PNG images");
    if (left_.size() != right_.size())
      fail("KITTI: " + std::to_string(left_.size()) + " left but " + std::to_string(right_.size()) +
           " right images in '" + dir + "'");
    for (size_t i = 0; i < left_.size(); ++i)
      if (left_[i] != right_[i])
        fail("KITTI: left/right image names differ: " + left_[i] + " vs " + right_[i]);
    const std::string ts = join(dir, "image_00/timestamps.txt");
    const bool has_stamps = exists(ts);
    if (has_stamps)
    {
      stamps_ = readKittiTimestamps(ts);
      if (stamps_.size() < left_.size())
        fail(ts + ": " + std::to_string(stamps_.size()) + " stamps for " + std::to_string(left_.size()) + " images");
      stamps_.resize(left_.size());
    }
    else
      for (size_t i = 0; i < left_.size(); ++i)
        stamps_.push_back(1000.0 + 0.1 * static_cast<double>(i));  // 10 Hz when the stamps are missing
    const bool has_oxts = isDir(join(dir, "oxts/data"));
    calib_ = readKittiRawCalib(dir, has_oxts);
    if (has_oxts)
    {
      const auto oxts = readOxtsFolder(join(dir, "oxts"));
      if (oxts.size() < left_.size())
        fail(join(dir, "oxts/data") + ": " + std::to_string(oxts.size()) + " packets for " +
             std::to_string(left_.size()) + " images");
      if (truth_ == KittiTruth::ImageStamp)
      {
        // the OXTS samples sit a few ms off the image stamps: move each to its image's stamp
        const std::string ots = join(dir, "oxts/timestamps.txt");
        if (!has_stamps)
          fail(ts + " not found: the truth at the image stamps needs it (or use --truth devkit)");
        if (!exists(ots))
          fail(ots + " not found: the truth at the image stamps needs it (or use --truth devkit)");
        const std::vector<double> oxts_stamps = readKittiTimestamps(ots);
        if (oxts_stamps.size() < oxts.size())
          fail(ots + ": " + std::to_string(oxts_stamps.size()) + " stamps for " + std::to_string(oxts.size()) +
               " OXTS packets");
        for (size_t i = 0; i < left_.size(); ++i)
          max_offset_s_ = std::max(max_offset_s_, std::abs(stamps_[i] - oxts_stamps[i]));
        gt_ = kittiCam0PosesWorld(oxtsToImuPosesAt(oxts, oxts_stamps, stamps_), calib_.T_cam0_imu);
      }
      else
        gt_ = kittiCam0PosesWorld(oxtsToImuPoses(oxts), calib_.T_cam0_imu);
      gt_.resize(left_.size());
    }
  }
  std::string truthNote() const override
  {
    if (gt_.empty())
      return std::string();
    char b[200];
    if (truth_ == KittiTruth::ImageStamp)
      std::snprintf(b, sizeof b, "OXTS poses moved to the image stamps (image_stamp; sample offsets up to %.2f ms)",
                    1e3 * max_offset_s_);
    else
      std::snprintf(b, sizeof b, "OXTS sample i as image i's pose (devkit convention)");
    return b;
  }
  std::string kind() const override { return "kitti"; }
  size_t size() const override { return left_.size(); }
  bool hasGroundTruth() const override { return !gt_.empty(); }
  StereoFrame frame(size_t i) const override
  {
    StereoFrame f;
    f.stamp = stamps_.at(i);
    const std::string lp = join(dir_, "image_00/data/" + left_.at(i)), rp = join(dir_, "image_01/data/" + right_.at(i));
    f.left = readGray(lp);
    f.right = readGray(rp);
    // Every image of a drive has the size of the first one read (the rectified calibration is one).
    if (size0_.empty())
      size0_ = f.left.size();
    checkImageSizes("KITTI", f.left, lp, f.right, rp, size0_, "the drive's first image");
    f.calib = calib_.calib;
    f.calib.width = f.left.cols;
    f.calib.height = f.left.rows;
    if (!gt_.empty())
    {
      f.has_gt_pose = true;
      f.gt_pose = gt_[i];
      f.gt_velocity = centralVelocity(gt_, stamps_, i);
    }
    return f;
  }

private:
  std::string dir_;
  std::vector<std::string> left_, right_;
  std::vector<double> stamps_;
  KittiTruth truth_;
  KittiRawCalib calib_;
  mutable cv::Size size0_;  ///< size of the first image read
  std::vector<Eigen::Isometry3d> gt_;
  double max_offset_s_ = 0.0;  ///< largest |image stamp - OXTS stamp| of the same index
};

// ------------------------------------------------------------------------------------- EuRoC
std::vector<std::pair<int64_t, std::string>> readEurocCsv(const std::string& path)
{
  std::vector<std::pair<int64_t, std::string>> out;
  size_t no = 0;
  for (const auto& l : readLines(path))
  {
    ++no;
    if (l.empty() || l[0] == '#')
      continue;
    const auto c = l.find(',');
    if (c == std::string::npos)
      fail(path + ":" + std::to_string(no) + ": expected 'timestamp,filename'");
    try
    {
      out.emplace_back(std::stoll(l.substr(0, c)), l.substr(c + 1));
    }
    catch (const std::exception&)
    {
      fail(path + ":" + std::to_string(no) + ": bad timestamp");
    }
    auto& name = out.back().second;
    name.erase(0, name.find_first_not_of(" \t"));
  }
  return out;
}

class EurocSource : public DatasetSource
{
public:
  explicit EurocSource(const std::string& dir_in)
  {
    mav_ = isDir(join(dir_in, "mav0")) ? join(dir_in, "mav0") : dir_in;
    for (const char* cam : {"cam0", "cam1"})
      if (!isDir(join(mav_, cam)))
        fail("EuRoC folder '" + dir_in + "' has no " + cam + " (expected mav0/cam0, mav0/cam1)");
    const EurocCamera c0 = readEurocSensorYaml(join(mav_, "cam0/sensor.yaml"));
    const EurocCamera c1 = readEurocSensorYaml(join(mav_, "cam1/sensor.yaml"));
    T_BS0_ = c0.T_BS;
    auto K = [](const EurocCamera& c) -> cv::Mat {
      cv::Mat k = (cv::Mat_<double>(3, 3) << c.fu, 0, c.cu, 0, c.fv, c.cv, 0, 0, 1);
      return k;
    };
    const Eigen::Isometry3d T_c1_c0 = c1.T_BS.inverse() * c0.T_BS;
    rect_ = makeStereoRectifier(K(c0), cv::Mat(c0.dist, true), K(c1), cv::Mat(c1.dist, true),
                                cv::Size(c0.width, c0.height), T_c1_c0);
    // frames: stamps present in both cameras
    const auto l = readEurocCsv(join(mav_, "cam0/data.csv"));
    const auto r = readEurocCsv(join(mav_, "cam1/data.csv"));
    std::map<int64_t, std::string> rm(r.begin(), r.end());
    for (const auto& e : l)
    {
      const auto it = rm.find(e.first);
      if (it != rm.end())
        frames_.push_back({e.first, e.second, it->second});
    }
    if (frames_.empty())
      fail("EuRoC '" + dir_in + "': no stamp is in both cam0/data.csv and cam1/data.csv");
    const std::string gt = join(mav_, "state_groundtruth_estimate0/data.csv");
    if (exists(gt))
      readGroundTruth(gt);
  }
  std::string kind() const override { return "euroc"; }
  size_t size() const override { return frames_.size(); }
  bool hasGroundTruth() const override { return has_gt_; }
  StereoFrame frame(size_t i) const override
  {
    const Frame& fr = frames_.at(i);
    StereoFrame f;
    f.stamp = static_cast<double>(fr.ns) * 1e-9;
    const std::string lp = join(mav_, "cam0/data/" + fr.left), rp = join(mav_, "cam1/data/" + fr.right);
    const cv::Mat l = readGray(lp);
    const cv::Mat r = readGray(rp);
    checkImageSizes("EuRoC", l, lp, r, rp, cv::Size(rect_.calib.width, rect_.calib.height), "cam0/sensor.yaml");
    rect_.rectify(l, r, f.left, f.right);
    f.calib = rect_.calib;
    if (!gt_pose_.empty() && gt_ok_[i])
    {
      f.has_gt_pose = true;
      f.gt_pose = gt_pose_[i];
      f.gt_velocity = gt_vel_[i];
    }
    return f;
  }

private:
  struct Frame
  {
    int64_t ns;
    std::string left, right;
  };
  void readGroundTruth(const std::string& path)
  {
    std::vector<int64_t> t;
    std::vector<Eigen::Isometry3d> pose;
    std::vector<Eigen::Vector3d> vel;
    size_t no = 0;
    for (const auto& line : readLines(path))
    {
      ++no;
      if (line.empty() || line[0] == '#')
        continue;
      std::vector<double> v;
      std::stringstream ss(line);
      std::string tok;
      int64_t ns = 0;
      bool first = true;
      while (std::getline(ss, tok, ','))
      {
        try
        {
          if (first)
            ns = std::stoll(tok);
          else
            v.push_back(std::stod(tok));
        }
        catch (const std::exception&)
        {
          fail(path + ":" + std::to_string(no) + ": not a number: '" + tok + "'");
        }
        first = false;
      }
      if (v.size() < 7)
        fail(path + ":" + std::to_string(no) + ": expected time,px,py,pz,qw,qx,qy,qz[,...]");
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
      T.linear() = Eigen::Quaterniond(v[3], v[4], v[5], v[6]).normalized().toRotationMatrix();
      t.push_back(ns);
      pose.push_back(T);
      vel.push_back(v.size() >= 10 ? Eigen::Vector3d(v[7], v[8], v[9]) : Eigen::Vector3d::Zero());
    }
    // pose of the rectified left camera: T_w_b * T_BS(cam0) * T_raw_rect
    Eigen::Isometry3d T_raw_rect = Eigen::Isometry3d::Identity();
    T_raw_rect.linear() = rect_.R_rect_raw0.transpose();
    const int64_t tol_ns = 1000000;  // 1 ms (gt stamps equal the camera stamps to within 256 ns)
    gt_pose_.resize(frames_.size());
    gt_vel_.resize(frames_.size(), Eigen::Vector3d::Zero());
    gt_ok_.assign(frames_.size(), 0);
    for (size_t i = 0; i < frames_.size(); ++i)
    {
      const auto it = std::lower_bound(t.begin(), t.end(), frames_[i].ns);
      size_t best = t.size();
      int64_t bd = tol_ns + 1;
      for (auto k : {it - t.begin() - 1, it - t.begin()})
        if (k >= 0 && static_cast<size_t>(k) < t.size() && std::llabs(t[static_cast<size_t>(k)] - frames_[i].ns) < bd)
        {
          bd = std::llabs(t[static_cast<size_t>(k)] - frames_[i].ns);
          best = static_cast<size_t>(k);
        }
      if (best < t.size())
      {
        gt_pose_[i] = pose[best] * T_BS0_ * T_raw_rect;
        gt_vel_[i] = vel[best];
        gt_ok_[i] = 1;
        has_gt_ = true;
      }
    }
  }
  std::string mav_;
  Eigen::Isometry3d T_BS0_ = Eigen::Isometry3d::Identity();
  StereoRectifier rect_;
  std::vector<Frame> frames_;
  std::vector<Eigen::Isometry3d> gt_pose_;
  std::vector<Eigen::Vector3d> gt_vel_;
  std::vector<char> gt_ok_;
  bool has_gt_ = false;
};

// ------------------------------------------------------------------------------------- pairs
struct CameraInfoYaml
{
  int width = 0, height = 0;
  cv::Mat K, D, R, P;
};

CameraInfoYaml readCameraInfoYaml(const std::string& path)
{
  const YAML::Node n = loadYaml(path);
  CameraInfoYaml c;
  try
  {
    if (!n["image_width"] || !n["image_height"])
      fail(path + ": image_width / image_height missing");
    c.width = n["image_width"].as<int>();
    c.height = n["image_height"].as<int>();
  }
  catch (const YAML::Exception&)
  {
    fail(path + ": image_width / image_height are not integers");
  }
  auto mat = [&](const char* key, int rows, int cols, bool required) {
    if (!n[key])
    {
      if (required)
        fail(path + ": field '" + key + "' missing");
      return cv::Mat();
    }
    const auto v = yamlNumbers(n[key], path, key, static_cast<size_t>(rows * cols));
    return cv::Mat(v, true).reshape(1, rows);
  };
  c.K = mat("camera_matrix", 3, 3, true);
  c.P = mat("projection_matrix", 3, 4, true);
  c.R = n["rectification_matrix"] ? mat("rectification_matrix", 3, 3, true) : cv::Mat::eye(3, 3, CV_64F);
  c.D = n["distortion_coefficients"] ? cv::Mat(yamlNumbers(n["distortion_coefficients"], path,
                                                           "distortion_coefficients", 0),
                                               true)
                                     : cv::Mat::zeros(1, 5, CV_64F);
  if (c.width <= 0 || c.height <= 0 || c.P.at<double>(0, 0) <= 0)
    fail(path + ": image size or projection matrix invalid");
  return c;
}

class PairsSource : public DatasetSource
{
public:
  explicit PairsSource(const std::string& dir) : dir_(dir)
  {
    if (!isDir(dir))
      fail("pairs folder '" + dir + "' does not exist");
    for (const char* sub : {"left", "right"})
      if (!isDir(join(dir, sub)))
        fail("pairs folder '" + dir + "' has no " + sub + "/ (expected left/, right/, stereo_left.yaml, stereo_right.yaml)");
    auto findYaml = [&](const std::string& side) {
      for (const std::string& n : {"stereo_" + side + ".yaml", side + ".yaml", side + "/camera_info.yaml"})
        if (exists(join(dir, n)))
          return join(dir, n);
      fail("pairs folder '" + dir + "': no camera_info yaml for the " + side + " camera (stereo_" + side + ".yaml)");
    };
    const CameraInfoYaml l = readCameraInfoYaml(findYaml("left")), r = readCameraInfoYaml(findYaml("right"));
    if (l.width != r.width || l.height != r.height)
      fail("pairs: left and right camera_info sizes differ");
    calib_.width = l.width;
    calib_.height = l.height;
    calib_.fx = l.P.at<double>(0, 0);
    calib_.fy = l.P.at<double>(1, 1);
    calib_.cx = l.P.at<double>(0, 2);
    calib_.cy = l.P.at<double>(1, 2);
    calib_.baseline = -r.P.at<double>(0, 3) / r.P.at<double>(0, 0);
    if (!(calib_.baseline > 0))
      fail("pairs: right projection_matrix P[3] must be -fx * baseline < 0 (got " +
           std::to_string(r.P.at<double>(0, 3)) + ")");
    auto needsRect = [](const CameraInfoYaml& c) {
      return cv::norm(c.D) > 0.0 || cv::norm(c.R - cv::Mat::eye(3, 3, CV_64F)) > 1e-9;
    };
    if (needsRect(l) || needsRect(r))
    {
      const cv::Size sz(l.width, l.height);
      cv::initUndistortRectifyMap(l.K, l.D, l.R, l.P.colRange(0, 3), sz, CV_32FC1, mlx_, mly_);
      cv::initUndistortRectifyMap(r.K, r.D, r.R, r.P.colRange(0, 3), sz, CV_32FC1, mrx_, mry_);
    }
    const std::vector<std::string> exts{"png", "jpg", "jpeg", "pgm", "bmp", "tif", "tiff"};
    const auto lf = listFiles(join(dir, "left"), exts), rf = listFiles(join(dir, "right"), exts);
    std::map<std::string, std::string> rs;
    for (const auto& f : rf)
      rs[stem(f)] = f;
    for (const auto& f : lf)
      if (rs.count(stem(f)))
        pairs_.emplace_back(f, rs[stem(f)]);
    if (pairs_.empty())
      fail("pairs folder '" + dir + "': no image name is in both left/ and right/");
  }
  std::string kind() const override { return "pairs"; }
  size_t size() const override { return pairs_.size(); }
  bool hasGroundTruth() const override { return false; }
  StereoFrame frame(size_t i) const override
  {
    StereoFrame f;
    f.stamp = 1000.0 + 0.1 * static_cast<double>(i);  // no stamps in the folder: 10 Hz
    const std::string lp = join(dir_, "left/" + pairs_.at(i).first), rp = join(dir_, "right/" + pairs_.at(i).second);
    cv::Mat l = readGray(lp);
    cv::Mat r = readGray(rp);
    checkImageSizes("pairs", l, lp, r, rp, cv::Size(calib_.width, calib_.height), "the camera_info yaml");
    if (!mlx_.empty())
    {
      cv::remap(l, f.left, mlx_, mly_, cv::INTER_LINEAR);
      cv::remap(r, f.right, mrx_, mry_, cv::INTER_LINEAR);
    }
    else
    {
      f.left = l;
      f.right = r;
    }
    f.calib = calib_;
    return f;
  }

private:
  std::string dir_;
  StereoCalib calib_;
  cv::Mat mlx_, mly_, mrx_, mry_;
  std::vector<std::pair<std::string, std::string>> pairs_;
};
}  // namespace

// ------------------------------------------------------------------------------------- API
KittiTruth parseKittiTruth(const std::string& s)
{
  if (s == "image_stamp")
    return KittiTruth::ImageStamp;
  if (s == "devkit")
    return KittiTruth::Devkit;
  fail("unknown KITTI truth '" + s + "' (image_stamp or devkit)");
}

const char* toString(KittiTruth t) { return t == KittiTruth::ImageStamp ? "image_stamp" : "devkit"; }

std::unique_ptr<DatasetSource> openDataset(const std::string& kind, const std::string& dir,
                                           const DatasetOptions& options)
{
  if (kind == "kitti")
    return std::make_unique<KittiSource>(dir, options.kitti_truth);
  if (kind == "euroc")
    return std::make_unique<EurocSource>(dir);
  if (kind == "pairs")
    return std::make_unique<PairsSource>(dir);
  fail("unknown dataset kind '" + kind + "' (kitti, euroc or pairs)");
}

std::map<std::string, std::vector<double>> readKittiCalibFile(const std::string& path)
{
  std::map<std::string, std::vector<double>> m;
  size_t no = 0;
  for (const auto& l : readLines(path))
  {
    ++no;
    const auto c = l.find(':');
    if (c == std::string::npos)
      continue;
    const std::string key = l.substr(0, c);
    std::istringstream is(l.substr(c + 1));
    std::vector<double> v;
    std::string tok;
    bool numeric = true;
    while (is >> tok)
    {
      try
      {
        size_t used = 0;
        v.push_back(std::stod(tok, &used));
        if (used != tok.size())
          numeric = false;
      }
      catch (const std::exception&)
      {
        numeric = false;
      }
    }
    if (numeric)
      m[key] = v;
    else if (key != "calib_time")
      fail(path + ":" + std::to_string(no) + ": key '" + key + "' holds a non-number");
  }
  if (m.empty())
    fail(path + ": no 'KEY: values' lines");
  return m;
}

double parseKittiTimestamp(const std::string& s)
{
  int Y, M, D, h, m;
  double sec;
  if (std::sscanf(s.c_str(), "%d-%d-%d %d:%d:%lf", &Y, &M, &D, &h, &m, &sec) != 6)
    fail("bad KITTI timestamp '" + s + "' (expected YYYY-MM-DD hh:mm:ss.fffffffff)");
  std::tm tm{};
  tm.tm_year = Y - 1900;
  tm.tm_mon = M - 1;
  tm.tm_mday = D;
  tm.tm_hour = h;
  tm.tm_min = m;
  tm.tm_sec = 0;
  return static_cast<double>(timegm(&tm)) + sec;
}

std::vector<OxtsPacket> readOxtsFolder(const std::string& oxts_dir)
{
  const std::string d = join(oxts_dir, "data");
  std::vector<OxtsPacket> out;
  for (const auto& f : listFiles(d, {"txt"}))
  {
    const std::string p = join(d, f);
    const auto lines = readLines(p);
    std::vector<double> v;
    if (!lines.empty())
    {
      std::istringstream is(lines[0]);
      double x;
      while (is >> x)
        v.push_back(x);
      if (!is.eof())
        fail(p + ":1: not a number in the OXTS packet");
    }
    if (v.size() != 30)
      fail(p + ": expected 30 OXTS values (lat lon alt roll pitch yaw ...), got " + std::to_string(v.size()));
    OxtsPacket o;
    o.lat = v[0];
    o.lon = v[1];
    o.alt = v[2];
    o.roll = v[3];
    o.pitch = v[4];
    o.yaw = v[5];
    o.vf = v[8];
    o.vl = v[9];
    o.vu = v[10];
    o.wf = v[20];
    o.wl = v[21];
    o.wu = v[22];
    out.push_back(o);
  }
  if (out.empty())
    fail(d + ": no OXTS packets");
  return out;
}

std::vector<Eigen::Isometry3d> oxtsToImuPoses(const std::vector<OxtsPacket>& oxts)
{
  std::vector<Eigen::Isometry3d> out;
  if (oxts.empty())
    return out;
  const double er = 6378137.0;
  const double scale = std::cos(oxts[0].lat * M_PI / 180.0);
  for (const auto& o : oxts)
  {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(scale * o.lon * M_PI * er / 180.0,
                                      scale * er * std::log(std::tan((90.0 + o.lat) * M_PI / 360.0)), o.alt);
    T.linear() = (Eigen::AngleAxisd(o.yaw, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(o.pitch, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(o.roll, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    out.push_back(T);
  }
  return out;
}

std::vector<Eigen::Isometry3d> oxtsToImuPosesAt(const std::vector<OxtsPacket>& oxts,
                                                const std::vector<double>& oxts_stamps,
                                                const std::vector<double>& stamps, double max_offset_s)
{
  if (oxts_stamps.size() != oxts.size())
    fail("OXTS: " + std::to_string(oxts_stamps.size()) + " stamps for " + std::to_string(oxts.size()) + " packets");
  std::vector<Eigen::Isometry3d> out;
  if (oxts.empty())
    return out;
  const std::vector<Eigen::Isometry3d> at_oxts = oxtsToImuPoses(oxts);
  const double scale = std::cos(oxts[0].lat * M_PI / 180.0);
  for (const double t : stamps)
  {
    size_t k = 0;  // the nearest sample
    for (size_t j = 1; j < oxts.size(); ++j)
      if (std::abs(oxts_stamps[j] - t) < std::abs(oxts_stamps[k] - t))
        k = j;
    const double dt = t - oxts_stamps[k];
    if (!(std::abs(dt) <= max_offset_s))
    {
      char b[160];
      std::snprintf(b, sizeof b, "OXTS: no sample within %.3f s of the image stamp %.6f (nearest %.6f)",
                    max_offset_s, t, oxts_stamps[k]);
      fail(b);
    }
    const OxtsPacket& o = oxts[k];
    // level (heading) frame at the sample: x forward, y left, z up, yawed by o.yaw in the
    // Mercator frame (x east, y north, z up)
    const Eigen::Matrix3d R_level = Eigen::AngleAxisd(o.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // constant speed and yaw rate: the level-frame velocity turns with the heading, so the
    // horizontal displacement is the arc int_0^dt Rz(wu s) ds * (vf, vl)
    const double x = o.wu * dt;
    double a, b;  // sin(x) / wu, (1 - cos(x)) / wu
    if (std::abs(x) < 1e-6)
    {
      a = dt * (1.0 - x * x / 6.0);
      b = dt * (x / 2.0 - x * x * x / 24.0);
    }
    else
    {
      a = std::sin(x) / o.wu;
      b = (1.0 - std::cos(x)) / o.wu;
    }
    Eigen::Vector3d d = R_level * Eigen::Vector3d(a * o.vf - b * o.vl, b * o.vf + a * o.vl, o.vu * dt);
    // metres -> Mercator units: the projection stretches by 1 / cos(lat), the devkit scales by cos(lat0)
    const double merc = scale / std::cos(o.lat * M_PI / 180.0);
    d.x() *= merc;
    d.y() *= merc;
    const Eigen::Vector3d w = R_level * Eigen::Vector3d(o.wf, o.wl, o.wu);  // rad/s in the Mercator frame
    Eigen::Isometry3d T = at_oxts[k];
    T.translation() += d;
    if (w.norm() * std::abs(dt) > 0.0)
      T.linear() = Eigen::AngleAxisd(w.norm() * dt, w.normalized()).toRotationMatrix() * T.linear();
    out.push_back(T);
  }
  return out;
}

std::vector<double> readKittiTimestamps(const std::string& path)
{
  std::vector<double> out;
  size_t no = 0;
  for (const auto& l : readLines(path))
  {
    ++no;
    if (l.find_first_not_of(" \t\r") == std::string::npos)
      continue;
    try
    {
      out.push_back(parseKittiTimestamp(l));
    }
    catch (const std::runtime_error& e)
    {
      fail(path + ":" + std::to_string(no) + ": " + e.what());
    }
  }
  if (out.empty())
    fail(path + ": no timestamps");
  return out;
}

KittiRawCalib readKittiRawCalib(const std::string& dir, bool with_imu)
{
  auto find = [&](const std::string& name) {
    for (const std::string& p : {join(dir, name), join(dir, "../" + name)})
      if (exists(p))
        return p;
    fail("KITTI calibration '" + name + "' not found in '" + dir + "' or its parent");
  };
  KittiRawCalib k;
  const std::string cc = find("calib_cam_to_cam.txt");
  const auto c = readKittiCalibFile(cc);
  const auto& P0 = need(c, "P_rect_00", 12, cc);
  const auto& P1 = need(c, "P_rect_01", 12, cc);
  const auto& Rr = need(c, "R_rect_00", 9, cc);
  k.calib.fx = P0[0];
  k.calib.fy = P0[5];
  k.calib.cx = P0[2];
  k.calib.cy = P0[6];
  k.calib.baseline = -P1[3] / P1[0];
  const auto s = c.find("S_rect_00");
  if (s != c.end() && s->second.size() == 2)
  {
    k.calib.width = static_cast<int>(s->second[0]);
    k.calib.height = static_cast<int>(s->second[1]);
  }
  if (with_imu)
  {
    const std::string vc = find("calib_velo_to_cam.txt"), iv = find("calib_imu_to_velo.txt");
    const auto v = readKittiCalibFile(vc), i = readKittiCalibFile(iv);
    const Eigen::Isometry3d T_cam0_velo = fromRt(need(v, "R", 9, vc), need(v, "T", 3, vc));
    const Eigen::Isometry3d T_velo_imu = fromRt(need(i, "R", 9, iv), need(i, "T", 3, iv));
    const Eigen::Isometry3d R_rect = fromRt(Rr, {0.0, 0.0, 0.0});
    k.T_cam0_imu = R_rect * T_cam0_velo * T_velo_imu;
    // the files give rotations to 7 digits: project onto the nearest rotation so that the
    // chain stays rigid (changes positions by < 0.01 mm over the 70 m clip)
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(k.T_cam0_imu.linear(), Eigen::ComputeFullU | Eigen::ComputeFullV);
    k.T_cam0_imu.linear() = svd.matrixU() * svd.matrixV().transpose();
  }
  return k;
}

std::vector<Eigen::Isometry3d> kittiCam0PosesDevkit(const std::vector<Eigen::Isometry3d>& imu,
                                                    const Eigen::Isometry3d& T_cam0_imu)
{
  std::vector<Eigen::Isometry3d> out;
  if (imu.empty())
    return out;
  const Eigen::Isometry3d T0inv = imu[0].inverse();
  const Eigen::Isometry3d T_imu_cam0 = T_cam0_imu.inverse();
  for (const auto& T : imu)
    out.push_back(T_cam0_imu * (T0inv * T) * T_imu_cam0);
  return out;
}

std::vector<Eigen::Isometry3d> kittiCam0PosesWorld(const std::vector<Eigen::Isometry3d>& imu,
                                                   const Eigen::Isometry3d& T_cam0_imu, double cam_height)
{
  std::vector<Eigen::Isometry3d> out;
  if (imu.empty())
    return out;
  const Eigen::Isometry3d T_imu_cam0 = T_cam0_imu.inverse();
  const Eigen::Isometry3d cam0 = imu[0] * T_imu_cam0;  // in the Mercator frame (z up)
  const Eigen::Vector3d f = cam0.linear() * Eigen::Vector3d::UnitZ();
  const double psi0 = std::atan2(f.y(), f.x());
  Eigen::Isometry3d T_world_merc = Eigen::Isometry3d::Identity();
  T_world_merc.linear() = Eigen::AngleAxisd(-psi0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_world_merc.translation() = -(T_world_merc.linear() * cam0.translation()) + Eigen::Vector3d(0, 0, cam_height);
  for (const auto& T : imu)
    out.push_back(T_world_merc * T * T_imu_cam0);
  return out;
}

EurocCamera readEurocSensorYaml(const std::string& path)
{
  const YAML::Node n = loadYaml(path);
  EurocCamera c;
  const auto T = yamlNumbers(n["T_BS"], path, "T_BS", 16);
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k)
      M(r, k) = T[static_cast<size_t>(4 * r + k)];
  c.T_BS.matrix() = M;
  const auto res = yamlNumbers(n["resolution"], path, "resolution", 2);
  c.width = static_cast<int>(res[0]);
  c.height = static_cast<int>(res[1]);
  const auto in = yamlNumbers(n["intrinsics"], path, "intrinsics", 4);
  c.fu = in[0];
  c.fv = in[1];
  c.cu = in[2];
  c.cv = in[3];
  c.dist = yamlNumbers(n["distortion_coefficients"], path, "distortion_coefficients", 4);
  if (n["camera_model"] && n["camera_model"].as<std::string>() != "pinhole")
    fail(path + ": camera_model '" + n["camera_model"].as<std::string>() + "' not supported (pinhole only)");
  if (n["distortion_model"] && n["distortion_model"].as<std::string>() != "radial-tangential")
    fail(path + ": distortion_model '" + n["distortion_model"].as<std::string>() +
         "' not supported (radial-tangential only)");
  return c;
}

StereoRectifier makeStereoRectifier(const cv::Mat& K0, const cv::Mat& D0, const cv::Mat& K1, const cv::Mat& D1,
                                    const cv::Size& size, const Eigen::Isometry3d& T_c1_c0)
{
  cv::Mat R(3, 3, CV_64F), T(3, 1, CV_64F);
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
      R.at<double>(r, c) = T_c1_c0.linear()(r, c);
    T.at<double>(r, 0) = T_c1_c0.translation()(r);
  }
  cv::Mat R1, R2, P1, P2, Q;
  cv::stereoRectify(K0, D0, K1, D1, size, R, T, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0.0, size);
  StereoRectifier s;
  cv::initUndistortRectifyMap(K0, D0, R1, P1, size, CV_32FC1, s.map0x, s.map0y);
  cv::initUndistortRectifyMap(K1, D1, R2, P2, size, CV_32FC1, s.map1x, s.map1y);
  s.calib.width = size.width;
  s.calib.height = size.height;
  s.calib.fx = P1.at<double>(0, 0);
  s.calib.fy = P1.at<double>(1, 1);
  s.calib.cx = P1.at<double>(0, 2);
  s.calib.cy = P1.at<double>(1, 2);
  s.calib.baseline = -P2.at<double>(0, 3) / P2.at<double>(0, 0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      s.R_rect_raw0(r, c) = R1.at<double>(r, c);
  return s;
}

void StereoRectifier::rectify(const cv::Mat& raw0, const cv::Mat& raw1, cv::Mat& out0, cv::Mat& out1) const
{
  cv::remap(raw0, out0, map0x, map0y, cv::INTER_LINEAR);
  cv::remap(raw1, out1, map1x, map1y, cv::INTER_LINEAR);
}

}  // namespace eval
}  // namespace assistive_sim
