// The pattern projector (issue 35): its dots give a plain wall texture the stereo pair agrees on,
// move with the head (not with the world), fall off with distance squared, are shadowed by what
// stands in front (checked against rays cast from the projector), are washed out by daylight, and
// a frame with the emitter off is the passive camera's to the bit.
#include <assistive_sim/motion.h>
#include <assistive_sim/renderer.h>

#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

using namespace assistive_sim;

namespace
{
/// A plain (textureless) wall across the view at x = `wall_x`, a plain box in front of it, under a
/// ceiling (indoors) or in the open.
std::string plainRoom(double wall_x, bool ceiling, const std::string& sky = "")
{
  std::string s = "name: plain\n"
                  "materials:\n"
                  "  paint: {pattern: plain, albedo: 0.5, contrast: 0.0}\n"
                  "floor: {min: [-2, -6], max: [12, 6], material: paint}\n";
  if (ceiling) s += "ceiling: {height: 3.0, material: paint}\n";
  s += sky;
  s += "elements:\n"
       "  - {type: wall, from: [" + std::to_string(wall_x + 0.1) + ", -6], to: [" + std::to_string(wall_x + 0.1) +
       ", 6], height: 3.0, thickness: 0.2, material: paint}\n"
       "  - {type: box, center: [1.0, -0.2], size: [0.2, 0.2, 3.0], material: paint}\n"
       "trajectory:\n  waypoints: [[0, 0], [1, 0]]\n";
  return s;
}

CameraParams camera(bool projector, double offset_x = 0.035)
{
  CameraParams p;
  p.calib = StereoCalib{160, 120, 125.0, 125.0, 79.5, 59.5, 0.12};
  p.noise_sigma = 0.0;
  p.exposure_variation = 0.0;
  p.projector.enabled = projector;
  p.projector.offset = Eigen::Vector3d(offset_x, 0.0, 0.0);
  return p;
}

/// Camera at (x, y, 1.5) looking along +x, level.
Eigen::Isometry3d levelPose(double x = 0.0, double y = 0.0)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, 1.5);
  return T * linkToLeftOptical();
}

/// Emitter-on minus emitter-off image, as floats.
cv::Mat dotsOnly(StereoRenderer& r, const Eigen::Isometry3d& T, RenderOutput& on, bool right = false)
{
  RenderOutput off;
  r.setEmitter(false);
  r.render(T, 0.0, 0, off);
  r.setEmitter(true);
  r.render(T, 0.0, 0, on);
  r.setEmitter(false);
  cv::Mat a, b;
  (right ? on.right : on.left).convertTo(a, CV_32F);
  (right ? off.right : off.left).convertTo(b, CV_32F);
  return a - b;
}

/// Mean of `img` over the pixels whose true depth lies within 2 % of `z` (the wall), rows 10-50
/// (above the floor's horizon band) and columns away from the box.
double meanOnWall(const cv::Mat& img, const cv::Mat& depth, double z, int* n = nullptr)
{
  double s = 0.0;
  int k = 0;
  for (int v = 10; v < 50; ++v)
    for (int u = 5; u < img.cols - 5; ++u)
      if (std::abs(depth.at<float>(v, u) - z) < 0.02 * z)
      {
        s += img.at<float>(v, u);
        ++k;
      }
  if (n) *n = k;
  return k > 0 ? s / k : 0.0;
}
}  // namespace

TEST(Projector, EmitterOffIsThePassiveCamera)
{
  const World w = World::parse(plainRoom(3.0, true), "plain");
  StereoRenderer passive(w, camera(false)), active(w, camera(true));
  EXPECT_EQ(passive.dotCount(), 0u);
  EXPECT_GT(active.dotCount(), 1000u);
  RenderOutput a, b;
  passive.render(levelPose(), 0.0, 7, a);
  active.render(levelPose(), 0.0, 7, b);  // emitter off by default
  EXPECT_EQ(cv::norm(a.left, b.left, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.right, b.right, cv::NORM_INF), 0.0);
  // The passive camera ignores the emitter.
  passive.setEmitter(true);
  passive.render(levelPose(), 0.0, 7, b);
  EXPECT_EQ(cv::norm(a.left, b.left, cv::NORM_INF), 0.0);
}

