#pragma once
// Simulated worlds: materials, solids (boxes, cylinders, glass), the wearer's script, parsed from
// a world YAML file (format in README.md "World files"). ROS-free.
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <assistive_sim/types.h>

namespace assistive_sim
{
/// Thrown for unreadable or malformed world files; what() names the file, line and field.
class WorldError : public std::runtime_error
{
public:
  explicit WorldError(const std::string& what) : std::runtime_error(what) {}
};

/// Procedural surface pattern.
enum class Pattern
{
  PLAIN,   ///< uniform (bare wall); `contrast` adds faint noise
  NOISE,   ///< multi-octave value noise
  BRICKS,  ///< staggered bricks with mortar
  TILES,   ///< square tiles with grout lines
  POSTERS  ///< plain wall with scattered posters (blobs, letters, stripes)
};

struct Material
{
  std::string name;
  Pattern pattern = Pattern::NOISE;
  double albedo = 0.5;     ///< mean reflectance 0..1
  double contrast = 0.5;   ///< amount of texture 0 (bare) .. 1
  double scale = 0.2;      ///< m, typical feature size (brick length, tile size, noise blob)
  uint32_t seed = 1;
};

/// A solid prism: a box (yawed rectangle footprint) or a vertical cylinder, from z0 to z1.
struct Solid
{
  enum Shape { BOX, CYLINDER } shape = BOX;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  ///< m
  Eigen::Vector2d half = Eigen::Vector2d(0.5, 0.5);  ///< m, box half sizes along its own x/y
  double radius = 0.2;  ///< m (cylinder)
  double yaw = 0.0;     ///< rad (box)
  double z0 = 0.0, z1 = 1.0;  ///< m
  int material = 0;
  bool walkable = false;  ///< steps / curbs: raise the floor instead of blocking
  bool glass = false;     ///< see-through panel (rendered as its mid plane)
  bool glazing = false;   ///< opaque part of a glass element: frame, rail or manifestation band
  double reflectance = 0.12;  ///< glass only
  std::string source;     ///< e.g. "elements[3] (table)", for messages

