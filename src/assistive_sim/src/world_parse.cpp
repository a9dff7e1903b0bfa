// World files (README "World files"): YAML parsing into World, with errors that name the file,
// line and field, and the lookup of shipped worlds. Geometry and occupancy: world_occupancy.cpp.
#include <assistive_sim/world.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace assistive_sim
{
namespace
{
constexpr double DEG = M_PI / 180.0;

/// Parsing context: file name for messages.
struct Ctx
{
  std::string origin;

  [[noreturn]] void fail(const YAML::Node& n, const std::string& field, const std::string& what) const
  {
    std::ostringstream s;
    s << origin << ":" << (n.Mark().line >= 0 ? n.Mark().line + 1 : 0) << ": field '" << field
      << "': " << what;
    throw WorldError(s.str());
  }

  void checkKeys(const YAML::Node& map, const std::string& field, const std::set<std::string>& allowed) const
  {
    if (!map.IsMap()) fail(map, field, "expected a mapping");
    for (const auto& kv : map)
    {
      const std::string k = kv.first.as<std::string>();
      if (!allowed.count(k))
      {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(kv.first, field.empty() ? k : field + "." + k, "unknown field (allowed: " + list + ")");
      }
    }
  }

  double num(const YAML::Node& map, const std::string& key, const std::string& field, double def,
             bool required = false, double lo = -1e9, double hi = 1e9) const
  {
    const YAML::Node n = map[key];
    const std::string f = field.empty() ? key : field + "." + key;
    if (!n)
    {
      if (required) fail(map, f, "missing (required)");
      return def;
    }
    double v;
    try
    {
      if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "");
      v = n.as<double>();
    }
    catch (const YAML::Exception&)
    {
      fail(n, f, "expected a number");
    }
    if (!std::isfinite(v) || v < lo || v > hi)
    {
      std::ostringstream s;
      s << "value " << v << " outside [" << lo << ", " << hi << "]";
      fail(n, f, s.str());
    }
    return v;
  }

  std::vector<double> vec(const YAML::Node& map, const std::string& key, const std::string& field,
                          size_t count, bool required, std::vector<double> def = {}) const
  {
    const YAML::Node n = map[key];
    const std::string f = field.empty() ? key : field + "." + key;
    if (!n)
    {
      if (required) fail(map, f, "missing (required)");
      return def;
    }
    if (!n.IsSequence() || n.size() != count)
      fail(n, f, "expected a list of " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (size_t i = 0; i < count; ++i)
    {
      try
      {
        out.push_back(n[i].as<double>());
      }
      catch (const YAML::Exception&)
      {
        fail(n[i], f + "[" + std::to_string(i) + "]", "expected a number");
      }
      if (!std::isfinite(out.back())) fail(n[i], f, "not finite");
    }
    return out;
  }

  std::string str(const YAML::Node& map, const std::string& key, const std::string& field,
                  const std::string& def, bool required = false) const
  {
    const YAML::Node n = map[key];
    const std::string f = field.empty() ? key : field + "." + key;
    if (!n)
    {
      if (required) fail(map, f, "missing (required)");
      return def;
    }
    if (!n.IsScalar()) fail(n, f, "expected a string");
    return n.as<std::string>();
  }

  bool boolean(const YAML::Node& map, const std::string& key, const std::string& field, bool def) const
  {
    const YAML::Node n = map[key];
    if (!n) return def;
    try
    {
      return n.as<bool>();
    }
    catch (const YAML::Exception&)
    {
      fail(n, field + "." + key, "expected true or false");
    }
  }
};

/// Each item of the optional list `parent[key]` (a list of maps with `keys`): fn(item, its field
/// name "field.key[i]"); `expected` is the message when it is not a list.
template <typename F>
void forEachItem(const Ctx& c, const YAML::Node& parent, const std::string& field, const char* key,
                 const std::set<std::string>& keys, const char* expected, F fn)
{
  if (!parent[key])
    return;
  const YAML::Node list = parent[key];
  if (!list.IsSequence()) c.fail(list, field + "." + key, expected);
  for (size_t k = 0; k < list.size(); ++k)
  {
    const std::string item = field + "." + key + "[" + std::to_string(k) + "]";
    c.checkKeys(list[k], item, keys);
    fn(list[k], item);
  }
}

Pattern parsePattern(const Ctx& c, const YAML::Node& n, const std::string& field)
{
  static const std::map<std::string, Pattern> names = {{"plain", Pattern::PLAIN},
                                                       {"noise", Pattern::NOISE},
                                                       {"bricks", Pattern::BRICKS},
                                                       {"tiles", Pattern::TILES},
                                                       {"posters", Pattern::POSTERS}};
  const std::string s = c.str(n, "pattern", field, "noise");
  auto it = names.find(s);
  if (it == names.end()) c.fail(n["pattern"], field + ".pattern", "unknown pattern '" + s + "' (plain, noise, bricks, tiles, posters)");
  return it->second;
}

int materialRef(const Ctx& c, const YAML::Node& n, const std::string& field,
                const std::map<std::string, int>& ids, int def)
{
  if (!n["material"]) return def;
  const std::string s = c.str(n, "material", field, "");
  auto it = ids.find(s);
  if (it == ids.end()) c.fail(n["material"], field + ".material", "unknown material '" + s + "'");
  return it->second;
}

Solid box(double cx, double cy, double sx, double sy, double yaw, double z0, double z1, int mat,
          const std::string& src)
{
  Solid s;
  s.shape = Solid::BOX;
  s.center = {cx, cy};
  s.half = {sx / 2, sy / 2};
  s.yaw = yaw;
  s.z0 = z0;
  s.z1 = z1;
  s.material = mat;
  s.source = src;
  return s;
}

/// A list of at least `min` [x, y] points at `map[key]`.
std::vector<Eigen::Vector2d> points(const Ctx& c, const YAML::Node& map, const std::string& key,
                                    const std::string& field, size_t min)
{
  const YAML::Node n = map[key];
  const std::string f = field + "." + key;
  if (!n) c.fail(map, f, "missing (required)");
  if (!n.IsSequence() || n.size() < min)
    c.fail(n, f, "expected a list of at least " + std::to_string(min) + " [x, y] points");
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0; i < n.size(); ++i)
  {
    const std::string fi = f + "[" + std::to_string(i) + "]";
    if (!n[i].IsSequence() || n[i].size() != 2) c.fail(n[i], fi, "expected [x, y]");
    try
    {
      out.emplace_back(n[i][0].as<double>(), n[i][1].as<double>());
    }
    catch (const YAML::Exception&)
    {
      c.fail(n[i], fi, "expected two numbers");
    }
    if (!out.back().allFinite()) c.fail(n[i], fi, "not finite");
  }
  return out;
}

/// Append a straight walk to `to` at `speed` (and a pause there) to a person's knots.
void walkTo(Person& p, const Eigen::Vector2d& to, double speed, double pause)
{
  const double d = (to - p.knot_p.back()).norm();
  if (d > 1e-9)
  {
    p.knot_t.push_back(p.knot_t.back() + d / speed);
    p.knot_p.push_back(to);
  }
  if (pause > 0)
  {
    p.knot_t.push_back(p.knot_t.back() + pause);
    p.knot_p.push_back(to);
  }
}

/// The `people:` list (README "World files"): each person's script expanded into knots.
void parsePeople(const YAML::Node& root, const Ctx& c, const std::map<std::string, int>& ids, World& w)
{
  if (!root["people"]) return;
  const YAML::Node ps = root["people"];
  if (!ps.IsSequence()) c.fail(ps, "people", "expected a list of people");
  for (size_t i = 0; i < ps.size(); ++i)
  {
    const YAML::Node n = ps[i];
    const std::string f = "people[" + std::to_string(i) + "]";
    c.checkKeys(n, f, {"name", "radius", "height", "material", "walk", "random_walk", "stand"});
    Person p;
    p.source = f;
    p.name = c.str(n, "name", f, f);
    p.radius = c.num(n, "radius", f, p.radius, false, 0.1, 0.4);
    p.height = c.num(n, "height", f, p.height, false, 1.0, 2.2);
    p.material = materialRef(c, n, f, ids, 0);
    const int kinds = (n["walk"] ? 1 : 0) + (n["random_walk"] ? 1 : 0) + (n["stand"] ? 1 : 0);
    if (kinds != 1) c.fail(n, f, "expected exactly one of walk, random_walk, stand");
    if (const YAML::Node s = n["stand"])
    {
      const std::string sf = f + ".stand";
      c.checkKeys(s, sf, {"at", "yaw"});
      p.kind = Person::STAND;
      const auto at = c.vec(s, "at", sf, 2, true);
      p.knot_t = {0.0};
      p.knot_p = {Eigen::Vector2d(at[0], at[1])};
      p.stand_yaw = c.num(s, "yaw", sf, 0.0, false, -360, 360) * DEG;
    }
    else if (const YAML::Node s = n["walk"])
    {
      const std::string sf = f + ".walk";
      c.checkKeys(s, sf, {"waypoints", "speed", "mode", "start", "pause"});
      p.kind = Person::WALK;
      const auto wp = points(c, s, "waypoints", sf, 2);
      const double speed = c.num(s, "speed", sf, 1.2, false, 0.3, 2.5);
      const double start = c.num(s, "start", sf, 0.0, false, 0.0, 1e5);
      const double pause = c.num(s, "pause", sf, 0.0, false, 0.0, 600);
      const std::string mode = c.str(s, "mode", sf, "once");
      if (mode != "once" && mode != "loop" && mode != "back_and_forth")
        c.fail(s["mode"], sf + ".mode", "unknown mode '" + mode + "' (once, loop, back_and_forth)");
      for (size_t k = 1; k < wp.size(); ++k)
        if ((wp[k] - wp[k - 1]).norm() < 1e-6)
          c.fail(s["waypoints"][k], sf + ".waypoints[" + std::to_string(k) + "]", "repeats the previous waypoint");
      p.knot_t = {start};
      p.knot_p = {wp[0]};
      for (size_t k = 1; k < wp.size(); ++k) walkTo(p, wp[k], speed, mode == "once" && k + 1 == wp.size() ? 0.0 : pause);
      if (mode == "loop")
        walkTo(p, wp[0], speed, pause);
      else if (mode == "back_and_forth")
        for (size_t k = wp.size() - 1; k-- > 0;) walkTo(p, wp[k], speed, pause);
      if (mode != "once") p.period = p.knot_t.back() - p.knot_t.front();
      const Eigen::Vector2d d0 = wp[1] - wp[0];
      p.stand_yaw = std::atan2(d0.y(), d0.x());
    }
    else if (const YAML::Node s = n["random_walk"])
    {
      const std::string sf = f + ".random_walk";
      c.checkKeys(s, sf, {"points", "speed", "seed", "start", "pause", "duration"});
      p.kind = Person::RANDOM_WALK;
      const auto pts = points(c, s, "points", sf, 2);
      const double speed = c.num(s, "speed", sf, 1.2, false, 0.3, 2.5);
      const uint32_t seed = static_cast<uint32_t>(c.num(s, "seed", sf, 1, false, 0, 1e9));
      const double start = c.num(s, "start", sf, 0.0, false, 0.0, 1e5);
      const double pause = c.num(s, "pause", sf, 0.0, false, 0.0, 600);
      const double duration = c.num(s, "duration", sf, 3600.0, false, 1.0, 36000.0);
      // From points[0], each next point drawn uniformly among the others (std::mt19937 from the
      // seed, integer draws only: the same knots on every platform).
      std::mt19937 rng(seed * 2654435761u + 12345u);
      size_t at = 0;
      p.knot_t = {start};
      p.knot_p = {pts[0]};
      while (p.knot_t.back() < start + duration)
      {
        size_t next = static_cast<size_t>(rng() % (pts.size() - 1));
        if (next >= at) ++next;
        const size_t before = p.knot_t.size();
        walkTo(p, pts[next], speed, pause);
        if (p.knot_t.size() == before)  // coincident points: stand a moment so time advances
        {
          p.knot_t.push_back(p.knot_t.back() + std::max(pause, 1.0));
          p.knot_p.push_back(pts[next]);
        }
        at = next;
      }
      const Eigen::Vector2d d0 = p.knot_p.size() > 1 ? Eigen::Vector2d(p.knot_p[1] - p.knot_p[0]) : Eigen::Vector2d(1, 0);
      p.stand_yaw = std::atan2(d0.y(), d0.x());
    }
    // Facing per segment: the walking direction, kept while standing.
    double last_yaw = p.stand_yaw;
    if (p.period > 0)  // a periodic walk stands (pauses) at its first knot facing the way it came in
      for (size_t k = p.knot_p.size() - 1; k > 0; --k)
      {
        const Eigen::Vector2d d = p.knot_p[k] - p.knot_p[k - 1];
        if (d.norm() > 1e-9)
        {
          last_yaw = std::atan2(d.y(), d.x());
          break;
        }
      }
    for (size_t k = 0; k + 1 < p.knot_p.size(); ++k)
    {
      const Eigen::Vector2d d = p.knot_p[k + 1] - p.knot_p[k];
      if (d.norm() > 1e-9) last_yaw = std::atan2(d.y(), d.x());
      p.seg_yaw.push_back(last_yaw);
    }
    w.people.push_back(p);
  }
}

World parseRoot(const YAML::Node& root, const Ctx& c)
{
  World w;
  if (!root.IsMap()) c.fail(root, "", "a world file is a mapping (name, materials, floor, elements, trajectory)");
  c.checkKeys(root, "", {"name", "description", "materials", "floor", "ceiling", "sky", "light", "elements", "trajectory", "people"});
  w.name = c.str(root, "name", "", "world");
  w.description = c.str(root, "description", "", "");

  // Materials: a default one first.
  std::map<std::string, int> ids;
  Material def;
  def.name = "default";
  w.materials.push_back(def);
  ids["default"] = 0;
  if (root["materials"])
  {
    const YAML::Node ms = root["materials"];
    if (!ms.IsMap()) c.fail(ms, "materials", "expected a mapping name -> {pattern, albedo, contrast, scale, seed}");
    uint32_t auto_seed = 11;
    for (const auto& kv : ms)
    {
      const std::string name = kv.first.as<std::string>();
      const std::string f = "materials." + name;
      const YAML::Node m = kv.second;
      c.checkKeys(m, f, {"pattern", "albedo", "contrast", "scale", "seed"});
      Material mat;
      mat.name = name;
      mat.pattern = parsePattern(c, m, f);
      mat.albedo = c.num(m, "albedo", f, 0.5, false, 0.0, 1.0);
      mat.contrast = c.num(m, "contrast", f, mat.pattern == Pattern::PLAIN ? 0.02 : 0.5, false, 0.0, 1.0);
      mat.scale = c.num(m, "scale", f, 0.2, false, 0.01, 10.0);
      mat.seed = static_cast<uint32_t>(c.num(m, "seed", f, auto_seed += 7, false, 0, 1e9));
      ids[name] = static_cast<int>(w.materials.size());
      w.materials.push_back(mat);
    }
  }

  // Floor.
  const YAML::Node fl = root["floor"];
  if (!fl) c.fail(root, "floor", "missing (required): {min: [x, y], max: [x, y], material}");
  c.checkKeys(fl, "floor", {"min", "max", "material"});
  auto fmin = c.vec(fl, "min", "floor", 2, true);
  auto fmax = c.vec(fl, "max", "floor", 2, true);
  if (fmax[0] <= fmin[0] || fmax[1] <= fmin[1]) c.fail(fl, "floor.max", "must be larger than floor.min");
  w.floor_min = {fmin[0], fmin[1]};
  w.floor_max = {fmax[0], fmax[1]};
  w.floor_material = materialRef(c, fl, "floor", ids, 0);

  if (root["ceiling"])
  {
    const YAML::Node n = root["ceiling"];
    c.checkKeys(n, "ceiling", {"height", "material"});
    w.has_ceiling = true;
    w.ceiling_height = c.num(n, "height", "ceiling", 2.7, false, 2.0, 20.0);
    w.ceiling_material = materialRef(c, n, "ceiling", ids, 0);
  }
  if (root["sky"])
  {
    const YAML::Node n = root["sky"];
    c.checkKeys(n, "sky", {"brightness", "illuminance"});
    w.sky_brightness = c.num(n, "brightness", "sky", 0.75, false, 0.0, 1.0);
    w.illuminance_lux = c.num(n, "illuminance", "sky", -1.0, false, 0.01, 200000.0);
  }
  if (root["light"])
  {
    auto d = c.vec(root, "light", "", 3, true);
    Eigen::Vector3d v(d[0], d[1], d[2]);
    if (v.norm() < 1e-6) c.fail(root["light"], "light", "zero vector");
    w.light_dir = v.normalized();
  }

  // Elements.
  if (root["elements"])
  {
    const YAML::Node es = root["elements"];
    if (!es.IsSequence()) c.fail(es, "elements", "expected a list");
    for (size_t i = 0; i < es.size(); ++i)
    {
      const YAML::Node e = es[i];
      std::string f = "elements[" + std::to_string(i) + "]";
      if (!e.IsMap()) c.fail(e, f, "expected a mapping with a 'type'");
      const std::string type = c.str(e, "type", f, "", true);
      const std::string src = f + " (" + type + ")";
      f += "(" + type + ")";
      const int mat = materialRef(c, e, f, ids, 0);
      const double yaw = c.num(e, "yaw", f, 0.0, false, -360, 360) * DEG;
      if (type == "wall")
      {
        c.checkKeys(e, f, {"type", "from", "to", "height", "thickness", "base", "material", "openings"});
        auto a = c.vec(e, "from", f, 2, true), b = c.vec(e, "to", f, 2, true);
        const double h = c.num(e, "height", f, 2.5, false, 0.01, 50);
        const double th = c.num(e, "thickness", f, 0.15, false, 0.01, 5);
        const double base = c.num(e, "base", f, 0.0, false, -5, 50);
        const Eigen::Vector2d A(a[0], a[1]), B(b[0], b[1]);
        const double len = (B - A).norm();
        if (len < 0.01) c.fail(e["to"], f + ".to", "wall has zero length");
        const Eigen::Vector2d dir = (B - A) / len;
        const double wyaw = std::atan2(dir.y(), dir.x());
        // Openings (doorways): split the wall, keep a lintel above each.
        struct Op { double s0, s1, h; };
        std::vector<Op> ops;
        forEachItem(c, e, f, "openings", {"at", "width", "height"}, "expected a list of {at, width, height}",
                    [&](const YAML::Node& o, const std::string& of) {
                      const double at = c.num(o, "at", of, 0, true, 0, len);
                      const double wd = c.num(o, "width", of, 0.9, false, 0.1, len);
                      const double oh = c.num(o, "height", of, 2.1, false, 0.5, 50);
                      if (at - wd / 2 < -1e-9 || at + wd / 2 > len + 1e-9)
                        c.fail(o, of + ".at", "opening extends past the wall's ends");
                      ops.push_back({at - wd / 2, at + wd / 2, oh});
                    });
        std::sort(ops.begin(), ops.end(), [](const Op& x, const Op& y) { return x.s0 < y.s0; });
        double s = 0.0;
        auto seg = [&](double s0, double s1, double z0, double z1) {
          if (s1 - s0 < 1e-3 || z1 - z0 < 1e-3) return;
          const Eigen::Vector2d mid = A + dir * (0.5 * (s0 + s1));
          w.solids.push_back(box(mid.x(), mid.y(), s1 - s0, th, wyaw, z0, z1, mat, src));
        };
        for (const Op& o : ops)
        {
          seg(s, o.s0, base, base + h);
          seg(o.s0, o.s1, base + o.h, base + h);
          s = std::max(s, o.s1);
        }
        seg(s, len, base, base + h);
      }
      else if (type == "box")
      {
        c.checkKeys(e, f, {"type", "center", "size", "yaw", "base", "material"});
        auto ctr = c.vec(e, "center", f, 2, true);
        auto sz = c.vec(e, "size", f, 3, true);
        if (sz[0] <= 0 || sz[1] <= 0 || sz[2] <= 0) c.fail(e["size"], f + ".size", "sizes must be positive");
        const double base = c.num(e, "base", f, 0.0, false, -5, 50);
        w.solids.push_back(box(ctr[0], ctr[1], sz[0], sz[1], yaw, base, base + sz[2], mat, src));
      }
      else if (type == "column")
      {
        c.checkKeys(e, f, {"type", "center", "radius", "height", "base", "material"});
        auto ctr = c.vec(e, "center", f, 2, true);
        Solid s;
        s.shape = Solid::CYLINDER;
        s.center = {ctr[0], ctr[1]};
        s.radius = c.num(e, "radius", f, 0.2, false, 0.01, 10);
        s.z0 = c.num(e, "base", f, 0.0, false, -5, 50);
        s.z1 = s.z0 + c.num(e, "height", f, 3.0, false, 0.01, 50);
        s.material = mat;
        s.source = src;
        w.solids.push_back(s);
      }
      else if (type == "table" || type == "bench")
      {
        c.checkKeys(e, f, {"type", "center", "size", "height", "yaw", "top_thickness", "leg", "material"});
        auto ctr = c.vec(e, "center", f, 2, true);
        auto sz = c.vec(e, "size", f, 2, true);
        if (sz[0] <= 0 || sz[1] <= 0) c.fail(e["size"], f + ".size", "sizes must be positive");
        const double h = c.num(e, "height", f, type == "table" ? 0.75 : 0.45, false, 0.05, 5);
        const double top = c.num(e, "top_thickness", f, type == "table" ? 0.04 : 0.06, false, 0.005, h);
        const double leg = c.num(e, "leg", f, 0.05, false, 0.01, 1);
        w.solids.push_back(box(ctr[0], ctr[1], sz[0], sz[1], yaw, h - top, h, mat, src));
        const double cy = std::cos(yaw), sy = std::sin(yaw);
        for (int lx = -1; lx <= 1; lx += 2)
          for (int ly = -1; ly <= 1; ly += 2)
          {
            const double ox = lx * (sz[0] / 2 - leg), oy = ly * (sz[1] / 2 - leg);
            w.solids.push_back(box(ctr[0] + cy * ox - sy * oy, ctr[1] + sy * ox + cy * oy, leg, leg, yaw,
                                   0.0, h - top, mat, src));
          }
      }
      else if (type == "overhang" || type == "sign")
      {
        c.checkKeys(e, f, {"type", "center", "size", "bottom", "top", "yaw", "material"});
        auto ctr = c.vec(e, "center", f, 2, true);
        auto sz = c.vec(e, "size", f, 2, true);
        const double z0 = c.num(e, "bottom", f, 1.5, true, 0.0, 50);
        const double z1 = c.num(e, "top", f, 1.9, true, 0.0, 50);
        if (z1 <= z0) c.fail(e["top"], f + ".top", "must be above bottom");
        if (sz[0] <= 0 || sz[1] <= 0) c.fail(e["size"], f + ".size", "sizes must be positive");
        w.solids.push_back(box(ctr[0], ctr[1], sz[0], sz[1], yaw, z0, z1, mat, src));
      }
      else if (type == "step" || type == "curb")
      {
        c.checkKeys(e, f, {"type", "center", "size", "height", "yaw", "material"});
        auto ctr = c.vec(e, "center", f, 2, true);
        auto sz = c.vec(e, "size", f, 2, true);
        if (sz[0] <= 0 || sz[1] <= 0) c.fail(e["size"], f + ".size", "sizes must be positive");
        const double h = c.num(e, "height", f, 0.15, false, 0.01, 0.5);
        Solid s = box(ctr[0], ctr[1], sz[0], sz[1], yaw, 0.0, h, mat, src);
        s.walkable = true;
        w.solids.push_back(s);
      }
      else if (type == "glass")
      {
        c.checkKeys(e, f, {"type", "from", "to", "bottom", "top", "thickness", "reflectance", "frame", "manifestation"});
        auto a = c.vec(e, "from", f, 2, true), b = c.vec(e, "to", f, 2, true);
        const Eigen::Vector2d A(a[0], a[1]), B(b[0], b[1]);
        const double len = (B - A).norm();
        if (len < 0.01) c.fail(e["to"], f + ".to", "glass panel has zero length");
        const Eigen::Vector2d mid = 0.5 * (A + B);
        const double th = c.num(e, "thickness", f, 0.02, false, 0.001, 0.5);
        Solid s = box(mid.x(), mid.y(), len, th, std::atan2(B.y() - A.y(), B.x() - A.x()),
                      c.num(e, "bottom", f, 0.0, false, 0, 50), c.num(e, "top", f, 2.5, false, 0.01, 50), 0, src);
        if (s.z1 <= s.z0) c.fail(e["top"], f + ".top", "must be above bottom");
        s.glass = true;
        s.reflectance = c.num(e, "reflectance", f, 0.12, false, 0.0, 0.5);
        w.solids.push_back(s);
        const double yaw = s.yaw;
        const Eigen::Vector2d dir = (B - A) / len;
        // Glazing the camera can see (issue 20): the frame (mullions, head and bottom rails) and
        // manifestation bands, opaque solids in the panel's plane, a little thicker than the glass
        // so they are what a ray meets first.
        auto glazing = [&](double along0, double along1, double z0, double z1, double depth, int m, const std::string& what) {
          const Eigen::Vector2d cxy = A + dir * (0.5 * (along0 + along1));
          Solid g = box(cxy.x(), cxy.y(), along1 - along0, depth, yaw, z0, z1, m, src + " " + what);
          g.glazing = true;
          w.solids.push_back(g);
        };
        if (const YAML::Node fr = e["frame"])
        {
          const std::string ff = f + ".frame";
          c.checkKeys(fr, ff, {"mullion_spacing", "mullion_width", "head_rail", "bottom_rail", "depth", "material"});
          const int fm = materialRef(c, fr, ff, ids, 0);
          const double depth = c.num(fr, "depth", ff, 0.06, false, th, 1.0);
          const double spacing = c.num(fr, "mullion_spacing", ff, 1.5, false, 0.0, 100);
          const double mw = c.num(fr, "mullion_width", ff, 0.05, false, 0.005, 1.0);
          const double head = c.num(fr, "head_rail", ff, 0.08, false, 0.0, 2.0);
          const double bottom = c.num(fr, "bottom_rail", ff, 0.10, false, 0.0, 2.0);
          if (head + bottom >= s.z1 - s.z0) c.fail(fr, ff, "the rails cover the whole panel");
          // Mullions at both ends and every mullion_spacing between (0: ends only).
          const int gaps = spacing > 0 ? std::max(1, static_cast<int>(std::round(len / spacing))) : 1;
          for (int k = 0; k <= gaps; ++k)
          {
            const double at = len * k / gaps;
            glazing(std::max(0.0, at - mw / 2), std::min(len, at + mw / 2), s.z0, s.z1, depth, fm,
                    "mullion " + std::to_string(k));
          }
          if (head > 0) glazing(0.0, len, s.z1 - head, s.z1, depth, fm, "head rail");
          if (bottom > 0) glazing(0.0, len, s.z0, s.z0 + bottom, depth, fm, "bottom rail");
        }
        forEachItem(c, e, f, "manifestation", {"bottom", "top", "material"},
                    "expected a list of {bottom, top, material} bands",
                    [&](const YAML::Node& n, const std::string& bf) {
                      const double z0 = c.num(n, "bottom", bf, 0.85, true, 0, 50);
                      const double z1 = c.num(n, "top", bf, 1.0, true, 0, 50);
                      if (z1 <= z0) c.fail(n["top"], bf + ".top", "must be above bottom");
                      glazing(0.0, len, z0, z1, th + 0.004, materialRef(c, n, bf, ids, 0), "band");
                    });
      }
      else
      {
        c.fail(e["type"], f + ".type",
               "unknown element type '" + type + "' (wall, box, column, table, bench, overhang, sign, step, curb, glass)");
      }
    }
  }

  // Trajectory.
  const YAML::Node tr = root["trajectory"];
  if (!tr) c.fail(root, "trajectory", "missing (required): {waypoints: [[x, y], ...], ...}");
  const std::string tf = "trajectory";
  c.checkKeys(tr, tf, {"waypoints", "loops", "speed", "speed_variation", "eye_height", "start_still",
                       "corner_radius", "turn_on_spot_above", "turn_rate", "max_walk_turn_rate", "pitch_down", "scan", "bob", "sway", "step_length", "head_turns",
                       "auto_head_turns"});
  TrajectoryScript& t = w.trajectory;
  const YAML::Node wps = tr["waypoints"];
  if (!wps || !wps.IsSequence() || wps.size() < 2)
    c.fail(wps ? wps : tr, tf + ".waypoints", "expected a list of at least 2 [x, y] points");
  for (size_t i = 0; i < wps.size(); ++i)
  {
    const std::string f = tf + ".waypoints[" + std::to_string(i) + "]";
    if (!wps[i].IsSequence() || wps[i].size() != 2) c.fail(wps[i], f, "expected [x, y]");
    try
    {
      t.waypoints.emplace_back(wps[i][0].as<double>(), wps[i][1].as<double>());
    }
    catch (const YAML::Exception&)
    {
      c.fail(wps[i], f, "expected two numbers");
    }
  }
  t.loops = static_cast<int>(c.num(tr, "loops", tf, 1, false, 1, 100));
  t.speed = c.num(tr, "speed", tf, t.speed, false, 0.3, 2.5);
  t.speed_variation = c.num(tr, "speed_variation", tf, t.speed_variation, false, 0.0, 0.5);
  t.eye_height = c.num(tr, "eye_height", tf, t.eye_height, false, 0.5, 2.5);
  t.start_still = c.num(tr, "start_still", tf, t.start_still, false, 0.0, 60);
  t.corner_radius = c.num(tr, "corner_radius", tf, t.corner_radius, false, 0.05, 10);
  t.turn_on_spot_above = c.num(tr, "turn_on_spot_above", tf, t.turn_on_spot_above / DEG, false, 30, 180) * DEG;
  t.turn_rate = c.num(tr, "turn_rate", tf, t.turn_rate / DEG, false, 5, 720) * DEG;
  t.max_walk_turn_rate = c.num(tr, "max_walk_turn_rate", tf, t.max_walk_turn_rate / DEG, false, 10, 3600) * DEG;
  if (tr["pitch_down"])
  {
    auto p = c.vec(tr, "pitch_down", tf, 2, true);
    if (p[1] < p[0]) c.fail(tr["pitch_down"], tf + ".pitch_down", "expected [min, max] in degrees");
    t.pitch_min = p[0] * DEG;
    t.pitch_max = p[1] * DEG;
  }
  if (tr["scan"])
  {
    const YAML::Node s = tr["scan"];
    c.checkKeys(s, tf + ".scan", {"amplitude", "period"});
    t.scan_amplitude = c.num(s, "amplitude", tf + ".scan", 8.0, false, 0, 90) * DEG;
    t.scan_period = c.num(s, "period", tf + ".scan", 7.0, false, 0.5, 600);
  }
  t.bob_amplitude = c.num(tr, "bob", tf, t.bob_amplitude, false, 0, 0.2);
  t.sway_amplitude = c.num(tr, "sway", tf, t.sway_amplitude, false, 0, 0.2);
  t.step_length = c.num(tr, "step_length", tf, t.step_length, false, 0.2, 1.5);
  t.auto_head_turns = c.boolean(tr, "auto_head_turns", tf, true);
  forEachItem(c, tr, tf, "head_turns", {"at", "yaw", "rate"}, "expected a list of {at, yaw, rate}",
              [&](const YAML::Node& n, const std::string& f) {
                HeadTurn h;
                h.at = c.num(n, "at", f, 0, true, 0, 1e6);
                h.yaw = c.num(n, "yaw", f, 0, true, -180, 180) * DEG;
                h.rate = c.num(n, "rate", f, 10, true, 0.1, 500) * DEG;
                t.head_turns.push_back(h);
              });
  parsePeople(root, c, ids, w);
  return w;
}
}  // namespace

