// Trajectory metrics on trajectories with known, injected errors.
#include <assistive_eval/metrics.h>
#include <assistive_eval/trajectory.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

using namespace assistive_eval;

namespace
{
constexpr double DEG = M_PI / 180.0;

Eigen::Isometry3d makePose(const Eigen::Vector3d& t, double yaw, double pitch = 0.0, double roll = 0.0)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = t;
  return T;
}

/// A walk on a curved 3D path with head scans: 200 frames at 10 Hz.
Trajectory curvedWalk()
{
  Trajectory tr;
  for (int i = 0; i < 200; ++i)
  {
    const double s = 0.1 * i;
    StampedPose sp;
    sp.t = 100.0 + s;
    sp.pose = makePose(Eigen::Vector3d(1.2 * s, 3.0 * std::sin(0.2 * s), 1.6 + 0.03 * std::sin(6.0 * s)),
                       0.4 * std::sin(0.5 * s), 0.2 * std::sin(0.3 * s), 0.05 * std::cos(s));
    tr.push_back(sp);
  }
  return tr;
}
}  // namespace

TEST(Alignment, KnownOffsetAndRotationIsRecoveredAndAteIsZero)
{
  const Trajectory gt = curvedWalk();
  // The estimate lives in another world frame: est = T_off^-1 * gt.
  const Eigen::Isometry3d T_off = makePose(Eigen::Vector3d(3.0, -2.0, 0.5), 30.0 * DEG, 5.0 * DEG, -3.0 * DEG);
  Trajectory est = gt;
  for (auto& sp : est)
    sp.pose = T_off.inverse() * sp.pose;

  // Without alignment the error is the offset.
  EXPECT_GT(ape(gt, est, AlignMode::NONE).rmse, 1.0);

  Alignment a;
  const ErrorStats s = ape(gt, est, AlignMode::SE3, &a);
  EXPECT_EQ(s.n, gt.size());
  EXPECT_NEAR(s.rmse, 0.0, 1e-9);
  EXPECT_NEAR(s.max, 0.0, 1e-9);
  EXPECT_NEAR(a.scale, 1.0, 1e-12);
  EXPECT_TRUE(a.transform.isApprox(T_off, 1e-9)) << a.transform.matrix() << "\nvs\n" << T_off.matrix();

  // First-pose alignment recovers it too (orientations included).
  const Alignment f = computeAlignment(gt, est, AlignMode::FIRST_POSE);
  EXPECT_TRUE(f.transform.isApprox(T_off, 1e-9));
  const Trajectory aligned = applyAlignment(est, f);
  for (size_t i = 0; i < gt.size(); i += 37)
    EXPECT_TRUE(aligned[i].pose.isApprox(gt[i].pose, 1e-9));
}

TEST(Alignment, Sim3RecoversScale)
{
  const Trajectory gt = curvedWalk();
  const Eigen::Isometry3d T_off = makePose(Eigen::Vector3d(-1.0, 4.0, 0.2), -70.0 * DEG);
  Trajectory est = gt;
  for (auto& sp : est)
  {
    sp.pose = T_off.inverse() * sp.pose;
    sp.pose.translation() *= 0.5;  // monocular-like scale
  }
  EXPECT_GT(ape(gt, est, AlignMode::SE3).rmse, 0.5);
  Alignment a;
  EXPECT_NEAR(ape(gt, est, AlignMode::SIM3, &a).rmse, 0.0, 1e-9);
  EXPECT_NEAR(a.scale, 2.0, 1e-9);
  EXPECT_TRUE(a.transform.linear().isApprox(T_off.linear(), 1e-9));
}

TEST(Ate, KnownConstantOffsetGivesThatRmseWithoutAlignment)
{
  const Trajectory gt = curvedWalk();
  Trajectory est = gt;
  for (size_t i = 0; i < est.size(); ++i)
    est[i].pose.translation() += Eigen::Vector3d(0.0, (i % 2) ? 0.3 : -0.3, 0.4);  // |e| = 0.5 each
  const ErrorStats s = ape(gt, est, AlignMode::NONE);
  EXPECT_NEAR(s.rmse, 0.5, 1e-12);
  EXPECT_NEAR(s.std, 0.0, 1e-12);
  EXPECT_NEAR(s.sse, 0.25 * gt.size(), 1e-9);
}