  /// Does the solid's footprint overlap the axis-aligned square [x0,x1]x[y0,y1]?
  bool overlapsRect(double x0, double y0, double x1, double y1) const;
  /// Is the ground point (x, y) inside the footprint?
  bool containsXY(double x, double y, double inflate = 0.0) const;
};

/// Scripted head turn: the yaw offset of the head moves by `yaw` (rad) starting at `at` (s after
/// the walk starts) with a smooth (quintic) profile whose peak rate is `rate` (rad/s).
struct HeadTurn
{
  double at = 0.0;
  double yaw = 0.0;
  double rate = 0.1;
};

/// The wearer's script.
struct TrajectoryScript
{
  std::vector<Eigen::Vector2d> waypoints;  ///< m, floor positions the walk follows in order
  int loops = 1;                 ///< walk the (closed) waypoint loop this many times
  double speed = 1.1;            ///< m/s cruise walking speed (0.8 .. 1.4)
  double speed_variation = 0.06;  ///< relative +- modulation of the speed
  double eye_height = 1.6;       ///< m, camera height above the floor
  double start_still = 1.0;      ///< s standing still before walking
  double corner_radius = 0.8;    ///< m, rounding of waypoint corners
  double turn_on_spot_above = 100.0 * M_PI / 180.0;  ///< rad, sharper corners: stop and turn on the spot
  double turn_rate = 60.0 * M_PI / 180.0;            ///< rad/s, peak rate of a turn on the spot
  double max_walk_turn_rate = 180.0 * M_PI / 180.0;  ///< rad/s, tighter rounded corners: stop and turn
  double pitch_min = 10.0 * M_PI / 180.0;  ///< rad, head pitch down range
  double pitch_max = 30.0 * M_PI / 180.0;
  double scan_amplitude = 8.0 * M_PI / 180.0;  ///< rad, background yaw scanning
  double scan_period = 7.0;                    ///< s
  double bob_amplitude = 0.025;   ///< m, vertical gait bob
  double sway_amplitude = 0.02;   ///< m, lateral gait sway
  double step_length = 0.65;      ///< m per step
  std::vector<HeadTurn> head_turns;  ///< explicit turns (rates in rad/s)
  bool auto_head_turns = true;    ///< add seeded slow/medium/fast turns and jerks
};

/// Where a person walks beside its script while giving way to the wearer (issue 37; people_give_way.h):
/// an offset on the floor (m) at each time, linear between the knots, the first before them and the
/// last after them. Filled in as a trial runs; shared by every copy of the Person, so the collider
/// and the planner's truth see the same person.
struct GiveWayTrack
{
  std::vector<double> t;
  std::vector<Eigen::Vector2d> offset;
  std::vector<double> delay;  ///< s its script runs behind the clock (it stood waiting that long)
  /// The offset at time `t`, and its rate (m/s) when `rate` is given; the delay and its rate (0:
  /// walking, 1: standing) when `delay` / `delay_rate` are given.
  Eigen::Vector2d at(double t, Eigen::Vector2d* rate = nullptr, double* delay = nullptr,
                     double* delay_rate = nullptr) const;
  /// A knot at time `t` after the last one (false, nothing added: `t` not after it, or a value not
  /// finite: a NaN knot would put the person nowhere from then on; the track only grows).
  bool append(double t, const Eigen::Vector2d& offset, double delay);
};

/// A walking (or standing) person (issue 22, README "World files": `people:`). Every kind of
/// script is expanded at parse time into a timed polyline (knots), so personAt() is a pure
/// function of the time. People are movers, not solids: they are rendered and heard by the ranger
/// at a frame's time, but never enter the static truth grid (computeOccupancy).
struct Person
{
  enum Kind { WALK, RANDOM_WALK, STAND } kind = STAND;
  std::string name;        ///< for messages (default "people[i]")
  double radius = 0.22;    ///< m, body (cylinder) radius = the footprint radius
  double height = 1.75;    ///< m, top of the head above the floor
  int material = 0;        ///< clothing texture
  /// Position knots: the person is at knot_p[k] at knot_t[k] and walks straight (constant
  /// velocity) to the next knot; equal consecutive points = standing. Before knot_t[0] the person
  /// stands at knot_p[0]; after the last knot they stand there (period == 0) or the knots repeat
  /// with `period` (loops and back-and-forth walks: the last knot equals the first).
  std::vector<double> knot_t;
  std::vector<Eigen::Vector2d> knot_p;
  double period = 0.0;     ///< s, > 0: periodic after knot_t[0]
  double stand_yaw = 0.0;  ///< rad, facing while standing before the first move (and of STAND)
  std::vector<double> seg_yaw;  ///< rad, facing from knot k to k + 1 (the last walking direction while standing)
  std::string source;      ///< "people[2]", for messages
  /// Giving way to the wearer (none: the script alone, as in every bag and world file).
  std::shared_ptr<GiveWayTrack> give_way;
};

/// A person's body as rendered: a cylinder of `radius` from the floor to the shoulders
/// (height - PERSON_HEAD_HEIGHT) and the head, a cylinder of PERSON_HEAD_RADIUS x radius, above.
constexpr double PERSON_HEAD_HEIGHT = 0.25;  ///< m
constexpr double PERSON_HEAD_RADIUS = 0.45;  ///< of the body's radius

/// Where a person is at time t (s on the walk's clock, 0 = the wearer's script starts).
struct PersonState
{
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< m, floor point under the body's axis
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< m/s
  double yaw = 0.0;                                     ///< rad, facing (the walking direction)
};

/// A whole world.
struct World
{
  std::string name;
  std::string description;
  std::vector<Material> materials;
  std::vector<Solid> solids;
  Eigen::Vector2d floor_min = Eigen::Vector2d(-5, -5), floor_max = Eigen::Vector2d(5, 5);
  int floor_material = 0;
  bool has_ceiling = false;
  double ceiling_height = 2.7;
  int ceiling_material = 0;
  double sky_brightness = 0.75;  ///< radiance of rays that hit nothing
  /// Ambient light on the scene (lux): `sky: {illuminance}`; < 0 (unset): 300 under a ceiling
  /// (an office's lighting), 10,000 in the open (daylight). A camera's exposure follows it, so it
  /// sets how strongly a pattern projector's dots show (ambientLux()).
  double illuminance_lux = -1.0;
  double ambientLux() const { return illuminance_lux > 0.0 ? illuminance_lux : has_ceiling ? 300.0 : 10000.0; }
  Eigen::Vector3d light_dir = Eigen::Vector3d(0.3, 0.2, 1.0).normalized();  ///< towards the light
  TrajectoryScript trajectory;
  std::vector<Person> people;  ///< movers (issue 22); empty in static worlds

