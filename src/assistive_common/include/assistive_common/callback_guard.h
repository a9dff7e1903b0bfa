#pragma once
// Callback hygiene: an exception thrown while handling one message (a malformed image that makes
// OpenCV throw, a bad_alloc on an absurd size, ...) must not unwind into the nodelet manager's
// thread, which would stop every nodelet in it, the vest bridge included.
#include <exception>
#include <string>

#include <ros/console.h>

namespace assistive_common
{
/// Runs `fn()`; an exception it throws (cv::Exception derives from std::exception) is logged as
/// an error at most every 5 s under the logger `name` (the nodelet's getName()), naming `what`
/// was being handled, and swallowed: that message is dropped, the next one is handled. Returns
/// false when `fn` threw.
template <class F>
bool guarded(const std::string& name, const char* what, F&& fn)
{
  try
  {
    fn();
    return true;
  }
  catch (const std::exception& e)
  {
    ROS_ERROR_THROTTLE_NAMED(5.0, name, "%s: %s failed, dropped: %s", name.c_str(), what, e.what());
  }
  catch (...)
  {
    ROS_ERROR_THROTTLE_NAMED(5.0, name, "%s: %s failed, dropped: unknown exception", name.c_str(), what);
  }
  return false;
}
}  // namespace assistive_common
