#include <assistive_description/params.h>

#include <sstream>

namespace assistive_description
{
namespace
{
template <typename T>
void clampValue(const char* name, T& value, T lo, T hi, std::vector<std::string>& msgs)
{
  // NaN fails both comparisons: treat it as out of range.
  if (value >= lo && value <= hi) return;
  T fixed = value < lo ? lo : hi;
  if (!(value == value)) fixed = lo;
  std::ostringstream s;
  s << name << " = " << value << " is outside [" << lo << ", " << hi << "], using " << fixed;
  msgs.push_back(s.str());
  value = fixed;
}
}  // namespace

std::vector<std::string> StereoCameraParams::clamp()
{
  std::vector<std::string> msgs;
  clampValue("width", width, 2, 8192, msgs);
  if (width % 2 != 0)
  {
    msgs.push_back("width = " + std::to_string(width) + " is odd (two equal halves needed), using " +
                   std::to_string(width + 1));
    width += 1;
  }
  clampValue("height", height, 1, 8192, msgs);
  clampValue("fps", fps, 0.5, 240.0, msgs);
  clampValue("retry_period", retry_period, 0.1, 3600.0, msgs);
  clampValue("time_offset", time_offset, -1.0, 1.0, msgs);
  clampValue("synthetic_disparity", synthetic_disparity, 0.0, width / 4.0, msgs);
  if (fourcc.size() != 4)
  {
    msgs.push_back("fourcc = '" + fourcc + "' is not 4 characters, using MJPG");
    fourcc = "MJPG";
  }
  if (device.empty())
  {
    msgs.push_back("device is empty, using /dev/video0");
    device = "/dev/video0";
  }
  return msgs;
}

}  // namespace assistive_description
