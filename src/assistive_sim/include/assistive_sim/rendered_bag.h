// Test support for the stages' rostests: a short bag rendered by `rosrun assistive_sim render_bag`
// into a fresh temporary folder that is removed with the object, also when an assertion ends the
// test early (each rendering is 35-45 MB; folders left behind per run once filled the disk of a
// machine that ran the tests many times). Header-only, so a stage's test needs only this package's
// include directory, never its libraries.
#pragma once

#include <stdlib.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace assistive_sim
{
class RenderedBag
{
public:
  /// Renders `frames` of `world` (a shipped world's name or a world file) into a folder named
  /// `<tmp>/<tag>_XXXXXX`; path() is empty when render_bag failed, and log() says why. A passive
  /// camera unless `active` (render_bag's default, the reference camera: issue 35's emitter-on
  /// pairs on /stereo/projected too, twice the rendering).
  RenderedBag(const std::string& world, int frames, const std::string& tag = "rendered_bag", bool active = false)
  {
    std::string tmpl = (std::filesystem::temp_directory_path() / (tag + "_XXXXXX")).string();
    if (!mkdtemp(tmpl.data()))
      return;
    dir_ = tmpl;
    std::string name = std::filesystem::path(world).stem().string();
    const std::string bag = dir_ + "/" + name + ".bag";
    const std::string render = "rosrun assistive_sim render_bag --world " + world + " --frames " +
                               std::to_string(frames) + (active ? "" : " --passive") + " --out " + bag + " > " + dir_ +
                               "/render.log 2>&1";
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
  /// render_bag's output (the folder goes with the object, so a failing test prints this text).
  std::string log() const
  {
    std::ifstream in(dir_ + "/render.log");
    std::ostringstream text;
    text << in.rdbuf();
    return dir_.empty() ? "no temporary folder" : text.str();
  }

private:
  std::string dir_, path_;
};
}  // namespace assistive_sim
