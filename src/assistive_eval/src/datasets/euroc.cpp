// EuRoC MAV folders (import_dataset euroc): cam0/cam1 csv + sensor.yaml, rectified on import,
// Vicon / Leica ground truth.
#include <assistive_eval/datasets.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "dataset_io.h"

namespace assistive_eval
{
using namespace dataset_io;
namespace
{
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
}  // namespace

std::unique_ptr<DatasetSource> openEuroc(const std::string& dir)
{
  return std::make_unique<EurocSource>(dir);
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
}  // namespace assistive_eval
