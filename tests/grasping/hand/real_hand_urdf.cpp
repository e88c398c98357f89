#include "real_hand_urdf.h"

#include <fstream>
#include <map>
#include <sstream>

#include "skelgrasp/common/json.h"

namespace skelgrasp::test {
namespace {

struct Names {
  std::string link;
  std::string joint;  // for nodes with a joint
};

// Simox node -> our link/joint names, where the default rule (joint nodes without a mesh become a
// joint of that name and a link "<name>_frame"; other nodes a link of their own name) does not
// give the built-in description's names.
std::map<std::string, Names> nameMap(const std::string& builtin) {
  if (builtin == "armar3") {
    std::map<std::string, Names> m = {{"Hand R Base", {"base", ""}},
                                      {"Hand Palm 1 R", {"palm1", ""}},
                                      {"Hand Palm 2 R", {"palm2", "palm2_joint"}}};
    for (const std::string f : {"Thumb", "Index", "Middle", "Ring", "Pinky"}) {
      std::string lower = f;
      lower[0] = static_cast<char>(std::tolower(lower[0]));
      m[f + " R J0"] = {lower + "_proximal", lower + "_j0"};
      m[f + " R J1"] = {lower + "_distal", lower + "_j1"};
    }
    return m;
  }
  if (builtin == "sdh") {
    std::map<std::string, Names> m = {
        {"left_hand_base", {"base", ""}},
        {"left_sdh_connector_link", {"connector", ""}},
        {"left_sdh_palm_link", {"palm", ""}},
        {"left_sdh_thumb_1_joint", {"thumb_base_frame", "thumb_base_joint"}},
        {"left_sdh_thumb_1_link", {"thumb_knuckle", ""}},
        {"left_sdh_thumb_2_joint", {"thumb_proximal_frame", "thumb_proximal_joint"}},
        {"left_sdh_thumb_2_link", {"thumb_proximal", ""}},
        {"left_sdh_thumb_3_joint", {"thumb_distal_frame", "thumb_distal_joint"}},
        {"left_sdh_thumb_3_link", {"thumb_distal", ""}}};
    for (const std::string f : {"1", "2"}) {
      const std::string p = "left_sdh_finger_" + f, ours = "finger" + f;
      m[p + "1_joint"] = {ours + "_base_frame", ours + "_base_joint"};
      m[p + "1_link"] = {ours + "_knuckle", ""};
      m[p + "2_joint"] = {ours + "_proximal_frame", ours + "_proximal_joint"};
      m[p + "2_link"] = {ours + "_proximal", ""};
      m[p + "3_joint"] = {ours + "_distal_frame", ours + "_distal_joint"};
      m[p + "3_link"] = {ours + "_distal", ""};
    }
    return m;
  }
  if (builtin == "parallel_gripper") {
    return {{"panda_hand", {"hand", ""}},
            {"panda_leftfinger", {"left_finger", "finger_left"}},
            {"panda_rightfinger", {"right_finger", "finger_right"}}};
  }
  // Shadow: Simox names are ours, but our root is the forearm link itself.
  return {{"shadowhand_hand_base", {"forearm", ""}}, {"forearm", {"forearm_shell", ""}}};
}

std::string sanitise(std::string s) {
  for (char& c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  }
  return s;
}

}  // namespace

std::string writeRealHandUrdf(const std::string& hand_dir, const std::string& builtin,
                              const std::string& out_dir) {
  const auto hand = readJsonFile(hand_dir + "/hand.json");
  const auto names = nameMap(builtin);
  auto namesOf = [&](const nlohmann::json& node) {
    const std::string n = node.at("name").get<std::string>();
    const auto it = names.find(n);
    if (it != names.end()) return it->second;
    const bool joint_only = !node.at("joint").is_null() && node.at("collision_mesh").is_null();
    return joint_only ? Names{sanitise(n) + "_frame", sanitise(n)}
                      : Names{sanitise(n), sanitise(n) + "_joint"};
  };
  std::map<std::string, Names> by_node;
  for (const auto& node : hand.at("nodes"))
    by_node[node.at("name").get<std::string>()] = namesOf(node);

  std::ostringstream urdf;
  urdf << "<?xml version=\"1.0\"?>\n<robot name=\"" << builtin << "_real\">\n";
  for (const auto& node : hand.at("nodes")) {
    const Names& n = by_node[node.at("name").get<std::string>()];
    urdf << "  <link name=\"" << n.link << "\">";
    if (!node.at("collision_mesh").is_null()) {
      urdf << "<collision><geometry><mesh filename=\"" << hand_dir << "/"
           << node.at("collision_mesh").get<std::string>()
           << "\" scale=\"0.001 0.001 0.001\"/></geometry></collision>";
    }
    urdf << "</link>\n";
    if (node.at("parent").is_null()) continue;
    const auto& T = node.at("T_parent_node_mm");
    Eigen::Matrix3d rotation;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) rotation(r, c) = T[r][c].get<double>();
    }
    const Eigen::Vector3d rpy = rotation.eulerAngles(2, 1, 0).reverse();  // URDF: Rz(y) Ry(p) Rx(r)
    const auto& joint = node.at("joint");
    const std::string parent_link = by_node[node.at("parent").get<std::string>()].link;
    std::string type = "fixed";
    double scale = 1.0;
    if (!joint.is_null()) {
      type = joint.at("type").get<std::string>();
      if (joint.value("unit", "") == "mm") scale = 0.001;
    }
    urdf << "  <joint name=\"" << (joint.is_null() ? n.link + "_fixed" : n.joint) << "\" type=\""
         << type << "\">\n"
         << "    <parent link=\"" << parent_link << "\"/><child link=\"" << n.link << "\"/>\n"
         << "    <origin xyz=\"" << T[0][3].get<double>() / 1000 << " "
         << T[1][3].get<double>() / 1000 << " " << T[2][3].get<double>() / 1000 << "\" rpy=\""
         << rpy.x() << " " << rpy.y() << " " << rpy.z() << "\"/>\n";
    if (!joint.is_null()) {
      const auto& axis = joint.at("axis");
      urdf << "    <axis xyz=\"" << axis[0].get<double>() << " " << axis[1].get<double>() << " "
           << axis[2].get<double>() << "\"/>\n    <limit lower=\""
           << joint.at("lo").get<double>() * scale << "\" upper=\""
           << joint.at("hi").get<double>() * scale << "\" effort=\"1\" velocity=\"1\"/>\n";
      // The built-in gripper's jaws close independently (parallel_gripper.urdf): its real
      // counterpart is written the same way.
      if (joint.contains("mimic") && builtin != "parallel_gripper") {
        urdf << "    <mimic joint=\"" << by_node[joint.at("mimic").get<std::string>()].joint
             << "\" multiplier=\"1\"/>\n";
      }
    }
    urdf << "  </joint>\n";
  }
  urdf << "</robot>\n";
  const std::string path = out_dir + "/" + builtin + "_real.urdf";
  std::ofstream(path) << urdf.str();
  return path;
}

}  // namespace skelgrasp::test
