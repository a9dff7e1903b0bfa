// The wearer model: urdfdom parses it, the frame tree matches README.md "Interfaces",
// check_urdf accepts it, and urdf/wearer.urdf equals scripts/make_urdf.py's default output.
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace
{
const std::string PKG = PKG_DIR;

// Run a shell command; returns its stdout and sets `status` to its exit code.
std::string run(const std::string& cmd, int& status)
{
  std::string out;
  FILE* f = popen(cmd.c_str(), "r");
  if (!f)
  {
    status = -1;
    return out;
  }
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof(buf), f)) > 0) out.append(buf, n);
  const int rc = pclose(f);
  status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  return out;
}

std::string readFile(const std::string& path)
{
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Pose
{
  urdf::Vector3 p;
  urdf::Rotation q;
};

// Pose of `link` in the root frame, composing the fixed joints up the tree.
Pose poseInRoot(const urdf::ModelInterfaceSharedPtr& model, const std::string& link)
{
  Pose pose;  // identity
  urdf::LinkConstSharedPtr l = model->getLink(link);
  while (l && l->parent_joint)
  {
    const urdf::Pose& j = l->parent_joint->parent_to_joint_origin_transform;
    // pose = j * pose
    pose.p = j.rotation * pose.p + j.position;
    pose.q = j.rotation * pose.q;
    l = l->getParent();
  }
  return pose;
}

urdf::Vector3 axis(const urdf::Rotation& q, double x, double y, double z)
{
  return q * urdf::Vector3(x, y, z);
}

void expectVec(const urdf::Vector3& v, double x, double y, double z, const std::string& what)
{
  EXPECT_NEAR(v.x, x, 1e-9) << what;
  EXPECT_NEAR(v.y, y, 1e-9) << what;
  EXPECT_NEAR(v.z, z, 1e-9) << what;
}

void checkTree(const urdf::ModelInterfaceSharedPtr& model, double baseline, double eye_height)
{
  ASSERT_TRUE(model);
  EXPECT_EQ(model->getName(), "wearer");
  ASSERT_TRUE(model->getRoot());
  EXPECT_EQ(model->getRoot()->name, "camera_link");
  const std::pair<const char*, const char*> parents[] = {
      {"camera_left_optical_frame", "camera_link"},
      {"camera_right_optical_frame", "camera_link"},
      {"torso", "camera_link"},
      {"motor_left_shoulder", "torso"},
      {"motor_right_shoulder", "torso"},
      {"motor_left_waist", "torso"},
      {"motor_right_waist", "torso"},
      {"base_footprint", "torso"},
      {"sonar_front", "torso"},
      {"vest_imu", "torso"}};
  for (const auto& pc : parents)
  {
    urdf::LinkConstSharedPtr l = model->getLink(pc.first);
    ASSERT_TRUE(l) << pc.first;
    ASSERT_TRUE(l->getParent()) << pc.first;
    EXPECT_EQ(l->getParent()->name, pc.second) << pc.first;
    EXPECT_EQ(l->parent_joint->type, urdf::Joint::FIXED) << pc.first;
  }
  EXPECT_EQ(model->links_.size(), 11u);

  // Optical frames: z forward (= camera_link x), x right (= -y), y down (= -z).
  for (const char* name : {"camera_left_optical_frame", "camera_right_optical_frame"})
  {
    const Pose o = poseInRoot(model, name);
    expectVec(axis(o.q, 0, 0, 1), 1, 0, 0, std::string(name) + " z");
    expectVec(axis(o.q, 1, 0, 0), 0, -1, 0, std::string(name) + " x");
    expectVec(axis(o.q, 0, 1, 0), 0, 0, -1, std::string(name) + " y");
  }
  expectVec(poseInRoot(model, "camera_left_optical_frame").p, 0, 0, 0, "left at camera_link");
  expectVec(poseInRoot(model, "camera_right_optical_frame").p, 0, -baseline, 0,
            "right = left + baseline along -y");
  // Ground frame: eye_height straight below camera_link, level.
  const Pose g = poseInRoot(model, "base_footprint");
  expectVec(g.p, 0, 0, -eye_height, "base_footprint");
  expectVec(axis(g.q, 0, 0, 1), 0, 0, 1, "base_footprint z up");
  // Motors: left ones at +y, right ones at -y (of the head's mid-plane), shoulders above waist,
  // all on the torso's front, between the eyes and the floor.
  const double mid = -baseline / 2.0;
  const Pose ls = poseInRoot(model, "motor_left_shoulder"), rs = poseInRoot(model, "motor_right_shoulder");
  const Pose lw = poseInRoot(model, "motor_left_waist"), rw = poseInRoot(model, "motor_right_waist");
  EXPECT_GT(ls.p.y, mid);
  EXPECT_GT(lw.p.y, mid);
  EXPECT_LT(rs.p.y, mid);
  EXPECT_LT(rw.p.y, mid);
  EXPECT_GT(ls.p.z, lw.p.z);
  EXPECT_GT(rs.p.z, rw.p.z);
  for (const Pose* m : {&ls, &rs, &lw, &rw})
  {
    EXPECT_LT(m->p.z, -0.1);
    EXPECT_GT(m->p.z, -eye_height);
  }
  // The forward ranger: on the chest's front in the head's mid-plane, looking along camera_link's x
  // (assistive_sim's linkToSonar() casts the simulated cone from this same pose).
  const Pose sonar = poseInRoot(model, "sonar_front");
  EXPECT_NEAR(sonar.p.y, mid, 1e-9);
  EXPECT_LT(sonar.p.z, -0.2);
  EXPECT_GT(sonar.p.z, -0.6);
  expectVec(axis(sonar.q, 1, 0, 0), 1, 0, 0, "sonar_front x forward");
  // The visuals the brief asks for: head, torso, motors.
  EXPECT_FALSE(model->getLink("camera_link")->visual_array.empty());
  EXPECT_TRUE(model->getLink("torso")->visual);
  EXPECT_TRUE(model->getLink("motor_left_waist")->visual);
}
}  // namespace

