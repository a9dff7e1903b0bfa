#include <gtest/gtest.h>
#include "assistive_vo/imu_buffer.h"

using namespace assistive_vo;

TEST(ImuBuffer, IntegratesConstantRateExactly)
{
  ImuBuffer b;
  const Eigen::Vector3d w(0.0, 0.0, 0.5);  // 0.5 rad/s yaw, 200 Hz
  for (int i = 0; i <= 200; ++i)
    b.add(i * 0.005, w, Eigen::Vector3d(0, 0, 9.81));
  Eigen::Quaterniond q;
  ASSERT_TRUE(b.integrate(0.1013, 0.1680, q));  // between samples at both ends
  const Eigen::AngleAxisd aa(q);
  EXPECT_NEAR(aa.angle(), 0.5 * (0.1680 - 0.1013), 1e-12);
  EXPECT_NEAR(aa.axis().z(), 1.0, 1e-12);
  Eigen::Vector3d a;
  double span = -1.0;
  ASSERT_TRUE(b.meanAccel(0.5, 0.2, a, &span));
  EXPECT_TRUE(a.isApprox(Eigen::Vector3d(0, 0, 9.81)));
  EXPECT_NEAR(span, 0.2, 0.011);  // the samples of [0.3, 0.5]: what the window really covers
  EXPECT_FALSE(b.integrate(0.9, 1.5, q));  // beyond the samples
  EXPECT_FALSE(b.integrate(0.5, 0.4, q));  // backwards
}

TEST(ImuBuffer, LinearRateAndBagLoop)
{
  ImuBuffer b;
  for (int i = 0; i <= 100; ++i)
    b.add(i * 0.01, Eigen::Vector3d(0.0, 2.0 * i * 0.01, 0.0), Eigen::Vector3d::Zero());
  Eigen::Quaterniond q;
  ASSERT_TRUE(b.integrate(0.2, 0.6, q));
  // integral of 2t dt from 0.2 to 0.6 = 0.32
  EXPECT_NEAR(Eigen::AngleAxisd(q).angle(), 0.32, 1e-12);
  b.add(0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());  // time went backwards: cleared
  EXPECT_FALSE(b.integrate(0.2, 0.6, q));
  b.add(1.0, Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d::Zero());  // NaN ignored
  Eigen::Vector3d a;
  ASSERT_TRUE(b.meanAccel(2.0, 5.0, a));
  EXPECT_TRUE(a.allFinite());
}

TEST(ImuBuffer, MeanRateOverAWindowAroundAStamp)
{
  ImuBuffer b;
  for (int i = 0; i <= 100; ++i)  // 200 Hz, rate rising 1 rad/s^2 about y
    b.add(i * 0.005, Eigen::Vector3d(0.0, i * 0.005, 0.0), Eigen::Vector3d::Zero());
  Eigen::Vector3d w;
  ASSERT_TRUE(b.meanRate(0.3, 0.03, w));  // samples 0.285 .. 0.315
  EXPECT_NEAR(w.y(), 0.3, 1e-9);
  ASSERT_TRUE(b.meanRate(0.5, 0.03, w));  // only the half before the newest sample
  EXPECT_NEAR(w.y(), 0.4925, 1e-9);
  EXPECT_FALSE(b.meanRate(0.7, 0.03, w));
}
