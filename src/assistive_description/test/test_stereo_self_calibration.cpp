// The right camera's rotation estimated online (issue 36), against exact synthetic answers: features
// projected through a rotated, distorted right camera, and images of a textured floor warped by it.
#include <assistive_description/stereo_camera.h>
#include <assistive_description/stereo_self_calibration.h>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdlib>
#include <random>

using namespace assistive_description;

namespace
{
constexpr double kSelfCalDeg = M_PI / 180.0;
constexpr double kSelfCalBaseline = 0.12;

RectifiedModel selfCalModel()
{
  RectifiedModel m;
  m.fx = m.fy = 500.0;
  m.cx = 319.5;
  m.cy = 239.5;
  return m;
}

// Normalised ideal coordinates -> where a camera with residual radial distortion k1 shows them
// (the renderer's model: pixel p sees the ray p (1 + k1 |p|^2)), by fixed-point iteration.
cv::Vec2d selfCalDistort(const cv::Vec2d& q, double k1)
{
  cv::Vec2d p = q;
  for (int i = 0; i < 20; ++i)
    p = q * (1.0 / (1.0 + k1 * p.dot(p)));
  return p;
}

// One frame of features: points 1-8 m ahead anywhere in the view, seen by the ideal left camera
// and by a right camera rotated by w (its pixel p sees the rig's ray R(w) p), both with k1.
std::vector<StereoSelfCalibration::Observation> selfCalFrame(const cv::Vec3d& w, double k1, double noise_px,
                                                             std::mt19937& rng, int n = 200)
{
  const RectifiedModel m = selfCalModel();
  cv::Matx33d R;
  cv::Rodrigues(w, R);
  std::uniform_real_distribution<double> ux(-0.62, 0.62), uy(-0.46, 0.46), uz(1.0, 8.0);
  std::normal_distribution<double> px(0.0, noise_px);
  std::vector<StereoSelfCalibration::Observation> out;
  for (int i = 0; i < n; ++i)
  {
    const double z = uz(rng);
    const cv::Vec3d P(ux(rng) * z, uy(rng) * z, z);
    const cv::Vec3d ray_r = R.t() * (P - cv::Vec3d(kSelfCalBaseline, 0, 0));
    const cv::Vec2d ql(P[0] / P[2], P[1] / P[2]), qr(ray_r[0] / ray_r[2], ray_r[1] / ray_r[2]);
    const cv::Vec2d pl = selfCalDistort(ql, k1), pr = selfCalDistort(qr, k1);
    if (std::abs(pr[0]) > 0.64 || std::abs(pr[1]) > 0.48)
      continue;
    StereoSelfCalibration::Observation o;
    o.x = pl[0];
    o.y = pl[1];
    o.delta = pl[0] - pr[0];
    o.dv_px = (pr[1] - pl[1]) * m.fy + px(rng);
    out.push_back(o);
  }
  return out;
}

// A floor-like scene: brightness of a smooth random texture at plane coordinates (a, b).
cv::Mat selfCalTexture(std::mt19937& rng)
{
  cv::Mat t(512, 512, CV_32F);
  cv::RNG cv_rng(rng());  // seeded here: OpenCV's global generator depends on the tests run before
  cv_rng.fill(t, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(t, t, cv::Size(0, 0), 1.5);
  cv::normalize(t, t, 0, 255, cv::NORM_MINMAX);
  return t;
}

// The image of a camera at (bx, 0, 0) looking along z, rotated by R, at a plane y = 1.5 - 0.1 z
// (a sloping floor) and a wall z = 9 beyond it, textured by `tex` (mono8).
cv::Mat selfCalRender(const cv::Mat& tex, double bx, const cv::Matx33d& R)
{
  const RectifiedModel m = selfCalModel();
  cv::Mat img(480, 640, CV_8UC1);
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u)
    {
      const cv::Vec3d d = R * cv::Vec3d((u - m.cx) / m.fx, (v - m.cy) / m.fy, 1.0);
      double s = 9.0 / d[2];                    // the wall
      const double floor_s = 1.5 / (d[1] + 0.1 * d[2]);
      if (floor_s > 0 && floor_s < s)
        s = floor_s;
      const cv::Vec3d X = s * d + cv::Vec3d(bx, 0, 0);
      const double a = 60.0 * X[0] + 256.0, b = 60.0 * (X[1] + X[2]);
      const float val = tex.at<float>(std::clamp(static_cast<int>(std::fmod(std::abs(b), 511.0)), 0, 511),
                                      std::clamp(static_cast<int>(std::fmod(std::abs(a), 511.0)), 0, 511));
      img.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(val);
    }
  return img;
}

// The pitched-and-rolled rig of the image tests: the left image, the ideal right one and the one
// the rotated right camera sees.
struct SelfCalScene
{
  cv::Mat left, right_ideal, right;
};

SelfCalScene selfCalScene(unsigned seed)
{
  std::mt19937 rng(seed);
  const cv::Mat tex = selfCalTexture(rng);
  cv::Matx33d R;
  cv::Rodrigues(cv::Vec3d(0.15 * kSelfCalDeg, 0.0, -0.10 * kSelfCalDeg), R);
  return {selfCalRender(tex, 0.0, cv::Matx33d::eye()), selfCalRender(tex, kSelfCalBaseline, cv::Matx33d::eye()),
          selfCalRender(tex, kSelfCalBaseline, R)};
}
}  // namespace

