// Rectified stereo pairs with ROS camera_info yaml (import_dataset pairs).
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

std::unique_ptr<DatasetSource> openPairs(const std::string& dir)
{
  return std::make_unique<PairsSource>(dir);
}
}  // namespace assistive_eval
