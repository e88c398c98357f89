#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <regex>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/datasets/fetch.h"
#include "skelgrasp/datasets/ycb_raw.h"

extern char** environ;

namespace skelgrasp::datasets {

bool isValidYcbId(const std::string& id) {
  static const std::regex pattern(R"([0-9]{3}(-[a-z])?_[a-z0-9_]+)");
  return id.size() <= 64 && std::regex_match(id, pattern);
}

std::string ycbRgbdArchiveUrl(const std::string& id, const std::string& base_url) {
  if (!isValidYcbId(id)) {
    throw InvalidArgument("'" + id + "' is not a YCB object id (e.g. 003_cracker_box, 065-a_cups)");
  }
  std::string base = base_url;
  while (!base.empty() && base.back() == '/') base.pop_back();
  if (base.empty()) throw InvalidArgument("empty base URL");
  return base + "/" + id + "/" + id + "_berkeley_rgbd.tgz";
}

void unpackTarGz(const std::string& archive, const std::string& directory) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(archive, ec)) throw IoError(archive, "no such archive");
  fs::create_directories(directory, ec);
  if (ec) throw IoError(directory, "cannot create directory: " + ec.message());
  // tar from the system: always present on Debian, handles every tar/gzip variant, and keeps
  // skelgrasp free of another archive library. Arguments go straight to execve (no shell).
  std::vector<std::string> args = {"tar", "-xzf", archive, "-C", directory, "--no-same-owner"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "tar", nullptr, nullptr, argv.data(), environ);
  if (spawned != 0)
    throw IoError(archive, std::string("cannot run tar: ") + std::strerror(spawned));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR)
      throw IoError(archive, std::string("waiting for tar: ") + std::strerror(errno));
  }
  if (!WIFEXITED(status)) throw IoError(archive, "tar was killed by a signal");
  if (WEXITSTATUS(status) != 0) {
    throw IoError(archive, "tar failed with exit code " + std::to_string(WEXITSTATUS(status)) +
                               " (not a gzip-compressed tar archive, or truncated)");
  }
}

std::vector<FetchResult> fetchYcbRgbd(const std::vector<std::string>& ids,
                                      const std::string& directory, const std::string& base_url,
                                      bool keep_archives) {
  namespace fs = std::filesystem;
  for (const auto& id : ids) ycbRgbdArchiveUrl(id, base_url);  // validate all before downloading
  std::vector<FetchResult> results;
  for (const auto& id : ids) {
    FetchResult r;
    r.id = id;
    r.url = ycbRgbdArchiveUrl(id, base_url);
    r.archive = (fs::path(directory) / (id + "_berkeley_rgbd.tgz")).string();
    downloadFile(r.url, r.archive);
    const std::string target = (fs::path(directory) / (id + "_berkeley_rgbd")).string();
    unpackTarGz(r.archive, target);
    r.folder = findYcbRawFolder(target);
    if (r.folder.empty()) {
      throw IoError(r.archive, "unpacked, but no folder with calibration.h5 inside " + target);
    }
    if (!keep_archives) {
      std::error_code ec;
      fs::remove(r.archive, ec);
    }
    log().info("{}: ready in {}", id, r.folder);
    results.push_back(r);
  }
  return results;
}

}  // namespace skelgrasp::datasets