// Pitch 0.08, yaw -0.06, roll 0.1 deg and residual distortion 0.003, features at 0.05 px noise:
// the rotation comes out within 0.005 deg on every axis (the yaw through the image's corners; the
// distortion's term looks like the yaw's in a scene at one depth, and its prior pulls it to 0),
// and it is applied.
TEST(StereoSelfCalibration, RecoversTheRightCamerasRotationFromVerticalOffsets)
{
  std::mt19937 rng(7);
  const cv::Vec3d w(0.08 * kSelfCalDeg, -0.06 * kSelfCalDeg, 0.10 * kSelfCalDeg);
  StereoSelfCalibration cal;
  for (int f = 0; f < 60; ++f)
    cal.addObservations(selfCalFrame(w - cal.applied(), 0.003, 0.05, rng), selfCalModel(), cv::Size(640, 480));
  ASSERT_TRUE(cal.valid());
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_NEAR(cal.rotation()[k] / kSelfCalDeg, w[k] / kSelfCalDeg, 0.005) << "axis " << k;
    EXPECT_LT(cal.rotationSigma()[k] / kSelfCalDeg, 0.004) << "axis " << k;
  }
  EXPECT_NEAR(cal.k1(), 0.003, 0.003);
  EXPECT_GT(cv::norm(cal.applied()), 0.0) << cal.status();
}

// A perfect rig stays untouched: features with noise only give an estimate within its
// uncertainty and a shift under min_shift_px, so nothing is applied.
TEST(StereoSelfCalibration, APerfectRigStaysUntouched)
{
  std::mt19937 rng(11);
  StereoSelfCalibration cal;
  for (int f = 0; f < 100; ++f)
    cal.addObservations(selfCalFrame(cv::Vec3d::all(0), 0.0, 0.08, rng), selfCalModel(), cv::Size(640, 480));
  ASSERT_TRUE(cal.valid());
  EXPECT_EQ(cal.applied(), cv::Vec3d::all(0)) << cal.status();
  EXPECT_FALSE(cal.status().empty());
}

// Measured on images already corrected, the estimate stays the absolute rotation: after the first
// correction the residual offsets are small and the estimate does not walk back towards zero.
TEST(StereoSelfCalibration, TheEstimateStaysAbsoluteOnceACorrectionIsApplied)
{
  std::mt19937 rng(3);
  const cv::Vec3d w(0.12 * kSelfCalDeg, 0.05 * kSelfCalDeg, -0.09 * kSelfCalDeg);
  StereoSelfCalibration cal;
  for (int f = 0; f < 150; ++f)
    // The rotation left in the corrected images: w less what is applied (small angles compose).
    cal.addObservations(selfCalFrame(w - cal.applied(), 0.0, 0.05, rng), selfCalModel(), cv::Size(640, 480));
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(cal.applied()[k] / kSelfCalDeg, w[k] / kSelfCalDeg, 0.005) << "axis " << k;
}