TEST(Projector, DotsGiveAPlainWallTextureBothCamerasAgreeOn)
{
  const World w = World::parse(plainRoom(3.0, true), "plain");
  StereoRenderer r(w, camera(true));
  RenderOutput on;
  const cv::Mat dots = dotsOnly(r, levelPose(), on);
  int n = 0;
  EXPECT_GT(meanOnWall(dots, on.depth_left, 3.0, &n), 1.0);
  ASSERT_GT(n, 1000);
  // Where a dot lands in the left image (a local peak), the right image shows it at the wall's
  // disparity f B / Z = 125 * 0.12 / 3 = 5 px (within a pixel).
  RenderOutput on_r;
  const cv::Mat dots_r = dotsOnly(r, levelPose(), on_r, true);
  int peaks = 0, matched = 0;
  for (int v = 12; v < 48; ++v)
    for (int u = 12; u < 150; ++u)
    {
      const float c = dots.at<float>(v, u);
      if (c < 8.f || std::abs(on.depth_left.at<float>(v, u) - 3.0f) > 0.06f) continue;
      bool peak = true;
      for (int dv = -1; dv <= 1 && peak; ++dv)
        for (int du = -1; du <= 1; ++du)
          if ((du || dv) && dots.at<float>(v + dv, u + du) > c) peak = false;
      if (!peak) continue;
      ++peaks;
      float best = -1.f;
      int best_u = -1;
      for (int ur = u - 10; ur <= u; ++ur)
        if (dots_r.at<float>(v, ur) > best) best = dots_r.at<float>(v, ur), best_u = ur;
      if (std::abs((u - best_u) - 5) <= 1) ++matched;
    }
  EXPECT_GT(peaks, 100);
  EXPECT_GT(matched, 0.8 * peaks) << matched << " of " << peaks;
}

TEST(Projector, DotsMoveWithTheHeadNotWithTheWorld)
{
  const World w = World::parse(plainRoom(3.0, true), "plain");
  StereoRenderer r(w, camera(true));
  RenderOutput a, b;
  const cv::Mat da = dotsOnly(r, levelPose(0.0, 1.0), a);
  const cv::Mat db = dotsOnly(r, levelPose(0.0, 1.3), b);  // 0.3 m to the left along the wall
  // A pattern fixed to the wall would shift by f * 0.3 / 3 = 12.5 px; the projector's stays put.
  const cv::Rect roi(20, 12, 120, 30);
  cv::Mat za = da(roi), zb = db(roi);
  const double same = za.dot(zb) / std::sqrt(za.dot(za) * zb.dot(zb));
  cv::Mat shifted = db(roi - cv::Point(12, 0));
  const double moved = za.dot(shifted) / std::sqrt(za.dot(za) * shifted.dot(shifted));
  EXPECT_GT(same, 0.95);
  EXPECT_LT(moved, 0.3);
}

TEST(Projector, DotsFallOffWithDistanceSquared)
{
  const World near_w = World::parse(plainRoom(1.5, true), "plain"), far_w = World::parse(plainRoom(3.0, true), "plain");
  StereoRenderer rn(near_w, camera(true)), rf(far_w, camera(true));
  RenderOutput on_n, on_f;
  // (the box at x = 1 stands before both walls; the mean is taken on the wall's own pixels)
  const double mn = meanOnWall(dotsOnly(rn, levelPose(), on_n), on_n.depth_left, 1.5);
  const double mf = meanOnWall(dotsOnly(rf, levelPose(), on_f), on_f.depth_left, 3.0);
  ASSERT_GT(mf, 0.5);
  EXPECT_NEAR(mn / mf, 4.0, 0.6);
}

TEST(Projector, WhatStandsInFrontShadowsTheWall)
{
  // A projector 0.3 m beside the camera casts a shadow of the box onto the wall that the camera
  // sees; which wall pixels lie in it is decided by rays cast from the projector.
  const World w = World::parse(plainRoom(3.0, true), "plain");
  StereoRenderer r(w, camera(true, 0.3));
  RenderOutput on;
  const Eigen::Isometry3d T = levelPose();
  const cv::Mat dots = dotsOnly(r, T, on);
  const Eigen::Vector3d proj = T * Eigen::Vector3d(0.3, 0.0, 0.0);
  double lit_sum = 0.0, shade_sum = 0.0;
  int lit = 0, shaded = 0;
  for (int v = 12; v < 48; ++v)
    for (int u = 2; u < 158; ++u)
    {
      const float z = on.depth_left.at<float>(v, u);
      if (std::abs(z - 3.0f) > 0.06f) continue;
      const Eigen::Vector3d p = T * Eigen::Vector3d((u - 79.5) / 125.0 * z, (v - 59.5) / 125.0 * z, z);
      const double dist = (p - proj).norm();
      const double hit = r.castRay(proj, (p - proj) / dist);
      // (a pixel within a dot's radius of the shadow's edge is left out)
      if (hit > 0 && hit < dist - 0.1)
      {
        const double hit_l = r.castRay(proj, (T * Eigen::Vector3d((u - 2 - 79.5) / 125.0 * z, (v - 59.5) / 125.0 * z, z) - proj).normalized());
        const double hit_r = r.castRay(proj, (T * Eigen::Vector3d((u + 2 - 79.5) / 125.0 * z, (v - 59.5) / 125.0 * z, z) - proj).normalized());
        if (hit_l < dist - 0.1 && hit_r < dist - 0.1) shade_sum += dots.at<float>(v, u), ++shaded;
      }
      else
        lit_sum += dots.at<float>(v, u), ++lit;
    }
  ASSERT_GT(shaded, 50);
  ASSERT_GT(lit, 1000);
  EXPECT_LT(shade_sum / shaded, 0.05);
  EXPECT_GT(lit_sum / lit, 1.0);
}

