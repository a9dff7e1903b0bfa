// The renderer: true depth agrees with the geometry and with the stereo pair (disparity = f*B/Z),
// glass is see-through, determinism per seed; and the same through a small generated bag.
#include <assistive_sim/motion.h>
#include <assistive_sim/renderer.h>
#include <assistive_eval/stereo_bag.h>

#include <cstdio>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

using namespace assistive_sim;
using assistive_eval::StereoBagReader;
using assistive_eval::StereoBagWriter;

namespace
{
const char* ROOM = R"(name: room
materials:
  tex:  {pattern: noise, albedo: 0.5, contrast: 0.9, scale: 0.05}
  brk:  {pattern: bricks, albedo: 0.5, contrast: 0.8}
floor: {min: [-2, -4], max: [12, 4], material: tex}
elements:
  - {type: wall, from: [6.0, -4], to: [6.0, 4], height: 3.0, thickness: 0.2, material: brk}
  - {type: box, center: [3.0, 0.8], size: [0.6, 0.6, 1.8], material: tex}
  - {type: glass, from: [2.0, -3.0], to: [2.0, -0.6], bottom: 0.0, top: 2.5}
trajectory:
  waypoints: [[0, 0], [4, 0]]
)";

CameraParams smallCamera(double noise = 0.0)
{
  CameraParams p;
  p.calib = StereoCalib{160, 120, 125.0, 125.0, 79.5, 59.5, 0.12};  // width height fx fy cx cy baseline
  p.noise_sigma = noise;
  p.exposure_variation = 0.0;
  return p;
}

/// Camera at (0, 0, 1.5) looking along +x (optical z = world x), level.
Eigen::Isometry3d levelPose(double x = 0.0, double y = 0.0)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, 1.5);
  return T * linkToLeftOptical();
}

/// Normalised cross-correlation of two 7x7 patches.
double ncc(const cv::Mat& a, int ua, int va, const cv::Mat& b, int ub, int vb)
{
  const int r = 3;
  if (ua < r || va < r || ub < r || vb < r || ua + r >= a.cols || ub + r >= b.cols || va + r >= a.rows ||
      vb + r >= b.rows)
    return -2.0;
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  const int n = (2 * r + 1) * (2 * r + 1);
  for (int dv = -r; dv <= r; ++dv)
    for (int du = -r; du <= r; ++du)
    {
      const double x = a.at<uint8_t>(va + dv, ua + du), y = b.at<uint8_t>(vb + dv, ub + du);
      sa += x;
      sb += y;
      saa += x * x;
      sbb += y * y;
      sab += x * y;
    }
  const double va_ = saa - sa * sa / n, vb_ = sbb - sb * sb / n;
  if (va_ < 1e-6 || vb_ < 1e-6) return -2.0;
  return (sab - sa * sb / n) / std::sqrt(va_ * vb_);
}

/// Fraction of textured, unoccluded pixels where the right image matches at disparity f*B/Z
/// (best NCC over -3..3 px is at the predicted disparity +- 1 px).
double stereoAgreement(const cv::Mat& left, const cv::Mat& right, const cv::Mat& depth, const cv::Mat& depth_right,
                       const StereoCalib& c, int* tested)
{
  int good = 0, n = 0;
  for (int v = 8; v < left.rows - 8; v += 3)
    for (int u = 8; u < left.cols - 8; u += 3)
    {
      const float Z = depth.at<float>(v, u);
      if (Z <= 0.f) continue;
      const double d = c.fx * c.baseline / Z;
      const int ur = static_cast<int>(std::lround(u - d));
      if (ur < 8 || ur >= left.cols - 8) continue;
      // Unoccluded: the right camera sees the same depth there.
      if (std::abs(depth_right.at<float>(v, ur) - Z) > 0.02f * Z) continue;
      // Textured enough to match.
      cv::Scalar mean, sd;
      cv::meanStdDev(left(cv::Rect(u - 3, v - 3, 7, 7)), mean, sd);
      if (sd[0] < 4.0) continue;
      double best = -3;
      int best_off = 99;
      for (int off = -3; off <= 3; ++off)
      {
        const double s = ncc(left, u, v, right, ur + off, v);
        if (s > best)
        {
          best = s;
          best_off = off;
        }
      }
      ++n;
      if (std::abs(best_off) <= 1 && best > 0.8) ++good;
    }
  if (tested) *tested = n;
  return n > 0 ? static_cast<double>(good) / n : 0.0;
}
}  // namespace

