// VoFrontEnd: the VO's driving loop of the nodelet and the benchmarks (issue 32), on exact
// synthetic data: a rendered walk with the head pitched down and a 200 Hz IMU that measures the
// true rotation rate and gravity.
#include <gtest/gtest.h>
#include <cmath>
#include <vector>
#include "assistive_vo/frames.h"
#include "assistive_vo/vo_front_end.h"
#include "synthetic.h"

using namespace assistive_vo;

// The tests and their helpers in a named namespace: the core's tests are one unity build, where
// anonymous namespaces meet.
namespace front_end_test
{
constexpr double kFrameDt = 1.0 / 15.0, kImuDt = 1.0 / 200.0;
constexpr double kT0 = 100.0;  // stamp of the walk's t = 0 (the loops take a stamp of 0 as "none yet")
constexpr double kYawRate = 6.0 * M_PI / 180.0;  // rad/s about the world's vertical
constexpr double kPitch = 15.0 * M_PI / 180.0;   // head pitched down

/// A small camera: the rendering, not the VO, is what costs here.
StereoCamera smallCamera()
{
  StereoCamera c = test::makeCamera();
  c.fx = c.fy = 250.0;
  c.cx = 159.5;
  c.cy = 119.5;
  c.width = 320;
  c.height = 240;
  return c;
}

/// The left optical frame at time t in the truth's world (the first optical frame unpitched: x
/// right, y down, z forward): walking forward at 0.9 m/s while turning, head pitched down.
Eigen::Isometry3d truePose(double t)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(kYawRate * t, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(-kPitch, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.06 * t, 0.0, 0.9 * t);
  return T;
}

/// The IMU of that walk in camera_link axes: a constant rotation rate, and gravity alone (no
/// linear acceleration).
struct ImuSample
{
  double t;
  Eigen::Vector3d gyro, accel;
};
ImuSample imuAt(double t)
{
  const Eigen::Matrix3d R_lo = R_link_optical();
  const Eigen::Matrix3d R_w_link = truePose(t).linear() * R_lo.transpose();
  ImuSample s;
  s.t = t;
  s.gyro = R_w_link.transpose() * (kYawRate * Eigen::Vector3d(0, 1, 0));
  s.accel = R_w_link.transpose() * Eigen::Vector3d(0, -9.81, 0);
  return s;
}
std::vector<ImuSample> imuBetween(double from, double to)
{
  std::vector<ImuSample> v;
  for (int j = static_cast<int>(std::ceil(from / kImuDt - 1e-9)); j * kImuDt <= to + 1e-12; ++j)
    v.push_back(imuAt(j * kImuDt));
  return v;
}

struct Walk
{
  StereoCamera cam = smallCamera();
  test::PlaneWorld world;
  cv::Mat left(double t) const { return world.render(cam, truePose(t), false); }
  cv::Mat right(double t) const { return world.render(cam, truePose(t), true); }
};

/// Tilt (deg) between the pose's up and the truth's at time t.
double tiltErrDeg(const VoOutput& o, double t)
{
  const Eigen::Vector3d est = o.T_odom_link.linear().transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d tru = imuAt(t).accel.normalized();
  return std::acos(std::clamp(est.dot(tru), -1.0, 1.0)) * 180.0 / M_PI;
}

// The front end hands VisualOdometry exactly what the nodelet's own loop did before it moved into
// the core (its code, verbatim, below): the same start, gyro and accelerometer integrals and
// gravity hints, hence bit-identical poses on every frame.
TEST(VoFrontEnd, ReachesVisualOdometryAsTheNodeletDid)
{
  Walk w;
  const int n = 12;
  // The IMU starts with the images: the hint needs 0.3 s of samples, so the first frames go without.
  const std::vector<ImuSample> imu = imuBetween(0.0, n * kFrameDt);

  // The nodelet's loop before issue 32 (nodelet.cpp, stereo()), with its defaults.
  std::vector<VoOutput> ref;
  {
    VisualOdometry vo((VoParams()));
    ImuBuffer buf;  // keep_s 2
    StartupRule::Options so;
    so.expect_imu = true;
    so.wait_s = 1.0;
    StartupRule startup(so);
    double last_stamp = -1.0;
    size_t next = 0;
    for (int k = 0; k < n; ++k)
    {
      const double t = k * kFrameDt;
      for (; next < imu.size() && imu[next].t <= t + 1e-9; ++next)
        buf.add(kT0 + imu[next].t, imu[next].gyro, imu[next].accel);
      if (k == 0)
        vo.setCamera(w.cam);
      if (!vo.started())
      {
        Eigen::Vector3d up;
        const StartupRule::Decision d = startup.decide(kT0 + t, buf, up);
        if (d == StartupRule::Decision::START_WITH_GRAVITY)
          vo.setInitialUp(up);
        else if (d == StartupRule::Decision::WAIT_FOR_IMU)
          continue;
      }
      Eigen::Quaterniond gyro;
      Eigen::Vector3d dv, dp;
      bool have_gyro = false;
      if (!buf.empty() && last_stamp > 0 && kT0 + t > last_stamp)
        have_gyro = buf.integrate(last_stamp, kT0 + t, gyro, dv, dp);
      last_stamp = kT0 + t;
      Eigen::Vector3d up;
      double span = 0.0;
      if (buf.meanAccel(kT0 + t, 0.5, up, &span) && span >= 0.3 && up.norm() > 5.0 && up.norm() < 15.0)
        vo.setGravityHint(up);
      ref.push_back(vo.process(w.left(t), w.right(t), kT0 + t, have_gyro ? &gyro : nullptr, have_gyro ? &dv : nullptr,
                               have_gyro ? &dp : nullptr));
    }
  }
  ASSERT_EQ(ref.size(), static_cast<size_t>(n)) << "the IMU came with the first image: no frame waits";

  VoFrontEnd fe;
  size_t next = 0;
  int hints = 0, gyros = 0;
  for (int k = 0; k < n; ++k)
  {
    const double t = k * kFrameDt;
    for (; next < imu.size() && imu[next].t <= t + 1e-9; ++next)
      fe.addImu(kT0 + imu[next].t, imu[next].gyro, imu[next].accel);
    const FrontEndStep s = fe.process(w.cam, w.left(t), w.right(t), kT0 + t);
    ASSERT_TRUE(s.processed);
    EXPECT_EQ(s.startup_decided, k == 0);
    if (k == 0)
    {
      EXPECT_EQ(s.startup, StartupRule::Decision::START_WITH_GRAVITY);
    }
    EXPECT_FALSE(s.camera_changed);
    // a gyro prior from the second frame on; a hint once the samples span 0.3 s (frame 5 at 0.333 s)
    EXPECT_EQ(s.have_gyro, k >= 1) << "frame " << k;
    EXPECT_EQ(s.gravity_hint, t >= 0.3) << "frame " << k;
    hints += s.gravity_hint;
    gyros += s.have_gyro;
    if (s.have_gyro)  // the gyro integral is the true rotation (constant rate, exact to rounding)
    {
      const Eigen::Matrix3d R_lo = R_link_optical();
      const Eigen::Matrix3d R_true =
          R_lo * truePose(t - kFrameDt).linear().transpose() * truePose(t).linear() * R_lo.transpose();
      EXPECT_LT(Eigen::AngleAxisd(s.gyro.toRotationMatrix().transpose() * R_true).angle(), 1e-9) << "frame " << k;
    }
    EXPECT_EQ(s.out.state, ref[k].state) << "frame " << k;
    EXPECT_EQ(s.out.pose_trusted, ref[k].pose_trusted) << "frame " << k;
    EXPECT_TRUE(s.out.T_odom_link.matrix() == ref[k].T_odom_link.matrix()) << "frame " << k << ":\n"
                                                                           << s.out.T_odom_link.matrix() << "\nvs\n"
                                                                           << ref[k].T_odom_link.matrix();
    EXPECT_TRUE(s.out.pose_covariance == ref[k].pose_covariance) << "frame " << k;
    // the odom frame took gravity from the accelerometer and keeps it
    EXPECT_LT(tiltErrDeg(s.out, t), 0.2) << "frame " << k;
  }
  EXPECT_EQ(hints, 7);
  EXPECT_EQ(gyros, n - 1);
  EXPECT_EQ(fe.vo().resets(), 0);
}

// Images before the IMU: the frames wait (VisualOdometry never sees them), then the first frame
// with an IMU sample fixes the odom frame by gravity: the pitched head's tilt, not a level camera.
TEST(VoFrontEnd, WaitsForTheImuThenStartsWithGravity)
{
  Walk w;
  VoFrontEnd fe;
  const double imu_from = 0.15;  // the IMU's first sample comes after the third image
  const std::vector<ImuSample> imu = imuBetween(imu_from, 1.0);
  size_t next = 0;
  int waited = 0;
  for (int k = 0; k < 6; ++k)
  {
    const double t = k * kFrameDt;
    for (; next < imu.size() && imu[next].t <= t + 1e-9; ++next)
      fe.addImu(kT0 + imu[next].t, imu[next].gyro, imu[next].accel);
    const FrontEndStep s = fe.process(w.cam, w.left(t), w.right(t), kT0 + t);
    if (t < imu_from)
    {
      EXPECT_FALSE(s.processed) << "frame " << k;
      EXPECT_EQ(s.startup, StartupRule::Decision::WAIT_FOR_IMU);
      EXPECT_FALSE(fe.vo().started());
      EXPECT_NEAR(fe.startup().waited(kT0 + t), t, 1e-12);
      ++waited;
      continue;
    }
    ASSERT_TRUE(s.processed) << "frame " << k;
    if (waited == k)  // the first processed frame
    {
      EXPECT_TRUE(s.startup_decided);
      EXPECT_EQ(s.startup, StartupRule::Decision::START_WITH_GRAVITY);
      EXPECT_FALSE(s.have_gyro);  // no previous frame
      // its pose: gravity from the accelerometer (exact here), on the floor under the camera
      EXPECT_LT(tiltErrDeg(s.out, t), 1e-6);
      EXPECT_NEAR(s.out.T_odom_link.translation().z(), VoParams().camera_height_m, 1e-12);
      const Eigen::Isometry3d start = startPoseFromUp(imuAt(t).accel, VoParams().camera_height_m);
      EXPECT_LT((s.out.T_odom_link.linear() - start.linear()).norm(), 1e-12);
    }
    else
    {
      EXPECT_FALSE(s.startup_decided);
      EXPECT_TRUE(s.have_gyro);
      EXPECT_LT(tiltErrDeg(s.out, t), 0.2);
    }
  }
  EXPECT_EQ(waited, 3);
}

// No IMU within imu_wait: the odom frame starts from initial_roll / initial_pitch (level here);
// input without an IMU, or use_imu off, starts at once and never integrates or hints.
TEST(VoFrontEnd, StartsWithoutTheImuAfterTheWaitOrAtOnce)
{
  Walk w;
  const cv::Mat l = w.left(0.0), r = w.right(0.0);
  {
    VoFrontEnd::Options o;
    o.imu_wait_s = 0.25;
    VoFrontEnd fe(VoParams(), o);
    for (int k = 0; k <= 4; ++k)
    {
      const double t = k * kFrameDt;
      const FrontEndStep s = fe.process(w.cam, l, r, kT0 + t);
      EXPECT_EQ(s.processed, k == 4) << "frame " << k;  // 4/15 s >= 0.25 s waited
      EXPECT_EQ(s.startup, k == 4 ? StartupRule::Decision::START_WITHOUT_IMU : StartupRule::Decision::WAIT_FOR_IMU);
      if (s.processed)  // level start (initial_roll = initial_pitch = 0)
      {
        EXPECT_LT((s.out.T_odom_link.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
      }
    }
  }
  VoFrontEnd::Options no_imu_input;
  no_imu_input.input_has_imu = false;
  VoParams no_imu;
  no_imu.use_imu = false;
  const std::vector<std::pair<VoParams, VoFrontEnd::Options>> cases{{VoParams(), no_imu_input},
                                                                    {no_imu, VoFrontEnd::Options()}};
  for (const auto& [p, o] : cases)
  {
    VoFrontEnd fe(p, o);
    for (const ImuSample& s : imuBetween(0.0, 0.2))
      fe.addImu(kT0 + s.t, s.gyro, s.accel);  // samples given anyway: used only with use_imu
    FrontEndStep s = fe.process(w.cam, l, r, kT0);
    EXPECT_TRUE(s.processed);
    EXPECT_EQ(s.startup, StartupRule::Decision::START_WITHOUT_IMU);
    s = fe.process(w.cam, w.left(kFrameDt), w.right(kFrameDt), kT0 + kFrameDt);
    EXPECT_EQ(s.have_gyro, p.use_imu) << "use_imu " << p.use_imu;
    EXPECT_EQ(s.gravity_hint, false);  // the samples span 0.067 s only, or use_imu is off
  }
}

// A changed calibration re-initialises tracking (reported; the first one is no change), and a
// stamp older than the last frame is reported and gets no gyro integral.
TEST(VoFrontEnd, ReportsCalibrationChangesAndTimeGoingBack)
{
  Walk w;
  VoFrontEnd::Options o;
  o.input_has_imu = false;
  VoFrontEnd fe(VoParams(), o);
  FrontEndStep s = fe.process(w.cam, w.left(0.0), w.right(0.0), 1.0);
  EXPECT_FALSE(s.camera_changed);
  EXPECT_FALSE(s.time_went_back);
  s = fe.process(w.cam, w.left(kFrameDt), w.right(kFrameDt), 1.0 + kFrameDt);
  EXPECT_FALSE(s.camera_changed);
  StereoCamera other = w.cam;
  other.baseline = 0.1;
  s = fe.process(other, w.left(2 * kFrameDt), w.right(2 * kFrameDt), 1.0 + 2 * kFrameDt);
  EXPECT_TRUE(s.camera_changed);
  EXPECT_TRUE(fe.vo().camera().baseline == 0.1);
  s = fe.process(other, w.left(3 * kFrameDt), w.right(3 * kFrameDt), 0.5);
  EXPECT_TRUE(s.time_went_back);
  EXPECT_FALSE(s.have_gyro);
  EXPECT_FALSE(s.out.pose_trusted);
}

// A gap in the image stream (frames dropped) while the IMU runs on: the next frame gets the gyro
// and accelerometer integrals over the whole gap while it is within imu_keep_s (the core bridges
// it within imu_coast_max_s), none beyond.
TEST(VoFrontEnd, HandsTheImuOverAGapWithinWhatItKeeps)
{
  const VoFrontEnd::Options o;
  ASSERT_GE(o.imu_keep_s, VoParams().imu_coast_max_s);
  for (const double gap : {2.4, o.imu_keep_s + 0.2})
  {
    const Walk w;
    const double t_end = 1.0 + gap;
    const std::vector<ImuSample> imu = imuBetween(0.0, t_end);
    VoFrontEnd fe;
    size_t next = 0;
    FrontEndStep s;
    for (const double t : {0.0, 1.0 / 15, 2.0 / 15, 1.0, t_end})
    {
      for (; next < imu.size() && imu[next].t <= t + 1e-9; ++next)
        fe.addImu(kT0 + imu[next].t, imu[next].gyro, imu[next].accel);
      s = fe.process(w.cam, w.left(t), w.right(t), kT0 + t);
      ASSERT_TRUE(s.processed);
    }
    EXPECT_EQ(s.have_gyro, gap <= o.imu_keep_s) << "gap " << gap;
    if (s.have_gyro)  // the integral over the whole gap is the true rotation
    {
      const Eigen::Matrix3d R_lo = R_link_optical();
      const Eigen::Matrix3d R_true =
          R_lo * truePose(1.0).linear().transpose() * truePose(t_end).linear() * R_lo.transpose();
      EXPECT_LT(Eigen::AngleAxisd(s.gyro.toRotationMatrix().transpose() * R_true).angle(), 1e-9);
      // no linear acceleration: dv is gravity's alone, dp half of it times the gap
      const Eigen::Vector3d up_link = imuAt(1.0).accel;
      EXPECT_LT((s.dv - up_link * gap).norm(), 1e-6 * gap);
    }
    EXPECT_EQ(fe.vo().failSafe().gaps, 1);
  }
}
}  // namespace front_end_test
