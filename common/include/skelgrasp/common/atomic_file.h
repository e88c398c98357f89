#pragma once
// Atomic file output. Every file skelgrasp writes goes first to a temporary sibling in the same
// directory (".NAME.tmp.PID.N.EXT": hidden, unique per process and call, same extension so that
// libraries choosing the format by extension still work), is checked (stream state, fsync,
// close) and only then renamed over the final path. A reader therefore sees the old file or the
// complete new one, never a truncated one; on any error the temporary is removed and IoError
// names the final path and the problem ("No space left on device").
//
// Paths that exist and are neither regular files nor directories (/dev/null, /dev/stdout, a
// FIFO) are written directly: renaming over them would replace the device node.
#include <cstddef>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "skelgrasp/common/signal_cleanup.h"

namespace skelgrasp {

// Writes `path` through `write(stream)`. Creates missing parent directories (and removes them
// again on failure). Throws IoError(path, problem); an exception from `write` removes the
// temporary and propagates (an IoError naming another path is renamed to `path`).
void writeFileAtomically(const std::string& path,
                         const std::function<void(std::ostream& out)>& write);
void writeFileAtomically(const std::string& path, const std::string& text);

// For libraries that only write to a file name (PCL, OctoMap, OpenCV, CGAL, HDF5):
// `write(temporary_path)` writes the whole file there (the name exists, empty, when it is
// called; the library may truncate or replace it). Same guarantees as writeFileAtomically.
void writeFileViaTemporary(const std::string& path,
                           const std::function<void(const std::string& temporary_path)>& write);

// The temporary sibling name used for `path`: DIR/.STEM.tmp.PID.N.EXT (N counts per process).
std::string temporarySiblingPath(const std::string& path);
// The final path a temporary of this process stands for: DIR/STEM.EXT for DIR/.STEM.tmp.PID.N.EXT
// with PID this process's id (a temporary of a temporary as well); any other path unchanged. Errors
// of the writers name it, so that a full disk names object_0.ply, not the hidden file it was
// written to.
std::string finalPathOfTemporary(const std::string& path);
// Removes the temporaries (.STEM.tmp.PID.N.EXT) in `dir` whose process no longer runs: what a
// command killed by SIGKILL or a power cut left. Those of live processes stay. Returns how many
// were removed; errors are ignored (a later command tries again).
std::size_t removeStaleTemporaries(const std::string& dir);

// Creates the output directory `dir` and its missing parents, as writing a file in it would
// (never a first directory in the filesystem root). Returns the directories it created, outermost
// first. Throws IoError(dir, problem).
std::vector<std::string> createOutputDirectory(const std::string& dir);

// An ostream over a POSIX file descriptor that keeps the errno of a failed write, which
// std::ofstream forgets. close() flushes, fsyncs and closes; it throws IoError(path, strerror).
class CheckedOutputFile {
 public:
  enum class Mode { kCreateNew, kTruncate };
  CheckedOutputFile(const std::string& path, Mode mode);
  ~CheckedOutputFile();  // closes without checking; call close() to learn about errors
  CheckedOutputFile(const CheckedOutputFile&) = delete;
  CheckedOutputFile& operator=(const CheckedOutputFile&) = delete;

  std::ostream& stream();
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Output paths checked before a command computes anything. Throws IoError(path, problem) unless
// `path` can be written: it is not a directory, and its nearest existing ancestor directory is a
// directory in which a probe file can be created (and is removed again). Creates nothing.
void checkOutputFile(const std::string& path);
// Same for an output directory: `path` is a directory or does not exist yet, and files can be
// created in it (or in its nearest existing ancestor).
void checkOutputDirectory(const std::string& path);

// Several output files of one command that appear together or not at all. stage(final) returns a
// temporary sibling name to write instead of `final` (with any writer, atomic or not); commit()
// renames them into place in staging order, so stage the file that indexes the others last.
// Destroyed without commit() (an exception, an early return) it removes every temporary and the
// directories it created, so a failed command leaves nothing behind.
class OutputTransaction {
 public:
  OutputTransaction() = default;
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  // Throws IoError when `final_path` is a directory or its directory cannot be created.
  std::string stage(const std::string& final_path);
  // Throws IoError naming the final path when a rename fails; temporaries not yet renamed are
  // removed. Then the hidden temporaries killed commands left in the directories written to are
  // removed (removeStaleTemporaries).
  void commit();

  // The files of `dir` this transaction writes replace those of the previous command that wrote
  // `dir` this way: commit() also removes the files that command listed in DIR/kOutputListFile
  // and this one did not write (a scene run's object_3.ply after a run with two objects), and
  // lists its own there. Files it never listed (the user's) are left alone. The list names plain
  // files of `dir` only; a malformed or oversized one is ignored.
  void replacePreviousOutputsIn(const std::string& dir);

 private:
  struct Staged {
    std::string temporary;
    std::string target;
    SignalCleanupEntry on_signal;  // the temporary, removed if a signal ends the process
  };
  std::vector<Staged> staged_;
  std::vector<std::string> created_directories_;  // outermost first
  std::vector<SignalCleanupEntry> created_on_signal_;
  std::string owned_directory_;  // replacePreviousOutputsIn's
  bool committed_ = false;
};

// The hidden file that lists the outputs a command wrote in its directory
// (OutputTransaction::replacePreviousOutputsIn), one name per line.
inline constexpr const char* kOutputListFile = ".skelgrasp-outputs";
// A longer list is not one skelgrasp wrote and is ignored.
inline constexpr std::size_t kMaxOutputListBytes = 1 << 20;

}  // namespace skelgrasp
