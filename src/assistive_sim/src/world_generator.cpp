#include <assistive_sim/world_generator.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <queue>
#include <random>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include <assistive_sim/motion.h>

namespace assistive_sim
{
namespace
{
constexpr double PLAN_RES = 0.05;       // m, planning grid
constexpr double PLAN_CLEAR = 0.6;      // m, clearance of the waypoint polyline (corners are rounded inside it)
constexpr double WALK_CLEAR_MIN = 0.4;  // m, the rendered camera path must keep this from every obstacle
constexpr double PASSAGE = 1.3;         // m, free gap kept between furniture so the walk can pass
// Ordinary passages (issue 33) are narrower than PLAN_CLEAR allows: a doorway of 0.80 m leaves
// 0.40 m to its middle. The builder lays a lane (a line 2 x LANE_HALF wide) through the middle of
// each passage the walk may use (a doorway, a hall, an aisle, the gap beside an object left in
// one); on a lane the walk needs only PASS_CLEAR, everywhere else PLAN_CLEAR as before. A straight
// leg may leave a lane only where the clearance is PLAN_CLEAR again, so it crosses a doorway along
// its middle line.
constexpr double DOOR_MIN = 0.80, DOOR_MAX = 0.90;  // m, clear width of an ordinary doorway
constexpr double AISLE_MIN = 1.2, AISLE_MAX = 1.5;  // m, clear width of a hall or an aisle
constexpr double GAP_MIN = 0.80, GAP_MAX = 0.95;    // m, the gap an object left in a passage leaves
constexpr double LANE_HALF = 0.05;       // m, half width of a lane (cells whose centre is this close)
constexpr double PASS_CLEAR = 0.30;      // m, a lane cell is walkable with this much clearance (0.40 m in the
                                         // middle of a 0.80 m doorway, less the 5 cm grid's error and LANE_HALF)
constexpr double DOOR_LANE = 1.5;        // m, a doorway's lane runs this far either side of the wall's centre line
constexpr double WALK_CLEAR_LANE = 0.31; // m, the camera's clearance within LANE_ZONE of a lane: 0.40 m less the
                                         // lane's width, the gait's sway (2 cm) and the head turning about the neck
constexpr double LANE_ZONE = 0.5;        // m, camera points this close to a lane count as in the passage

std::string num(double v)
{
  char b[32];
  std::snprintf(b, sizeof b, "%.3f", std::abs(v) < 5e-4 ? 0.0 : v);
  return b;
}
std::string pt(double x, double y) { return "[" + num(x) + ", " + num(y) + "]"; }

/// Furniture footprint for placement (bounding circle) and the walk's close passes.
struct Item
{
  double x, y, r;
  bool furniture;  // a close pass may target it
};

/// An axis-aligned rectangle [x0, x1] x [y0, y1] (a room's floor, a piece of furniture).
struct Rect
{
  double x0, y0, x1, y1;
  double cx() const { return 0.5 * (x0 + x1); }
  double cy() const { return 0.5 * (y0 + y1); }
  /// Distance from a point to the rectangle (0 inside).
  double dist(double x, double y) const
  {
    return std::hypot(std::max({x0 - x, 0.0, x - x1}), std::max({y0 - y, 0.0, y - y1}));
  }
  double dist(const Rect& o) const
  {
    return std::hypot(std::max({o.x0 - x1, 0.0, x0 - o.x1}), std::max({o.y0 - y1, 0.0, y0 - o.y1}));
  }
};

/// One goal of a course laid out by the builder (home, shop): a point drawn in a region (a room),
/// or a given point (the middle of an aisle); `close_first`: a close pass by furniture in the
/// same region before it.
struct CourseGoal
{
  Rect region{0, 0, 0, 0};
  bool is_point = false;
  double px = 0, py = 0;
  bool close_first = false;
};

class Builder
{
public:
  Builder(uint32_t seed, std::string kind) : rng_(seed), kind_(std::move(kind)) {}

  double U(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  int I(int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng_); }
  bool P(double p) { return U(0, 1) < p; }

  // ---- materials: bare and pale .. rich, by the world's richness
  void materials(double richness)
  {
    if (pale_) richness *= 0.2;
    rich_ = richness;
    const char* rich_patterns[] = {"bricks", "posters", "tiles", "noise"};
    auto add = [&](const std::string& name, const std::string& pattern, double albedo, double contrast, double scale) {
      mats_ << "  " << name << ": {pattern: " << pattern << ", albedo: " << num(albedo) << ", contrast: "
            << num(contrast) << ", scale: " << num(scale) << ", seed: " << I(1, 100000) << "}\n";
    };
    // Walls: bare below ~0.35 richness, patterned above.
    for (int i = 0; i < 2; ++i)
    {
      if (U(0, 1) > richness) add("wall" + std::to_string(i), "plain", U(0.6, 0.9), U(0.0, 0.08), 0.2);
      else add("wall" + std::to_string(i), rich_patterns[I(0, 3)], U(0.4, 0.7), U(0.3, 0.3 + 0.6 * richness), U(0.15, 0.4));
    }
    add("plainwall", "plain", U(0.65, 0.9), U(0.0, 0.05), 0.2);  // the wall the walk ends facing
    add("floor", U(0, 1) < 0.5 ? "tiles" : "noise", U(0.35, 0.7), U(0.05, 0.1 + 0.5 * richness), U(0.2, 0.6));
    add("ceiling", "plain", U(0.75, 0.9), U(0.0, 0.05), 0.2);
    add("furn0", "noise", U(0.3, 0.6), U(0.1, 0.2 + 0.7 * richness), U(0.04, 0.15));
    add("furn1", U(0, 1) < richness ? "tiles" : "plain", U(0.4, 0.8), U(0.05, 0.1 + 0.6 * richness), U(0.1, 0.3));
    add("wood", "noise", U(0.35, 0.55), U(0.2, 0.3 + 0.5 * richness), U(0.05, 0.1));
    add("metal", "plain", U(0.2, 0.4), U(0.02, 0.08), 0.2);
    add("column", U(0, 1) < richness ? "noise" : "plain", U(0.55, 0.85), U(0.02, 0.05 + 0.4 * richness), 0.15);
    add("sign", "posters", U(0.7, 0.9), U(0.5, 1.0), 0.2);
  }
  std::string wallMat() { return "wall" + std::to_string(I(0, 1)); }
  std::string furnMat() { return "furn" + std::to_string(I(0, 1)); }

