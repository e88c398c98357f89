#pragma once
// The contact list file of `skelgrasp quality` (docs/hands.md):
//   {"contacts": [{"point": [x, y, z], "normal": [x, y, z]}, ...],
//    "center": [x, y, z], "torque_scale": s}   (center and torque_scale optional)
#include <string>
#include <vector>

#include <Eigen/Core>

#include "skelgrasp/grasping/contact.h"

namespace skelgrasp::grasping {

struct ContactsFile {
  std::vector<Contact> contacts;  // normals unit length
  Eigen::Vector3d center;         // the file's, or the contacts' centroid
  double torque_scale = 0;        // the file's, or torqueScaleLongestSide of the contacts' box
};

// Largest contact list a file may hold: the 6D hull of contacts x cone edges wrenches grows
// quickly, and no hand has more than a few dozen contacts.
constexpr std::size_t kMaxContactsInFile = 1000;
// Coordinates beyond this many metres are not a grasp of a household object.
constexpr double kMaxContactCoordinateM = 1e3;

// Reads and validates the file. Throws IoError naming the file and the problem (missing, a
// directory, not JSON, wrong structure, non-finite or absurd values, too many contacts).
ContactsFile readContactsFile(const std::string& path);

}  // namespace skelgrasp::grasping