  /// Parse a world YAML file; throws WorldError "<file>:<line>: <field>: <problem>".
  static World load(const std::string& path);
  /// Parse YAML text (`origin` names it in messages).
  static World parse(const std::string& yaml_text, const std::string& origin = "<string>");

  /// Floor height under (x, y): the top of the highest walkable solid there, else 0.
  double floorHeight(double x, double y) const;
};

/// Person `i` of `world` at time `t` (s): exact, deterministic in t (constant velocity between
/// the script's knots; a random walk's knots are drawn from its seed at parse time), moved by its
/// give-way track when it has one.
PersonState personAt(const World& world, size_t i, double t);
PersonState personAt(const Person& p, double t);
/// The script alone (where the person means to walk), without giving way.
PersonState personScriptAt(const Person& p, double t);

/// Ground-truth occupancy options.
struct OccupancyParams
{
  double resolution = 0.2;        ///< m
  double head_margin = 0.15;      ///< m above the head that still counts
  double head_above_eye = 0.12;   ///< m, top of the head above the eye height
  double min_obstacle_height = 0.02;  ///< m above the floor below which nothing counts
  double step_threshold = 0.05;   ///< m floor height change that marks a step (50)
  double border = 1.0;            ///< m around the floor outside which cells are unknown
};

/// Rasterise the world into the README grid codes: 100 where any non-walkable solid overlaps
/// the cell between floor + min_obstacle_height and eye_height + head_above_eye + head_margin,
/// 50 where the floor height differs from a neighbour's by more than step_threshold, 0 on the
/// floor, -1 outside it.
OccupancyGrid computeOccupancy(const World& world, const OccupancyParams& p = {});

/// Per-cell facts behind the ground-truth grid that its codes cannot carry (issue 17, the
/// obstacles benchmark's scoring): flags per cell, same geometry as computeOccupancy().
enum OccupancyDetailFlag : uint8_t
{
  /// Obstacle (100) only because a solid reaches at most `partial_depth` into the cell, and that
  /// solid reaches deeper into another cell (so the map can and must find it there). A thin solid
  /// that reaches no cell that deep keeps all its cells.
  DETAIL_PARTIAL = 1,
  /// Free or step, with an obstacle's solid within `partial_depth` outside the cell's border.
  DETAIL_NEAR = 2,
  /// A glass panel (see-through solid) overlaps the cell in the obstacle height range.
  DETAIL_GLASS = 4,
};

/// The DETAIL_* flags of every cell of computeOccupancy(world, p) (row-major, same size).
std::vector<uint8_t> computeOccupancyDetail(const World& world, const OccupancyParams& p = {},
                                            double partial_depth = 0.05);

/// Path to a shipped world: `name` is a file name stem/substring in `worlds_dir` (e.g. "course")
/// or a path to a YAML file. Throws WorldError when nothing matches.
std::string resolveWorldPath(const std::string& name, const std::string& worlds_dir);

}  // namespace assistive_sim
