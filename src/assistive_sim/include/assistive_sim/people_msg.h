#pragma once
// The simulator's people truth as assistive_msgs/MoverArray (/ground_truth/people in bags, the
// trials' truth `obstacles/movers`): id = person index + 1, covariance zeros (exact), radius and
// height of the body, position on the floor (z = 0: people walk on the z = 0 floor).
#include <assistive_msgs/MoverArray.h>
#include <ros/time.h>

#include <assistive_sim/world.h>

namespace assistive_sim
{
/// Every person of `world` at time `t` (personAt's clock), optionally moved into another frame by
/// the planar transform (x, y, yaw) -> T_frame_world, stamped `stamp` in `frame_id`.
inline assistive_msgs::MoverArray peopleMessage(const World& world, double t, const ros::Time& stamp,
                                                const std::string& frame_id,
                                                const Eigen::Isometry3d& T_frame_world = Eigen::Isometry3d::Identity())
{
  assistive_msgs::MoverArray m;
  m.header.stamp = stamp;
  m.header.frame_id = frame_id;
  for (size_t i = 0; i < world.people.size(); ++i)
  {
    const PersonState s = personAt(world, i, t);
    const Eigen::Vector3d p = T_frame_world * Eigen::Vector3d(s.position.x(), s.position.y(), 0.0);
    const Eigen::Vector3d v = T_frame_world.linear() * Eigen::Vector3d(s.velocity.x(), s.velocity.y(), 0.0);
    assistive_msgs::Mover mv;
    mv.id = static_cast<uint32_t>(i + 1);
    mv.position.x = p.x();
    mv.position.y = p.y();
    mv.position.z = p.z();
    mv.velocity.x = v.x();
    mv.velocity.y = v.y();
    mv.velocity.z = 0.0;
    mv.covariance.fill(0.0);
    mv.radius = static_cast<float>(world.people[i].radius);
    mv.height = static_cast<float>(world.people[i].height);
    m.movers.push_back(mv);
  }
  return m;
}
}  // namespace assistive_sim
