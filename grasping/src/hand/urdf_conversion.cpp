// urdfdom conversion: URDF text -> skelgrasp Link/Joint trees. The only file that sees urdfdom.
#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <fmt/format.h>

#include <filesystem>
#include <map>

#include "hand_loading.h"
#include "skelgrasp/common/error.h"

namespace skelgrasp::grasping::internal {
namespace {

Pose toPose(const urdf::Pose& p) {
  Pose pose = Pose::Identity();
  pose.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  pose.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                      .normalized()
                      .toRotationMatrix();
  return pose;
}

// "package://pkg/path", "file:///abs" or a relative path (to the URDF's directory). For package
// URLs the package is looked for next to and above the URDF's directory.
std::string resolveMeshPath(const std::string& filename, const std::string& base_dir) {
  namespace fs = std::filesystem;
  std::string path = filename;
  if (path.rfind("file://", 0) == 0) return path.substr(7);
  if (path.rfind("package://", 0) == 0) {
    const std::string rest = path.substr(10);
    const auto slash = rest.find('/');
    const std::string package = rest.substr(0, slash),
                      inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
    for (fs::path dir = fs::absolute(base_dir); !dir.empty(); dir = dir.parent_path()) {
      for (const fs::path& candidate : {dir / package / inside, dir / inside}) {
        if (fs::exists(candidate)) return candidate.string();
      }
      if (dir == dir.parent_path()) break;
    }
    return (fs::path(base_dir) / inside).string();
  }
  if (fs::path(path).is_absolute()) return path;
  return (fs::path(base_dir) / path).string();
}

// Ranges of the numbers a hand's URDF may hold besides kMaxHandLengthM and kMaxJointLimit
// (hand_loading.h); shapes must have a size.
// Mesh scales: 0.001 turns millimetre meshes into metres; beyond these no mesh is a hand part.
constexpr double kMinMeshScale = 1e-6;
constexpr double kMaxMeshScale = 1e3;
// A joint axis shorter than this has no direction.
constexpr double kMinAxisNorm = 1e-9;

// `value` (named `what`) is finite and in [min, max], else IoError(origin, ...).
void checkRange(const std::string& origin, const std::string& what, double value, double min,
                double max) {
  if (!(value >= min && value <= max)) {
    throw IoError(origin, fmt::format("{} is {:g}, outside [{:g}, {:g}]", what, value, min, max));
  }
}

// A shape's or a joint's origin: finite and within kMaxHandLengthM of its parent's frame.
void checkOrigin(const std::string& origin, const std::string& what, const urdf::Pose& pose) {
  const Eigen::Vector3d p(pose.position.x, pose.position.y, pose.position.z);
  const Eigen::Vector4d q(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z);
  if (!q.allFinite() || !(q.norm() > 0))
    throw IoError(origin, what + " origin has no finite rotation");
  checkRange(origin, what + " origin offset (m)", p.stableNorm(), 0, kMaxHandLengthM);
}

}  // namespace

ParsedUrdf parseUrdf(const std::string& urdf_xml, const std::string& base_dir,
                     const std::string& origin) {
  // urdfdom reports through console_bridge on stderr; we report one error line ourselves.
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  // Before urdfdom builds its tree (and we our per-link tables): count the elements in the text.
  for (const char* element : {"<link", "<joint"}) {
    std::size_t count = 0;
    for (auto at = urdf_xml.find(element); at != std::string::npos;
         at = urdf_xml.find(element, at + 1)) {
      if (++count > kMaxHandLinks) {
        throw IoError(origin, std::string("URDF has more than ") + std::to_string(kMaxHandLinks) +
                                  " " + (element + 1) + " elements");
      }
    }
  }
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(urdf_xml);
  } catch (const std::exception& e) {
    throw IoError(origin, std::string("invalid URDF: ") + e.what());
  }
  if (!model)
    throw IoError(origin, "invalid URDF (malformed XML or missing robot/link/joint attributes)");
  // urdfdom links hold their children by shared pointers: a URDF with a kinematic loop (refused
  // later, by the hand model) makes a cycle that would never be freed. Cut every link's child
  // pointers when the model is done with.
  struct CutChildLinks {
    const urdf::ModelInterfaceSharedPtr& model;
    ~CutChildLinks() {
      for (auto& entry : model->links_) {
        entry.second->child_links.clear();
        entry.second->child_joints.clear();
      }
    }
  } cut_child_links{model};
  if (!model->getRoot()) throw IoError(origin, "URDF has no root link");

