// World files: parsing, error messages with line and field, ground-truth occupancy.
#include <assistive_sim/world.h>

#include <gtest/gtest.h>

using namespace assistive_sim;

namespace
{
const char* MINIMAL = R"(name: t
materials:
  m: {pattern: noise, albedo: 0.5, contrast: 0.5}
floor: {min: [0, 0], max: [10, 6], material: m}
elements:
  - {type: box, center: [3.0, 3.0], size: [1.0, 1.0, 1.0], material: m}
  - {type: overhang, center: [6.0, 1.0], size: [1.0, 0.4], bottom: 1.5, top: 1.9, material: m}
  - {type: overhang, center: [6.0, 5.0], size: [1.0, 0.4], bottom: 2.3, top: 2.6, material: m}
  - {type: curb, center: [9.0, 3.0], size: [2.0, 6.0], height: 0.15, material: m}
  - {type: glass, from: [1.0, 5.5], to: [4.0, 5.5]}
  - {type: wall, from: [0.0, 0.1], to: [5.0, 0.1], height: 2.5, openings: [{at: 2.5, width: 1.0, height: 2.1}]}
  - {type: table, center: [6.0, 3.0], size: [1.2, 0.6]}
trajectory:
  eye_height: 1.6
  waypoints: [[1, 2], [8, 2]]
)";