TEST(Drift, KnownScaleDriftReadsExactlyK)
{
  // Straight walk along x at 1.2 m/s, 10 Hz, head scanning in yaw; the estimate's distances are
  // 3 % too long.
  const double k = 3.0;
  Trajectory gt, est;
  for (int i = 0; i < 300; ++i)
  {
    StampedPose sp;
    sp.t = 0.1 * i;
    sp.pose = makePose(Eigen::Vector3d(0.12 * i, 0.0, 1.6), 0.5 * std::sin(0.05 * i));
    gt.push_back(sp);
    sp.pose.translation().x() *= (1.0 + k / 100.0);
    est.push_back(sp);
  }
  const DriftResult d = segmentDrift(gt, est, {1.0, 2.0, 5.0, 10.0});
  ASSERT_EQ(d.per_length.size(), 4u);
  EXPECT_NEAR(d.drift_pct, k, 1e-9);
  EXPECT_NEAR(d.drift_deg_per_m, 0.0, 1e-6);
  for (const auto& s : d.per_length)
  {
    EXPECT_NEAR(s.t_err_pct, k, 1e-9) << s.length_m;
    EXPECT_GT(s.segments, 0u);
  }
  // 10 m segments: start frames 0..(299 - 84): the end frame is the first at >= 10 m (84 steps of 0.12 m).
  EXPECT_EQ(d.per_length[3].segments, 300u - 84u);
  EXPECT_NEAR(endpointDriftPct(gt, est), k, 1e-9);
  const TrajectoryReport r = evaluateTrajectory(gt, est);
  EXPECT_NEAR(r.drift.drift_pct, k, 1e-9);
  EXPECT_NEAR(r.endpoint_drift_pct, k, 1e-9);
  EXPECT_NEAR(r.path_length_m, 0.12 * 299, 1e-9);
}

TEST(Drift, KnownRotationDriftReadsDegPerMetre)
{
  // The estimate turns 0.5 deg more per metre walked than the truth (a pure heading drift).
  Trajectory gt, est;
  for (int i = 0; i < 200; ++i)
  {
    StampedPose sp;
    sp.t = 0.1 * i;
    sp.pose = makePose(Eigen::Vector3d(0.1 * i, 0.0, 0.0), 0.0);
    gt.push_back(sp);
  }
  // integrate the estimate: each 0.1 m step, then a rotation of 0.05 deg about z (body)
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 200; ++i)
  {
    StampedPose sp = gt[i];
    sp.pose = T;
    est.push_back(sp);
    T = T * makePose(Eigen::Vector3d(0.1, 0.0, 0.0), 0.0) * makePose(Eigen::Vector3d::Zero(), 0.05 * DEG);
  }
  const DriftResult d = segmentDrift(gt, est, {5.0});
  ASSERT_EQ(d.per_length.size(), 1u);
  EXPECT_NEAR(d.drift_deg_per_m, 0.5, 1e-6);
  // all of it about the up axis
  EXPECT_NEAR(d.drift_deg_per_m_yaw, 0.5, 1e-6);
  EXPECT_NEAR(d.drift_deg_per_m_tilt, 0.0, 1e-9);
}