TEST(Renderer, DepthMatchesGeometry)
{
  const World w = World::parse(ROOM, "room");
  StereoRenderer r(w, smallCamera());
  RenderOutput out;
  r.render(levelPose(), 0.0, 0, out);
  ASSERT_EQ(out.left.size(), cv::Size(160, 120));
  ASSERT_EQ(out.depth_left.type(), CV_32FC1);
  // Centre pixel row 59.5 -> between rows 59 and 60: look straight ahead at pixel (40, 59) which
  // sees the wall at x = 5.9 (left of the box). Z = 5.9 exactly (depth along the optical axis).
  const float z_wall = out.depth_left.at<float>(50, 140);
  EXPECT_NEAR(z_wall, 5.9f, 1e-3f);
  // The box front face at x = 2.7 (box centred at y = 0.8 -> left of the image centre).
  const int u_box = static_cast<int>(std::lround(79.5 - 125.0 * 0.8 / 2.7));
  EXPECT_NEAR(out.depth_left.at<float>(59, u_box), 2.7f, 1e-3f);
  // Floor below: row v sees the floor at Z = f * h / (v - cy).
  const int v_floor = 115;
  EXPECT_NEAR(out.depth_left.at<float>(v_floor, 140), 125.0 * 1.5 / (v_floor - 59.5), 1e-3);
  // Depth equals the distance cast along the pixel ray (Z = t for a ray with unit z component).
  const Eigen::Isometry3d T = levelPose();
  const Eigen::Vector3d d = T.linear() * Eigen::Vector3d((100 - 79.5) / 125.0, (90 - 59.5) / 125.0, 1.0);
  EXPECT_NEAR(out.depth_left.at<float>(90, 100), r.castRay(T.translation(), d), 1e-3);
}

TEST(Renderer, StereoDisparityMatchesDepth)
{
  const World w = World::parse(ROOM, "room");
  StereoRenderer r(w, smallCamera(2.0));
  RenderOutput out;
  Eigen::Isometry3d T = levelPose(0.5, 0.2);
  T.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.25, Eigen::Vector3d::UnitY()) *
               linkToLeftOptical().linear();
  r.render(T, 0.0, 0, out);
  // The right camera sees a point of depth Z at u - f*B/Z, with the same depth.
  int tested = 0;
  const double frac = stereoAgreement(out.left, out.right, out.depth_left, out.depth_right, r.params().calib, &tested);
  EXPECT_GT(tested, 300);
  EXPECT_GT(frac, 0.9) << "tested " << tested;
  // Counter-check: a wrong baseline does not agree.
  StereoCalib wrong = r.params().calib;
  wrong.baseline = 0.24;
  EXPECT_LT(stereoAgreement(out.left, out.right, out.depth_left, out.depth_right, wrong, nullptr), 0.5);
}

TEST(Renderer, GlassIsSeeThroughWithFaintReflection)
{
  const World w = World::parse(ROOM, "room");
  StereoRenderer r(w, smallCamera());
  RenderOutput out;
  // Look along -y through the glass panel at x = 2 ... no: stand at (0.5,-1.8), look at +x.
  Eigen::Isometry3d T = levelPose(0.5, -1.8);
  r.render(T, 0.0, 0, out);
  // Pixel straight ahead hits the glass at x = 2.0 and sees the wall at x = 5.9 behind it.
  EXPECT_EQ(out.glass_left.at<uint8_t>(59, 79), 255);
  EXPECT_NEAR(out.depth_left.at<float>(59, 79), 5.4f, 1e-2f);  // 5.9 - 0.5
  // Same pixel without the glass: the image differs only a little (faint reflection).
  World no_glass = w;
  no_glass.solids.erase(std::remove_if(no_glass.solids.begin(), no_glass.solids.end(),
                                       [](const Solid& s) { return s.glass; }),
                        no_glass.solids.end());
  StereoRenderer r2(no_glass, smallCamera());
  RenderOutput out2;
  r2.render(T, 0.0, 0, out2);
  EXPECT_EQ(out2.glass_left.at<uint8_t>(59, 79), 0);
  cv::Mat diff;
  cv::absdiff(out.left, out2.left, diff);
  const double mean_diff = cv::mean(diff, out.glass_left)[0];
  EXPECT_GT(mean_diff, 0.5);
  EXPECT_LT(mean_diff, 40.0);
}