std::string errorOf(const std::string& text)
{
  try
  {
    World::parse(text, "test.yaml");
  }
  catch (const WorldError& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(World, ParsesMinimal)
{
  const World w = World::parse(MINIMAL, "min");
  EXPECT_EQ(w.name, "t");
  ASSERT_EQ(w.materials.size(), 2u);  // default + m
  // box, 2 overhangs, curb, glass, wall split into 2 segments + lintel, table top + 4 legs
  EXPECT_EQ(w.solids.size(), 1u + 2u + 1u + 1u + 3u + 5u);
  EXPECT_TRUE(w.solids[3].walkable);
  EXPECT_TRUE(w.solids[4].glass);
  EXPECT_NEAR(w.floorHeight(9.0, 3.0), 0.15, 1e-12);
  EXPECT_NEAR(w.floorHeight(2.0, 3.0), 0.0, 1e-12);
  ASSERT_EQ(w.trajectory.waypoints.size(), 2u);
  EXPECT_DOUBLE_EQ(w.trajectory.eye_height, 1.6);
}

TEST(World, WrongTypeNamesLineAndField)
{
  std::string text = MINIMAL;
  text.replace(text.find("size: [1.0, 1.0, 1.0]"), 21, "size: [1.0, one, 1.0]");
  const std::string e = errorOf(text);
  EXPECT_NE(e.find("test.yaml:6:"), std::string::npos) << e;
  EXPECT_NE(e.find("elements[0](box).size"), std::string::npos) << e;
}

TEST(World, MissingFieldNamesLineAndField)
{
  std::string text = MINIMAL;
  text.replace(text.find("bottom: 1.5, "), 13, "");
  const std::string e = errorOf(text);
  EXPECT_NE(e.find("test.yaml:7:"), std::string::npos) << e;
  EXPECT_NE(e.find("elements[1](overhang).bottom"), std::string::npos) << e;
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
}

TEST(World, UnknownTypeAndFieldAndMaterial)
{
  std::string a = MINIMAL;
  a.replace(a.find("type: table"), 11, "type: tabel");
  std::string e = errorOf(a);
  EXPECT_NE(e.find("test.yaml:12:"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown element type 'tabel'"), std::string::npos) << e;

  std::string b = MINIMAL;
  b.replace(b.find("eye_height: 1.6"), 15, "eye_hieght: 1.6");
  e = errorOf(b);
  EXPECT_NE(e.find("test.yaml:14:"), std::string::npos) << e;
  EXPECT_NE(e.find("trajectory.eye_hieght"), std::string::npos) << e;

  std::string c = MINIMAL;
  c.replace(c.find("material: m}\n  - {type: overhang"), 11, "material: x");
  e = errorOf(c);
  EXPECT_NE(e.find("test.yaml:6:"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown material 'x'"), std::string::npos) << e;
}

TEST(World, OutOfRangeAndSyntaxError)
{
  std::string a = MINIMAL;
  a.replace(a.find("albedo: 0.5"), 11, "albedo: 7.5");
  std::string e = errorOf(a);
  EXPECT_NE(e.find("test.yaml:3:"), std::string::npos) << e;
  EXPECT_NE(e.find("materials.m.albedo"), std::string::npos) << e;

  std::string b = MINIMAL;
  b.replace(b.find("waypoints: [[1, 2], [8, 2]]"), 27, "waypoints: [[1, 2], [8, 2]");
  e = errorOf(b);
  EXPECT_NE(e.find("test.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("syntax"), std::string::npos) << e;

  EXPECT_THROW(World::load("/nonexistent/world.yaml"), WorldError);
}

TEST(World, SolidGeometry)
{
  Solid s;
  s.center = {0, 0};
  s.half = {1.0, 0.1};
  s.yaw = M_PI / 2;
  EXPECT_TRUE(s.containsXY(0.0, 0.9));
  EXPECT_FALSE(s.containsXY(0.9, 0.0));
  EXPECT_TRUE(s.overlapsRect(-0.05, 0.95, 0.05, 1.2));
  EXPECT_FALSE(s.overlapsRect(0.15, -0.5, 0.3, 0.5));
  // A 45-degree box: the bounding boxes overlap, the shapes do not (separating axis).
  s.yaw = M_PI / 4;
  s.half = {1.0, 0.05};
  EXPECT_FALSE(s.overlapsRect(0.5, -0.8, 0.8, -0.5));
  EXPECT_TRUE(s.overlapsRect(0.3, 0.3, 0.45, 0.45));
  Solid c;
  c.shape = Solid::CYLINDER;
  c.center = {1, 1};
  c.radius = 0.3;
  EXPECT_TRUE(c.overlapsRect(1.2, 1.2, 1.4, 1.4));
  EXPECT_FALSE(c.overlapsRect(1.25, 1.25, 1.4, 1.4));
}

TEST(Occupancy, KnownCells)
{
  const World w = World::parse(MINIMAL, "min");
  const OccupancyGrid g = computeOccupancy(w);
  EXPECT_NEAR(g.resolution, 0.2, 1e-12);
  EXPECT_EQ(g.atWorld(3.0, 3.0), CELL_OBSTACLE);   // box
  EXPECT_EQ(g.atWorld(3.45, 2.55), CELL_OBSTACLE);  // box corner cell
  EXPECT_EQ(g.atWorld(3.7, 3.0), CELL_FREE);       // beside the box
  EXPECT_EQ(g.atWorld(2.0, 2.0), CELL_FREE);       // open floor
  EXPECT_EQ(g.atWorld(6.0, 1.0), CELL_OBSTACLE);   // overhang at head height
  EXPECT_EQ(g.atWorld(6.0, 5.0), CELL_FREE);       // overhang above head + margin (2.3 m)
  EXPECT_EQ(g.atWorld(8.0, 3.0), CELL_STEP);       // curb edge (x = 8), both sides
  EXPECT_EQ(g.atWorld(7.9, 3.0), CELL_STEP);
  EXPECT_EQ(g.atWorld(9.0, 3.0), CELL_FREE);       // on top of the curb
  EXPECT_EQ(g.atWorld(2.5, 5.5), CELL_OBSTACLE);   // glass
  EXPECT_EQ(g.atWorld(2.5, 0.1), CELL_FREE);       // doorway (lintel at 2.1 m is above the head)
  EXPECT_EQ(g.atWorld(1.0, 0.1), CELL_OBSTACLE);   // wall beside the doorway
  EXPECT_EQ(g.atWorld(6.0, 3.0), CELL_OBSTACLE);   // table top
  EXPECT_EQ(g.atWorld(-0.5, 3.0), CELL_UNKNOWN);   // outside the floor
  EXPECT_EQ(g.atWorld(100.0, 3.0), CELL_UNKNOWN);  // outside the grid

  // Head height follows the wearer: a shorter wearer passes under the overhang.
  World low = w;
  low.trajectory.eye_height = 1.0;
  EXPECT_EQ(computeOccupancy(low).atWorld(6.0, 1.0), CELL_FREE);
}

TEST(World, GlassFrameAndManifestationAreOpaqueGlazing)
{
  // A 4.5 m panel from (0, 2) to (4.5, 2), 2.5 m high: mullions every 1.5 m (4, at 0, 1.5, 3, 4.5),
  // head and bottom rails, two manifestation bands; all in the panel's plane, thicker than the glass.
  const World w = World::parse(R"(
name: g
materials: {alu: {pattern: plain}, band: {pattern: tiles}}
floor: {min: [-1, -1], max: [6, 4]}
elements:
  - type: glass
    from: [0, 2]
    to: [4.5, 2]
    top: 2.5
    frame: {mullion_spacing: 1.5, mullion_width: 0.06, head_rail: 0.1, bottom_rail: 0.12, material: alu}
    manifestation: [{bottom: 0.85, top: 1.0, material: band}, {bottom: 1.4, top: 1.6}]
trajectory: {waypoints: [[0, 0], [4, 0]]}
)", "glass frame");
  ASSERT_EQ(w.solids.size(), 1u + 4u + 2u + 2u);
  EXPECT_TRUE(w.solids[0].glass);
  int mullions = 0, rails = 0, bands = 0;
  for (size_t i = 1; i < w.solids.size(); ++i)
  {
    const Solid& s = w.solids[i];
    EXPECT_TRUE(s.glazing);
    EXPECT_FALSE(s.glass);
    EXPECT_NEAR(s.center.y(), 2.0, 1e-12);
    EXPECT_GT(s.half.y(), w.solids[0].half.y());  // in front of the glass on both faces
    if (s.z1 - s.z0 > 2.0)
    {
      // Full width inside the panel, half at its two ends (the frame stops at the panel's edge).
      const bool end = s.center.x() < 0.1 || s.center.x() > 4.4;
      EXPECT_NEAR(s.half.x(), end ? 0.015 : 0.03, 1e-9) << s.center.x();
      EXPECT_NEAR(std::remainder(s.center.x(), 1.5), 0.0, end ? 0.016 : 1e-9) << s.center.x();
      ++mullions;
    }
    else if (s.half.x() > 2.0 && (s.z0 == 0.0 || s.z1 == 2.5))
      ++rails;
    else
      ++bands;
  }
  EXPECT_EQ(mullions, 4);
  EXPECT_EQ(rails, 2);
  EXPECT_EQ(bands, 2);
  EXPECT_NEAR(w.solids.back().z0, 1.4, 1e-12);
  EXPECT_NEAR(w.solids.back().z1, 1.6, 1e-12);
  // A band whose top is below its bottom is refused with its field named.
  EXPECT_THROW(World::parse(R"(
name: g
floor: {min: [-1, -1], max: [6, 4]}
elements:
  - {type: glass, from: [0, 2], to: [4.5, 2], manifestation: [{bottom: 1.0, top: 0.9}]}
trajectory: {waypoints: [[0, 0], [4, 0]]}
)", "bad band"), WorldError);
}

TEST(World, ShippedWorldsLoad)
{
  for (const char* name : {"course", "corridor", "parking", "glass", "glass_bare", "plaza"})
  {
    const std::string path = resolveWorldPath(name, ASSISTIVE_SIM_SOURCE_WORLDS);
    EXPECT_NE(path.find(name), std::string::npos);
    const World w = World::load(path);
    EXPECT_FALSE(w.solids.empty()) << name;
    EXPECT_GE(w.trajectory.waypoints.size(), 2u) << name;
  }
  EXPECT_THROW(resolveWorldPath("nowhere", ASSISTIVE_SIM_SOURCE_WORLDS), WorldError);
}

TEST(World, CourseMatchesTheSeed)
{
  const World w = World::load(resolveWorldPath("course", ASSISTIVE_SIM_SOURCE_WORLDS));
  const OccupancyGrid g = computeOccupancy(w);
  // 12.2 m long (x 0 .. 12.2 free inside), 3 m wide (side walls' inner faces 3 m apart).
  EXPECT_EQ(g.atWorld(0.1, 0.0), CELL_FREE);
  EXPECT_EQ(g.atWorld(12.1, 0.0), CELL_FREE);
  EXPECT_EQ(g.atWorld(1.0, 1.3), CELL_FREE);
  EXPECT_EQ(g.atWorld(1.0, 1.6), CELL_OBSTACLE);
  EXPECT_EQ(g.atWorld(1.0, -1.6), CELL_OBSTACLE);
  // The 2 m wall in the middle.
  EXPECT_EQ(g.atWorld(6.1, -1.0), CELL_OBSTACLE);
  EXPECT_EQ(g.atWorld(6.1, 0.4), CELL_OBSTACLE);
  EXPECT_EQ(g.atWorld(6.1, 1.0), CELL_FREE);
}

TEST(Occupancy, DetailFlagsPartialNearGlass)
{
  // Floor [0,4]^2, 0.2 m cells from -1 (border 1 m). A box over x 0.97-1.6, y 0.4-0.8: it reaches
  // 3 cm into the cells of x 0.8-1.0 (partial: scored neither way) and deeper into x 1.0-1.2 (core);
  // the cells of x 1.6-1.8 and of y 0.8-1.0 only border it (near). A 2 cm pole at (3.02, 3.0)
  // reaches no cell deeper than 5 cm: every cell it touches stays a plain obstacle. A glass panel.
  World w;
  w.floor_min = {0, 0};
  w.floor_max = {4, 4};
  Solid box;
  box.center = {1.285, 0.6};
  box.half = {0.315, 0.2};
  box.z0 = 0.0;
  box.z1 = 1.0;
  Solid pole;
  pole.shape = Solid::CYLINDER;
  pole.center = {3.02, 3.0};
  pole.radius = 0.02;
  pole.z1 = 1.5;
  Solid glass;
  glass.center = {2.0, 3.5};
  glass.half = {0.5, 0.01};
  glass.z1 = 2.0;
  glass.glass = true;
  w.solids = {box, pole, glass};
  const OccupancyGrid g = computeOccupancy(w);
  const std::vector<uint8_t> f = computeOccupancyDetail(w);
  ASSERT_EQ(f.size(), g.data.size());
  auto at = [&](double x, double y) {
    const int ix = static_cast<int>(std::floor((x - g.origin_x) / g.resolution));
    const int iy = static_cast<int>(std::floor((y - g.origin_y) / g.resolution));
    return f[static_cast<size_t>(iy) * g.width + ix];
  };
  EXPECT_EQ(g.atWorld(0.9, 0.6), CELL_OBSTACLE);
  EXPECT_EQ(at(0.9, 0.6), DETAIL_PARTIAL);
  EXPECT_EQ(at(1.1, 0.6), 0);
  EXPECT_EQ(at(1.5, 0.5), 0);
  EXPECT_EQ(g.atWorld(1.7, 0.6), CELL_FREE);
  EXPECT_EQ(at(1.7, 0.6), DETAIL_NEAR);
  EXPECT_EQ(at(1.1, 0.9), DETAIL_NEAR);
  EXPECT_EQ(at(1.1, 0.3), DETAIL_NEAR);
  EXPECT_EQ(at(2.5, 2.5), 0);
  EXPECT_EQ(g.atWorld(3.1, 2.9), CELL_OBSTACLE);
  EXPECT_EQ(g.atWorld(3.1, 3.1), CELL_OBSTACLE);
  EXPECT_EQ(at(3.1, 2.9), 0);  // thin: kept
  EXPECT_EQ(at(3.1, 3.1), 0);
  EXPECT_EQ(at(2.1, 3.5), DETAIL_GLASS);
  // partial_depth 0: nothing is partial or near.
  const std::vector<uint8_t> f0 = computeOccupancyDetail(w, {}, 0.0);
  for (const uint8_t v : f0) EXPECT_EQ(v & (DETAIL_PARTIAL | DETAIL_NEAR), 0);
}
