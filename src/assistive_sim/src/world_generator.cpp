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
  void wall(double x0, double y0, double x1, double y1, double h, const std::string& mat,
            const std::vector<std::pair<double, double>>& doors = {}, double door_h = 2.1)
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
      keep_.push_back({x0 + (x1 - x0) * d.first / len, y0 + (y1 - y0) * d.first / len, 1.4 + d.second / 2, false});
  }
  void raw(const std::string& e) { elems_.push_back(e); }

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
  std::ostringstream mats_;
  std::vector<std::string> elems_;
  std::vector<std::array<double, 4>> walls_;
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
  // A partition across the room with a doorway, and maybe a second one closing a side room.
  const double px = L * b.U(0.4, 0.6);
  b.wall(px, 0, px, W, H, b.wallMat(), {{b.U(1.3, W - 1.3), b.U(1.3, 1.5)}});
  if (b.P(0.6))
  {
    const double py = W * b.U(0.45, 0.6);
    b.wall(0, py, px, py, H, b.wallMat(), {{b.U(1.3, px - 1.3), b.U(1.3, 1.5)}});
  }
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

// ---- the walk
struct Plan
{
  const World* w;
  int nx, ny;
  double ox, oy;
  cv::Mat clear;  // CV_32F, m to the nearest obstacle (or the floor's edge)
  cv::Mat furn;   // CV_32F, m to the nearest obstacle that is not a wall
  cv::Mat comp;   // CV_32S component labels of clear >= PLAN_CLEAR
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
};

Plan makePlan(const World& w, const std::vector<bool>& is_wall)
{
  Plan p;
  p.w = &w;
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
  cv::Mat ok = p.clear >= PLAN_CLEAR;
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
        if (cl < PLAN_CLEAR) continue;
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
  // Shortcut: from each kept point, the farthest point still reachable in a clear straight line.
  size_t i = 0;
  out.push_back(path[0]);
  while (i + 1 < path.size())
  {
    size_t j = path.size() - 1;
    while (j > i + 1 && !p.segmentClear(path[i], path[j], PLAN_CLEAR)) --j;
    out.push_back(path[j]);
    i = j;
  }
  return true;
}

