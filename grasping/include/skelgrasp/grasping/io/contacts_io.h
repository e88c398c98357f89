#pragma once
// Contact sets from JSON files (input of `skelgrasp quality`):
//   {"contacts": [{"point": [x, y, z], "normal": [x, y, z]}, ...],
//    "center": [x, y, z], "torque_scale": s}        // center and torque_scale optional
// Points in metres in any frame; normals are the object's outward normals.
#include <string>
#include <vector>

#include "skelgrasp/grasping/contact.h"

namespace skelgrasp::grasping {

struct ContactFileLimits {
  // The wrench-space hull grows steeply with contacts x cone edges in 6-D: with 8 cone edges,
  // 100 contacts take 19 s and 240 MB (300 000 facets), 1000 contacts did not finish in 5 minutes
  // (1.4 GB and growing). A hand makes a few dozen contacts at most.
  std::size_t max_contacts = 100;
  // Contact points and the centre lie within this distance of the origin (metres): household
  // objects in any sensible frame are well inside it, and 1e308 would overflow the torques.
  double max_distance_m = 1e3;
  // Normals whose length differs from 1 by more than this are normalised with a warning.
  double normal_tolerance = 1e-3;
};

struct ContactSet {
  std::vector<Contact> contacts;                     // unit normals
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // given, or the contacts' centroid
  double torque_scale = 1.0;  // given, or 2 / longest side of the contacts' bounding box
};

// Throws IoError naming the file and the problem (and the contact index for a bad contact):
// unreadable or invalid JSON, wrong layout, no contacts, more than `max_contacts`, non-finite
// or too distant points, zero or non-finite normals, a non-positive or non-finite torque scale.
ContactSet readContactsFile(const std::string& path, const ContactFileLimits& limits = {});

}  // namespace skelgrasp::grasping