Eigen::Vector2d GiveWayTrack::at(double tt, Eigen::Vector2d* rate, double* delay_at, double* delay_rate) const
{
  if (rate) rate->setZero();
  if (delay_at) *delay_at = 0.0;
  if (delay_rate) *delay_rate = 0.0;
  if (t.empty()) return Eigen::Vector2d::Zero();
  size_t k = 0;
  double a = 0.0;
  if (tt >= t.back())
    k = t.size() - 1;
  else if (tt >= t.front())  // (at a knot: the rate on from it, the first knot too)
  {
    k = static_cast<size_t>(std::upper_bound(t.begin(), t.end(), tt) - t.begin()) - 1;
    const double dt = t[k + 1] - t[k];
    if (dt > 0.0)
    {
      a = (tt - t[k]) / dt;
      if (rate) *rate = (offset[k + 1] - offset[k]) / dt;
      if (delay_rate) *delay_rate = (delay[k + 1] - delay[k]) / dt;
    }
  }
  if (a == 0.0)
  {
    if (delay_at) *delay_at = delay[k];
    return offset[k];
  }
  if (delay_at) *delay_at = delay[k] + a * (delay[k + 1] - delay[k]);
  return offset[k] + a * (offset[k + 1] - offset[k]);
}

bool GiveWayTrack::append(double tt, const Eigen::Vector2d& o, double d)
{
  if (!std::isfinite(tt) || !o.allFinite() || !std::isfinite(d) || (!t.empty() && tt <= t.back()))
    return false;
  t.push_back(tt);
  offset.push_back(o);
  delay.push_back(d);
  return true;
}

