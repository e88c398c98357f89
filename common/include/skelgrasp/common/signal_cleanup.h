#pragma once
// Cleanup of half-made outputs when the process is ended by SIGINT, SIGTERM or SIGHUP (Ctrl-C,
// `kill`, a closed terminal). The atomic writer (atomic_file.h) registers its hidden temporaries
// and the directories it creates for outputs; if such a signal arrives while they are registered,
// the handler removes the files, then the directories that are left empty (innermost first), and
// lets the signal end the process with its usual status. A normal exit or an exception leaves the
// cleanup to the owners' destructors.
//
// Only the command-line program installs the handlers (installSignalCleanup); the Python module
// leaves the interpreter's signals alone. Registering without handlers costs a few atomic
// operations. At most kMaxSignalCleanupEntries paths of up to kMaxSignalCleanupPathBytes bytes are
// registered at once; beyond that a path is simply not cleaned on a signal.
#include <cstddef>
#include <string>

namespace skelgrasp {

inline constexpr std::size_t kMaxSignalCleanupEntries = 256;
inline constexpr std::size_t kMaxSignalCleanupPathBytes = 4096;

// Installs the handlers for SIGINT, SIGTERM and SIGHUP, except for a signal this process ignores
// (a background job's SIGINT, nohup's SIGHUP), which stays ignored. Idempotent.
void installSignalCleanup();

// What the handler does before the signal ends the process: removes every registered file, then
// every registered directory that is empty, the last registered first. Async-signal-safe; callable
// outside a handler (tests). Entries stay registered.
void runSignalCleanup();

// A file or a directory removed by runSignalCleanup while this object lives.
class SignalCleanupEntry {
 public:
  enum class Kind { kFile, kEmptyDirectory };
  SignalCleanupEntry() = default;  // registers nothing
  SignalCleanupEntry(const std::string& path, Kind kind);
  ~SignalCleanupEntry();
  SignalCleanupEntry(SignalCleanupEntry&& other) noexcept;
  SignalCleanupEntry& operator=(SignalCleanupEntry&& other) noexcept;
  SignalCleanupEntry(const SignalCleanupEntry&) = delete;
  SignalCleanupEntry& operator=(const SignalCleanupEntry&) = delete;

 private:
  void release();
  int slot_ = -1;  // -1: nothing registered (none given, no free slot or the path too long)
};

}  // namespace skelgrasp
