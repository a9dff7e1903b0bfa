#include "assistive_tactile/params.h"

#include "assistive_tactile/serial_port.h"

namespace assistive_tactile
{
std::vector<std::string> clampParams(BridgeParams& p)
{
  std::vector<std::string> m = assistive_common::clampToTable(p);
  unsigned int speed = 0;
  if (!baudToSpeed(p.baud, &speed))
  {
    m.push_back("baud " + std::to_string(p.baud) + " unsupported, using 57600");
    p.baud = 57600;
  }
  return m;
}
}  // namespace assistive_tactile