PersonState personAt(const Person& p, double t)
{
  if (!p.give_way) return personScriptAt(p, t);
  Eigen::Vector2d rate;
  double delay = 0.0, delay_rate = 0.0;
  const Eigen::Vector2d offset = p.give_way->at(t, &rate, &delay, &delay_rate);
  PersonState s = personScriptAt(p, t - delay);
  s.position += offset;
  s.velocity = s.velocity * (1.0 - delay_rate) + rate;
  return s;
}

PersonState personScriptAt(const Person& p, double t)
{
  PersonState s;
  const size_t n = p.knot_t.size();
  if (n == 0) return s;
  if (n == 1 || t <= p.knot_t[0])
  {
    s.position = p.knot_p[0];
    s.yaw = p.stand_yaw;
    return s;
  }
  double tt = t;
  if (p.period > 0) tt = p.knot_t[0] + std::fmod(t - p.knot_t[0], p.period);
  if (tt >= p.knot_t[n - 1])
  {
    s.position = p.knot_p[n - 1];
    s.yaw = p.seg_yaw.back();
    return s;
  }
  // Segment k: knot_t[k] <= tt < knot_t[k + 1].
  const size_t k = static_cast<size_t>(std::upper_bound(p.knot_t.begin(), p.knot_t.end(), tt) - p.knot_t.begin()) - 1;
  const double dt = p.knot_t[k + 1] - p.knot_t[k];
  const double a = (tt - p.knot_t[k]) / dt;
  s.position = p.knot_p[k] + a * (p.knot_p[k + 1] - p.knot_p[k]);
  s.velocity = (p.knot_p[k + 1] - p.knot_p[k]) / dt;
  s.yaw = p.seg_yaw[k];
  return s;
}

