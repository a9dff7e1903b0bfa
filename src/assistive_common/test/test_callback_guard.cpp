// guarded(): an exception thrown while handling a message is logged and swallowed; the next
// message is handled.
#include <gtest/gtest.h>

#include <stdexcept>

#include <opencv2/core.hpp>
#include <ros/time.h>

#include "assistive_common/callback_guard.h"

TEST(CallbackGuard, SwallowsExceptionsAndReportsThem)
{
  ros::Time::init();  // the throttled log reads the clock
  int handled = 0;
  EXPECT_TRUE(assistive_common::guarded("test", "message", [&] { ++handled; }));
  EXPECT_FALSE(assistive_common::guarded("test", "message", [] { throw std::runtime_error("bad frame"); }));
  // OpenCV's own error type (an assertion on a malformed image)
  EXPECT_FALSE(assistive_common::guarded("test", "image", [] {
    cv::Mat a(4, 4, CV_8UC1), b(5, 5, CV_8UC1), c;
    cv::add(a, b, c);  // size mismatch: cv::Exception
  }));
  EXPECT_FALSE(assistive_common::guarded("test", "message", [] { throw 42; }));
  EXPECT_TRUE(assistive_common::guarded("test", "message", [&] { ++handled; }));
  EXPECT_EQ(handled, 2);
}
