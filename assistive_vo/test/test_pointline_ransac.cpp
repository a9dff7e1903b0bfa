// RANSAC over mixed points and lines with the quaternion trifocal solver: exact motion and the
// true inliers with 30 % gross outliers among points and lines.
#include <gtest/gtest.h>
#include "assistive_vo/pointline_ransac.h"
#include "assistive_vo/trifocal_synthetic.h"

using namespace assistive_vo;

TEST(PointLineRansac, ExactMotionWithThirtyPercentOutliers)
{
  for (int sample : {3, 4, 5})
  {
    std::mt19937 rng(20 + sample);
    TrifocalScene s = makeTrifocalScene(rng, 30, 15, TrifocalSceneOptions());
    ASSERT_EQ(s.points.size(), 30u);
    ASSERT_EQ(s.lines.size(), 15u);
    std::vector<int> true_pts, true_lines;
    const Eigen::Vector2d off(30.0 / 500.0, -25.0 / 500.0);  // 30 px, 25 px
    for (size_t i = 0; i < s.points.size(); ++i)
    {
      if (i % 10 < 3)
      {
        s.points[i].x[2] += off;  // a mismatch after the motion, in both views
        s.points[i].x[3] += off;
      }
      else
        true_pts.push_back(static_cast<int>(i));
    }
    for (size_t i = 0; i < s.lines.size(); ++i)
    {
      if (i % 10 < 3)
      {
        s.lines[i].p[2] += off, s.lines[i].q[2] += off;
        s.lines[i].p[3] += off, s.lines[i].q[3] += off;
      }
      else
        true_lines.push_back(static_cast<int>(i));
    }
    PointLineRansacOptions opt;
    opt.sample_size = sample;
    PointLineRansac ransac(7);
    const PointLineRansacResult r = ransac.estimate(s.rig, s.points, s.lines, opt);
    ASSERT_TRUE(r.ok) << "n=" << sample;
    EXPECT_LT((r.motion.R - s.motion.R).norm(), 1e-8) << "n=" << sample;
    EXPECT_LT((r.motion.t - s.motion.t).norm(), 1e-8) << "n=" << sample;
    EXPECT_EQ(r.point_inliers, true_pts) << "n=" << sample;
    EXPECT_EQ(r.line_inliers, true_lines) << "n=" << sample;
    EXPECT_LE(r.trials, opt.max_trials);
  }
}

TEST(PointLineRansac, TooFewFeatures)
{
  std::mt19937 rng(3);
  const TrifocalScene s = makeTrifocalScene(rng, 2, 1, TrifocalSceneOptions());
  PointLineRansac ransac;
  PointLineRansacOptions opt;
  EXPECT_FALSE(ransac.estimate(s.rig, s.points, s.lines, opt).ok);  // 3 features, sample of 5
  opt.sample_size = 3;
  EXPECT_TRUE(ransac.estimate(s.rig, s.points, s.lines, opt).ok);
}