TEST(Urdf, CheckedInModelParsesWithTheRightTree)
{
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(PKG + "/urdf/wearer.urdf");
  checkTree(model, 0.12, 1.6);
}

TEST(Urdf, CheckUrdfAcceptsTheModel)
{
  int status = 0;
  const std::string out = run("check_urdf '" + PKG + "/urdf/wearer.urdf' 2>&1", status);
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("Successfully Parsed XML"), std::string::npos) << out;
  EXPECT_NE(out.find("root Link: camera_link"), std::string::npos) << out;
}

TEST(Urdf, CheckedInFileEqualsGeneratorDefault)
{
  int status = 0;
  const std::string generated = run("python3 '" + PKG + "/scripts/make_urdf.py'", status);
  ASSERT_EQ(status, 0);
  EXPECT_EQ(generated, readFile(PKG + "/urdf/wearer.urdf"))
      << "regenerate: scripts/make_urdf.py > urdf/wearer.urdf";
}

TEST(Urdf, GeneratorTakesBaselineAndEyeHeight)
{
  int status = 0;
  const std::string xml = run(
      "python3 '" + PKG + "/scripts/make_urdf.py' --baseline 0.065 --eye-height 1.25", status);
  ASSERT_EQ(status, 0);
  checkTree(urdf::parseURDF(xml), 0.065, 1.25);
}

TEST(Urdf, GeneratorRejectsBadValues)
{
  int status = 0;
  run("python3 '" + PKG + "/scripts/make_urdf.py' --baseline -0.1 2>/dev/null", status);
  EXPECT_NE(status, 0);
  run("python3 '" + PKG + "/scripts/make_urdf.py' --eye-height 0.2 2>/dev/null", status);
  EXPECT_NE(status, 0);
}
