#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "builtin_hand_data.h"
#include "hand_loading.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp::grasping {

namespace internal {

std::string readBoundedText(const std::string& path, std::uintmax_t max_bytes,
                            const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IoError(path, "no such file");
  if (fs::is_directory(path, ec)) throw IoError(path, "is a directory");
  // A device or a pipe (/dev/zero) has no size to check and may never end.
  if (!fs::is_regular_file(path, ec)) throw IoError(path, "is not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw IoError(path, "cannot read file size: " + ec.message());
  if (size > max_bytes) {
    throw IoError(path, what + " of " + std::to_string(size) + " bytes exceeds the limit of " +
                            std::to_string(max_bytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open for reading");
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(size))) throw IoError(path, "read failed");
  if (text.empty()) throw IoError(path, "file is empty");
  return text;
}

}  // namespace internal

namespace {

// URDF problems are reported against `urdf_origin`, description problems against `desc_origin`.
HandModel buildHand(const std::string& urdf_xml, const std::string& description_json,
                    const std::string& base_dir, const std::string& urdf_origin,
                    const std::string& desc_origin) {
  auto parsed = internal::parseUrdf(urdf_xml, base_dir, urdf_origin);
  const std::string& origin = desc_origin;
  std::string title = parsed.name;
  try {
    const auto d = nlohmann::json::parse(description_json);
    title = d.value("title", parsed.name);
    if (d.contains("name")) parsed.name = d.at("name").get<std::string>();
    if (d.contains("base_link") &&
        d.at("base_link").get<std::string>() != parsed.links[parsed.root_link].name) {
      throw IoError(origin, "base_link '" + d.at("base_link").get<std::string>() +
                                "' is not the URDF's root link '" +
                                parsed.links[parsed.root_link].name + "'");
    }
  } catch (const nlohmann::json::exception&) {
    // Reported with its position by applyGraspDescription below.
  }
  // The tree's own checks (a kinematic loop, a link not connected to the root) are about the
  // URDF: they name its file.
  HandModel hand = [&] {
    try {
      return HandModel(parsed.name, title, std::move(parsed.links), std::move(parsed.joints),
                       parsed.root_link);
    } catch (const InvalidArgument& e) {
      throw IoError(urdf_origin, e.what());
    }
  }();
  internal::applyGraspDescription(hand, description_json, origin);
  log().debug("hand '{}': {} links, {} joints, {} fingers, {} drives", hand.name(),
              hand.links().size(), hand.joints().size(), hand.fingers().size(), hand.numDrives());
  return hand;
}

}  // namespace

HandModel loadHandFromText(const std::string& urdf_xml, const std::string& description_json,
                           const std::string& base_dir, const std::string& origin) {
  return buildHand(urdf_xml, description_json, base_dir, origin, origin);
}

HandModel loadHand(const std::string& urdf_path, const std::string& description_path) {
  const std::string urdf = internal::readBoundedText(urdf_path, internal::kMaxUrdfBytes, "URDF");
  const std::string description = internal::readBoundedText(
      description_path, internal::kMaxGraspDescriptionBytes, "grasp description");
  const std::string dir = std::filesystem::path(urdf_path).parent_path().string();
  return buildHand(urdf, description, dir.empty() ? "." : dir, urdf_path, description_path);
}

std::vector<std::string> builtinHandNames() {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < internal::kNumEmbeddedHands; ++i)
    names.push_back(internal::kEmbeddedHands[i].name);
  return names;
}

HandFiles builtinHandFiles(const std::string& name) {
  for (std::size_t i = 0; i < internal::kNumEmbeddedHands; ++i) {
    const auto& h = internal::kEmbeddedHands[i];
    if (name == h.name) return {h.urdf, h.description};
  }
  throw InvalidArgument("unknown built-in hand '" + name + "'");
}

HandModel loadBuiltinHand(const std::string& name) {
  for (std::size_t i = 0; i < internal::kNumEmbeddedHands; ++i) {
    const auto& h = internal::kEmbeddedHands[i];
    if (name == h.name)
      return loadHandFromText(h.urdf, h.description, ".", "built-in hand '" + name + "'");
  }
  std::string known;
  for (const auto& n : builtinHandNames()) known += (known.empty() ? "" : ", ") + n;
  throw InvalidArgument("unknown hand '" + name + "' (built-in hands: " + known +
                        "; or pass a .urdf with --grasp-description)");
}

HandModel resolveHand(const std::string& hand, const std::string& description_path) {
  const bool is_urdf = hand.size() > 5 && hand.substr(hand.size() - 5) == ".urdf";
  if (!is_urdf) {
    if (!description_path.empty()) {
      throw InvalidArgument(
          "--grasp-description is only used with a .urdf hand, not the built-in '" + hand + "'");
    }
    return loadBuiltinHand(hand);
  }
  if (description_path.empty()) {
    throw InvalidArgument("hand '" + hand +
                          "' is a URDF file: also pass --grasp-description DESC.json");
  }
  return loadHand(hand, description_path);
}

}  // namespace skelgrasp::grasping
