#pragma once
// What the stages need to know about the wearer comes from the URDF on robot_description
// (assistive_description/urdf, generated with the wearer's eye height), not from copies in every
// stage's parameters.
#include <cmath>
#include <cstdio>
#include <string>

#include <ros/node_handle.h>
#include <urdf/model.h>

namespace assistive_common
{
/// Height of `camera_frame` above `ground_frame` (the z of camera_frame in ground_frame) from the
/// fixed joints of the URDF text `xml`. False, with `why`, when it is not a URDF or does not hold a
/// fixed chain between the two frames.
inline bool cameraHeightFromUrdfText(const std::string& xml, const std::string& camera_frame,
                                     const std::string& ground_frame, double& height, std::string* why,
                                     const std::string& param = "robot_description")
{
  urdf::Model model;
  if (!model.initString(xml))
  {
    *why = param + " is not a valid URDF";
    return false;
  }
  // Pose of a link in the root link's frame, through fixed joints only.
  auto inRoot = [&](const std::string& name, urdf::Pose& out) {
    out = urdf::Pose();
    urdf::LinkConstSharedPtr link = model.getLink(name);
    if (!link)
      return false;
    while (link->parent_joint)
    {
      if (link->parent_joint->type != urdf::Joint::FIXED)
        return false;
      const urdf::Pose& j = link->parent_joint->parent_to_joint_origin_transform;
      const urdf::Vector3 r = j.rotation * out.position;
      out.position = urdf::Vector3(j.position.x + r.x, j.position.y + r.y, j.position.z + r.z);
      out.rotation = j.rotation * out.rotation;
      link = model.getLink(link->parent_joint->parent_link_name);
      if (!link)
        return false;
    }
    return true;
  };
  urdf::Pose cam, ground;
  if (!inRoot(camera_frame, cam) || !inRoot(ground_frame, ground))
  {
    *why = param + " has no fixed chain between '" + camera_frame + "' and '" + ground_frame + "'";
    return false;
  }
  // camera in ground = ground^-1 * camera; only its z is needed.
  const urdf::Vector3 d(cam.position.x - ground.position.x, cam.position.y - ground.position.y,
                        cam.position.z - ground.position.z);
  const urdf::Rotation inv = ground.rotation.GetInverse();
  height = (inv * d).z;
  if (!std::isfinite(height))
  {
    *why = param + " gives a non-finite camera height";
    return false;
  }
  return true;
}
/// The same from the URDF on the parameter `param` (looked up from `nh` upwards). False, with
/// `why`, also when there is no such parameter; the caller then keeps its parameter (the table's
/// default: benchmarks and tests run without a URDF).
inline bool cameraHeightFromUrdf(const ros::NodeHandle& nh, const std::string& camera_frame,
                                 const std::string& ground_frame, double& height, std::string* why,
                                 const std::string& param = "robot_description")
{
  std::string key, xml;
  if (!nh.searchParam(param, key) || !nh.getParam(key, xml))
  {
    *why = "no " + param + " parameter";
    return false;
  }
  return cameraHeightFromUrdfText(xml, camera_frame, ground_frame, height, why, param);
}

/// A stage's camera height: the URDF's (cameraHeightFromUrdf(), rounded to the URDF's 6 digits:
/// 1.6, not 1.5999999999999999) when robot_description holds the chain, else `height` is kept
/// (the parameter `param`, or its table default). Returns the line to log; `overridden` is set
/// when an explicit `param` differing from the URDF was ignored (log it as a warning).
inline std::string wearerCameraHeight(const ros::NodeHandle& pnh, const std::string& camera_frame,
                                      const std::string& ground_frame, const std::string& param, double& height,
                                      bool* overridden)
{
  *overridden = false;
  double h = 0.0;
  std::string why;
  char buf[160];
  if (!cameraHeightFromUrdf(pnh, camera_frame, ground_frame, h, &why))
  {
    std::snprintf(buf, sizeof(buf), "%s %.3f m from the parameter (", param.c_str(), height);
    return buf + why + ")";
  }
  h = std::round(h * 1e6) / 1e6;
  *overridden = pnh.hasParam(param) && h != height;
  std::snprintf(buf, sizeof(buf), "%s %.3f m from the URDF (%s above %s)%s", param.c_str(), h, camera_frame.c_str(),
                ground_frame.c_str(), *overridden ? ": the parameter's value is ignored" : "");
  height = h;
  return buf;
}
}  // namespace assistive_common
