#pragma once
// Private to the dataset readers (kitti.cpp, euroc.cpp, pairs.cpp, datasets.cpp): the helpers they
// share and each reader's factory. Every error is a std::runtime_error naming the file.
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <yaml-cpp/yaml.h>

#include <assistive_eval/datasets.h>

namespace assistive_eval
{
std::unique_ptr<DatasetSource> openKitti(const std::string& dir, KittiTruth truth);
std::unique_ptr<DatasetSource> openEuroc(const std::string& dir);
std::unique_ptr<DatasetSource> openPairs(const std::string& dir);

namespace dataset_io
{
[[noreturn]] inline void fail(const std::string& msg) { throw std::runtime_error(msg); }

bool exists(const std::string& p);
bool isDir(const std::string& p);
std::string join(const std::string& a, const std::string& b);
std::string stem(const std::string& f);
std::string lower(std::string s);
/// Files in `dir` whose extension is one of `exts`, sorted (numerically when the stems are numbers).
std::vector<std::string> listFiles(const std::string& dir, const std::vector<std::string>& exts);
/// mono8 image (colour converted); fails naming the file when it cannot be read.
cv::Mat readGray(const std::string& path);
/// Fails naming the image (its file path) whose size is not `expected` (`source` says where the
/// expected size comes from): the left one first, then the right one.
void checkImageSizes(const std::string& dataset, const cv::Mat& left, const std::string& left_path,
                     const cv::Mat& right, const std::string& right_path, const cv::Size& expected,
                     const std::string& source);
std::vector<std::string> readLines(const std::string& path);
/// yaml-cpp does not accept OpenCV's "%YAML:1.0" directive: drop it.
YAML::Node loadYaml(const std::string& path);
/// `count` numbers of `key` (a sequence, or an OpenCV matrix's `data`).
std::vector<double> yamlNumbers(const YAML::Node& n, const std::string& path, const std::string& key, size_t count);
/// Row-major 3x3 R and t -> isometry.
Eigen::Isometry3d fromRt(const std::vector<double>& R, const std::vector<double>& t);
/// m[key] with at least `count` values, else fails naming `path`.
const std::vector<double>& need(const std::map<std::string, std::vector<double>>& m, const std::string& key,
                                size_t count, const std::string& path);
/// Velocity at pose i by central differences (one-sided at the ends).
Eigen::Vector3d centralVelocity(const std::vector<Eigen::Isometry3d>& p, const std::vector<double>& t, size_t i);
}  // namespace dataset_io
}  // namespace assistive_eval
