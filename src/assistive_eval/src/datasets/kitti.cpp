// KITTI raw sync drives (import_dataset kitti): calibration, timestamps, OXTS poses and the
// ground truth at the image stamps (or the devkit convention).
#include <assistive_eval/datasets.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <ctime>
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
}  // namespace

std::unique_ptr<DatasetSource> openKitti(const std::string& dir, KittiTruth truth)
{
  return std::make_unique<KittiSource>(dir, truth);
}

KittiTruth parseKittiTruth(const std::string& s)
{
  if (s == "image_stamp")
    return KittiTruth::ImageStamp;
  if (s == "devkit")
    return KittiTruth::Devkit;
  fail("unknown KITTI truth '" + s + "' (image_stamp or devkit)");
}

const char* toString(KittiTruth t) { return t == KittiTruth::ImageStamp ? "image_stamp" : "devkit"; }

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
    // OXTS dataformat.txt: lat lon alt roll pitch yaw (0-5), vf vl vu (8-10), wf wl wu (20-22)
    out.push_back(OxtsPacket{v[0], v[1], v[2], v[3], v[4], v[5], v[8], v[9], v[10], v[20], v[21], v[22]});
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
}  // namespace assistive_eval