// An early estimate off by 0.03 deg of yaw (a first correction taken from a few poor frames) is not
// kept once better frames come: a corrected axis follows its estimate (the floor gates only
// whether an axis is corrected at all).
TEST(StereoSelfCalibration, AnEarlyCorrectionFollowsTheBetterEstimate)
{
  std::mt19937 rng(13);
  const cv::Vec3d w(0.06 * kSelfCalDeg, 0.08 * kSelfCalDeg, -0.05 * kSelfCalDeg);
  const cv::Vec3d early_error(0.0, 0.03 * kSelfCalDeg, 0.0);
  StereoSelfCalibration cal;
  for (int f = 0; f < 20; ++f)
    cal.addObservations(selfCalFrame(w + early_error - cal.applied(), 0.0, 0.05, rng), selfCalModel(),
                        cv::Size(640, 480));
  EXPECT_NEAR(cal.applied()[1] / kSelfCalDeg, 0.11, 0.005) << cal.status();
  for (int f = 0; f < 150; ++f)
    cal.addObservations(selfCalFrame(w - cal.applied(), 0.0, 0.05, rng), selfCalModel(), cv::Size(640, 480));
  EXPECT_NEAR(cal.applied()[1] / kSelfCalDeg, 0.08, 0.006) << cal.status();
}

// Mismatches (a fifth of the features 0.5-3 px off) do not move the estimate.
TEST(StereoSelfCalibration, MismatchesAreGatedOut)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> off(0.5, 3.0);
  const cv::Vec3d w(-0.1 * kSelfCalDeg, 0.0, 0.07 * kSelfCalDeg);
  StereoSelfCalibration cal;
  for (int f = 0; f < 60; ++f)
  {
    auto obs = selfCalFrame(w - cal.applied(), 0.0, 0.05, rng);
    for (size_t i = 0; i < obs.size(); i += 5)
      obs[i].dv_px += (i % 2 ? 1 : -1) * off(rng);
    cal.addObservations(obs, selfCalModel(), cv::Size(640, 480));
  }
  EXPECT_NEAR(cal.rotation()[0] / kSelfCalDeg, -0.1, 0.005);
  EXPECT_NEAR(cal.rotation()[2] / kSelfCalDeg, 0.07, 0.005);
}

// Images: a floor and a wall seen by a right camera pitched 0.15 deg and rolled -0.1 deg (rows
// 1.3 px apart at the left edge). The matcher finds the offsets, the estimate comes out within
// 0.02 deg, and the corrected right image equals the ideal one within interpolation.
TEST(StereoSelfCalibration, ImagesOfARotatedRightCameraAreCorrected)
{
  const SelfCalScene scene = selfCalScene(1);
  const cv::Mat &left = scene.left, &right_ideal = scene.right_ideal, &right = scene.right;
  StereoSelfCalibration::Options o;
  o.every_n_frames = 1;
  o.min_frames = 3;
  StereoSelfCalibration cal(o);
  const auto obs = cal.match(left, right, selfCalModel());
  ASSERT_GE(obs.size(), 40u);  // min_inliers
  cv::Mat corrected;
  for (int f = 0; f < 5; ++f)
  {
    cal.correctRight(right, corrected, selfCalModel());
    cal.addFrame(left, corrected, selfCalModel());
  }
  EXPECT_NEAR(cal.rotation()[0] / kSelfCalDeg, 0.15, 0.02);
  EXPECT_NEAR(cal.rotation()[2] / kSelfCalDeg, -0.10, 0.02);
  cal.correctRight(right, corrected, selfCalModel());
  const cv::Rect inner(20, 20, 600, 440);
  cv::Mat diff_before, diff_after;
  cv::absdiff(right(inner), right_ideal(inner), diff_before);
  cv::absdiff(corrected(inner), right_ideal(inner), diff_after);
  EXPECT_LT(cv::mean(diff_after)[0], 0.5 * cv::mean(diff_before)[0]);
}

