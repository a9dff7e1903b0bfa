#include <gtest/gtest.h>

#include <cstdio>
#include <unistd.h>

#include <octomap/OcTree.h>

#include <assistive_obstacles/params.h>
#include <assistive_obstacles/seen_octree.h>

using namespace assistive_obstacles;

TEST(SeenOctree, WallIsOccupiedRayIsFreeAndSavedAsBt)
{
  ObstaclesParams p;
  p.octomap_point_stride = 1;
  SeenOctree tree(p);
  std::vector<Eigen::Vector3f> wall;
  for (float y = -0.5f; y <= 0.5f; y += 0.05f)
    for (float z = 0.5f; z <= 1.5f; z += 0.05f) wall.emplace_back(3.0f, y, z);
  for (int i = 0; i < 3; ++i) tree.insert(wall, Eigen::Vector3f(0.f, 0.f, 1.0f));
  std::vector<Eigen::Vector3f> c;
  std::vector<float> s;
  tree.occupiedCenters(c, s);
  ASSERT_FALSE(c.empty());
  for (const auto& v : c) EXPECT_NEAR(v.x(), 3.0f, 0.1f);

  const std::string path = testing::TempDir() + "/test_seen_octree_" + std::to_string(::getpid()) + ".bt";
  ASSERT_TRUE(tree.save(path));
  octomap::OcTree back(path);
  std::remove(path.c_str());
  const octomap::OcTreeNode* hit = back.search(3.0, 0.0, 1.0);
  ASSERT_NE(hit, nullptr);
  EXPECT_TRUE(back.isNodeOccupied(hit));
  const octomap::OcTreeNode* ray = back.search(1.5, 0.0, 1.0);
  ASSERT_NE(ray, nullptr);
  EXPECT_FALSE(back.isNodeOccupied(ray));
  EXPECT_EQ(back.search(-2.0, 0.0, 1.0), nullptr);  // never seen: unknown
}

TEST(Params, ClampFixesInvalidValues)
{
  ObstaclesParams p;
  EXPECT_TRUE(clampParams(p).empty());  // the defaults are valid
  p.block_size = 6;
  p.disparity_scale = 3.0;
  p.disparity_method = "magic";
  p.min_traversable_edges = 12;
  const auto msgs = clampParams(p);
  EXPECT_EQ(msgs.size(), 4u);
  EXPECT_EQ(p.block_size % 2, 1);
  EXPECT_DOUBLE_EQ(p.disparity_scale, 1.0);
  EXPECT_EQ(p.disparity_method, "sgbm3way");
  EXPECT_EQ(p.min_traversable_edges, 8);
}