  // ---- elements
  /// A wall with open doorways `doors` ({at, width}: centre along the wall, clear width). Each
  /// doorway keeps a circle free of furniture: radius `keep` (< 0: 1.4 m + half its width).
  /// `walked`: the walk may pass through these doorways (a lane through each one's middle).
  void wall(double x0, double y0, double x1, double y1, double h, const std::string& mat,
            const std::vector<std::pair<double, double>>& doors = {}, double door_h = 2.1, double keep = -1.0,
            bool walked = false, const std::string& what = "doorway")
  {
    std::ostringstream e;
    e << "{type: wall, from: " << pt(x0, y0) << ", to: " << pt(x1, y1) << ", height: " << num(h)
      << ", thickness: 0.15, material: " << mat;
    if (!doors.empty())
    {
      e << ", openings: [";
      for (size_t i = 0; i < doors.size(); ++i)
        e << (i ? ", " : "") << "{at: " << num(doors[i].first) << ", width: " << num(doors[i].second)
          << ", height: " << num(door_h) << "}";
      e << "]";
    }
    e << "}";
    elems_.push_back(e.str());
    walls_.push_back({x0, y0, x1, y1});
    const double len = std::hypot(x1 - x0, y1 - y0);
    for (const auto& d : doors)  // keep the doorway and 1.4 m either side free of furniture
    {
      const double cx = x0 + (x1 - x0) * d.first / len, cy = y0 + (y1 - y0) * d.first / len;
      keep_.push_back({cx, cy, keep < 0 ? 1.4 + d.second / 2 : keep, false});
      passage(what, cx, cy, (x1 - x0) / len, (y1 - y0) / len, d.second);
      if (!walked) continue;
      const double nx = -(y1 - y0) / len, ny = (x1 - x0) / len;  // the wall's normal
      lane(cx - nx * DOOR_LANE, cy - ny * DOOR_LANE, cx + nx * DOOR_LANE, cy + ny * DOOR_LANE);
      doors_.push_back({cx, cy, nx, ny, d.second});
    }
  }
  void raw(const std::string& e) { elems_.push_back(e); }
  void passage(const std::string& what, double cx, double cy, double ux, double uy, double width)
  {
    passages_.push_back({what, Eigen::Vector2d(cx, cy), Eigen::Vector2d(ux, uy), width});
  }
  /// A lane: the walk may follow the segment through a passage narrower than PLAN_CLEAR allows.
  void lane(double x0, double y0, double x1, double y1) { lanes_.push_back({x0, y0, x1, y1}); }
  /// Lanes along a polyline.
  void lanes(const std::vector<std::pair<double, double>>& pts)
  {
    for (size_t i = 1; i < pts.size(); ++i) lane(pts[i - 1].first, pts[i - 1].second, pts[i].first, pts[i].second);
  }
  /// Distance from (x, y) to the nearest lane (1e9: none).
  double laneDist(double x, double y) const
  {
    double best = 1e9;
    for (const auto& l : lanes_) best = std::min(best, segDist(l, x, y));
    return best;
  }
  static double segDist(const std::array<double, 4>& w, double x, double y)
  {
    const double dx = w[2] - w[0], dy = w[3] - w[1];
    const double t = std::clamp(((x - w[0]) * dx + (y - w[1]) * dy) / (dx * dx + dy * dy + 1e-12), 0.0, 1.0);
    return std::hypot(x - w[0] - t * dx, y - w[1] - t * dy);
  }
  /// Distance from a rectangle to the nearest lane (sampled every 2.5 cm along the lanes).
  double laneDist(const Rect& r) const
  {
    double best = 1e9;
    for (const auto& l : lanes_)
    {
      const double len = std::hypot(l[2] - l[0], l[3] - l[1]);
      const int n = std::max(1, static_cast<int>(len / 0.025));
      for (int k = 0; k <= n; ++k)
        best = std::min(best, r.dist(l[0] + (l[2] - l[0]) * k / n, l[1] + (l[3] - l[1]) * k / n));
    }
    return best;
  }
  /// Can a piece of furniture stand on `r`: inside `room`, `gap` from other furniture, off the
  /// doorways' free circles and `lane_gap` from every lane?
  bool rectFits(const Rect& r, const Rect& room, double gap, double lane_gap = 0.5) const
  {
    if (r.x0 < room.x0 - 1e-9 || r.y0 < room.y0 - 1e-9 || r.x1 > room.x1 + 1e-9 || r.y1 > room.y1 + 1e-9) return false;
    for (const Rect& o : rects_)
      if (r.dist(o) < gap) return false;
    for (const Item& it : items_)
      if (r.dist(it.x, it.y) < it.r + gap) return false;
    for (const Item& k : keep_)
      if (r.dist(k.x, k.y) < k.r) return false;
    return laneDist(r) >= lane_gap;
  }
  void placeRect(const Rect& r) { rects_.push_back(r); }
  /// A box `along` x `depth` x `h` against one of the room's walls (`side` 0..3: y0, y1, x0, x1;
  /// -1: any), `gap` from other furniture. Returns false when no place was found.
  bool againstWall(const Rect& room, double along, double depth, double h, const std::string& mat, double gap,
                   const std::string& what, int side = -1, Rect* placed = nullptr)
  {
    for (int k = 0; k < 60; ++k)
    {
      const int sd = side >= 0 ? side : I(0, 3);
      Rect r{};
      if (sd < 2)
      {
        if (room.x1 - room.x0 < along) continue;
        const double cx = U(room.x0 + along / 2, room.x1 - along / 2);
        const double y0 = sd == 0 ? room.y0 + 0.02 : room.y1 - 0.02 - depth;
        r = {cx - along / 2, y0, cx + along / 2, y0 + depth};
      }
      else
      {
        if (room.y1 - room.y0 < along) continue;
        const double cy = U(room.y0 + along / 2, room.y1 - along / 2);
        const double x0 = sd == 2 ? room.x0 + 0.02 : room.x1 - 0.02 - depth;
        r = {x0, cy - along / 2, x0 + depth, cy + along / 2};
      }
      if (!rectFits(r, room, gap)) continue;
      boxAt(r, h, mat, what);
      if (placed) *placed = r;
      return true;
    }
    return false;
  }
  /// A free-standing piece (`type` table or box) of `sx` x `sy` in the room, `wall_gap` from its
  /// walls; `pad`: extra room around it that counts as its footprint (chairs round a table).
  bool freeStanding(const Rect& room, double sx, double sy, double h, const std::string& type, const std::string& mat,
                    double gap, double wall_gap, double pad, const std::string& what, Rect* placed = nullptr)
  {
    const Rect inner{room.x0 + wall_gap + pad, room.y0 + wall_gap + pad, room.x1 - wall_gap - pad, room.y1 - wall_gap - pad};
    if (inner.x1 - inner.x0 < sx || inner.y1 - inner.y0 < sy) return false;
    for (int k = 0; k < 60; ++k)
    {
      const double cx = U(inner.x0 + sx / 2, inner.x1 - sx / 2), cy = U(inner.y0 + sy / 2, inner.y1 - sy / 2);
      const Rect r{cx - sx / 2, cy - sy / 2, cx + sx / 2, cy + sy / 2};
      const Rect padded{r.x0 - pad, r.y0 - pad, r.x1 + pad, r.y1 + pad};
      if (!rectFits(padded, room, gap)) continue;
      if (type == "table")
        raw("{type: table, center: " + pt(cx, cy) + ", size: " + pt(sx, sy) + ", height: " + num(h) +
            ", material: " + mat + "}  # " + what);
      else
        boxAt(r, h, mat, what, false);
      placeRect(padded);
      if (placed) *placed = r;
      return true;
    }
    return false;
  }
  /// An axis-aligned box on `r`, `h` high (a YAML comment names it).
  void boxAt(const Rect& r, double h, const std::string& mat, const std::string& what, bool keep_out = true)
  {
    raw("{type: box, center: " + pt(r.cx(), r.cy()) + ", size: [" + num(r.x1 - r.x0) + ", " + num(r.y1 - r.y0) + ", " +
        num(h) + "], material: " + mat + "}  # " + what);
    if (keep_out) placeRect(r);
  }

  /// Distance from (x, y) to the nearest wall segment.
  double wallDist(double x, double y) const
  {
    double best = 1e9;
    for (const auto& w : walls_)
    {
      const double dx = w[2] - w[0], dy = w[3] - w[1];
      const double t = std::clamp(((x - w[0]) * dx + (y - w[1]) * dy) / (dx * dx + dy * dy + 1e-12), 0.0, 1.0);
      best = std::min(best, std::hypot(x - w[0] - t * dx, y - w[1] - t * dy));
    }
    return best;
  }
  /// Is a bounding circle (x, y, r) placeable: inside [lo, hi], off the walls by `wall_gap`
  /// (negative: against a wall is fine), a passage away from other items and doorways?
  bool fits(double x, double y, double r, double wall_gap) const
  {
    if (x - r < lo_x_ + 0.2 || x + r > hi_x_ - 0.2 || y - r < lo_y_ + 0.2 || y + r > hi_y_ - 0.2) return false;
    if (wall_gap >= 0 && wallDist(x, y) < r + wall_gap) return false;
    if (wall_gap < 0 && wallDist(x, y) < r * 0.5) return false;
    for (const Item& it : items_)
      if (std::hypot(x - it.x, y - it.y) < r + it.r + PASSAGE) return false;
    for (const Item& k : keep_)
      if (std::hypot(x - k.x, y - k.y) < r + k.r) return false;
    return true;
  }
  /// Random free spot for a circle of radius r; false after many tries.
  bool spot(double r, double wall_gap, double& x, double& y)
  {
    for (int k = 0; k < 200; ++k)
    {
      x = U(lo_x_ + r, hi_x_ - r);
      y = U(lo_y_ + r, hi_y_ - r);
      if (fits(x, y, r, wall_gap)) return true;
    }
    return false;
  }
  void place(double x, double y, double r, bool furniture) { items_.push_back({x, y, r, furniture}); }

  // Furniture kinds (each returns false when no room was found).
  bool table(bool bench)
  {
    const double l = bench ? U(1.2, 2.0) : U(1.0, 1.8), w = bench ? U(0.35, 0.5) : U(0.6, 0.9);
    const double r = 0.5 * std::hypot(l, w);
    double x, y;
    if (!spot(r, PASSAGE, x, y)) return false;
    raw("{type: " + std::string(bench ? "bench" : "table") + ", center: " + pt(x, y) + ", size: " + pt(l, w) +
        ", yaw: " + num(U(0, 1) < 0.7 ? 90.0 * I(0, 1) : U(-60, 60)) + ", material: " + (bench ? "wood" : furnMat()) + "}");
    place(x, y, r, true);
    return true;
  }
  bool box(double hmin, double hmax)
  {
    const double sx = U(0.4, 1.2), sy = U(0.4, 1.0), r = 0.5 * std::hypot(sx, sy);
    double x, y;
    if (!spot(r, P(0.5) ? -1 : PASSAGE, x, y)) return false;
    raw("{type: box, center: " + pt(x, y) + ", size: [" + num(sx) + ", " + num(sy) + ", " + num(U(hmin, hmax)) +
        "], yaw: " + num(U(-30, 30)) + ", material: " + furnMat() + "}");
    place(x, y, r, true);
    return true;
  }
  bool column(double rmin, double rmax, double h, const std::string& mat)
  {
    const double rc = U(rmin, rmax);
    double x, y;
    if (!spot(rc, PASSAGE, x, y)) return false;
    raw("{type: column, center: " + pt(x, y) + ", radius: " + num(rc) + ", height: " + num(h) + ", material: " + mat + "}");
    place(x, y, rc, true);
    return true;
  }
  /// A shelf at head height (0.4 m deep, bottom 1.35-1.5 m) against an axis-aligned outer wall,
  /// or a sign hanging at head height (a thin slab, 1.45-1.6 m to 1.85-2.0 m) in the open.
  bool shelf()
  {
    const double len = U(0.9, 1.6), depth = 0.4;
    for (int k = 0; k < 100; ++k)
    {
      const int side = I(0, 3);  // against x = lo, x = hi, y = lo, y = hi
      double x, y, sx, sy;
      if (side < 2)
      {
        x = side == 0 ? lo_x_ + 0.075 + depth / 2 : hi_x_ - 0.075 - depth / 2;
        y = U(lo_y_ + len, hi_y_ - len);
        sx = depth, sy = len;
      }
      else
      {
        y = side == 2 ? lo_y_ + 0.075 + depth / 2 : hi_y_ - 0.075 - depth / 2;
        x = U(lo_x_ + len, hi_x_ - len);
        sx = len, sy = depth;
      }
      const double r = 0.5 * len;
      // Against its own wall only: no other wall (a partition) across it or at its ends.
      const double ax = side < 2 ? 0.0 : 1.0, ay = side < 2 ? 1.0 : 0.0;
      bool ok = wallDist(x, y) > 0.25 && wallDist(x + ax * (r + 0.1), y + ay * (r + 0.1)) > 0.25 &&
                wallDist(x - ax * (r + 0.1), y - ay * (r + 0.1)) > 0.25;
      for (const Item& it : items_) ok = ok && std::hypot(x - it.x, y - it.y) > r + it.r + PASSAGE;
      for (const Item& kp : keep_) ok = ok && std::hypot(x - kp.x, y - kp.y) > r + kp.r;
      if (!ok) continue;
      const double b = U(1.35, 1.5);
      raw("{type: overhang, center: " + pt(x, y) + ", size: " + pt(sx, sy) + ", bottom: " + num(b) + ", top: " +
          num(b + U(0.3, 0.45)) + ", material: " + furnMat() + "}");
      place(x, y, r, true);
      return true;
    }
    return false;
  }
  bool sign()
  {
    const double l = U(0.6, 1.2), r = l / 2;
    double x, y;
    if (!spot(r, PASSAGE, x, y)) return false;
    const double b = U(1.45, 1.6);
    const bool along_x = P(0.5);
    raw("{type: sign, center: " + pt(x, y) + ", size: " + (along_x ? pt(l, 0.05) : pt(0.05, l)) + ", bottom: " +
        num(b) + ", top: " + num(b + U(0.35, 0.45)) + ", material: sign}");
    place(x, y, r, true);
    return true;
  }
  bool step(double h)
  {
    const double sx = U(1.2, 3.0), sy = U(0.8, 2.0), r = 0.5 * std::hypot(sx, sy);
    double x, y;
    if (!spot(r, PASSAGE, x, y)) return false;
    raw("{type: step, center: " + pt(x, y) + ", size: " + pt(sx, sy) + ", height: " + num(h) + ", material: furn1}");
    place(x, y, r, false);
    return true;
  }

