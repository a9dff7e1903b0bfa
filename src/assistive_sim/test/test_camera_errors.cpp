// The camera imperfections (renderer.h CameraErrors) against known answers: each one moves a known
// edge of a known scene by the pixel offset the geometry predicts (the box's edges seen in the true
// depth images), the auto-exposure steps scale the image exactly by the scheduled gain, and the
// random draw stays inside the documented ranges and is deterministic per seed.
#include <assistive_sim/renderer.h>

#include <cmath>

#include <gtest/gtest.h>

using namespace assistive_sim;

namespace
{
// A wall at x = 6 (face at 5.9) and a thin box (2 cm deep: its side faces are too thin to move an
// edge) whose front face is at x = 2.7, spanning y 0.5..1.1 and z 0..1.8. The camera at (0, 0, 1.5) looks along +x: the box's right edge is at optical
// X = -0.5, Z = 2.7 (u = cx + f * -0.5 / 2.7), its left edge at X = -1.1, its top at Y = -0.3.
const char* ROOM = R"(name: room
materials:
  tex:  {pattern: noise, albedo: 0.5, contrast: 0.9, scale: 0.05}
floor: {min: [-2, -4], max: [12, 4], material: tex}
elements:
  - {type: wall, from: [6.0, -4], to: [6.0, 4], height: 3.0, thickness: 0.2, material: tex}
  - {type: box, center: [2.71, 0.8], size: [0.02, 0.6, 1.8], material: tex}
trajectory:
  waypoints: [[0, 0], [4, 0]]
)";
constexpr double F = 125.0, CX = 79.5, CY = 59.5, B = 0.12, ZBOX = 2.7;
/// An edge is located to half a pixel (the last pixel centre inside + 0.5), plus up to 0.2 px of the
/// box's 2 cm side face seen obliquely.
constexpr double TOL = 0.75;

CameraParams camera(const CameraErrors& e = {})
{
  CameraParams p;
  p.calib = StereoCalib{160, 120, F, F, CX, CY, B};
  p.noise_sigma = 0.0;
  p.exposure_variation = 0.0;
  p.errors = e;
  return p;
}
Eigen::Isometry3d levelPose()
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0, 0, 1.5);
  return T * linkToLeftOptical();
}
/// The box's front face (depth 2.7; the floor in the lowest rows is beyond 3.1, the wall at 5.9).
bool isBox(const cv::Mat& depth, int v, int u) { return std::abs(depth.at<float>(v, u) - ZBOX) < 0.1f; }
/// Sub-pixel column of the box's right edge in row v: the last box pixel + 0.5 (the edge lies
/// between that pixel's centre and the next one's; error < 0.5 px).
double rightEdge(const cv::Mat& depth, int v)
{
  for (int u = depth.cols - 2; u >= 0; --u)
    if (isBox(depth, v, u)) return u + 0.5;
  return NAN;
}
/// Sub-pixel column of the box's left edge in row v: the first box pixel - 0.5.
double leftEdge(const cv::Mat& depth, int v)
{
  for (int u = 0; u < depth.cols; ++u)
    if (isBox(depth, v, u)) return u - 0.5;
  return NAN;
}
/// Sub-pixel row of the box's top edge in column u.
double topEdge(const cv::Mat& depth, int u)
{
  for (int v = 0; v < depth.rows; ++v)
    if (isBox(depth, v, u)) return v - 0.5;
  return NAN;
}
RenderOutput renderWith(const CameraErrors& e, const Eigen::Vector3d& omega = Eigen::Vector3d::Zero())
{
  const World w = World::parse(ROOM, "room");
  StereoRenderer r(w, camera(e));
  RenderOutput out;
  r.render(levelPose(), 0.0, 0, out, omega);
  return out;
}
}  // namespace

TEST(CameraErrors, IdealRigEdgesWhereTheNominalCalibrationSaysSoTheTestCanSeeThem)
{
  const RenderOutput o = renderWith({});
  EXPECT_NEAR(rightEdge(o.depth_left, 80), CX + F * -0.5 / ZBOX, TOL);
  EXPECT_NEAR(rightEdge(o.depth_right, 80), CX + F * (-0.5 - B) / ZBOX, TOL);
  EXPECT_NEAR(leftEdge(o.depth_left, 80), CX + F * -1.1 / ZBOX, TOL);
}

