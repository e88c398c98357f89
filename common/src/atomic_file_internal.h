#pragma once
// The path helpers atomic_file.cpp and output_transaction.cpp share (not installed).
#include <filesystem>
#include <string>
#include <vector>

namespace skelgrasp::internal {

// Absolute, lexically normal form, so that walking up the ancestors ends at the root.
std::filesystem::path absoluteNormal(const std::string& path);

// The directories above `file` that do not exist yet, innermost first, and the nearest one that
// does. Throws IoError(report_path) when that one is not a directory, or when the first missing
// directory would be made in the filesystem root: "/nonexistent/dir/x.png" is a typo far more
// often than a wish (and as root it would succeed).
std::vector<std::filesystem::path> missingDirectories(const std::filesystem::path& file,
                                                      const std::string& report_path,
                                                      std::filesystem::path* existing);

// Removes the directories `created` (outermost first) again where they are empty.
void removeCreatedDirectories(const std::vector<std::string>& created);

// Creates the missing parent directories of `file`; returns those it created, outermost first.
std::vector<std::string> createParentDirectories(const std::filesystem::path& file,
                                                 const std::string& report_path);

// Where the output really goes: the file a symlink points to (replacing the link itself would
// silently detach it).
std::filesystem::path resolveTarget(const std::string& path);

// Existing and neither a regular file nor a directory: a device or a FIFO, written in place.
bool isSpecialFile(const std::filesystem::path& path);

// Throws IoError(report_path, "is a directory") when `path` is one.
void requireNotDirectory(const std::filesystem::path& path, const std::string& report_path);

// Renames `temporary` over `target`; throws IoError(report_path) when that fails.
void replaceWith(const std::string& temporary, const std::filesystem::path& target,
                 const std::string& report_path);

}  // namespace skelgrasp::internal
