// libcurl translation unit: file downloads.
#include <curl/curl.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/datasets/fetch.h"

namespace skelgrasp::datasets {
namespace {

struct Transfer {
  std::ofstream* out = nullptr;
  std::string url;
  Stopwatch watch;
  double last_report_s = 0;
};

std::size_t writeBody(char* data, std::size_t size, std::size_t count, void* user) {
  auto* transfer = static_cast<Transfer*>(user);
  transfer->out->write(data, static_cast<std::streamsize>(size * count));
  return *transfer->out ? size * count : 0;  // a short count makes curl fail with a write error
}

int progress(void* user, curl_off_t total, curl_off_t now, curl_off_t, curl_off_t) {
  auto* transfer = static_cast<Transfer*>(user);
  const double t = transfer->watch.seconds();
  if (t - transfer->last_report_s < 5.0) return 0;
  transfer->last_report_s = t;
  if (total > 0) {
    log().info("{}: {:.1f} of {:.1f} MB ({:.0f}%)", transfer->url, now / 1e6, total / 1e6,
               100.0 * static_cast<double>(now) / static_cast<double>(total));
  } else {
    log().info("{}: {:.1f} MB", transfer->url, now / 1e6);
  }
  return 0;
}

}  // namespace

void downloadFile(const std::string& url, const std::string& destination) {
  static const CURLcode global = curl_global_init(CURL_GLOBAL_DEFAULT);
  if (global != CURLE_OK) throw IoError(url, "cannot initialise libcurl");
  namespace fs = std::filesystem;
  const fs::path target(destination);
  if (target.has_parent_path()) fs::create_directories(target.parent_path());
  const std::string part = destination + ".part";
  std::ofstream out(part, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError(part, "cannot open for writing");

  CURL* curl = curl_easy_init();
  if (!curl) throw IoError(url, "cannot create a libcurl handle");
  Transfer transfer;
  transfer.out = &out;
  transfer.url = url;
  char error[CURL_ERROR_SIZE] = {0};
  curl_easy_setopt(curl, CURLOPT_URL, url.c_str());
  curl_easy_setopt(curl, CURLOPT_ERRORBUFFER, error);
  curl_easy_setopt(curl, CURLOPT_FOLLOWLOCATION, 1L);
  curl_easy_setopt(curl, CURLOPT_FAILONERROR, 1L);  // HTTP >= 400 is an error, not a body
  curl_easy_setopt(curl, CURLOPT_CONNECTTIMEOUT, 30L);
  curl_easy_setopt(curl, CURLOPT_LOW_SPEED_LIMIT, 1024L);  // abort below 1 kB/s for a minute
  curl_easy_setopt(curl, CURLOPT_LOW_SPEED_TIME, 60L);
  curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, writeBody);
  curl_easy_setopt(curl, CURLOPT_WRITEDATA, &transfer);
  curl_easy_setopt(curl, CURLOPT_XFERINFOFUNCTION, progress);
  curl_easy_setopt(curl, CURLOPT_XFERINFODATA, &transfer);
  curl_easy_setopt(curl, CURLOPT_NOPROGRESS, 0L);
  const CURLcode code = curl_easy_perform(curl);
  long http = 0;
  curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &http);
  curl_easy_cleanup(curl);
  out.close();
  if (code != CURLE_OK || !out) {
    std::error_code ec;
    fs::remove(part, ec);
    std::string reason = error[0] ? error : curl_easy_strerror(code);
    if (http >= 400) reason = "HTTP " + std::to_string(http) + " (" + reason + ")";
    throw IoError(url, "download failed: " + reason);
  }
  fs::rename(part, destination);
  log().info("{}: downloaded to {} ({:.1f} MB, {:.1f} s)", url, destination,
             static_cast<double>(fs::file_size(destination)) / 1e6, transfer.watch.seconds());
}

}  // namespace skelgrasp::datasets