// The estimate reads the images and never writes them (the brightness matching works on a copy).
TEST(StereoSelfCalibration, LeavesItsInputImagesAlone)
{
  std::mt19937 rng(2);
  const cv::Mat tex = selfCalTexture(rng);
  const cv::Mat left = selfCalRender(tex, 0.0, cv::Matx33d::eye());
  cv::Mat right = selfCalRender(tex, kSelfCalBaseline, cv::Matx33d::eye());
  right *= 0.8;  // the right camera exposed darker
  const cv::Mat left_before = left.clone(), right_before = right.clone();
  StereoSelfCalibration cal;
  cal.addFrame(left, right, selfCalModel());
  EXPECT_EQ(cv::norm(left, left_before, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(right, right_before, cv::NORM_INF), 0.0);
}

namespace
{
// Side-by-side frames of one rendered pair, as a camera delivers them.
class SelfCalPairSource : public FrameSource
{
public:
  cv::Mat frame;
  double stamp = 0.0;
  bool open() override { return open_ = true; }
  bool read(cv::Mat& f, double& s) override
  {
    f = frame;
    s = stamp += 1.0 / 15.0;
    return true;
  }
  void close() override { open_ = false; }
  bool isOpen() const override { return open_; }
  std::string describe() const override { return "self-calibration pair"; }

private:
  bool open_ = false;
};

CameraCalibration selfCalCalibration(double tx)
{
  const RectifiedModel m = selfCalModel();
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.D = {0, 0, 0, 0, 0};
  c.K = cv::Matx33d(m.fx, 0, m.cx, 0, m.fy, m.cy, 0, 0, 1);
  c.P = cv::Matx34d(m.fx, 0, m.cx, tx, 0, m.fy, m.cy, 0, 0, 0, 1, 0);
  return c;
}
}  // namespace

// The driver: a rig whose right camera is pitched 0.15 deg and rolled -0.1 deg against its
// calibration. Within 30 frames the correction is folded into the right rectification map (the
// change reported, to be kept), and the right images it publishes come out nearer the ideal rig's.
TEST(StereoSelfCalibration, TheDriverUndoesTheRotationInItsRightMap)
{
  const SelfCalScene scene = selfCalScene(4);
  const cv::Mat& right_ideal = scene.right_ideal;
  auto source = std::make_unique<SelfCalPairSource>();
  cv::hconcat(scene.left, scene.right, source->frame);
  StereoCameraParams p;
  p.width = 1280;
  p.height = 480;
  p.self_calibration_every = 1;
  StereoCamera cam(std::move(source), p);
  ASSERT_TRUE(cam.setCalibration(selfCalCalibration(0.0), selfCalCalibration(-500.0 * kSelfCalBaseline)));
  ASSERT_NE(cam.selfCalibration(), nullptr);
  StereoOutput out;
  ASSERT_EQ(cam.grab(0.0, out), GrabStatus::OK);
  ASSERT_TRUE(out.rectified);
  const cv::Rect inner(20, 20, 600, 440);
  cv::Mat diff;
  cv::absdiff(out.right_rect(inner), right_ideal(inner), diff);
  const double before = cv::mean(diff)[0];
  int changes = 0;
  for (int i = 0; i < 30; ++i)
  {
    ASSERT_EQ(cam.grab(0.0, out), GrabStatus::OK);
    cam.selfCalibrate(out);
    changes += cam.takeSelfCalibrationChange();
  }
  EXPECT_GE(changes, 1);
  EXPECT_LE(changes, 2);  // a refinement once the first correction is in
  EXPECT_NEAR(cam.selfCalibration()->applied()[0] / kSelfCalDeg, 0.15, 0.02);
  EXPECT_NEAR(cam.selfCalibration()->applied()[2] / kSelfCalDeg, -0.10, 0.02);
  cv::absdiff(out.right_rect(inner), right_ideal(inner), diff);
  EXPECT_LT(cv::mean(diff)[0], 0.5 * before);
}

// Kept per camera: read back as written; another camera's file is refused.
TEST(StereoSelfCalibration, TheCorrectionIsKeptPerCamera)
{
  const cv::Vec3d w(0.05 * kSelfCalDeg, -0.03 * kSelfCalDeg, 0.02 * kSelfCalDeg);
  StereoSelfCalibration cal;
  cal.setApplied(w);
  const char* tmp = std::getenv("TEST_TMPDIR");
  const std::string path = std::string(tmp ? tmp : "/tmp") + "/self_calibration_test_right.yaml";
  std::string err;
  ASSERT_TRUE(saveSelfCalibration(path, "right", cal, &err)) << err;
  cv::Vec3d back;
  ASSERT_TRUE(loadSelfCalibration(path, "right", back, &err)) << err;
  EXPECT_LT(cv::norm(back - w), 1e-9);
  EXPECT_FALSE(loadSelfCalibration(path, "another_right", back, &err));
  EXPECT_NE(err.find("another_right"), std::string::npos);
  EXPECT_FALSE(loadSelfCalibration(path + ".missing", "right", back, &err));
}
