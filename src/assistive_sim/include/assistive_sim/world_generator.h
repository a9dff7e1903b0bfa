#pragma once
// Random world generator: layouts nobody tuned for (office, lobby, corridor, hall, street, home,
// shop), with furniture, materials from bare to rich, and a collision-free walk, written as world
// YAML text in the format of README.md "World files" and checked by the world parser. Ordinary
// passages (issue 33): the doorways the walk uses are 0.80-0.90 m clear, halls and aisles
// 1.2-1.5 m, objects left in them leave 0.80-0.95 m. Deterministic per seed (std::mt19937 seeded
// with the seed; no clock). ROS-free.
#include <cstdint>
#include <string>
#include <vector>

#include <assistive_sim/world.h>

namespace assistive_sim
{
/// A passage the generator made narrow on purpose (issue 33), as drawn: a `doorway` (any opening
/// in a wall; `entrance` for a shop's wide one), a `hall` or an `aisle`, or the `gap` an object
/// left in a hall or an aisle leaves. Its clear width is measured from `center` along +-`across`.
struct GeneratedPassage
{
  std::string what;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  Eigen::Vector2d across = Eigen::Vector2d::UnitX();  ///< unit vector across the passage
  double width = 0.0;                                 ///< m, clear width as drawn
};

/// One generated world: its YAML text and the same text parsed.
struct GeneratedWorld
{
  std::string kind;
  std::string yaml;
  World world;
  int elements = 0;          ///< entries of `elements:`
  double walk_length = 0.0;  ///< m, length of the waypoint polyline
  int people = 0;            ///< entries of `people:` (fewer than asked when no clear crossing was found)
  std::vector<GeneratedPassage> passages;  ///< the doorways, halls, aisles and gaps it made
};

class WorldGenerator
{
public:
  /// The layout kinds, in the order `--kind` lists them.
  static const std::vector<std::string>& kinds();

  /// `kind` empty: chosen by the seed among the first five kinds (`kinds()[seed % 5]`, as before
  /// `home` and `shop` existed). Throws std::invalid_argument for an unknown kind.
  /// `people` > 0 adds that many people whose walks cross the generated walk (README
  /// "generate_world"); 0 gives the same bytes as before people existed.
  WorldGenerator(uint32_t seed, const std::string& kind = "", int people = 0);

  /// Build the world. Throws std::runtime_error if no clear walk was found (not seen for seeds
  /// 1-20 of any kind, nor seeds 1001-1030 of home and shop).
  GeneratedWorld generate() const;

  const std::string& kind() const { return kind_; }

  /// Pale (issue 35): the kind's texture richness cut to a fifth (below 0.2: bare paint, plain
  /// floors and furniture: what passive stereo cannot see). The layout differs from the same
  /// seed's ordinary one (the materials draw from the same generator); named gen_<kind>_pale_<seed>.
  void setPale(bool pale) { pale_ = pale; }

private:
  uint32_t seed_;
  std::string kind_;
  int people_ = 0;
  bool pale_ = false;
};

}  // namespace assistive_sim