  ParsedUrdf out;
  out.name = model->getName();
  std::map<std::string, int> link_index;
  // Deterministic order: root first, then the rest alphabetically (std::map order).
  std::vector<urdf::LinkConstSharedPtr> links{model->getRoot()};
  for (const auto& [name, link] : model->links_) {
    if (link != model->getRoot()) links.push_back(link);
  }
  for (const auto& l : links) {
    Link link;
    link.name = l->name;
    for (const auto& c : l->collision_array) {
      if (!c || !c->geometry) continue;
      const std::string what = "link '" + l->name + "' collision";
      checkOrigin(origin, what, c->origin);
      CollisionShape shape;
      shape.origin = toPose(c->origin);
      switch (c->geometry->type) {
        case urdf::Geometry::BOX: {
          const auto* b = static_cast<const urdf::Box*>(c->geometry.get());
          shape.type = ShapeType::kBox;
          shape.box_size = Eigen::Vector3d(b->dim.x, b->dim.y, b->dim.z);
          for (int k = 0; k < 3; ++k)
            checkRange(origin, what + " box size (m)", shape.box_size[k], 0, kMaxHandLengthM);
          if (!(shape.box_size.minCoeff() > 0)) throw IoError(origin, what + " box has no volume");
          break;
        }
        case urdf::Geometry::SPHERE:
          shape.type = ShapeType::kSphere;
          shape.radius = static_cast<const urdf::Sphere*>(c->geometry.get())->radius;
          checkRange(origin, what + " sphere radius (m)", shape.radius, 0, kMaxHandLengthM);
          if (!(shape.radius > 0)) throw IoError(origin, what + " sphere has no radius");
          break;
        case urdf::Geometry::CYLINDER: {
          const auto* cyl = static_cast<const urdf::Cylinder*>(c->geometry.get());
          shape.type = ShapeType::kCylinder;
          shape.radius = cyl->radius;
          shape.length = cyl->length;
          checkRange(origin, what + " cylinder radius (m)", shape.radius, 0, kMaxHandLengthM);
          checkRange(origin, what + " cylinder length (m)", shape.length, 0, kMaxHandLengthM);
          if (!(shape.radius > 0 && shape.length > 0))
            throw IoError(origin, what + " cylinder has no volume");
          break;
        }
        case urdf::Geometry::MESH: {
          const auto* m = static_cast<const urdf::Mesh*>(c->geometry.get());
          shape.type = ShapeType::kMesh;
          for (const double scale : {m->scale.x, m->scale.y, m->scale.z})
            checkRange(origin, what + " mesh scale", scale, kMinMeshScale, kMaxMeshScale);
          const std::string path = resolveMeshPath(m->filename, base_dir);
          shape.mesh = std::make_shared<const TriangleMesh>(
              loadMeshFile(path, Eigen::Vector3d(m->scale.x, m->scale.y, m->scale.z)));
          break;
        }
      }
      link.shapes.push_back(std::move(shape));
    }
    link_index[link.name] = static_cast<int>(out.links.size());
    out.links.push_back(std::move(link));
  }
  std::map<std::string, int> joint_index;
  for (const auto& [name, j] : model->joints_) {
    joint_index[name] = static_cast<int>(out.joints.size());
    Joint joint;
    joint.name = name;
    switch (j->type) {
      case urdf::Joint::FIXED:
        joint.type = JointType::kFixed;
        break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        joint.type = JointType::kRevolute;
        break;
      case urdf::Joint::PRISMATIC:
        joint.type = JointType::kPrismatic;
        break;
      default:
        throw IoError(
            origin, "joint '" + name + "': floating and planar joints are not supported in a hand");
    }
    joint.parent_link = link_index.at(j->parent_link_name);
    joint.child_link = link_index.at(j->child_link_name);
    checkOrigin(origin, "joint '" + name + "'", j->parent_to_joint_origin_transform);
    joint.origin = toPose(j->parent_to_joint_origin_transform);
    joint.axis = Eigen::Vector3d(j->axis.x, j->axis.y, j->axis.z);
    if (joint.movable()) {
      if (!joint.axis.allFinite() || !(joint.axis.stableNorm() >= kMinAxisNorm))
        throw IoError(origin, "joint '" + name + "' has a zero or non-finite axis");
      joint.axis /= joint.axis.stableNorm();
    }
    if (j->type == urdf::Joint::CONTINUOUS) {
      joint.lower = -1e9;
      joint.upper = 1e9;
    } else if (joint.movable()) {
      if (!j->limits) throw IoError(origin, "joint '" + name + "' has no <limit>");
      joint.lower = j->limits->lower;
      joint.upper = j->limits->upper;
      checkRange(origin, "joint '" + name + "' lower limit", joint.lower, -kMaxJointLimit,
                 kMaxJointLimit);
      checkRange(origin, "joint '" + name + "' upper limit", joint.upper, -kMaxJointLimit,
                 kMaxJointLimit);
      if (joint.lower > joint.upper)
        throw IoError(origin, "joint '" + name + "': lower limit above upper");
    }
    out.joints.push_back(std::move(joint));
    out.links[out.joints.back().child_link].parent_joint = static_cast<int>(out.joints.size()) - 1;
  }
  // Mimic references are resolved once all joints are known.
  for (const auto& [name, j] : model->joints_) {
    if (!j->mimic) continue;
    const auto it = joint_index.find(j->mimic->joint_name);
    if (it == joint_index.end()) {
      throw IoError(origin,
                    "joint '" + name + "' mimics unknown joint '" + j->mimic->joint_name + "'");
    }
    auto& joint = out.joints[joint_index[name]];
    if (it->second == joint_index[name])
      throw IoError(origin, "joint '" + name + "' mimics itself");
    joint.mimic_of = it->second;
    joint.mimic_multiplier = j->mimic->multiplier;
    joint.mimic_offset = j->mimic->offset;
    checkRange(origin, "joint '" + name + "' mimic multiplier", joint.mimic_multiplier,
               -kMaxJointLimit, kMaxJointLimit);
    checkRange(origin, "joint '" + name + "' mimic offset", joint.mimic_offset, -kMaxJointLimit,
               kMaxJointLimit);
  }
  // A joint follows its leader, which must lead back to a joint that follows none: a cycle of
  // mimics has no value to start from.
  for (const auto& joint : out.joints) {
    int leader = joint.mimic_of;
    for (std::size_t steps = 0; leader >= 0; ++steps) {
      if (steps >= out.joints.size())
        throw IoError(origin, "joint '" + joint.name + "' is in a cycle of mimic joints");
      leader = out.joints[static_cast<std::size_t>(leader)].mimic_of;
    }
  }
  out.root_link = 0;
  return out;
}

}  // namespace skelgrasp::grasping::internal