PersonState personAt(const World& world, size_t i, double t) { return personAt(world.people.at(i), t); }

World World::parse(const std::string& text, const std::string& origin)
{
  Ctx c{origin};
  YAML::Node root;
  try
  {
    root = YAML::Load(text);
  }
  catch (const YAML::ParserException& e)
  {
    std::ostringstream s;
    s << origin << ":" << e.mark.line + 1 << ": YAML syntax error: " << e.msg;
    throw WorldError(s.str());
  }
  try
  {
    return parseRoot(root, c);
  }
  catch (const WorldError&)
  {
    throw;
  }
  catch (const YAML::Exception& e)
  {
    std::ostringstream s;
    s << origin << ":" << e.mark.line + 1 << ": " << e.msg;
    throw WorldError(s.str());
  }
}

World World::load(const std::string& path)
{
  std::ifstream in(path);
  if (!in) throw WorldError(path + ": cannot open world file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), path);
}

std::string resolveWorldPath(const std::string& name, const std::string& worlds_dir)
{
  {
    std::ifstream f(name);
    if (f.good() && (name.find('/') != std::string::npos || name.size() > 5))
    {
      // An existing file path.
      if (name.size() >= 5 && (name.substr(name.size() - 5) == ".yaml" || name.find('/') != std::string::npos))
        return name;
    }
  }
  for (const char* stem : {"", "_world"})
  {
    const std::string p = worlds_dir + "/" + name + stem + ".yaml";
    std::ifstream f(p);
    if (f.good()) return p;
  }
  throw WorldError("world '" + name + "' is neither a YAML file nor a shipped world in " + worlds_dir +
                   " (course, corridor, parking, glass, plaza)");
}

}  // namespace assistive_sim