TEST(Drift, TiltDriftIsSplitFromYaw)
{
  // The estimate rolls 0.3 deg per metre about its forward axis (x): tilt, no yaw.
  Trajectory gt, est;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 200; ++i)
  {
    StampedPose sp;
    sp.t = 0.1 * i;
    sp.pose = makePose(Eigen::Vector3d(0.1 * i, 0.0, 0.0), 0.0);
    gt.push_back(sp);
    sp.pose = T;
    est.push_back(sp);
    Eigen::Isometry3d roll = Eigen::Isometry3d::Identity();
    roll.linear() = Eigen::AngleAxisd(0.03 * DEG, Eigen::Vector3d::UnitX()).toRotationMatrix();
    T = T * makePose(Eigen::Vector3d(0.1, 0.0, 0.0), 0.0) * roll;
  }
  const DriftResult d = segmentDrift(gt, est, {5.0});
  EXPECT_NEAR(d.drift_deg_per_m, 0.3, 1e-6);
  EXPECT_NEAR(d.drift_deg_per_m_tilt, 0.3, 1e-6);
  EXPECT_NEAR(d.drift_deg_per_m_yaw, 0.0, 1e-9);
}

TEST(Tilt, AbsoluteTiltIsSeenAndYawIsNot)
{
  // The estimate's world is tilted 0.4 deg about x and turned 30 deg about up: the tilt error is
  // 0.4 deg on every frame, whatever the pose; a pure turn of the world gives none.
  const Trajectory gt = curvedWalk();
  Eigen::Isometry3d tilt = Eigen::Isometry3d::Identity(), turn = Eigen::Isometry3d::Identity();
  tilt.linear() = Eigen::AngleAxisd(0.4 * DEG, Eigen::Vector3d::UnitX()).toRotationMatrix();
  turn.linear() = Eigen::AngleAxisd(30 * DEG, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Trajectory tilted(gt), turned(gt);
  for (size_t i = 0; i < gt.size(); ++i)
  {
    tilted[i].pose = tilt * turn * gt[i].pose;
    turned[i].pose = turn * gt[i].pose;
  }
  for (double e : tiltErrorsDeg(gt, tilted))
    EXPECT_NEAR(e, 0.4, 1e-9);
  for (double e : tiltErrorsDeg(gt, turned))
    EXPECT_NEAR(e, 0.0, 1e-6);
  EXPECT_NEAR(evaluateTrajectory(gt, tilted).tilt_deg.max, 0.4, 1e-9);
  // a segment metric does not see a constant tilt
  EXPECT_LT(segmentDrift(gt, tilted, {1.0}).drift_deg_per_m, 1e-6);
}

TEST(GyroOnly, KnownBiasIsRecoveredAndRemoved)
{
  // A gyro that reads the true rotation plus a constant bias: the bias is found, and the chained,
  // corrected gyro reproduces the true orientation (no drift). Without the correction it drifts.
  const Trajectory gt = curvedWalk();
  const Eigen::Vector3d b(0.003, -0.001, 0.002);  // rad/s, body frame
  std::vector<Eigen::Matrix3d> rel(gt.size(), Eigen::Matrix3d::Identity());
  for (size_t i = 1; i < gt.size(); ++i)
  {
    const Eigen::Vector3d bdt = b * (gt[i].t - gt[i - 1].t);
    rel[i] = gt[i - 1].pose.linear().transpose() * gt[i].pose.linear() *
             Eigen::AngleAxisd(bdt.norm(), bdt.normalized()).toRotationMatrix();
  }
  Eigen::Vector3d found;
  const Trajectory g = gyroOnlyTrajectory(gt, rel, &found);
  ASSERT_EQ(g.size(), gt.size());
  EXPECT_LT((found - b).norm(), 1e-9);
  EXPECT_LT(segmentDrift(gt, g, {1.0, 5.0}).drift_deg_per_m, 1e-6);
  for (size_t i = 0; i < gt.size(); ++i)
    EXPECT_LT((g[i].pose.translation() - gt[i].pose.translation()).norm(), 1e-12);

  // Angle random walk on top: the floor is positive and grows with the noise.
  std::vector<Eigen::Matrix3d> noisy(rel), noisier(rel);
  uint32_t state = 12345;
  auto gauss = [&state]() {  // Box-Muller on a small LCG: deterministic on every platform
    auto u = [&state]() {
      state = state * 1664525u + 1013904223u;
      return (static_cast<double>(state >> 8) + 0.5) / 16777216.0;
    };
    const double u1 = u(), u2 = u();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  };
  for (size_t i = 1; i < gt.size(); ++i)
  {
    const Eigen::Vector3d w(gauss(), gauss(), gauss());
    const Eigen::Vector3d e = w * 1e-3;  // rad per frame
    noisy[i] = rel[i] * Eigen::AngleAxisd(e.norm(), e.normalized()).toRotationMatrix();
    noisier[i] = rel[i] * Eigen::AngleAxisd(3 * e.norm(), e.normalized()).toRotationMatrix();
  }
  const double d1 = segmentDrift(gt, gyroOnlyTrajectory(gt, noisy), {1.0, 5.0}).drift_deg_per_m;
  const double d3 = segmentDrift(gt, gyroOnlyTrajectory(gt, noisier), {1.0, 5.0}).drift_deg_per_m;
  EXPECT_GT(d1, 1e-3);
  EXPECT_GT(d3, 2.0 * d1);

  // Unusable input: sizes differ.
  rel.pop_back();
  EXPECT_TRUE(gyroOnlyTrajectory(gt, rel).empty());
}

TEST(MaxJump, SingleFrameJumpIsFound)
{
  const Trajectory gt = curvedWalk();
  Trajectory est = gt;
  for (size_t i = 120; i < est.size(); ++i)
    est[i].pose.translation() += Eigen::Vector3d(0.0, 0.3, 0.4);  // a 0.5 m jump at frame 120
  EXPECT_NEAR(maxErrorJump(gt, est), 0.5, 1e-9);
  EXPECT_NEAR(maxErrorJump(gt, gt), 0.0, 1e-12);
}

TEST(YawBands, ErrorInjectedOnlyInFastBandShowsOnlyThere)
{
  // 10 Hz; yaw rates 2, 10, 25, 45 deg/s for 40 frame pairs each, while walking.
  const double rates[4] = {2.0, 10.0, 25.0, 45.0};
  Trajectory gt, est;
  double yaw_gt = 0.0, yaw_est = 0.0;
  int i = 0;
  for (int b = 0; b < 4; ++b)
    for (int k = 0; k < 40; ++k, ++i)
    {
      StampedPose g;
      g.t = 0.1 * i;
      // the optical frame (z forward) of a head with yaw about world z: R = Rz(yaw) * linkToOptical
      g.pose = makePose(Eigen::Vector3d(0.1 * i, 0.0, 1.6), yaw_gt) * linkToOptical();
      StampedPose e = g;
      e.pose = makePose(Eigen::Vector3d(0.1 * i, 0.0, 1.6), yaw_est) * linkToOptical();
      gt.push_back(g);
      est.push_back(e);
      yaw_gt += rates[b] * 0.1 * DEG;
      yaw_est += rates[b] * 0.1 * DEG + (b == 3 ? 0.5 * DEG : 0.0);  // error only while fast
    }
  const auto bands = yawErrorByBand(gt, est);
  ASSERT_EQ(bands.size(), 4u);
  EXPECT_EQ(bands[0].name, "lt5");
  EXPECT_EQ(bands[1].name, "5_20");
  EXPECT_EQ(bands[2].name, "20_30");
  EXPECT_EQ(bands[3].name, "gt30");
  // frame pairs: the transition pair between two bands moves at the earlier band's rate
  EXPECT_EQ(bands[0].pairs, 40u);
  EXPECT_EQ(bands[1].pairs, 40u);
  EXPECT_EQ(bands[2].pairs, 40u);
  EXPECT_EQ(bands[3].pairs, 39u);
  for (int b = 0; b < 3; ++b)
    EXPECT_NEAR(bands[b].mean_err_deg, 0.0, 1e-9) << bands[b].name;
  EXPECT_NEAR(bands[3].mean_err_deg, 0.5, 1e-9);
  EXPECT_NEAR(bands[3].err_pct_of_rotation, 100.0 * 0.5 / 4.5, 1e-6);
  EXPECT_NEAR(bands[3].err_deg_per_s, 5.0, 1e-6);
  EXPECT_NEAR(bands[2].true_rotation_deg, 40 * 2.5, 1e-6);
}

TEST(Rpe, ConsecutivePairsByEstimatePath)
{
  // Straight line, 1 m per frame in the estimate, truth 0.9 m per frame: with delta 3 m the marks
  // are at frames 3, 6, 9 (path reset at each), pairs (3,6) and (6,9), each with error 0.3 m.
  Trajectory gt, est;
  for (int i = 0; i < 11; ++i)
  {
    StampedPose sp;
    sp.t = i;
    sp.pose.translation() = Eigen::Vector3d(0.9 * i, 0, 0);
    gt.push_back(sp);
    sp.pose.translation() = Eigen::Vector3d(1.0 * i, 0, 0);
    est.push_back(sp);
  }
  const auto e = rpeTranslationErrors(gt, est, 3.0);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_NEAR(e[0], 0.3, 1e-12);
  EXPECT_NEAR(e[1], 0.3, 1e-12);
}

TEST(Association, TumGreedyAndEvoNearest)
{
  using Pair = std::pair<size_t, size_t>;
  Trajectory a, b;
  for (double t : {0.0, 1.0, 2.0, 3.0})
  {
    StampedPose sp;
    sp.t = t;
    a.push_back(sp);
  }
  for (double t : {0.004, 0.009, 1.015, 2.5, 3.001, 3.002})
  {
    StampedPose sp;
    sp.t = t;
    b.push_back(sp);
  }
  // greedy, < 0.02: 0<->0.004, 1<->1.015, 3<->3.001 (each stamp used once)
  const auto g = associate(a, b, 0.02, AssociationMethod::TUM_GREEDY);
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[0], Pair(0u, 0u));
  EXPECT_EQ(g[1], Pair(1u, 2u));
  EXPECT_EQ(g[2], Pair(3u, 4u));
  // evo, <= 0.01: the shorter trajectory (a) looks up its nearest stamp in b
  const auto e = associate(a, b, 0.01, AssociationMethod::EVO_NEAREST);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0], Pair(0u, 0u));
  EXPECT_EQ(e[1], Pair(3u, 4u));
}