TEST(Projector, DaylightWashesTheDotsOut)
{
  const World indoor = World::parse(plainRoom(3.0, true), "plain");
  const World open = World::parse(plainRoom(3.0, false), "plain");
  const World dusk = World::parse(plainRoom(3.0, false, "sky: {brightness: 0.75, illuminance: 3000}\n"), "plain");
  EXPECT_DOUBLE_EQ(indoor.ambientLux(), 300.0);
  EXPECT_DOUBLE_EQ(open.ambientLux(), 10000.0);
  EXPECT_DOUBLE_EQ(dusk.ambientLux(), 3000.0);
  StereoRenderer ri(indoor, camera(true)), ro(open, camera(true)), rd(dusk, camera(true));
  RenderOutput a, b, c;
  const double mi = meanOnWall(dotsOnly(ri, levelPose(), a), a.depth_left, 3.0);
  const double mo = meanOnWall(dotsOnly(ro, levelPose(), b), b.depth_left, 3.0);
  const double md = meanOnWall(dotsOnly(rd, levelPose(), c), c.depth_left, 3.0);
  // the dots scale with 1 / lux (the grey levels are rounded: the open wall's are faint)
  EXPECT_LT(mo, 0.1 * mi);
  EXPECT_NEAR(md / mi, 0.1, 0.03);
}

TEST(LowLight, GainRaisesTheNoiseThenTheImageDarkens)
{
  // A plain wall filling rows 10-50 (no texture: what varies there is the noise).
  auto wallStats = [](double lux, double& mean, double& sd) {
    const std::string sky = lux > 0 ? "sky: {brightness: 0.75, illuminance: " + std::to_string(lux) + "}\n" : "";
    const World w = World::parse(plainRoom(3.0, true, sky), "plain");
    CameraParams p = camera(false);
    p.noise_sigma = 2.0;
    StereoRenderer r(w, p);
    RenderOutput out;
    r.render(levelPose(), 0.0, 3, out);
    cv::Mat roi;
    out.left(cv::Rect(5, 10, 60, 40)).convertTo(roi, CV_32F);
    cv::Scalar m, s;
    cv::meanStdDev(roi, m, s);
    mean = m[0];
    sd = s[0];
    return out.left.clone();
  };
  double m300, s300, m1000, s1000, m10, s10, m1, s1;
  const cv::Mat a = wallStats(300.0, m300, s300), b = wallStats(1000.0, m1000, s1000), c = wallStats(-1.0, m1000, s1000);
  // in good light nothing changes: 300 and 1000 lux and the default give the same image
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a, c, cv::NORM_INF), 0.0);
  EXPECT_NEAR(s300, 2.0, 0.3);
  // 10 lux: gain 10, the level kept; the noise as the model says at that level
  wallStats(10.0, m10, s10);
  const LowLightParams ll;
  const double g = 10.0, epg = ll.full_well_e / 255.0;
  const double want = std::sqrt(4.0 + ll.read_noise_e * ll.read_noise_e * (g * g - 1) / (epg * epg) + (g - 1) * m10 / epg);
  EXPECT_NEAR(m10, m300, 1.0);
  EXPECT_NEAR(s10, want, 0.15 * want);
  EXPECT_GT(s10, 2.5 * s300);
  // 1 lux: the gain capped at 16 of the 100 needed: the image at 16 %
  wallStats(1.0, m1, s1);
  EXPECT_NEAR(m1 / m300, 0.16, 0.02);
}
