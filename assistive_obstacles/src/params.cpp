#include <assistive_obstacles/params.h>

namespace assistive_obstacles
{
std::vector<std::string> clampParams(ObstaclesParams& p)
{
  std::vector<std::string> m = assistive_common::clampToTable(p);
  if (p.disparity_method != "sgbm3way" && p.disparity_method != "sgbm" && p.disparity_method != "hh" &&
      p.disparity_method != "hh4" && p.disparity_method != "bm")
  {
    m.push_back("disparity_method '" + p.disparity_method + "' unknown, using sgbm3way");
    p.disparity_method = "sgbm3way";
  }
  if (p.block_size % 2 == 0)  // within [1, 21] an even size becomes the odd one above it
  {
    m.push_back("block_size must be odd, using " + std::to_string(p.block_size + 1));
    ++p.block_size;
  }
  return m;
}

}  // namespace assistive_obstacles