double minCameraClearance(const World& w, const WearerMotion& m)
{
  double best = 1e9;
  for (double t = 0.0; t <= m.duration(); t += 0.05)
  {
    const Eigen::Vector3d c = m.linkPose(t).translation();
    for (const Solid& s : w.solids)
    {
      if (s.z1 <= 0.02 || s.z0 >= c.z() + 0.3) continue;
      if (s.containsXY(c.x(), c.y(), 0.0)) return 0.0;
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
  return best;
}

/// Waypoints: stand and turn on the spot, visit random goals with close passes by furniture,
/// end walking straight at the plain wall and stopping 0.9 m before it.
bool walk(Builder& b, const Plan& p, std::ostringstream& tr, double& length)
{
  // Candidate cells of the main component.
  std::vector<Eigen::Vector2d> open, close;
  for (int j = 0; j < p.ny; ++j)
    for (int i = 0; i < p.nx; ++i)
    {
      if (p.comp.at<int>(j, i) != p.main_label) continue;
      const float c = p.clear.at<float>(j, i), f = p.furn.at<float>(j, i);
      if (c >= 1.0f) open.push_back(p.at(i, j));
      if (f >= PLAN_CLEAR && f <= PLAN_CLEAR + 0.1f) close.push_back(p.at(i, j));
    }
  if (open.empty()) return false;
  // End: facing the plain wall.
  Eigen::Vector2d end, pre;
  bool found = false;
  for (int k = 0; k < 200 && !found; ++k)
  {
    const double u = b.U(0.1, 0.9);
    const Eigen::Vector2d wp(b.end_x0_ + u * (b.end_x1_ - b.end_x0_), b.end_y0_ + u * (b.end_y1_ - b.end_y0_));
    const Eigen::Vector2d n(b.end_nx_, b.end_ny_);
    end = wp + 0.95 * n;
    pre = wp + 3.0 * n;
    found = p.inMain(pre) && p.inMain(end) && p.segmentClear(pre, end, PLAN_CLEAR);
  }
  if (!found) return false;
  auto pick = [&](const std::vector<Eigen::Vector2d>& v) { return v[static_cast<size_t>(b.I(0, static_cast<int>(v.size()) - 1))]; };
  std::vector<Eigen::Vector2d> goals{pick(open)};
  const int n_goals = b.I(2, 3);
  for (int k = 0; k < n_goals; ++k)
  {
    if (!close.empty()) goals.push_back(pick(close));  // pass close by furniture
    Eigen::Vector2d g = pick(open);
    for (int tries = 0; tries < 20 && (g - goals.back()).norm() < 4.0; ++tries) g = pick(open);
    goals.push_back(g);
  }
  goals.push_back(pre);
  std::vector<Eigen::Vector2d> wps{goals[0]};
  for (size_t k = 0; k + 1 < goals.size(); ++k)
  {
    std::vector<Eigen::Vector2d> seg;
    if (!route(p, goals[k], goals[k + 1], seg)) return false;
    for (size_t i = 1; i < seg.size(); ++i)
      if ((seg[i] - wps.back()).norm() > 0.3) wps.push_back(seg[i]);
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
  if (minCameraClearance(*p.w, m) < WALK_CLEAR_MIN) return false;

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
  static const std::vector<std::string> k{"office", "lobby", "corridor", "hall", "street"};
  return k;
}

WorldGenerator::WorldGenerator(uint32_t seed, const std::string& kind, int people)
  : seed_(seed), kind_(kind), people_(people)
{
  if (people_ < 0 || people_ > 100) throw std::invalid_argument("people: 0 .. 100");
  if (kind_.empty()) kind_ = kinds()[seed % kinds().size()];
  if (std::find(kinds().begin(), kinds().end(), kind_) == kinds().end())
    throw std::invalid_argument("unknown world kind '" + kind_ + "' (office, lobby, corridor, hall, street)");
}

GeneratedWorld WorldGenerator::generate() const
{
  // Layout attempts: each draws a fresh layout from the same generator, so the result depends
  // only on the seed.
  std::mt19937 outer(seed_);
  for (int attempt = 0; attempt < 20; ++attempt)
  {
    Builder b(outer(), kind_);
    if (kind_ == "office") office(b);
    else if (kind_ == "lobby") lobby(b);
    else if (kind_ == "corridor") corridor(b);
    else if (kind_ == "hall") hall(b);
    else street(b);

    std::ostringstream head, mats_end;
    head << "# Generated by `generate_world --seed " << seed_ << " --kind " << kind_ << "` (assistive_sim).\n"
         << "name: gen_" << kind_ << "_" << seed_ << "\n"
         << "description: Generated " << kind_ << " (seed " << seed_ << ", texture richness " << num(b.rich_) << ").\n"
         << "materials:\n" << b.mats_.str();
    const std::string head_materials = head.str();  // people add their clothing after these
    mats_end << b.header_ << "elements:\n";
    for (const auto& e : b.elems_) mats_end << "  - " << e << "\n";
    head << mats_end.str();
    // Parse the layout alone (a stand-in walk) to plan on the parser's own solids.
    const World layout = World::parse(head.str() + "trajectory: {waypoints: [[0, 0], [1, 0]]}\n", "generated layout");
    std::vector<bool> is_wall(layout.solids.size(), false);
    for (size_t k = 0; k < layout.solids.size(); ++k) is_wall[k] = layout.solids[k].source.find("(wall)") != std::string::npos;
    const Plan plan = makePlan(layout, is_wall);
    for (int w = 0; w < 5; ++w)
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
      return g;
    }
  }
  throw std::runtime_error("generate_world: no clear walk found for seed " + std::to_string(seed_) + " kind " + kind_);
}

}  // namespace assistive_sim
