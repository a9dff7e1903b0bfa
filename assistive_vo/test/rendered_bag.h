// Test support for the VO rostests: a short bag rendered by assistive_sim's render_bag into a fresh
// temporary folder that is removed when the test is done (each rendering is 35-45 MB; a folder left
// behind per run filled the disk of a machine that ran the tests many times).
#pragma once

#include <stdlib.h>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace assistive_vo_test
{
class RenderedBag
{
public:
  /// Renders `frames` of `world`; path() is empty when render_bag failed (its log is in the folder).
  RenderedBag(const std::string& world, int frames)
  {
    std::string tmpl = (std::filesystem::temp_directory_path() / "vo_rostest_XXXXXX").string();
    if (!mkdtemp(tmpl.data()))
      return;
    dir_ = tmpl;
    const std::string bag = dir_ + "/" + world + ".bag";
    const std::string render = "rosrun assistive_sim render_bag --world " + world + " --frames " +
                               std::to_string(frames) + " --out " + bag + " > " + dir_ + "/render.log 2>&1";
    if (std::system(render.c_str()) == 0)
      path_ = bag;
  }
  ~RenderedBag()
  {
    std::error_code ec;
    if (!dir_.empty())
      std::filesystem::remove_all(dir_, ec);
  }
  RenderedBag(const RenderedBag&) = delete;
  RenderedBag& operator=(const RenderedBag&) = delete;
  const std::string& path() const { return path_; }

private:
  std::string dir_, path_;
};
}  // namespace assistive_vo_test
