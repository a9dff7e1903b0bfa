#include <assistive_description/params.h>

namespace assistive_description
{
std::vector<std::string> StereoCameraParams::clamp()
{
  std::vector<std::string> msgs = assistive_common::clampToTable(*this);
  if (layout != "side_by_side" && layout != "interleaved")
  {
    msgs.push_back("layout = '" + layout + "' is neither side_by_side nor interleaved, using side_by_side");
    layout = "side_by_side";
  }
  if (emitter != "none" && emitter != "alternate")
  {
    msgs.push_back("emitter = '" + emitter + "' is neither none nor alternate, using none");
    emitter = "none";
  }
  if (width % 2 != 0 && layout == "side_by_side")  // within [2, 8192] an odd width becomes the even one above it
  {
    msgs.push_back("width = " + std::to_string(width) + " is odd (two equal halves needed), using " +
                   std::to_string(width + 1));
    width += 1;
  }
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
