// The synthetic stereo camera of the SLAM core's gtests (local BA, the SLAM system, its reset):
// 640 x 480, f = 400 px, principal point at the centre, a 0.12 m baseline.
#pragma once
#include "assistive_slam/keyframe.h"

namespace slam_test
{
inline assistive_slam::StereoModel camera()
{
  assistive_slam::StereoModel c;
  c.fx = c.fy = 400;
  c.cx = 320;
  c.cy = 240;
  c.baseline = 0.12;
  return c;
}
}  // namespace slam_test