TEST(Renderer, DeterministicPerSeed)
{
  const World w = World::parse(ROOM, "room");
  StereoRenderer a(w, smallCamera(2.0)), b(w, smallCamera(2.0));
  CameraParams pc = smallCamera(2.0);
  pc.seed = 2;
  StereoRenderer c(w, pc);
  RenderOutput oa, ob, oc, oa2;
  a.render(levelPose(), 1.0, 7, oa);
  b.render(levelPose(), 1.0, 7, ob);
  c.render(levelPose(), 1.0, 7, oc);
  a.render(levelPose(), 1.0, 8, oa2);
  EXPECT_EQ(cv::norm(oa.left, ob.left, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(oa.right, ob.right, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(oa.left, oc.left, cv::NORM_L1), 0.0);
  EXPECT_GT(cv::norm(oa.left, oa2.left, cv::NORM_L1), 0.0);  // fresh noise every frame
  // Noise has the requested size.
  CameraParams clean = smallCamera(0.0);
  StereoRenderer d(w, clean);
  RenderOutput od;
  d.render(levelPose(), 1.0, 7, od);
  cv::Mat diff;
  cv::subtract(oa.left, od.left, diff, cv::noArray(), CV_32F);
  cv::Scalar mean, sd;
  cv::meanStdDev(diff, mean, sd);
  EXPECT_NEAR(sd[0], 2.0, 0.4);
}

TEST(Renderer, MotionBlurSmearsAlongTheMotion)
{
  const World w = World::parse(ROOM, "room");
  CameraParams p = smallCamera(0.0);
  p.exposure_time = 0.02;
  StereoRenderer blur(w, p);
  StereoRenderer sharp(w, smallCamera(0.0));
  RenderOutput ob, os;
  // Fast yaw (2 rad/s about the optical y axis) -> horizontal blur of 125*2*0.02 = 5 px.
  blur.render(levelPose(), 0.0, 0, ob, Eigen::Vector3d(0, 2.0, 0));
  sharp.render(levelPose(), 0.0, 0, os);
  cv::Mat gb, gs;
  cv::Sobel(ob.left, gb, CV_32F, 1, 0);
  cv::Sobel(os.left, gs, CV_32F, 1, 0);
  EXPECT_LT(cv::norm(gb, cv::NORM_L1), 0.7 * cv::norm(gs, cv::NORM_L1));
}

TEST(RenderedBag, GroundTruthDepthMatchesStereoInBag)
{
  // A small bag generated like render_bag does, read back with the reader.
  const World w = World::load(resolveWorldPath("course", ASSISTIVE_SIM_SOURCE_WORLDS));
  const WearerMotion motion(w.trajectory, 4);
  CameraParams p = smallCamera(2.0);
  p.calib.width = 320;
  p.calib.height = 240;
  p.calib.fx = p.calib.fy = 250.0;
  p.calib.cx = 159.5;
  p.calib.cy = 119.5;
  StereoRenderer r(w, p);
  const std::string path = std::string(::testing::TempDir()) + "assistive_sim_test_render.bag";
  {
    StereoBagWriter writer(path);
    writer.writeOccupancy(computeOccupancy(w), 100.0);
    RenderOutput out;
    for (int k = 0; k < 3; ++k)
    {
      const double t = 3.0 + k / 15.0;
      r.render(motion.leftOpticalPose(t), t, k, out);
      StereoFrame f;
      f.stamp = 100.0 + t;
      f.left = out.left;
      f.right = out.right;
      f.calib = p.calib;
      f.has_gt_pose = true;
      f.gt_pose = motion.leftOpticalPose(t);
      writer.writeFrame(f);
    }
  }
  StereoBagReader reader(path);
  StereoFrame f;
  int frames = 0;
  while (reader.next(f))
  {
    ASSERT_TRUE(f.has_gt_pose);
    // Truth depth from the bag's gt pose by ray casting, per pixel of a grid.
    cv::Mat depth(f.left.size(), CV_32F, cv::Scalar(0)), depth_r(f.left.size(), CV_32F, cv::Scalar(0));
    const Eigen::Isometry3d Tl = f.gt_pose;
    const Eigen::Isometry3d Tr = Tl * Eigen::Translation3d(f.calib.baseline, 0, 0);
    for (int v = 8; v < f.left.rows - 8; v += 3)
      for (int u = 8; u < f.left.cols - 8; u += 3)
      {
        const Eigen::Vector3d d((u - f.calib.cx) / f.calib.fx, (v - f.calib.cy) / f.calib.fy, 1.0);
        const double t = r.castRay(Tl.translation(), Tl.linear() * d);
        depth.at<float>(v, u) = t > 0 ? static_cast<float>(t) : 0.f;
        const double Z = t;
        if (t > 0)
        {
          const int ur = static_cast<int>(std::lround(u - f.calib.fx * f.calib.baseline / Z));
          if (ur >= 0 && ur < f.left.cols)
          {
            const Eigen::Vector3d dr((ur - f.calib.cx) / f.calib.fx, (v - f.calib.cy) / f.calib.fy, 1.0);
            const double tr = r.castRay(Tr.translation(), Tr.linear() * dr);
            depth_r.at<float>(v, ur) = tr > 0 ? static_cast<float>(tr) : 0.f;
          }
        }
      }
    int tested = 0;
    EXPECT_GT(stereoAgreement(f.left, f.right, depth, depth_r, f.calib, &tested), 0.85);
    EXPECT_GT(tested, 200);
    ++frames;
  }
  EXPECT_EQ(frames, 3);
  OccupancyGrid g;
  ASSERT_TRUE(reader.readOccupancy(g));
  EXPECT_EQ(g.atWorld(6.1, -1.0), CELL_OBSTACLE);
  std::remove(path.c_str());
}