TEST(Files, TumAndKittiRoundTripAndErrorsNameTheLine)
{
  const Trajectory gt = curvedWalk();
  const std::string tum = testing::TempDir() + "/traj_roundtrip.tum";
  const std::string kit = testing::TempDir() + "/traj_roundtrip.kitti";
  writeTum(tum, gt);
  writeKitti(kit, gt);
  const Trajectory a = readTum(tum), b = readKitti(kit);
  ASSERT_EQ(a.size(), gt.size());
  ASSERT_EQ(b.size(), gt.size());
  for (size_t i = 0; i < gt.size(); i += 19)
  {
    EXPECT_NEAR(a[i].t, gt[i].t, 1e-9);
    EXPECT_TRUE(a[i].pose.isApprox(gt[i].pose, 1e-7));
    EXPECT_TRUE(b[i].pose.isApprox(gt[i].pose, 1e-7));
  }
  const std::string bad = testing::TempDir() + "/traj_bad.tum";
  {
    std::ofstream f(bad);
    f << "# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 zero 0 0 0 1\n";
  }
  try
  {
    readTum(bad);
    FAIL() << "no exception";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readTum(testing::TempDir() + "/does_not_exist.txt"), std::runtime_error);
  std::remove(tum.c_str());
  std::remove(kit.c_str());
  std::remove(bad.c_str());
}

TEST(Report, JsonUsesNullForUnmeasured)
{
  Trajectory one(1);
  const TrajectoryReport r = evaluateTrajectory(one, one);
  const std::string j = reportJson(r);
  EXPECT_NE(j.find("\"drift_pct\": null"), std::string::npos) << j;
  EXPECT_EQ(j.find("nan"), std::string::npos) << j;
}
