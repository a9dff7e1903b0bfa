#pragma once
// The nodelets' side of the parameter tables (param_table.h): every row is read from the private
// node handle under its ROS name, the table's default when it is not set.
#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "assistive_common/param_table.h"

namespace assistive_common
{
/// Reads every parameter of `p` from `pnh` (pnh.param(name, field, field)), then clamps by the
/// table; returns the clamp messages (the nodelet logs them as warnings).
template <class P>
std::vector<std::string> readParams(const ros::NodeHandle& pnh, P& p)
{
  p.forEach([&](const ParamInfo& info, auto& v) { pnh.param(info.name, v, v); });
  return clampToTable(p);
}

/// True when `name` is set explicitly (not left to the table's default).
inline bool isSet(const ros::NodeHandle& pnh, const std::string& name)
{
  return pnh.hasParam(name);
}
}  // namespace assistive_common
