// The camera height the VO and obstacle nodelets take from the URDF: the chain of fixed joints
// from the camera down to the ground frame, whatever the links in between.
#include <gtest/gtest.h>

#include "assistive_common/wearer.h"

namespace
{
// The shape of assistive_description's wearer.urdf (make_urdf.py --eye-height 1.7): camera_link
// is the root, the torso hangs below it, base_footprint below the torso, straight under the camera.
std::string wearer(const char* joint_type = "fixed", const char* rpy = "0 0 0")
{
  return std::string(R"(<?xml version="1.0"?>
<robot name="wearer">
  <link name="camera_link"/>
  <link name="camera_left_optical_frame"/>
  <link name="torso"/>
  <link name="base_footprint"/>
  <joint name="optical" type="fixed"><parent link="camera_link"/><child link="camera_left_optical_frame"/>
    <origin xyz="0 0 0" rpy="-1.5707963267948966 0 -1.5707963267948966"/></joint>
  <joint name="neck_joint" type=")") +
         joint_type + R"("><parent link="camera_link"/><child link="torso"/>
    <origin xyz="-0.1 -0.06 -0.45" rpy=")" + rpy + R"("/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="base_footprint_joint" type="fixed"><parent link="torso"/><child link="base_footprint"/>
    <origin xyz="0.1 0.06 -1.25" rpy="0 0 0"/></joint>
</robot>)";
}
}  // namespace

TEST(Wearer, CameraHeightFromTheFixedChain)
{
  double h = 0.0;
  std::string why;
  ASSERT_TRUE(assistive_common::cameraHeightFromUrdfText(wearer(), "camera_link", "base_footprint", h, &why)) << why;
  EXPECT_NEAR(h, 1.7, 1e-12);
  // The optical frame shares the camera's origin.
  ASSERT_TRUE(assistive_common::cameraHeightFromUrdfText(wearer(), "camera_left_optical_frame", "base_footprint", h,
                                                         &why));
  EXPECT_NEAR(h, 1.7, 1e-12);
  // A yawed torso moves base_footprint sideways, not up or down.
  ASSERT_TRUE(assistive_common::cameraHeightFromUrdfText(wearer("fixed", "0 0 0.7"), "camera_link", "base_footprint",
                                                         h, &why));
  EXPECT_NEAR(h, 1.7, 1e-12);
}

TEST(Wearer, NoHeightWithoutAFixedChain)
{
  double h = 1.6;
  std::string why;
  EXPECT_FALSE(assistive_common::cameraHeightFromUrdfText(wearer(), "camera_link", "no_such_frame", h, &why));
  EXPECT_NE(why.find("no fixed chain"), std::string::npos) << why;
  EXPECT_FALSE(assistive_common::cameraHeightFromUrdfText(wearer("revolute"), "camera_link", "base_footprint", h, &why));
  EXPECT_FALSE(assistive_common::cameraHeightFromUrdfText("<robot>", "camera_link", "base_footprint", h, &why));
  EXPECT_EQ(h, 1.6);  // untouched
}
