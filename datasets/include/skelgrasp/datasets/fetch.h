#pragma once
// Downloading and unpacking the official YCB raw RGB-D archives.
#include <string>
#include <vector>

namespace skelgrasp::datasets {

// Where the YCB object set is published (http only; the bucket's website endpoint).
inline constexpr const char* kYcbDefaultBaseUrl =
    "http://ycb-benchmarks.s3-website-us-east-1.amazonaws.com/data/berkeley";

// True for YCB object ids such as "003_cracker_box" or "065-a_cups" (three digits, an optional
// "-letter", "_", then lower-case letters, digits and underscores). Ids go into URLs and paths,
// so nothing else is accepted.
bool isValidYcbId(const std::string& id);

// "<base>/<id>/<id>_berkeley_rgbd.tgz" (a trailing "/" on base is ignored). Throws InvalidArgument
// for an invalid id or an empty base.
std::string ycbRgbdArchiveUrl(const std::string& id,
                              const std::string& base_url = kYcbDefaultBaseUrl);

// Downloads `url` (http, https or file) to `destination` through a ".part" file renamed on
// success, logging progress. Throws IoError naming the URL on any failure (HTTP status >= 400,
// connection, write).
void downloadFile(const std::string& url, const std::string& destination);

// Unpacks a gzip-compressed tar archive into `directory` (created if needed) by running the
// system `tar -xzf ARCHIVE -C DIR --no-same-owner` without a shell. GNU tar refuses members with
// ".." and strips leading "/", so an archive cannot write outside `directory`. Throws IoError when
// tar cannot run or exits non-zero.
void unpackTarGz(const std::string& archive, const std::string& directory);

struct FetchResult {
  std::string id;
  std::string url;
  std::string archive;  // downloaded file (deleted after unpacking unless kept)
  std::string folder;   // unpacked capture folder (contains calibration.h5)
};

// Downloads and unpacks each id into `directory`. Throws InvalidArgument / IoError.
std::vector<FetchResult> fetchYcbRgbd(const std::vector<std::string>& ids,
                                      const std::string& directory,
                                      const std::string& base_url = kYcbDefaultBaseUrl,
                                      bool keep_archives = false);

}  // namespace skelgrasp::datasets