TEST(CameraErrors, BaselineErrorMovesTheRightImageByThePredictedDisparity)
{
  CameraErrors e;
  e.baseline_scale = 0.5;  // true baseline 0.18 m while camera_info says 0.12 m
  const RenderOutput o = renderWith(e);
  const double expected = CX + F * (-0.5 - B * 1.5) / ZBOX;  // disparity f * 0.18 / 2.7 = 8.33 px
  EXPECT_NEAR(rightEdge(o.depth_right, 80), expected, TOL);
  // predicted offset against the nominal rig: -f * B * 0.5 / Z = -2.78 px
  EXPECT_LT(rightEdge(o.depth_right, 80) - (CX + F * (-0.5 - B) / ZBOX), -2.0);
  EXPECT_NEAR(rightEdge(o.depth_left, 80), CX + F * -0.5 / ZBOX, TOL);  // left camera unchanged
}

TEST(CameraErrors, FocalErrorScalesImageCoordinatesAboutThePrincipalPoint)
{
  CameraErrors e;
  e.focal_scale = 0.2;
  const RenderOutput o = renderWith(e);
  EXPECT_NEAR(leftEdge(o.depth_left, 80), CX + 1.2 * F * -1.1 / ZBOX, TOL);   // 18.4 (nominal 28.7)
  EXPECT_NEAR(rightEdge(o.depth_left, 80), CX + 1.2 * F * -0.5 / ZBOX, TOL);  // 51.7 (nominal 56.4)
}

TEST(CameraErrors, RightCameraPitchGivesThePredictedVerticalMisalignment)
{
  CameraErrors e;
  const double a = 2.0 * M_PI / 180.0;
  e.right_rotation = Eigen::Vector3d(a, 0, 0);  // about the optical x axis
  const RenderOutput o = renderWith(e);
  // The box's top (Y = -0.3, Z = 2.7) in the right camera's frame R_x(a)^T (X, Y, Z).
  const double Y = std::cos(a) * -0.3 + std::sin(a) * ZBOX, Z = -std::sin(a) * -0.3 + std::cos(a) * ZBOX;
  const int u = 40;  // inside the box in the right image (box X -1.1..-0.5 -> u 23..45)
  EXPECT_NEAR(topEdge(o.depth_right, u), CY + F * Y / Z, TOL);   // ~50.9
  EXPECT_NEAR(topEdge(o.depth_left, u), CY + F * -0.3 / ZBOX, TOL);  // 45.6: the left is unchanged
}

TEST(CameraErrors, ResidualRadialDistortionMovesAnEdgeWhereThePolynomialSays)
{
  CameraErrors e;
  e.k1 = 1.0;  // exaggerated so that the shift is several pixels
  const RenderOutput o = renderWith(e);
  // The edge ray x_u = -1.1 / 2.7 is seen at x_d with x_d (1 + k1 (x_d^2 + y^2)) = x_u (row 80:
  // y = 0.164).
  const double y = (80 - CY) / F, xu = -1.1 / ZBOX;
  double xd = xu;
  for (int i = 0; i < 50; ++i)
  {
    // Newton on g(x_d) = x_d s(x_d) - x_u: pixel (x_d, y) sees the ray (x_d s, y s, 1).
    const double s = 1.0 + e.k1 * (xd * xd + y * y);
    const double g = xd * s - xu, dg = s + 2.0 * e.k1 * xd * xd;
    xd -= g / dg;
  }
  EXPECT_NEAR(leftEdge(o.depth_left, 80), CX + F * xd, TOL);
  EXPECT_GT(leftEdge(o.depth_left, 80) - (CX + F * xu), 4.0);  // a barrel residual pulls it inwards
}

