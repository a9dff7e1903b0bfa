#include "assistive_vo/pointline_ransac.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include "assistive_vo/p3p_ransac.h"

namespace assistive_vo
{
namespace
{
struct Score
{
  int inliers = 0;
  double sum = 0;  ///< truncated error sum (tie break)
  bool better(const Score& o) const { return inliers > o.inliers || (inliers == o.inliers && sum < o.sum); }
};

Score score(const StereoRig& rig, const PointQuads& points, const LineQuads& lines, const StereoMotion& m,
            const PointLineRansacOptions& opt, std::vector<int>* pin, std::vector<int>* lin)
{
  Score s;
  for (size_t i = 0; i < points.size(); ++i)
  {
    const double e = pointReprojectionError(rig, m, points[i], opt.focal_px);
    if (e < opt.threshold_px)
    {
      ++s.inliers;
      if (pin)
        pin->push_back(static_cast<int>(i));
    }
    s.sum += std::min(e, opt.threshold_px);
  }
  for (size_t i = 0; i < lines.size(); ++i)
  {
    const double e = lineReprojectionError(rig, m, lines[i], opt.focal_px);
    if (e < opt.threshold_px)
    {
      ++s.inliers;
      if (lin)
        lin->push_back(static_cast<int>(i));
    }
    s.sum += std::min(e, opt.threshold_px);
  }
  return s;
}
}  // namespace

PointLineRansacResult PointLineRansac::estimate(const StereoRig& rig, const PointQuads& points, const LineQuads& lines,
                                                const PointLineRansacOptions& opt)
{
  PointLineRansacResult res;
  const int total = static_cast<int>(points.size() + lines.size());
  const int n = std::max(3, opt.sample_size);
  if (total < n)
    return res;
  std::vector<int> idx(static_cast<size_t>(total));
  std::iota(idx.begin(), idx.end(), 0);
  Score best;
  int k = opt.max_trials;
  for (int trial = 0; trial < k && trial < opt.max_trials; ++trial)
  {
    ++res.trials;
    for (int i = 0; i < n; ++i)  // partial Fisher-Yates: n distinct features
    {
      std::uniform_int_distribution<int> pick(i, total - 1);
      std::swap(idx[static_cast<size_t>(i)], idx[static_cast<size_t>(pick(rng_))]);
    }
    PointQuads sp;
    LineQuads sl;
    for (int i = 0; i < n; ++i)
    {
      const int f = idx[static_cast<size_t>(i)];
      if (f < static_cast<int>(points.size()))
        sp.push_back(points[static_cast<size_t>(f)]);
      else
        sl.push_back(lines[static_cast<size_t>(f) - points.size()]);
    }
    const TrifocalResult r = solveTrifocalQuaternion(rig, sp, sl);
    for (const StereoMotion& m : r.solutions)
    {
      const Score s = score(rig, points, lines, m, opt, nullptr, nullptr);
      if (s.better(best))
      {
        best = s;
        res.motion = m;
        res.ok = true;
        // eq. 2.18 with the inlier ratio of the best model so far
        k = P3PRansac::trialCount(opt.probability, static_cast<double>(s.inliers) / total, n, opt.max_trials);
      }
    }
  }
  if (!res.ok)
    return res;
  // re-solve from all inliers (the over-determined quaternion solution), keep it if not worse
  score(rig, points, lines, res.motion, opt, &res.point_inliers, &res.line_inliers);
  PointQuads ip;
  LineQuads il;
  for (int i : res.point_inliers)
    ip.push_back(points[static_cast<size_t>(i)]);
  for (int i : res.line_inliers)
    il.push_back(lines[static_cast<size_t>(i)]);
  const TrifocalResult all = solveTrifocalQuaternion(rig, ip, il);
  for (const StereoMotion& m : all.solutions)
  {
    const Score s = score(rig, points, lines, m, opt, nullptr, nullptr);
    if (!best.better(s))
    {
      best = s;
      res.motion = m;
    }
  }
  res.point_inliers.clear();
  res.line_inliers.clear();
  score(rig, points, lines, res.motion, opt, &res.point_inliers, &res.line_inliers);
  return res;
}
}  // namespace assistive_vo
