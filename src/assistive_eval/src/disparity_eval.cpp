#include <assistive_eval/disparity_eval.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace assistive_eval
{
cv::Mat readPfm(const std::string& path)
{
  std::ifstream f(path, std::ios::binary);
  if (!f) return {};
  std::string magic;
  int w = 0, h = 0;
  double scale = 0;
  f >> magic >> w >> h >> scale;
  f.get();
  if (magic != "Pf" || w <= 0 || h <= 0 || scale >= 0) return {};  // grey, little-endian only
  cv::Mat m(h, w, CV_32F);
  for (int r = h - 1; r >= 0; --r) f.read(reinterpret_cast<char*>(m.ptr<float>(r)), sizeof(float) * w);
  if (!f) return {};
  return m;
}

std::vector<RealPair> loadRealPairs(const std::string& dir, std::vector<std::string>* skipped)
{
  struct Spec
  {
    const char *name, *folder, *left, *right, *metric;
  };
  const Spec specs[] = {
      {"kitti2015_000005", "kitti2015_training_000005_10", "stereo_left.png", "stereo_right.png", "d1"},
      {"middlebury3_teddy_half", "middlebury_eval3_teddy_half", "im0.png", "im1.png", "bad2"},
      {"middlebury2003_cones_quarter", "middlebury2003_cones_quarter", "Cones_LEFT.tif", "Cones_RIGHT.tif", "bad2"},
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<RealPair> out;
  for (const Spec& s : specs)
  {
    const std::string f = dir + "/" + s.folder;
    RealPair p;
    p.name = s.name;
    p.metric = s.metric;
    p.left = cv::imread(f + "/" + s.left, cv::IMREAD_GRAYSCALE);
    p.right = cv::imread(f + "/" + s.right, cv::IMREAD_GRAYSCALE);
    if (p.name == "kitti2015_000005")
    {
      cv::Mat raw = cv::imread(f + "/gt_disparity.png", cv::IMREAD_UNCHANGED);
      if (!raw.empty() && raw.depth() == CV_16U)
      {
        raw.convertTo(p.gt, CV_32F, 1.0 / 256.0);
        p.gt.setTo(nan, raw == 0);
      }
    }
    else if (p.name == "middlebury3_teddy_half")
    {
      p.gt = readPfm(f + "/disp0GT.pfm");
      for (int r = 0; r < p.gt.rows; ++r)
        for (int c = 0; c < p.gt.cols; ++c)
          if (!std::isfinite(p.gt.at<float>(r, c))) p.gt.at<float>(r, c) = nan;
    }
    else
    {
      cv::Mat raw = cv::imread(f + "/Cones_LEFT_GT.tif", cv::IMREAD_UNCHANGED);
      if (!raw.empty())
      {
        raw.convertTo(p.gt, CV_32F);
        p.gt.setTo(nan, p.gt <= 0.0f);
      }
    }
    if (p.left.empty() || p.right.empty() || p.gt.empty() || p.left.size() != p.right.size() ||
        p.gt.size() != p.left.size())
    {
      if (skipped) skipped->push_back(p.name + ": missing or unreadable files under " + f);
      continue;
    }
    out.push_back(p);
  }
  return out;
}

DisparityScore scoreDisparity(const cv::Mat& est, const cv::Mat& gt)
{
  DisparityScore s;
  size_t d1 = 0, bad2 = 0, have = 0;
  for (int r = 0; r < gt.rows; ++r)
    for (int c = 0; c < gt.cols; ++c)
    {
      const float g = gt.at<float>(r, c);
      if (!std::isfinite(g)) continue;
      ++s.valid;
      const float e = est.at<float>(r, c);
      if (!(e > 0.f))
      {
        ++d1;
        ++bad2;
        continue;
      }
      ++have;
      const float err = std::abs(e - g);
      if (err > 3.f && err > 0.05f * g) ++d1;
      if (err > 2.f) ++bad2;
    }
  if (s.valid == 0) return s;
  s.d1_pct = 100.0 * d1 / s.valid;
  s.bad2_pct = 100.0 * bad2 / s.valid;
  s.density_pct = 100.0 * have / s.valid;
  return s;
}
cv::Mat peerSgbm(const cv::Mat& left, const cv::Mat& right, int num_disparities)
{
  auto grey = [](const cv::Mat& in) {  // BGR / BGRA / grey
    cv::Mat out = in;
    if (in.channels() > 1) cv::cvtColor(in, out, in.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
    return out;
  };
  const int bs = 5;
  const int nd = std::max(16, (num_disparities + 15) / 16 * 16);
  auto sg = cv::StereoSGBM::create(0, nd, bs, 8 * bs * bs, 32 * bs * bs, 1, 63, 10, 100, 2,
                                   cv::StereoSGBM::MODE_SGBM);
  cv::Mat d16, d;
  sg->compute(grey(left), grey(right), d16);
  d16.convertTo(d, CV_32F, 1.0 / 16.0);
  d.setTo(-1.0f, d <= 0.0f);
  return d;
}

}  // namespace assistive_eval