TEST(CameraErrors, RollingShutterShiftsEachRowByTheRotationDuringItsReadout)
{
  CameraErrors e;
  e.rolling_shutter_s = 0.033;
  const double w = 3.0;  // rad/s about the optical y axis (a fast head turn)
  const RenderOutput o = renderWith(e, Eigen::Vector3d(0, w, 0));
  const double theta = std::atan2(-0.5, ZBOX);
  for (int v : {50, 80, 115})
  {
    // Row v is exposed at dt = (v / (H - 1) - 0.5) * readout: the camera turned by a = w dt, so the
    // edge at angle theta is seen at u = cx + f tan(theta - a).
    const double dt = (v / 119.0 - 0.5) * e.rolling_shutter_s;
    EXPECT_NEAR(rightEdge(o.depth_left, v), CX + F * std::tan(theta - w * dt), TOL) << "row " << v;
  }
  // Global shutter: every row at the same column.
  const RenderOutput g = renderWith({}, Eigen::Vector3d(0, w, 0));
  EXPECT_EQ(rightEdge(g.depth_left, 50), rightEdge(g.depth_left, 115));
  EXPECT_LT(rightEdge(o.depth_left, 115) - rightEdge(o.depth_left, 50), -5.0);  // a 6.4 px slant
}

TEST(CameraErrors, AutoExposureStepsScaleEachCameraByItsScheduledGain)
{
  const World w = World::parse(ROOM, "room");
  CameraErrors e;
  e.ae_step = 0.2;
  e.ae_interval_s = 1.0;
  StereoRenderer r(w, camera(e));
  // The schedule: levels within +-2 steps, one step at a time, roughly one per interval, the two
  // cameras independent.
  int steps = 0, differ = 0;
  double prev = 1.0;
  for (double t = 0.0; t < 100.0; t += 0.01)
  {
    const double g = r.autoExposureGain(0, t);
    const double level = std::log(g) / std::log(1.2);
    EXPECT_NEAR(level, std::round(level), 1e-9);
    EXPECT_LE(std::abs(std::round(level)), 2.0);
    if (g != prev)
    {
      ++steps;
      EXPECT_NEAR(std::abs(std::log(g / prev) / std::log(1.2)), 1.0, 1e-9) << t;
    }
    prev = g;
    differ += r.autoExposureGain(1, t) != g;
  }
  EXPECT_GT(steps, 60);
  EXPECT_LT(steps, 140);
  EXPECT_GT(differ, 1000);
  EXPECT_EQ(r.autoExposureGain(0, 0.0), 1.0);
  // The image equals the same render with the gain scaled by the schedule, exactly.
  for (double t : {0.0, 7.3, 23.9, 61.2})
  {
    RenderOutput a, b;
    r.render(levelPose(), t, 0, a);
    CameraParams p = camera();
    p.gain = r.autoExposureGain(0, t);
    StereoRenderer ref(w, p);
    ref.render(levelPose(), t, 0, b);
    EXPECT_EQ(cv::norm(a.left, b.left, cv::NORM_INF), 0.0) << "t " << t;
  }
}

TEST(CameraErrors, RandomDrawIsInsideTheRangesAndDeterministicPerSeed)
{
  double ea = 0, eb = 0;
  const CameraErrors a = CameraErrors::random(5, &ea), b = CameraErrors::random(5, &eb);
  const CameraErrors c = CameraErrors::random(6);
  EXPECT_EQ(a.json(ea), b.json(eb));
  EXPECT_NE(a.json(ea), c.json(ea));
  for (uint32_t s = 1; s <= 50; ++s)
  {
    double ex = 0;
    const CameraErrors e = CameraErrors::random(s, &ex);
    EXPECT_TRUE(e.any());
    EXPECT_LE(std::abs(e.baseline_scale), 0.01);
    EXPECT_LE(std::abs(e.focal_scale), 0.005);
    EXPECT_LE(e.right_rotation.cwiseAbs().maxCoeff(), 0.1 * M_PI / 180 + 1e-12);
    EXPECT_LE(std::abs(e.k1), 0.005);
    EXPECT_GE(e.rolling_shutter_s, 0.010);
    EXPECT_LE(e.rolling_shutter_s, 0.033);
    EXPECT_GE(e.ae_step, 0.05);
    EXPECT_LE(e.ae_step, 0.20);
    EXPECT_GE(ex, 0.002);
    EXPECT_LE(ex, 0.012);
  }
  EXPECT_FALSE(CameraErrors().any());
}
