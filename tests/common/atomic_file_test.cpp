// Atomic outputs: a file is replaced completely or not at all, errors name the final path, and no
// temporary is ever left behind.
#include "skelgrasp/common/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <sys/wait.h>
#include <unistd.h>

#include "skelgrasp/common/error.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Every entry below `dir` whose name marks it as one of our temporaries.
std::vector<std::string> temporariesUnder(const std::string& dir) {
  std::vector<std::string> found;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".tmp") != std::string::npos || name.find("probe") != std::string::npos) {
      found.push_back(entry.path().string());
    }
  }
  return found;
}

TEST(AtomicFile, WriteReplacesTheOldContentAndLeavesNoTemporary) {
  const std::string dir = test::tempDir("atomic_replace");
  const std::string path = dir + "/result.json";
  writeFileAtomically(path, std::string("old"));
  writeFileAtomically(path, [](std::ostream& out) { out << "new " << 42; });
  EXPECT_EQ(slurp(path), "new 42");
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(AtomicFile, LargeWritesPassTheBufferIntact) {
  const std::string dir = test::tempDir("atomic_large");
  std::string payload(3'000'000, '\0');
  for (std::size_t i = 0; i < payload.size(); ++i) payload[i] = static_cast<char>(i * 7919 % 251);
  writeFileAtomically(dir + "/big.bin", [&](std::ostream& out) {
    out << "header\n";
    out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
  });
  EXPECT_EQ(slurp(dir + "/big.bin"), "header\n" + payload);
}

TEST(AtomicFile, ThrowingWriterKeepsTheOldFileAndRemovesTheTemporary) {
  const std::string dir = test::tempDir("atomic_throw");
  const std::string path = dir + "/mesh.ply";
  writeFileAtomically(path, std::string("complete old mesh"));
  EXPECT_THROW(writeFileAtomically(path,
                                   [](std::ostream& out) {
                                     out << "half a mesh";
                                     throw std::runtime_error("writer failed");
                                   }),
               std::runtime_error);
  EXPECT_THROW(writeFileViaTemporary(path,
                                     [](const std::string& temporary) {
                                       std::ofstream(temporary) << "half";
                                       throw std::runtime_error("library failed");
                                     }),
               std::runtime_error);
  EXPECT_EQ(slurp(path), "complete old mesh");
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(AtomicFile, FailedWriteIntoANewDirectoryRemovesTheDirectoryAgain) {
  const std::string dir = test::tempDir("atomic_new_dir");
  EXPECT_THROW(
      writeFileAtomically(dir + "/a/b/out.json", [](std::ostream&) { throw IoError("x", "no"); }),
      IoError);
  EXPECT_FALSE(fs::exists(dir + "/a"));
  writeFileAtomically(dir + "/a/b/out.json", std::string("{}"));
  EXPECT_EQ(slurp(dir + "/a/b/out.json"), "{}");
}

TEST(AtomicFile, CallbackVariantKeepsTheExtensionForFormatChoosingLibraries) {
  const std::string dir = test::tempDir("atomic_callback");
  std::string seen;
  writeFileViaTemporary(dir + "/scene.pcd", [&](const std::string& temporary) {
    seen = temporary;
    std::ofstream(temporary) << "cloud";
  });
  EXPECT_EQ(fs::path(seen).extension(), ".pcd");
  EXPECT_EQ(fs::path(seen).parent_path(), fs::path(dir));
  EXPECT_EQ(fs::path(seen).filename().string().rfind(".scene.tmp.", 0), 0u) << seen;
  EXPECT_EQ(slurp(dir + "/scene.pcd"), "cloud");
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(AtomicFile, PathBelowARegularFileThrowsIoErrorNamingThePath) {
  const std::string dir = test::tempDir("atomic_not_dir");
  writeFileAtomically(dir + "/plain", std::string("a file, not a directory"));
  const std::string path = dir + "/plain/sub/out.png";
  try {
    writeFileAtomically(path, std::string("x"));
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_NE(e.problem().find("is not a directory"), std::string::npos) << e.what();
  }
  EXPECT_THROW(writeFileViaTemporary(path, [](const std::string&) {}), IoError);
  EXPECT_THROW(checkOutputFile(path), IoError);
  EXPECT_THROW(checkOutputDirectory(dir + "/plain"), IoError);
  EXPECT_EQ(slurp(dir + "/plain"), "a file, not a directory");
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(AtomicFile, DirectoryAsTargetIsRefused) {
  const std::string dir = test::tempDir("atomic_target_dir");
  fs::create_directories(dir + "/out.json");
  EXPECT_THROW(writeFileAtomically(dir + "/out.json", std::string("x")), IoError);
  EXPECT_THROW(checkOutputFile(dir + "/out.json"), IoError);
  EXPECT_NO_THROW(checkOutputDirectory(dir + "/out.json"));
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(AtomicFile, FullDiskIsReportedWithTheSystemsReason) {
  // /dev/full fails every write with ENOSPC: the stream path must say so instead of "failed".
  CheckedOutputFile full("/dev/full", CheckedOutputFile::Mode::kTruncate);
  full.stream() << std::string(1 << 20, 'x');
  try {
    full.close();
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), "/dev/full");
    EXPECT_NE(e.problem().find("No space left on device"), std::string::npos) << e.what();
  }
}

TEST(AtomicFile, FullDiskInsideACallbackLeavesTheOldFile) {
  const std::string dir = test::tempDir("atomic_full_callback");
  const std::string path = dir + "/scene.bt";
  writeFileAtomically(path, std::string("old tree"));
  try {
    writeFileViaTemporary(path, [](const std::string&) {
      CheckedOutputFile full("/dev/full", CheckedOutputFile::Mode::kTruncate);
      full.stream() << std::string(1 << 20, 'x');
      full.close();
    });
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(e.problem().find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(path), "old tree");
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(AtomicFile, SpecialFilesAreWrittenInPlace) {
  // Renaming a temporary over /dev/null would replace the device node.
  EXPECT_NO_THROW(writeFileAtomically("/dev/null", std::string("discarded")));
  EXPECT_NO_THROW(checkOutputFile("/dev/null"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

TEST(AtomicFile, SymlinkedTargetIsReplacedBehindTheLink) {
  const std::string dir = test::tempDir("atomic_symlink");
  writeFileAtomically(dir + "/real.json", std::string("old"));
  fs::create_symlink(dir + "/real.json", dir + "/link.json");
  writeFileAtomically(dir + "/link.json", std::string("new"));
  EXPECT_TRUE(fs::is_symlink(dir + "/link.json"));
  EXPECT_EQ(slurp(dir + "/real.json"), "new");
}

TEST(OutputPaths, CheckAcceptsWritableAndRefusesImpossiblePathsCreatingNothing) {
  const std::string dir = test::tempDir("output_paths");
  EXPECT_NO_THROW(checkOutputFile(dir + "/x.png"));
  EXPECT_NO_THROW(checkOutputFile(dir + "/new/deeper/x.png"));  // made by the writer later
  EXPECT_NO_THROW(checkOutputDirectory(dir + "/run_out"));
  EXPECT_FALSE(fs::exists(dir + "/new"));
  EXPECT_FALSE(fs::exists(dir + "/run_out"));
  try {
    checkOutputFile("/no/such/dir/x.png");
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), "/no/such/dir/x.png");
    EXPECT_NE(e.problem().find("no such directory /no/such/dir"), std::string::npos) << e.what();
  }
  EXPECT_THROW(checkOutputDirectory("/no/such/dir"), IoError);
  EXPECT_THROW(checkOutputFile(""), InvalidArgument);
  EXPECT_FALSE(fs::exists("/no"));
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

TEST(OutputTransaction, FilesAppearOnlyAtCommitInStagingOrder) {
  const std::string dir = test::tempDir("transaction_commit");
  const std::string out = dir + "/run";
  {
    OutputTransaction outputs;
    const std::string mesh = outputs.stage(out + "/object.ply");
    const std::string index = outputs.stage(out + "/grasps.json");
    const std::string skipped = outputs.stage(out + "/empty.png");  // its writer writes nothing
    writeFileAtomically(mesh, std::string("mesh"));
    writeFileAtomically(index, std::string("index"));
    EXPECT_FALSE(fs::exists(out + "/object.ply"));
    EXPECT_FALSE(fs::exists(out + "/grasps.json"));
    EXPECT_EQ(outputs.stage(out + "/object.ply"), mesh);
    EXPECT_NE(skipped, mesh);
    outputs.commit();
  }
  EXPECT_EQ(slurp(out + "/object.ply"), "mesh");
  EXPECT_EQ(slurp(out + "/grasps.json"), "index");
  EXPECT_FALSE(fs::exists(out + "/empty.png"));
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

// A command killed while writing leaves hidden temporaries named after its process; the next
// command to commit files into that directory (a second `plan --out` there) removes them, and
// leaves those of a process that still runs and the user's own files.
TEST(OutputTransaction, ACommitClearsTheTemporariesOfKilledCommands) {
  const std::string dir = test::tempDir("transaction_stale");
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);  // a process id that no longer runs
  const std::string stale = dir + "/.grasps.tmp." + std::to_string(child) + ".3.json";
  const std::string alive = dir + "/.grasps.tmp." + std::to_string(::getppid()) + ".1.json";
  const std::string users = dir + "/notes.tmp.1.txt";
  for (const auto& path : {stale, alive, users}) std::ofstream(path) << "x";
  {
    OutputTransaction outputs;
    writeFileAtomically(outputs.stage(dir + "/grasps.json"), std::string("new"));
    EXPECT_TRUE(fs::exists(stale));  // only at commit
    outputs.commit();
  }
  EXPECT_EQ(slurp(dir + "/grasps.json"), "new");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(alive));
  EXPECT_TRUE(fs::exists(users));
}

TEST(OutputTransaction, FailureBeforeCommitLeavesNothingNewAndKeepsOldFiles) {
  const std::string dir = test::tempDir("transaction_rollback");
  writeFileAtomically(dir + "/kept.json", std::string("old"));
  writeFileAtomically(dir + "/plain", std::string("a file"));
  try {
    OutputTransaction outputs;
    writeFileAtomically(outputs.stage(dir + "/fresh/object.ply"), std::string("mesh"));
    writeFileAtomically(outputs.stage(dir + "/kept.json"), std::string("new"));
    outputs.stage(dir + "/plain/render.png");  // below a regular file: throws
    outputs.commit();
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), dir + "/plain/render.png");
  }
  EXPECT_FALSE(fs::exists(dir + "/fresh"));
  EXPECT_EQ(slurp(dir + "/plain"), "a file");
  EXPECT_EQ(slurp(dir + "/kept.json"), "old");
  EXPECT_TRUE(temporariesUnder(dir).empty());
}

}  // namespace
}  // namespace skelgrasp