  void bounds(double x0, double y0, double x1, double y1) { lo_x_ = x0, lo_y_ = y0, hi_x_ = x1, hi_y_ = y1; }

  std::mt19937 rng_;
  std::string kind_;
  double rich_ = 0.5;
  bool pale_ = false;  ///< richness cut to a fifth (WorldGenerator::setPale)
  std::ostringstream mats_;
  std::vector<std::string> elems_;
  std::vector<std::array<double, 4>> walls_;
  std::vector<std::array<double, 4>> lanes_;  // x0, y0, x1, y1: the middle lines of narrow passages
  std::vector<Rect> rects_;                   // furniture footprints placed by rectFits (home, shop)
  std::vector<std::array<double, 5>> doors_;  // doorways the walk may use: centre x, y, normal x, y, width
  std::vector<CourseGoal> course_;            // the course's goals in order (empty: random goals)
  std::vector<GeneratedPassage> passages_;    // what GeneratedWorld::passages reports
  double end_approach_ = 3.0;                 // m, the walk's last leg runs this far straight at the end wall
  std::vector<Item> items_, keep_;
  double lo_x_ = 0, lo_y_ = 0, hi_x_ = 1, hi_y_ = 1;
  // The plain wall the walk ends facing: a segment and its inward normal.
  double end_x0_ = 0, end_y0_ = 0, end_x1_ = 0, end_y1_ = 0, end_nx_ = 0, end_ny_ = 0;
  std::string header_;  // floor, ceiling, sky, light
};

// ---- layouts (the room spans [0, L] x [0, W]; outer walls on its border)
void outerWalls(Builder& b, double L, double W, double h, const std::vector<std::pair<double, double>>& front_doors)
{
  // The far end wall (x = L) is plain: the walk ends facing it.
  b.wall(0, 0, L, 0, h, b.wallMat(), front_doors);
  b.wall(0, W, L, W, h, b.wallMat());
  b.wall(0, 0, 0, W, h, b.wallMat());
  b.wall(L, 0, L, W, h, "plainwall");
  b.end_x0_ = L, b.end_y0_ = 0, b.end_x1_ = L, b.end_y1_ = W, b.end_nx_ = -1, b.end_ny_ = 0;
}

void header(Builder& b, double L, double W, bool ceiling, double ceil_h, bool outdoor)
{
  std::ostringstream h;
  h << "floor: {min: " << pt(-0.5, -0.5) << ", max: " << pt(L + 0.5, W + 0.5) << ", material: floor}\n";
  if (ceiling) h << "ceiling: {height: " << num(ceil_h) << ", material: ceiling}\n";
  h << "sky: {brightness: " << num(outdoor ? b.U(0.8, 0.95) : 0.75) << "}\n";
  h << "light: [" << num(b.U(-0.5, 0.5)) << ", " << num(b.U(-0.5, 0.5)) << ", 1.000]\n";
  b.header_ = h.str();
  b.bounds(0, 0, L, W);
}

void office(Builder& b)
{
  const double L = b.U(9, 13), W = b.U(6, 9), H = b.U(2.6, 3.0);
  b.materials(b.U(0, 1));
  header(b, L, W, true, H, false);
  outerWalls(b, L, W, H, {});
  // A partition across the room with a doorway, and maybe a second one closing a side room. The
  // doorways are ordinary (0.80-0.90 m clear, issue 33; they were 1.3-1.5 m): the width is drawn
  // as before and mapped onto the new range, and the free circle round each doorway keeps its old
  // size, so a seed's furniture and materials are those it had before; only the doorways and the
  // walk through them changed.
  auto door = [&](double lo, double hi) {
    const double at = b.U(lo, hi), drawn = b.U(1.3, 1.5);
    return std::make_pair(std::make_pair(at, DOOR_MIN + (drawn - 1.3) / 0.2 * (DOOR_MAX - DOOR_MIN)), 1.4 + drawn / 2);
  };
  // The draws keep their order (the partition's doorway and material, then the side room's), the
  // walls are written after: a side wall ending in the partition's doorway (0.44 m left clear in
  // office seed 12) moves that doorway clear of its end.
  const double px = L * b.U(0.4, 0.6);
  auto d1 = door(1.3, W - 1.3);
  const std::string m1 = b.wallMat();
  const bool side = b.P(0.6);
  double py = 0.0;
  std::pair<std::pair<double, double>, double> d2;
  std::string m2;
  if (side)
  {
    py = W * b.U(0.45, 0.6);
    d2 = door(1.3, px - 1.3);
    m2 = b.wallMat();
    double& at = d1.first.first;
    const double w = d1.first.second, need = w / 2 + 0.075 + 0.1;  // past the side wall's face, 0.1 m to spare
    if (std::abs(at - py) < need) at = at > py ? (py + need + w / 2 <= W - 0.6 ? py + need : py - need)
                                                : (py - need - w / 2 >= 0.6 ? py - need : py + need);
  }
  b.wall(px, 0, px, W, H, m1, {d1.first}, 2.1, d1.second, true);
  if (side) b.wall(0, py, px, py, H, m2, {d2.first}, 2.1, d2.second, true);
  for (int i = b.I(2, 4); i > 0; --i) b.table(false);
  for (int i = b.I(2, 4); i > 0; --i) b.box(0.5, 1.9);
  b.table(true);
  for (int i = b.I(1, 2); i > 0; --i) b.shelf();
  if (b.P(0.5)) b.sign();
}

void lobby(Builder& b)
{
  const double L = b.U(12, 18), W = b.U(10, 14), H = b.U(3.5, 4.5);
  b.materials(b.U(0, 0.3));  // pale, low texture
  header(b, L, W, true, H, false);
  outerWalls(b, L, W, H, {{b.U(2, L - 2), b.U(1.8, 2.4)}});
  // Plain columns on a grid, then a reception desk, benches, planters and a sign.
  const int nx = b.I(2, 3), ny = 2;
  const double rc = b.U(0.25, 0.4);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
    {
      const double x = L * (i + 1) / (nx + 1) + b.U(-0.3, 0.3), y = W * (j + 1) / (ny + 1);
      if (!b.fits(x, y, rc, PASSAGE)) continue;
      b.raw("{type: column, center: " + pt(x, y) + ", radius: " + num(rc) + ", height: " + num(H) + ", material: column}");
      b.place(x, y, rc, true);
    }
  double x, y;
  if (b.spot(1.4, PASSAGE, x, y))
  {
    b.raw("{type: box, center: " + pt(x, y) + ", size: [2.400, 0.800, 1.100], yaw: " + num(90.0 * b.I(0, 1)) +
          ", material: furn1}");
    b.place(x, y, 1.3, true);
  }
  for (int i = b.I(2, 3); i > 0; --i) b.table(true);
  for (int i = b.I(1, 3); i > 0; --i) b.box(0.4, 0.8);
  b.sign();
}

void corridor(Builder& b)
{
  const double L = b.U(18, 28), W = b.U(2.8, 3.4), H = b.U(2.5, 2.9);
  b.materials(b.U(0, 1));
  header(b, L, W, true, H, false);
  // Doors along both sides (open doorways onto nothing the walk uses).
  std::vector<std::pair<double, double>> doors;
  for (double at = b.U(2, 4); at < L - 3; at += b.U(4, 7)) doors.push_back({at, 0.9});
  outerWalls(b, L, W, H, doors);
  // Furniture against alternating walls, about every 2.5-4 m: boxes, benches, shelves and signs
  // sticking out at head height; the middle 1.3 m stays free.
  int side = b.I(0, 1);
  for (double x = b.U(2.5, 4); x < L - 2.5; x += b.U(2.5, 4), side ^= 1)
  {
    // The doors are in the y = 0 wall: keep that side's furniture off them.
    bool clash = false;
    for (const Item& k : b.keep_) clash = clash || (side == 0 && std::abs(x - k.x) < 1.2);
    if (clash) side ^= 1;
    const int what = b.I(0, 3);
    const double depth = what == 1 ? b.U(0.35, 0.45) : b.U(0.3, 0.5);
    const double y = side ? W - 0.075 - depth / 2 : 0.075 + depth / 2;
    const double len = b.U(0.8, 1.6);
    if (what == 0)
      b.raw("{type: box, center: " + pt(x, y) + ", size: [" + num(len) + ", " + num(depth) + ", " + num(b.U(0.5, 1.9)) +
            "], material: " + b.furnMat() + "}");
    else if (what == 1)
      b.raw("{type: bench, center: " + pt(x, y) + ", size: " + pt(len, depth) + ", material: wood}");
    else if (what == 2)
    {
      const double bt = b.U(1.35, 1.5);
      b.raw("{type: overhang, center: " + pt(x, y) + ", size: " + pt(len, 0.4) + ", bottom: " + num(bt) +
            ", top: " + num(bt + 0.4) + ", material: " + b.furnMat() + "}");
    }
    else
    {
      const double bt = b.U(1.45, 1.6), l = b.U(0.35, 0.5), ys = side ? W - 0.075 - l / 2 : 0.075 + l / 2;
      b.raw("{type: sign, center: " + pt(x, ys) + ", size: " + pt(0.05, l) + ", bottom: " + num(bt) + ", top: " +
            num(bt + 0.4) + ", material: sign}");
    }
    b.place(x, y, len / 2, true);
  }
}

void hall(Builder& b)
{
  const double L = b.U(20, 28), W = b.U(14, 18), H = b.U(5, 7);
  b.materials(b.U(0.2, 1));
  header(b, L, W, true, H, false);
  outerWalls(b, L, W, H, {{b.U(3, L / 2), 3.0}, {b.U(L / 2 + 2, L - 3), 3.0}});
  // Two rows of pillars, then kiosks, benches, hanging signs and a raised platform.
  const double rc = b.U(0.3, 0.5), sp = b.U(4, 6);
  for (int row = 0; row < 2; ++row)
    for (double x = b.U(3, 5); x < L - 3; x += sp)
    {
      const double y = W * (row == 0 ? 0.33 : 0.67);
      if (!b.fits(x, y, rc, PASSAGE)) continue;
      b.raw("{type: column, center: " + pt(x, y) + ", radius: " + num(rc) + ", height: " + num(H) + ", material: column}");
      b.place(x, y, rc, true);
    }
  for (int i = b.I(1, 3); i > 0; --i) b.box(1.8, 2.4);
  for (int i = b.I(2, 4); i > 0; --i) b.table(true);
  for (int i = b.I(1, 2); i > 0; --i) b.sign();
  b.step(b.U(0.12, 0.18));
}

void street(Builder& b)
{
  const double L = b.U(24, 34), W = b.U(10, 13);
  b.materials(b.U(0.3, 1));
  header(b, L, W, false, 0, true);
  const double sw = b.U(2.0, 3.0);  // raised sidewalk on the far side, behind a curb
  b.wall(0, 0, L, 0, b.U(5, 9), b.wallMat(), {{b.U(3, L - 3), 1.4}}, 2.4);
  b.wall(0, W, L, W, b.U(5, 9), b.wallMat(), {{b.U(3, L - 3), 1.4}}, 2.4);
  b.wall(0, 0, 0, W, 4.0, b.wallMat());
  b.wall(L, 0, L, W, b.U(3, 5), "plainwall");
  b.end_x0_ = L, b.end_y0_ = 0, b.end_x1_ = L, b.end_y1_ = W, b.end_nx_ = -1, b.end_ny_ = 0;
  b.raw("{type: curb, center: " + pt(L / 2, W - sw / 2) + ", size: " + pt(L, sw) + ", height: " +
        num(b.U(0.1, 0.16)) + ", material: furn1}");
  b.place(L / 2, W - sw / 2, 0.0, false);
  b.bounds(0, 0, L, W - sw);  // the rest is placed on the lower level
  b.keep_.push_back({L / 2, W - sw / 2, 0.0, false});
  // Lamp posts and bollards along the curb, benches, planters, a bus-stop sign at head height on a post, a step.
  for (double x = b.U(2, 4); x < L - 2; x += b.U(6, 9))
  {
    const double y = W - sw - 0.4;
    b.raw("{type: column, center: " + pt(x, y) + ", radius: 0.060, height: 4.500, material: metal}");
  }
  for (int i = b.I(2, 4); i > 0; --i) b.column(0.08, 0.12, b.U(0.8, 1.0), "metal");
  for (int i = b.I(1, 3); i > 0; --i) b.table(true);
  for (int i = b.I(1, 3); i > 0; --i) b.box(0.5, 0.8);
  double x, y;
  if (b.spot(0.6, PASSAGE, x, y))
  {
    b.raw("{type: column, center: " + pt(x, y) + ", radius: 0.050, height: 2.300, material: metal}");
    b.raw("{type: sign, center: " + pt(x, y - 0.4) + ", size: " + pt(0.05, 0.8) + ", bottom: " + num(b.U(1.45, 1.6)) +
          ", top: 2.000, material: sign}");
    b.place(x, y - 0.2, 0.6, true);
  }
  b.step(b.U(0.12, 0.17));
}

/// An object left in a straight passage along x (a hall, an aisle) whose clear space is
/// [x_lo, x_hi] x [y_lo, y_hi]: `kinds` names what it may be ({name, along x, across, height}).
/// It stands against one side or a little off it and leaves a gap of GAP_MIN..GAP_MAX on the
/// other, clear of the doorways off the passage (`avoid_low`: x of the doorways in the y_lo side,
/// `avoid_high`: the y_hi side): `avoid_r` from those on its own side, and none across the gap
/// from it (the gap is between it and a wall). Returns the passage's lane from lane_x0 to
/// lane_x1: its middle line, jogging to the gap's middle past the object (straight: no object).
std::vector<std::pair<double, double>> leftInPassage(Builder& b, double x_lo, double x_hi, double y_lo, double y_hi,
                                                     const std::vector<std::array<double, 4>>& kinds,
                                                     const std::vector<std::string>& names,
                                                     const std::vector<double>& avoid_low,
                                                     const std::vector<double>& avoid_high, double avoid_r, double lane_x0,
                                                     double lane_x1, Rect* placed = nullptr)
{
  const double yc = 0.5 * (y_lo + y_hi), width = y_hi - y_lo;
  const size_t k = static_cast<size_t>(b.I(0, static_cast<int>(kinds.size()) - 1));
  const double along = kinds[k][0], h = kinds[k][2];
  const double across = std::min(kinds[k][1], width - GAP_MIN);
  const double gap = b.U(GAP_MIN, std::min(GAP_MAX, width - across));
  const double off = width - gap - across;  // from the wall (or shelf) it stands by
  const bool low_side = b.P(0.5);
  const double xa = x_lo + 1.3 + along / 2, xb = x_hi - 1.3 - along / 2;
  for (int tries = 0; tries < 50 && xa < xb; ++tries)
  {
    const double x = b.U(xa, xb);
    bool ok = true;
    for (double a : low_side ? avoid_low : avoid_high) ok = ok && std::abs(x - a) >= avoid_r + along / 2;
    for (double a : low_side ? avoid_high : avoid_low) ok = ok && std::abs(x - a) >= DOOR_MAX / 2 + 0.05 + along / 2;
    if (!ok) continue;
    const double y0 = low_side ? y_lo + off : y_hi - off - across;
    const Rect r{x - along / 2, y0, x + along / 2, y0 + across};
    const double yg = low_side ? 0.5 * (r.y1 + y_hi) : 0.5 * (y_lo + r.y0);
    b.boxAt(r, h, names[k].find("trolley") != std::string::npos ? "metal" : b.furnMat(),
            names[k] + " left in the passage: " + num(across) + " m of its " + num(width) + " m, a gap of " + num(gap) +
                " m");
    if (placed) *placed = r;
    b.passage("gap", x, yg, 0, 1, gap);
    // The jog to the gap's middle ends 0.45 m before the object (its corner stays 0.45 m off the lane).
    return {{lane_x0, yc}, {r.x0 - 1.2, yc}, {r.x0 - 0.45, yg}, {r.x1 + 0.45, yg}, {r.x1 + 1.2, yc}, {lane_x1, yc}};
  }
  return {{lane_x0, yc}, {lane_x1, yc}};
}

/// A home (issue 33): a hall 1.2-1.5 m wide with rooms off it (two south of it, a living room
/// north of it) and a kitchen across its far end, every doorway 0.80-0.90 m clear; often a chair,
/// a basket or a box left in the hall. The course visits the three rooms in a random order and
/// ends in the kitchen facing its plain east wall, so it goes through several doorways.
void home(Builder& b)
{
  const double t2 = 0.075;  // half a wall's thickness
  const double L = b.U(10.5, 13), W = b.U(7.5, 9), H = b.U(2.4, 2.7);
  b.materials(b.U(0.2, 1));
  header(b, L, W, true, H, false);
  b.end_approach_ = 2.2;
  const double DH = 2.1, KEEP = 1.2;  // doorway height; furniture keeps this far from a doorway's centre
  auto dw = [&]() { return b.U(DOOR_MIN, DOOR_MAX); };
  const double hw = b.U(AISLE_MIN, AISLE_MAX);                       // the hall's clear width
  const double hy = b.U(2.9 + hw / 2 + t2, W - 2.9 - hw / 2 - t2);   // its middle line
  const double ys = hy - hw / 2 - t2, yn = hy + hw / 2 + t2;         // its walls' centre lines
  const double he = L - b.U(3.8, 4.6);                               // the kitchen's west wall
  const double sx = he * b.U(0.42, 0.58);                            // between the two south rooms
  // Outer walls: the front door at the hall's west end (not walked), the plain east wall.
  const double wf = dw();
  b.wall(0, 0, L, 0, H, b.wallMat());
  b.wall(0, W, L, W, H, b.wallMat());
  b.wall(0, 0, 0, W, H, b.wallMat(), {{hy, wf}}, DH, KEEP);
  b.wall(L, 0, L, W, H, "plainwall");
  b.end_x0_ = L, b.end_y0_ = 0, b.end_x1_ = L, b.end_y1_ = W, b.end_nx_ = -1, b.end_ny_ = 0;
  // The hall's walls with the rooms' doorways.
  const double w1 = dw(), w2 = dw(), w3 = dw();
  const double d1 = b.U(0.6 + w1 / 2, sx - 0.6 - w1 / 2), d2 = b.U(sx + 0.6 + w2 / 2, he - 0.6 - w2 / 2);
  const double d3 = b.U(0.6 + w3 / 2, he - 0.6 - w3 / 2);
  b.wall(0, ys, he, ys, H, b.wallMat(), {{d1, w1}, {d2, w2}}, DH, KEEP, true);
  b.wall(0, yn, he, yn, H, b.wallMat(), {{d3, w3}}, DH, KEEP, true);
  // The kitchen's wall: from the hall, often from the living room, sometimes from the south-east room.
  std::vector<std::pair<double, double>> kd{{hy, dw()}};
  if (b.P(0.7))
  {
    const double w = dw();
    kd.push_back({b.U(yn + t2 + 0.5 + w / 2, W - 0.5 - w / 2), w});
  }
  if (b.P(0.3))
  {
    const double w = dw();
    kd.push_back({b.U(0.5 + w / 2, ys - t2 - 0.5 - w / 2), w});
  }
  std::sort(kd.begin(), kd.end());
  b.wall(he, 0, he, W, H, b.wallMat(), kd, DH, KEEP, true);
  // Between the south rooms, sometimes a doorway.
  if (b.P(0.4))
  {
    const double w = dw(), at = b.U(0.5 + w / 2, ys - t2 - 0.5 - w / 2);
    b.wall(sx, 0, sx, ys, H, b.wallMat(), {{at, w}}, DH, KEEP, true);
  }
  else
    b.wall(sx, 0, sx, ys, H, b.wallMat());
  // The hall's lane, past what was left in it.
  std::vector<std::pair<double, double>> hall_lane{{0.0, hy}, {he, hy}};
  if (b.P(0.85))
    hall_lane = leftInPassage(b, t2, he - t2, ys + t2, yn - t2,
                              {{0.45, b.U(0.45, 0.5), 0.9, 0}, {b.U(0.4, 0.7), b.U(0.3, 0.55), b.U(0.35, 0.7), 0},
                               {0.55, 0.4, 0.5, 0}},
                              {"a chair", "a box", "a laundry basket"}, {d1, d2}, {d3}, 0.3 + DOOR_MAX / 2, 0.0, he);
  b.lanes(hall_lane);
  // The hall's width where nothing opens off it and nothing stands in it.
  for (double x = 0.5; x < he - 0.5; x += 0.05)
  {
    bool clear = true;
    for (const auto& d : {std::make_pair(d1, w1), std::make_pair(d2, w2), std::make_pair(d3, w3)})
      clear = clear && std::abs(x - d.first) > d.second / 2 + 0.1;
    for (const Rect& r : b.rects_) clear = clear && (x < r.x0 - 0.1 || x > r.x1 + 0.1);
    if (!clear) continue;
    b.passage("hall", x, hy, 0, 1, hw);
    break;
  }

  const Rect sw{t2, t2, sx - t2, ys - t2}, se{sx + t2, t2, he - t2, ys - t2}, liv{t2, yn + t2, he - t2, W - t2},
      kit{he + t2, t2, L - t2, W - t2};
  const double GAP = 0.75;  // between pieces of furniture in a home
  // Bedrooms (the south-east one is a study half the time).
  // (One draw per statement: the order of a call's arguments is the compiler's.)
  auto bedroom = [&](const Rect& r) {
    const double bed_w = b.P(0.5) ? b.U(1.4, 1.6) : b.U(0.9, 1.0);
    b.againstWall(r, bed_w, 2.0, 0.5, b.furnMat(), GAP, "a bed");
    b.againstWall(r, b.U(1.0, 1.8), 0.6, 2.0, "wood", GAP, "a wardrobe");
    if (b.P(0.5))
    {
      const double w = b.U(0.4, 0.5);
      b.againstWall(r, w, 0.4, 0.5, b.furnMat(), GAP, "a bedside table");
    }
  };
  auto bookcase = [&](const Rect& r) {
    const double len = b.U(0.8, 1.2), h = b.U(1.8, 2.0);
    b.againstWall(r, len, 0.35, h, "wood", GAP, "a bookcase");
  };
  bedroom(sw);
  if (b.P(0.5)) bedroom(se);
  else
  {
    b.againstWall(se, b.U(1.2, 1.6), 0.7, 0.75, "wood", GAP, "a desk");
    bookcase(se);
    b.freeStanding(se, 0.5, 0.5, 0.9, "box", b.furnMat(), GAP, 0.3, 0.0, "an armchair");
  }
  // Living room: a sofa, a TV unit, a coffee table, an armchair, a bookcase, a shelf at head height.
  const double sofa = b.U(1.8, 2.4);
  b.againstWall(liv, sofa, 0.9, 0.85, b.furnMat(), GAP, "a sofa");
  b.againstWall(liv, b.U(1.2, 1.8), 0.45, 0.55, "wood", GAP, "a TV unit");
  const double ct_l = b.U(0.9, 1.2), ct_w = b.U(0.5, 0.7);
  b.freeStanding(liv, ct_l, ct_w, 0.45, "table", "wood", GAP, 0.6, 0.0, "a coffee table");
  if (b.P(0.6)) b.againstWall(liv, 0.85, 0.85, 0.9, b.furnMat(), GAP, "an armchair");
  if (b.P(0.6)) bookcase(liv);
  if (b.P(0.4))
  {
    Rect s{};
    const double bt = b.U(1.35, 1.5);
    for (int k = 0; k < 30; ++k)
    {
      const double len = b.U(0.8, 1.4), cx = b.U(liv.x0 + len / 2, liv.x1 - len / 2);
      const bool north = b.P(0.5);
      s = north ? Rect{cx - len / 2, liv.y1 - 0.3, cx + len / 2, liv.y1} : Rect{cx - len / 2, liv.y0, cx + len / 2, liv.y0 + 0.3};
      if (!b.rectFits(s, liv, GAP)) continue;
      b.raw("{type: overhang, center: " + pt(s.cx(), s.cy()) + ", size: " + pt(s.x1 - s.x0, 0.3) + ", bottom: " + num(bt) +
            ", top: " + num(bt + 0.3) + ", material: wood}  # a shelf at head height");
      b.placeRect(s);
      break;
    }
  }
  // Kitchen: a counter with wall cabinets above it along the north or south wall, an island (an
  // aisle 1.2-1.5 m wide between it and the counter) or a dining table with chairs, a fridge.
  Rect counter{};
  const bool north = b.P(0.5);
  const double counter_l = b.U(2.0, 3.2);
  const bool has_counter =
      b.againstWall(kit, counter_l, 0.6, 0.9, b.furnMat(), GAP, "a kitchen counter", north ? 1 : 0, &counter);
  if (has_counter)
  {
    const double bt = b.U(1.45, 1.55), cy = north ? counter.y1 - 0.175 : counter.y0 + 0.175;
    b.raw("{type: overhang, center: " + pt(counter.cx(), cy) + ", size: " + pt(counter.x1 - counter.x0, 0.35) +
          ", bottom: " + num(bt) + ", top: " + num(std::min(H - 0.05, 2.2)) + ", material: wood}  # wall cabinets");
  }
  bool island = false;
  if (has_counter && b.P(0.5))
  {
    const double aisle = b.U(AISLE_MIN, AISLE_MAX), len = b.U(1.2, 1.8), dep = b.U(0.8, 1.0);
    // its middle over the counter, 0.9 m from the kitchen's side walls
    const double lo = std::max(kit.x0 + 0.9 + len / 2, counter.x0), hi = std::min(kit.x1 - 0.9 - len / 2, counter.x1);
    const double cx = lo < hi ? b.U(lo, hi) : lo;
    const Rect r = north ? Rect{cx - len / 2, counter.y0 - aisle - dep, cx + len / 2, counter.y0 - aisle}
                         : Rect{cx - len / 2, counter.y1 + aisle, cx + len / 2, counter.y1 + aisle + dep};
    if (lo < hi && b.rectFits(r, kit, 1.0))
    {
      b.boxAt(r, 0.9, b.furnMat(), "a kitchen island, an aisle of " + num(aisle) + " m from the counter");
      const double ya = north ? counter.y0 - aisle / 2 : counter.y1 + aisle / 2;
      b.lane(r.x0 - 0.7, ya, r.x1 + 0.7, ya);
      b.passage("aisle", r.cx(), ya, 0, 1, aisle);
      island = true;
    }
  }
  if (!island)
  {
    Rect t{};
    const double tl = b.U(1.2, 1.6), tw = b.U(0.8, 0.9);
    if (b.freeStanding(kit, tl, tw, 0.75, "table", "wood", GAP, 0.3, 0.5, "a dining table", &t))
      for (int side = 0; side < 2; ++side)
        for (int k = 0; k < 2; ++k)
          if (b.P(0.7))
          {
            const double cx = t.cx() + (k ? 0.3 : -0.3), cy = side ? t.y1 + 0.25 : t.y0 - 0.25;
            b.boxAt(Rect{cx - 0.22, cy - 0.22, cx + 0.22, cy + 0.22}, 0.9, b.furnMat(), "a chair", false);
          }
  }
  b.againstWall(kit, 0.7, 0.7, 1.8, "metal", GAP, "a fridge");

  // The course: the three rooms in a random order, close passes by furniture, then the kitchen.
  std::vector<Rect> rooms{sw, se, liv};
  std::shuffle(rooms.begin(), rooms.end(), b.rng_);
  for (size_t k = 0; k < rooms.size(); ++k)
  {
    CourseGoal g;
    g.region = rooms[k];
    g.close_first = k > 0;
    b.course_.push_back(g);
  }
}

/// A shop (issue 33): rows of shelving (gondolas) with aisles 1.2-1.5 m wide between them and
/// along the wall shelves, sometimes a cross aisle, a front area with checkouts and a back aisle;
/// a trolley (or a box of stock) left in one aisle, sometimes a box in another, each leaving a gap
/// of 0.80-0.95 m. The course walks up and down aisles (through the narrowed one last) and ends
/// facing the plain back wall.
void shop(Builder& b)
{
  const double t2 = 0.075;
  const int rows = b.I(3, 5);
  const double wd = b.U(0.4, 0.6);  // the wall shelves' depth
  std::vector<double> aisle(static_cast<size_t>(rows) + 1), gd(static_cast<size_t>(rows));
  for (double& a : aisle) a = b.U(AISLE_MIN, AISLE_MAX);
  for (double& g : gd) g = b.U(0.9, 1.2);
  double W = 2 * (t2 + 0.02 + wd);
  for (double a : aisle) W += a;
  for (double g : gd) W += g;
  const double fz = b.U(3.0, 4.0), rl = b.U(8.0, 12.0), bz = b.U(3.0, 3.6);  // front area, rows, back aisle
  const double L = fz + rl + bz, H = b.U(3.0, 4.0);
  b.materials(b.U(0.3, 1));
  header(b, L, W, true, H, false);
  b.end_approach_ = 2.2;
  b.wall(0, 0, L, 0, H, b.wallMat());
  b.wall(0, W, L, W, H, b.wallMat());
  const double entrance = b.U(1.5, W - 1.5), entrance_w = b.U(1.8, 2.4);
  b.wall(0, 0, 0, W, H, b.wallMat(), {{entrance, entrance_w}}, 2.3, 1.8, false, "entrance");  // not walked
  b.wall(L, 0, L, W, H, "plainwall");
  b.end_x0_ = L, b.end_y0_ = 0, b.end_x1_ = L, b.end_y1_ = W, b.end_nx_ = -1, b.end_ny_ = 0;
  const double x0 = fz, x1 = fz + rl;
  const bool cross = b.P(0.5);
  const double xm = x0 + rl * b.U(0.4, 0.6), cw = b.U(AISLE_MIN, AISLE_MAX);
  const double sh = b.U(1.4, 1.9);
  auto shelving = [&](double ya, double yb, const std::string& what, bool split) {
    if (split)
    {
      b.boxAt(Rect{x0, ya, xm - cw / 2, yb}, sh, b.furnMat(), what);
      b.boxAt(Rect{xm + cw / 2, ya, x1, yb}, sh, b.furnMat(), what);
    }
    else
      b.boxAt(Rect{x0, ya, x1, yb}, sh, b.furnMat(), what);
  };
  double y = t2 + 0.02;
  shelving(y, y + wd, "wall shelves", false);
  y += wd;
  std::vector<double> ya(aisle.size()), yb(aisle.size());
  for (size_t i = 0; i < aisle.size(); ++i)
  {
    ya[i] = y, yb[i] = y + aisle[i];
    y += aisle[i];
    if (i < gd.size())
    {
      shelving(y, y + gd[i], "a row of shelving, aisles of " + num(aisle[i]) + " and " + num(aisle[i + 1]) + " m", cross);
      y += gd[i];
    }
  }
  shelving(y, y + wd, "wall shelves", false);
  // Objects left in the aisles: a trolley (or a box of stock where a trolley would leave less
  // than GAP_MIN), sometimes a box in another aisle. Each aisle's lane runs its length and 0.7 m
  // into the front and back areas.
  // The trolley's aisle: one wide enough for a trolley (1.35 m) if there is one.
  std::vector<size_t> wide;
  for (size_t i = 0; i < aisle.size(); ++i)
    if (aisle[i] - 0.55 >= GAP_MIN) wide.push_back(i);
  const size_t k_trolley = wide.empty() ? static_cast<size_t>(b.I(0, rows)) : wide[static_cast<size_t>(b.I(0, static_cast<int>(wide.size()) - 1))];
  const size_t k_box = b.P(0.5) ? static_cast<size_t>(b.I(0, rows)) : aisle.size();
  std::vector<double> avoid;
  if (cross) avoid.push_back(xm);
  std::vector<Rect> left(aisle.size(), Rect{0, 0, 0, 0});  // what was left in each aisle (x1 = 0: nothing)
  for (size_t i = 0; i < aisle.size(); ++i)
  {
    std::vector<std::pair<double, double>> lane{{x0 - 0.7, 0.5 * (ya[i] + yb[i])}, {x1 + 0.7, 0.5 * (ya[i] + yb[i])}};
    if (i == k_trolley)
    {
      // not in the last 2 m of the aisle: the course's place in this aisle lies past it
      const double tx1 = x1 - 2.0;
      if (aisle[i] - 0.55 >= GAP_MIN)
        lane = leftInPassage(b, x0, tx1, ya[i], yb[i], {{0.9, 0.55, 1.0, 0}}, {"a shopping trolley"}, avoid, avoid,
                             cw / 2 + 0.8, x0 - 0.7, x1 + 0.7, &left[i]);
      else
        lane = leftInPassage(b, x0, tx1, ya[i], yb[i], {{b.U(0.4, 0.8), b.U(0.25, aisle[i] - GAP_MIN), b.U(0.3, 0.6), 0}},
                             {"a box of stock"}, avoid, avoid, cw / 2 + 0.8, x0 - 0.7, x1 + 0.7, &left[i]);
    }
    else if (i == k_box)
      lane = leftInPassage(b, x0, x1, ya[i], yb[i], {{b.U(0.4, 0.8), b.U(0.25, 0.4), b.U(0.3, 0.6), 0}},
                           {"a box of stock"}, avoid, avoid, cw / 2 + 0.8, x0 - 0.7, x1 + 0.7, &left[i]);
    b.lanes(lane);
  }
  if (cross) b.lane(xm, 0.5 * (ya.front() + yb.front()), xm, 0.5 * (ya.back() + yb.back()));
  for (size_t i = 0; i < aisle.size(); ++i)  // each aisle's width where nothing stands in it
    for (double x = x0 + 0.3; x < x1 - 0.3; x += 0.05)
      if ((!cross || std::abs(x - xm) > cw / 2 + 0.1) && (left[i].x1 <= 0 || x < left[i].x0 - 0.1 || x > left[i].x1 + 0.1))
      {
        b.passage("aisle", x, 0.5 * (ya[i] + yb[i]), 0, 1, aisle[i]);
        break;
      }
  if (cross) b.passage("aisle", xm, 0.5 * (ya[0] + yb[0]) + 0.5 * aisle[0] + 0.5 * gd[0], 1, 0, cw);
  // Checkouts in the front area, a stack of boxes in the back aisle.
  const Rect front{t2, t2, fz - 0.3, W - t2}, back{x1 + 0.3, t2, L - t2, W - t2};
  for (int i = b.I(1, 2); i > 0; --i)
  {
    const double len = b.U(1.2, 2.0);
    b.freeStanding(front, 0.7, len, 0.9, "box", b.furnMat(), 1.3, 0.9, 0.0, "a checkout");
  }
  if (b.P(0.5))
  {
    const double sx = b.U(0.8, 1.2), sy = b.U(0.8, 1.2), h = b.U(1.0, 1.6);
    const int side = b.I(0, 1);
    b.againstWall(back, sx, sy, h, b.furnMat(), 1.3, "boxes of stock", side);
  }
  // The course: into one aisle, to the back, down another, to the front, up the narrowed one, to the back wall.
  std::vector<size_t> others;
  for (size_t i = 0; i < aisle.size(); ++i)
    if (i != k_trolley) others.push_back(i);
  std::shuffle(others.begin(), others.end(), b.rng_);
  // A place on aisle i's middle line, near x: off the cross aisle and clear of what was left there.
  auto aislePoint = [&](size_t i, double x) {
    for (int k = 0; k < 20; ++k)
    {
      const bool off_cross = !cross || std::abs(x - xm) > cw / 2 + 0.7;
      const bool off_left = left[i].x1 <= 0 || x < left[i].x0 - 0.8 || x > left[i].x1 + 0.8;
      if (off_cross && off_left) break;
      x = x0 + rl * b.U(0.15, 0.85);
    }
    CourseGoal g;
    g.is_point = true;
    g.px = x;
    g.py = 0.5 * (ya[i] + yb[i]);
    return g;
  };
  auto region = [&](const Rect& r) {
    CourseGoal g;
    g.region = r;
    return g;
  };
  const double past = std::min(x1 - 0.5, (left[k_trolley].x1 > 0 ? left[k_trolley].x1 : x0 + rl * 0.5) + b.U(1.0, 2.0));
  const CourseGoal a1 = aislePoint(others[0], x0 + rl * b.U(0.3, 0.7));
  const CourseGoal a2 = aislePoint(others[1], x0 + rl * b.U(0.3, 0.7));
  b.course_ = {region(front), a1, region(back), a2, region(front), aislePoint(k_trolley, past)};
}

// ---- the walk
struct Plan
{
  const World* w;
  int nx, ny;
  double ox, oy;
  cv::Mat clear;  // CV_32F, m to the nearest obstacle (or the floor's edge)
  cv::Mat furn;   // CV_32F, m to the nearest obstacle that is not a wall
  cv::Mat comp;   // CV_32S component labels of the walkable cells (pass)
  cv::Mat lane;   // CV_8U, 255: the cell's centre is within LANE_HALF of a lane
  std::vector<std::array<double, 4>> lanes;
  std::vector<std::array<double, 5>> doors;  // Builder::doors_
  int main_label = 0;

