#pragma once
#include <string>

#include <Eigen/Core>

namespace skelgrasp::grasping {

// A contact between a hand link and the object, in the object frame.
struct Contact {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // on the object surface
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // object's outward unit normal there
  std::string link;                                   // hand link touching it
  bool palm = false;                                  // a palm (static) link
  double distance = 0;                                // link-object gap when recorded, metres
};

}  // namespace skelgrasp::grasping