  Eigen::Vector2d at(int i, int j) const { return {ox + (i + 0.5) * PLAN_RES, oy + (j + 0.5) * PLAN_RES}; }
  bool cell(const Eigen::Vector2d& p, int& i, int& j) const
  {
    i = static_cast<int>(std::floor((p.x() - ox) / PLAN_RES));
    j = static_cast<int>(std::floor((p.y() - oy) / PLAN_RES));
    return i >= 0 && j >= 0 && i < nx && j < ny;
  }
  float clr(const Eigen::Vector2d& p) const
  {
    int i, j;
    return cell(p, i, j) ? clear.at<float>(j, i) : 0.f;
  }
  bool inMain(const Eigen::Vector2d& p) const
  {
    int i, j;
    return cell(p, i, j) && comp.at<int>(j, i) == main_label;
  }
  bool segmentClear(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double c) const
  {
    const int n = std::max(1, static_cast<int>((b - a).norm() / (PLAN_RES * 0.5)));
    for (int k = 0; k <= n; ++k)
      if (clr(a + (b - a) * (static_cast<double>(k) / n)) < c) return false;
    return true;
  }
  /// May the walk stand on cell (i, j): PLAN_CLEAR, or PASS_CLEAR on a lane?
  bool pass(int i, int j) const
  {
    const float c = clear.at<float>(j, i);
    return c >= PLAN_CLEAR || (lane.at<uint8_t>(j, i) && c >= PASS_CLEAR);
  }
  bool pass(const Eigen::Vector2d& p) const
  {
    int i, j;
    return cell(p, i, j) && pass(i, j);
  }
  /// May a straight leg run from a to b (every sample walkable)?
  bool segmentPass(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const
  {
    const int n = std::max(1, static_cast<int>((b - a).norm() / (PLAN_RES * 0.5)));
    for (int k = 0; k <= n; ++k)
      if (!pass(a + (b - a) * (static_cast<double>(k) / n))) return false;
    return true;
  }
  double laneDist(const Eigen::Vector2d& p) const
  {
    double best = 1e9;
    for (const auto& l : lanes) best = std::min(best, Builder::segDist(l, p.x(), p.y()));
    return best;
  }
};

Plan makePlan(const World& w, const std::vector<bool>& is_wall, const std::vector<std::array<double, 4>>& lanes,
              const std::vector<std::array<double, 5>>& doors)
{
  Plan p;
  p.w = &w;
  p.lanes = lanes;
  p.doors = doors;
  p.ox = w.floor_min.x();
  p.oy = w.floor_min.y();
  p.nx = static_cast<int>(std::ceil((w.floor_max.x() - p.ox) / PLAN_RES));
  p.ny = static_cast<int>(std::ceil((w.floor_max.y() - p.oy) / PLAN_RES));
  cv::Mat freeAll(p.ny, p.nx, CV_8U, cv::Scalar(255)), freeFurn(p.ny, p.nx, CV_8U, cv::Scalar(255));
  for (size_t k = 0; k < w.solids.size(); ++k)
  {
    const Solid& s = w.solids[k];
    // Everything below 2 m blocks the walk, steps and curbs too (the walker stays on z = 0).
    if (s.z1 <= 0.02 || s.z0 >= 2.0) continue;
    for (int j = 0; j < p.ny; ++j)
      for (int i = 0; i < p.nx; ++i)
        if (s.containsXY(p.at(i, j).x(), p.at(i, j).y()))
        {
          freeAll.at<uint8_t>(j, i) = 0;
          if (!is_wall[k] && !s.walkable) freeFurn.at<uint8_t>(j, i) = 0;
        }
  }
  // The floor's edge is an obstacle too.
  cv::rectangle(freeAll, cv::Rect(0, 0, p.nx, p.ny), cv::Scalar(0), 1);
  cv::distanceTransform(freeAll, p.clear, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::distanceTransform(freeFurn, p.furn, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  p.clear *= PLAN_RES;
  p.furn *= PLAN_RES;
  p.lane = cv::Mat(p.ny, p.nx, CV_8U, cv::Scalar(0));
  for (const auto& l : lanes)
  {
    const int i0 = std::max(0, static_cast<int>(std::floor((std::min(l[0], l[2]) - LANE_HALF - p.ox) / PLAN_RES)));
    const int i1 = std::min(p.nx - 1, static_cast<int>(std::ceil((std::max(l[0], l[2]) + LANE_HALF - p.ox) / PLAN_RES)));
    const int j0 = std::max(0, static_cast<int>(std::floor((std::min(l[1], l[3]) - LANE_HALF - p.oy) / PLAN_RES)));
    const int j1 = std::min(p.ny - 1, static_cast<int>(std::ceil((std::max(l[1], l[3]) + LANE_HALF - p.oy) / PLAN_RES)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        if (Builder::segDist(l, p.at(i, j).x(), p.at(i, j).y()) <= LANE_HALF + 1e-9) p.lane.at<uint8_t>(j, i) = 255;
  }
  cv::Mat ok = (p.clear >= PLAN_CLEAR) | (p.lane & (p.clear >= PASS_CLEAR));
  cv::Mat stats, cents;
  const int n = cv::connectedComponentsWithStats(ok, p.comp, stats, cents, 8, CV_32S);
  int best = 0;
  for (int l = 1; l < n; ++l)
    if (best == 0 || stats.at<int>(l, cv::CC_STAT_AREA) > stats.at<int>(best, cv::CC_STAT_AREA)) best = l;
  p.main_label = best;
  return p;
}

/// A* on the planning grid through cells with clearance >= PLAN_CLEAR, preferring more clearance;
/// the path is shortened to the fewest points whose segments keep PLAN_CLEAR.
bool route(const Plan& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b, std::vector<Eigen::Vector2d>& out)
{
  int ai, aj, bi, bj;
  if (!p.cell(a, ai, aj) || !p.cell(b, bi, bj)) return false;
  const int N = p.nx * p.ny;
  std::vector<float> g(N, 1e30f);
  std::vector<int> parent(N, -1);
  using QE = std::pair<float, int>;
  std::priority_queue<QE, std::vector<QE>, std::greater<QE>> q;
  const int s = aj * p.nx + ai, t = bj * p.nx + bi;
  g[s] = 0;
  q.push({0, s});
  while (!q.empty())
  {
    const auto [f, c] = q.top();
    q.pop();
    if (c == t) break;
    const int ci = c % p.nx, cj = c / p.nx;
    if (f - std::hypot(ci - bi, cj - bj) > g[c] + 1e-3f) continue;
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di)
      {
        if (!di && !dj) continue;
        const int ni = ci + di, nj = cj + dj;
        if (ni < 0 || nj < 0 || ni >= p.nx || nj >= p.ny) continue;
        const float cl = p.clear.at<float>(nj, ni);
        if (!p.pass(ni, nj)) continue;
        const float step = std::hypot(static_cast<float>(di), static_cast<float>(dj)) * (1.f + 2.f * std::max(0.f, 1.2f - cl));
        const int n = nj * p.nx + ni;
        if (g[c] + step < g[n])
        {
          g[n] = g[c] + step;
          parent[n] = c;
          q.push({g[n] + static_cast<float>(std::hypot(ni - bi, nj - bj)), n});
        }
      }
  }
  if (parent[t] < 0 && s != t) return false;
  std::vector<Eigen::Vector2d> path;
  for (int c = t; c != s; c = parent[c]) path.push_back(p.at(c % p.nx, c / p.nx));
  path.push_back(a);
  std::reverse(path.begin(), path.end());
  path.back() = b;
  // Where the path goes through a doorway the walk may use, it goes through the doorway's centre,
  // which the shortcut keeps: the legs either side run in the doorway's lane wherever the
  // clearance is below PLAN_CLEAR, so the walk crosses the doorway along its middle line.
  std::vector<bool> forced(path.size(), false);
  for (const auto& d : p.doors)
  {
    const Eigen::Vector2d c(d[0], d[1]), n(d[2], d[3]), tw(-d[3], d[2]);
    for (size_t k = 0; k + 1 < path.size(); ++k)
    {
      const double sa = (path[k] - c).dot(n), sb = (path[k + 1] - c).dot(n);
      if (forced[k] || forced[k + 1] || (sa > 0) == (sb > 0) || sa == sb) continue;
      const Eigen::Vector2d x = path[k] + (path[k + 1] - path[k]) * (sa / (sa - sb));
      if (std::abs((x - c).dot(tw)) > d[4] / 2) continue;
      path.insert(path.begin() + static_cast<long>(k) + 1, c);
      forced.insert(forced.begin() + static_cast<long>(k) + 1, true);
      ++k;
    }
  }
  // Shortcut: from each kept point, the farthest point still reachable in a clear straight line
  // (never past a doorway's centre).
  size_t i = 0;
  out.push_back(path[0]);
  while (i + 1 < path.size())
  {
    size_t j = path.size() - 1;
    for (size_t k = i + 1; k < path.size(); ++k)
      if (forced[k])
      {
        j = k;
        break;
      }
    while (j > i + 1 && !p.segmentPass(path[i], path[j])) --j;
    out.push_back(path[j]);
    i = j;
  }
  return true;
}

/// The camera's clearance from every solid below the head along the walk, sampled every 0.05 s:
/// the smallest where the camera is in a passage (within LANE_ZONE of a lane) and elsewhere.
void minCameraClearance(const Plan& p, const WearerMotion& m, double& open, double& passage)
{
  open = passage = 1e9;
  for (double t = 0.0; t <= m.duration(); t += 0.05)
  {
    const Eigen::Vector3d c = m.linkPose(t).translation();
    double& best = p.laneDist(Eigen::Vector2d(c.x(), c.y())) <= LANE_ZONE ? passage : open;
    for (const Solid& s : p.w->solids)
    {
      if (s.z1 <= 0.02 || s.z0 >= c.z() + 0.3) continue;
      if (s.containsXY(c.x(), c.y(), 0.0))
      {
        best = 0.0;
        return;
      }
      double lo = 0.0, hi = std::min(best, 2.0);
      if (!s.containsXY(c.x(), c.y(), hi)) continue;
      for (int it = 0; it < 16; ++it)
      {
        const double mid = 0.5 * (lo + hi);
        (s.containsXY(c.x(), c.y(), mid) ? hi : lo) = mid;
      }
      best = std::min(best, lo);
    }
  }
}

/// Waypoints: stand and turn on the spot, visit random goals with close passes by furniture,
/// end walking straight at the plain wall and stopping 0.9 m before it.
bool walk(Builder& b, const Plan& p, std::ostringstream& tr, double& length)
{
  // Candidate cells of the main component.
  std::vector<Eigen::Vector2d> open, close, roomy;
  for (int j = 0; j < p.ny; ++j)
    for (int i = 0; i < p.nx; ++i)
    {
      if (p.comp.at<int>(j, i) != p.main_label) continue;
      const float c = p.clear.at<float>(j, i), f = p.furn.at<float>(j, i);
      if (c >= 1.0f) open.push_back(p.at(i, j));
      if (c >= 0.75f && !b.course_.empty()) roomy.push_back(p.at(i, j));  // a course's places in small rooms
      if (f >= PLAN_CLEAR && f <= PLAN_CLEAR + 0.1f && c >= PLAN_CLEAR) close.push_back(p.at(i, j));
    }
  if (open.empty() && b.course_.empty()) return false;
  // End: facing the plain wall.
  Eigen::Vector2d end, pre;
  bool found = false;
  for (int k = 0; k < 200 && !found; ++k)
  {
    const double u = b.U(0.1, 0.9);
    const Eigen::Vector2d wp(b.end_x0_ + u * (b.end_x1_ - b.end_x0_), b.end_y0_ + u * (b.end_y1_ - b.end_y0_));
    const Eigen::Vector2d n(b.end_nx_, b.end_ny_);
    end = wp + 0.95 * n;
    pre = wp + b.end_approach_ * n;
    found = p.inMain(pre) && p.inMain(end) && p.segmentClear(pre, end, PLAN_CLEAR);
  }
  if (!found) return false;
  auto pick = [&](const std::vector<Eigen::Vector2d>& v) { return v[static_cast<size_t>(b.I(0, static_cast<int>(v.size()) - 1))]; };
  std::vector<Eigen::Vector2d> goals;
  if (b.course_.empty())
  {
    goals.push_back(pick(open));
    const int n_goals = b.I(2, 3);
    for (int k = 0; k < n_goals; ++k)
    {
      if (!close.empty()) goals.push_back(pick(close));  // pass close by furniture
      Eigen::Vector2d g = pick(open);
      for (int tries = 0; tries < 20 && (g - goals.back()).norm() < 4.0; ++tries) g = pick(open);
      goals.push_back(g);
    }
  }
  else
  {
    // The builder's course (home, shop): a place in each region in turn (or the given point),
    // some preceded by a close pass by furniture in the same region.
    auto inside = [&](const std::vector<Eigen::Vector2d>& v, const Rect& r) {
      std::vector<Eigen::Vector2d> in;
      for (const auto& q : v)
        if (q.x() >= r.x0 && q.x() <= r.x1 && q.y() >= r.y0 && q.y() <= r.y1) in.push_back(q);
      return in;
    };
    for (const CourseGoal& cg : b.course_)
    {
      if (cg.is_point)
      {
        const Eigen::Vector2d q(cg.px, cg.py);
        if (!p.inMain(q)) return false;
        goals.push_back(q);
        continue;
      }
      const std::vector<Eigen::Vector2d> near = inside(close, cg.region), far = inside(roomy, cg.region);
      if (cg.close_first && !near.empty() && !goals.empty()) goals.push_back(pick(near));
      if (far.empty()) return false;
      goals.push_back(pick(far));
    }
  }
  goals.push_back(pre);
  std::vector<Eigen::Vector2d> wps{goals[0]};
  for (size_t k = 0; k + 1 < goals.size(); ++k)
  {
    std::vector<Eigen::Vector2d> seg;
    if (!route(p, goals[k], goals[k + 1], seg)) return false;
    // A point closer than 0.3 m to the last one is dropped (unless the leg past it would then
    // leave a passage's lane).
    for (size_t i = 1; i < seg.size(); ++i)
      if ((seg[i] - wps.back()).norm() > 0.3 ||
          (!p.lanes.empty() && i + 1 < seg.size() && !p.segmentPass(wps.back(), seg[i + 1])))
        wps.push_back(seg[i]);
  }
  wps.push_back(end);
  length = 0.0;
  for (size_t i = 1; i < wps.size(); ++i) length += (wps[i] - wps[i - 1]).norm();

  TrajectoryScript s;
  s.waypoints = wps;
  s.speed = b.U(0.9, 1.3);
  s.eye_height = b.U(1.5, 1.75);
  s.corner_radius = 0.4;
  // Turning on the spot while standing at the start: a large head-and-body turn and back.
  const double yaw = b.U(60, 100) * (b.P(0.5) ? 1 : -1), rate = b.U(35, 55), back = b.U(35, 55);
  const double t1 = 0.5, d1 = 1.875 * std::abs(yaw) / rate, t2 = t1 + d1 + b.U(0.5, 1.5),
               d2 = 1.875 * std::abs(yaw) / back;
  s.start_still = t2 + d2 + 0.5;
  s.head_turns = {{t1, yaw * M_PI / 180, rate * M_PI / 180}, {t2, -yaw * M_PI / 180, back * M_PI / 180}};
  const WearerMotion m(s, 1);
  double open_clear, passage_clear;
  minCameraClearance(p, m, open_clear, passage_clear);
  if (open_clear < WALK_CLEAR_MIN || passage_clear < WALK_CLEAR_LANE) return false;

  tr << "trajectory:\n  speed: " << num(s.speed) << "\n  eye_height: " << num(s.eye_height)
     << "\n  start_still: " << num(s.start_still) << "\n  corner_radius: " << num(s.corner_radius)
     << "\n  # Stands, turns on the spot and back, walks past furniture, ends facing a plain wall.\n"
     << "  head_turns: [{at: " << num(t1) << ", yaw: " << num(yaw) << ", rate: " << num(rate) << "}, {at: " << num(t2)
     << ", yaw: " << num(-yaw) << ", rate: " << num(back) << "}]\n  waypoints: [";
  for (size_t i = 0; i < wps.size(); ++i) tr << (i ? ", " : "") << pt(wps[i].x(), wps[i].y());
  tr << "]\n";
  return true;
}
/// Clothing materials for generated people (appended to `materials:` only when there are people).
const char* CLOTHING =
    "  person_dark: {pattern: noise, albedo: 0.2, contrast: 0.5, scale: 0.06, seed: 41}\n"
    "  person_red: {pattern: noise, albedo: 0.45, contrast: 0.7, scale: 0.1, seed: 42}\n"
    "  person_check: {pattern: tiles, albedo: 0.55, contrast: 0.5, scale: 0.12, seed: 43}\n"
    "  person_light: {pattern: bricks, albedo: 0.7, contrast: 0.4, scale: 0.1, seed: 44}\n";

/// `count` people whose straight walks cross the scripted walk where the wearer is at a drawn
/// time (crossing at 45-135 deg either side, or head-on, 0-0.3 m off the walk), on legs that keep
/// radius + 0.2 m from every obstacle (the planning grid's clearance); each starts early enough
/// to meet the wearer then. A separate generator (seeded with the seed and the count), so the
/// world itself does not change with `count`. The `people:` YAML list.
std::string peopleYaml(const Plan& p, const TrajectoryScript& script, uint32_t seed, int count)
{
  std::mt19937 rng(seed * 2654435761u + 7919u * static_cast<uint32_t>(count) + 1u);
  auto U = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  const WearerMotion m(script, 1);
  const char* mats[] = {"person_dark", "person_red", "person_check", "person_light"};
  std::ostringstream y;
  y << "people:\n  # Each crosses the scripted walk where the wearer is at `meets` s (generate_world --people).\n";
  int made = 0;
  for (int k = 0; k < count; ++k)
  {
    for (int tries = 0; tries < 60; ++tries)
    {
      const double t_lo = script.start_still + 1.0, t_hi = m.duration() - 0.5;
      if (t_hi <= t_lo) break;
      const double te = U(t_lo, t_hi);
      const Eigen::Vector3d c = m.linkPose(te).translation();
      const Eigen::Vector3d v = m.velocity(te);
      if (std::hypot(v.x(), v.y()) < 0.2) continue;
      const double heading = std::atan2(v.y(), v.x());
      const bool head_on = U(0, 1) < 0.25;
      const double side = U(0, 1) < 0.5 ? 1.0 : -1.0;
      const double ang = head_on ? heading + M_PI + U(-0.15, 0.15) : heading + side * U(M_PI / 4, 3 * M_PI / 4);
      const Eigen::Vector2d d(std::cos(ang), std::sin(ang));
      const Eigen::Vector2d n(-std::sin(heading), std::cos(heading));
      const Eigen::Vector2d meet = Eigen::Vector2d(c.x(), c.y()) + n * U(-0.3, 0.3);
      const double radius = U(0.19, 0.25), height = U(1.55, 1.9), speed = U(0.6, 1.6);
      const double need = radius + 0.2;  // the 5 cm grid's clearance is up to ~0.1 m optimistic
      if (p.clr(meet) < need) continue;
      // The longest legs (before: up to 5 m and no earlier than t = 0; after: up to 3 m) that stay clear.
      double before = std::min(5.0, te * speed), after = 3.0;
      while (before > 1.0 && !p.segmentClear(meet - d * before, meet, need)) before -= 0.25;
      while (after > 0.5 && !p.segmentClear(meet, meet + d * after, need)) after -= 0.25;
      if (before <= 1.0 || after <= 0.5) continue;
      const Eigen::Vector2d a = meet - d * before, b = meet + d * after;
      y << "  - {name: gen_person_" << made << ", radius: " << num(radius) << ", height: " << num(height)
        << ", material: " << mats[made % 4] << ", walk: {waypoints: [" << pt(a.x(), a.y()) << ", " << pt(b.x(), b.y())
        << "], speed: " << num(speed) << ", start: " << num(std::max(0.0, te - before / speed)) << "}}  # meets "
        << num(te) << (head_on ? " head-on" : " crossing") << "\n";
      ++made;
      break;
    }
  }
  return made > 0 ? y.str() : std::string();
}
}  // namespace

const std::vector<std::string>& WorldGenerator::kinds()
{
  static const std::vector<std::string> k{"office", "lobby", "corridor", "hall", "street", "home", "shop"};
  return k;
}

WorldGenerator::WorldGenerator(uint32_t seed, const std::string& kind, int people)
  : seed_(seed), kind_(kind), people_(people)
{
  if (people_ < 0 || people_ > 100) throw std::invalid_argument("people: 0 .. 100");
  // The seed chooses among the first five kinds, as before `home` and `shop` existed (the shared
  // generated sets, e.g. vo_benchmark --generated N, keep their worlds); those two by name only.
  if (kind_.empty()) kind_ = kinds()[seed % 5];
  if (std::find(kinds().begin(), kinds().end(), kind_) == kinds().end())
    throw std::invalid_argument("unknown world kind '" + kind_ + "' (office, lobby, corridor, hall, street, home, shop)");
}

GeneratedWorld WorldGenerator::generate() const
{
  // Layout attempts: each draws a fresh layout from the same generator, so the result depends
  // only on the seed.
  std::mt19937 outer(seed_);
  for (int attempt = 0; attempt < 20; ++attempt)
  {
    Builder b(outer(), kind_);
    b.pale_ = pale_;
    if (kind_ == "office") office(b);
    else if (kind_ == "lobby") lobby(b);
    else if (kind_ == "corridor") corridor(b);
    else if (kind_ == "hall") hall(b);
    else if (kind_ == "home") home(b);
    else if (kind_ == "shop") shop(b);
    else street(b);

    std::ostringstream head, mats_end;
    head << "# Generated by `generate_world --seed " << seed_ << " --kind " << kind_ << (pale_ ? " --pale" : "")
         << "` (assistive_sim).\n"
         << "name: gen_" << kind_ << (pale_ ? "_pale_" : "_") << seed_ << "\n"
         << "description: Generated " << (pale_ ? "pale " : "") << kind_ << " (seed " << seed_ << ", texture richness "
         << num(b.rich_) << ").\n"
         << "materials:\n" << b.mats_.str();
    const std::string head_materials = head.str();  // people add their clothing after these
    mats_end << b.header_ << "elements:\n";
    for (const auto& e : b.elems_) mats_end << "  - " << e << "\n";
    head << mats_end.str();
    // Parse the layout alone (a stand-in walk) to plan on the parser's own solids.
    const World layout = World::parse(head.str() + "trajectory: {waypoints: [[0, 0], [1, 0]]}\n", "generated layout");
    std::vector<bool> is_wall(layout.solids.size(), false);
    for (size_t k = 0; k < layout.solids.size(); ++k) is_wall[k] = layout.solids[k].source.find("(wall)") != std::string::npos;
    const Plan plan = makePlan(layout, is_wall, b.lanes_, b.doors_);
    // Walks drawn per layout: 5 (20 where there are narrow passages: a walk through several
    // doorways is refused more often for coming too close to something).
    for (int w = 0; w < (b.lanes_.empty() ? 5 : 20); ++w)
    {
      std::ostringstream tr;
      double len = 0.0;
      if (!walk(b, plan, tr, len)) continue;
      GeneratedWorld g;
      g.kind = kind_;
      g.yaml = head.str() + tr.str();
      if (people_ > 0)
      {
        const World walked = World::parse(g.yaml, "generated walk");
        const std::string people = peopleYaml(plan, walked.trajectory, seed_, people_);
        if (!people.empty()) g.yaml = head_materials + CLOTHING + mats_end.str() + tr.str() + people;
      }
      g.world = World::parse(g.yaml, "generated " + kind_ + " seed " + std::to_string(seed_));
      g.elements = static_cast<int>(b.elems_.size());
      g.walk_length = len;
      g.people = static_cast<int>(g.world.people.size());
      g.passages = b.passages_;
      return g;
    }
  }
  throw std::runtime_error("generate_world: no clear walk found for seed " + std::to_string(seed_) + " kind " + kind_);
}

}  // namespace assistive_sim
