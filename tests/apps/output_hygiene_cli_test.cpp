// Output hygiene of `run` and `plan` (issue 77): a signal removes the command's hidden temporaries
// and the output directories it made and left empty; a later run removes the temporaries killed
// commands left; two runs never write one --out at once nor leave a mixed directory; a write
// error names the final file, not its hidden temporary.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.h"
#include "hostile_files.h"
#include "perception/synthetic_scenes.h"
#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/directory_lock.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/signal_cleanup.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/perception/cloud_io.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::countLines;
using test::lastLine;
using test::runCli;

// Hidden temporaries (.NAME.tmp.PID.N.EXT) in `dir`.
int temporariesIn(const std::string& dir) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir))
    count += entry.path().filename().string().find(".tmp.") != std::string::npos;
  return count;
}

// A process id no process has: above the kernel's largest.
long deadProcessId() {
  long pid_max = 4194304;
  std::ifstream("/proc/sys/kernel/pid_max") >> pid_max;
  return pid_max + 1;
}

TEST(SignalCleanup, RemovesRegisteredFilesThenEmptyDirectoriesInnermostFirst) {
  const std::string dir = test::tempDir("signal_cleanup");
  fs::create_directories(dir + "/made/inner");
  fs::create_directories(dir + "/kept");
  test::writeText(dir + "/made/inner/.object_0.tmp.1.2.ply", "partial");
  test::writeText(dir + "/kept/user.txt", "the user's");
  {
    // Registered outermost first, as the atomic writer creates them.
    const SignalCleanupEntry made(dir + "/made", SignalCleanupEntry::Kind::kEmptyDirectory);
    const SignalCleanupEntry inner(dir + "/made/inner", SignalCleanupEntry::Kind::kEmptyDirectory);
    const SignalCleanupEntry kept(dir + "/kept", SignalCleanupEntry::Kind::kEmptyDirectory);
    const SignalCleanupEntry file(dir + "/made/inner/.object_0.tmp.1.2.ply",
                                  SignalCleanupEntry::Kind::kFile);
    runSignalCleanup();
  }
  EXPECT_FALSE(fs::exists(dir + "/made"));
  EXPECT_TRUE(fs::exists(dir + "/kept/user.txt"));  // not empty: stays
  // Unregistered entries are left alone.
  fs::create_directories(dir + "/later");
  runSignalCleanup();
  EXPECT_TRUE(fs::exists(dir + "/later"));
}

// A staged output of a transaction and the directory made for it, as SIGTERM finds them in the
// middle of a command: the child process dies by the signal and leaves neither.
TEST(SignalCleanup, ASignalDuringATransactionLeavesNothing) {
  const std::string dir = test::tempDir("signal_cleanup_transaction");
  const std::string out = dir + "/out";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    installSignalCleanup();
    OutputTransaction outputs;
    writeFileAtomically(outputs.stage(out + "/object_0.ply"), std::string(1000, 'x'));
    outputs.stage(out + "/grasps.json");  // staged, not written yet
    ::raise(SIGTERM);
    ::_exit(0);  // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << status;
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_FALSE(fs::exists(out)) << "the output directory the child made is left";
  EXPECT_EQ(temporariesIn(dir), 0);
}

// A write error inside a transaction names the final file.
TEST(AtomicFile, ErrorsOfAStagedFileNameTheFinalFile) {
  const std::string dir = test::tempDir("atomic_file_final_name");
  OutputTransaction outputs;
  const std::string staged = outputs.stage(dir + "/object_0.ply");
  EXPECT_EQ(finalPathOfTemporary(staged), dir + "/object_0.ply");
  EXPECT_EQ(finalPathOfTemporary(temporarySiblingPath(staged)), dir + "/object_0.ply");
  EXPECT_EQ(finalPathOfTemporary(dir + "/.x.tmp.1.2.ply"), dir + "/.x.tmp.1.2.ply");  // not ours
  try {
    writeFileAtomically(staged, [&](std::ostream&) { throw IoError(staged, "No space left"); });
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), dir + "/object_0.ply");
  }
}

// A full disk, made by a file size limit of 1 KiB (SIGXFSZ ignored: writes fail with EFBIG): the
// error line names the PNG, not the hidden temporary it was staged as.
TEST(OutputHygieneCli, AWriteErrorNamesTheFinalFile) {
  const std::string dir = test::tempDir("cli_hygiene_full_disk");
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  const std::string command =
      "sh -c 'trap \"\" XFSZ; ulimit -f 2; exec " + std::string(SKELGRASP_CLI_PATH) + " -q plan " +
      dir + "/capsule.ply --hand sdh --render " + dir + "/out/grasps.png --out " + dir +
      "/out/grasps.json' > " + dir + "/stdout.txt 2> " + dir + "/stderr.txt";
  const int status = std::system(command.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::ifstream err_file(dir + "/stderr.txt");
  const std::string err((std::istreambuf_iterator<char>(err_file)), {});
  EXPECT_EQ(countLines(err), 1) << err;
  EXPECT_EQ(err.rfind("skelgrasp: error: " + dir + "/out/grasps.png: cannot write", 0), 0u) << err;
  EXPECT_EQ(err.find(".tmp."), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir + "/out")) << "a directory made for the outputs is left";
}

// run --out: temporaries of dead processes are removed, those of live ones stay; an --out made
// by a failed run is removed again.
TEST(OutputHygieneCli, RunRemovesStaleTemporariesAndItsEmptyOutput) {
  const std::string dir = test::tempDir("cli_hygiene_stale");
  const std::string out = dir + "/out";
  fs::create_directories(out);
  const std::string stale = out + "/.object_0.tmp." + std::to_string(deadProcessId()) + ".3.ply";
  const std::string live = out + "/.object_1.tmp." + std::to_string(::getpid()) + ".4.ply";
  test::writeText(stale, "half an object");
  test::writeText(live, "being written");
  // The input is missing: the run fails after taking --out, which is enough.
  const CliRun r = runCli("-q run " + dir + "/none.pcd --out " + out, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  const CliRun made = runCli("-q run " + dir + "/none.pcd --out " + dir + "/new/out", dir);
  EXPECT_EQ(made.exit_code, 2) << made.err;
  EXPECT_NE(lastLine(made.err).find("none.pcd"), std::string::npos) << made.err;
  EXPECT_FALSE(fs::exists(dir + "/new")) << "the failed run left the directories it made";
}

// A second run into an --out a run is writing stops at once, naming the directory and the process.
TEST(OutputHygieneCli, ASecondRunIntoTheSameOutIsRefused) {
  const std::string dir = test::tempDir("cli_hygiene_lock");
  const std::string out = dir + "/out";
  fs::create_directories(out);
  const DirectoryLock held(out);  // this test process plays the first run
  const CliRun r = runCli("-q run " + dir + "/none.pcd --out " + out, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(countLines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(out + ": is in use by process " + std::to_string(::getpid())),
            std::string::npos)
      << r.err;
}

// A run into the --out of an earlier run replaces that run's files: after `--object all` (object_0,
// object_1) a one-object run leaves no object_<k>.ply beside its grasps.json; the user's own file
// stays.
TEST(OutputHygieneCli, ALaterRunReplacesTheEarlierRunsFiles) {
  const std::string dir = test::tempDir("cli_hygiene_replace");
  const std::string out = dir + "/out";
  perception::savePointCloud(dir + "/scene.pcd", test::renderTableScene(41).cloud);
  const CliRun all =
      runCli("-q run " + dir + "/scene.pcd --hand sdh --object all --out " + out, dir);
  ASSERT_EQ(all.exit_code, 0) << all.err;
  ASSERT_TRUE(fs::exists(out + "/object_1.ply"));
  ASSERT_TRUE(fs::exists(out + "/skeleton_1.json"));
  test::writeText(out + "/notes.txt", "the user's notes");
  const CliRun one = runCli("-q run " + dir +
                                "/scene.pcd --hand sdh --object "
                                "nearest:0.05,-0.09,0.05 --export moveit --out " +
                                out,
                            dir);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(name.rfind("object_", 0), std::string::npos) << "left from the first run: " << name;
    EXPECT_EQ(name.rfind("skeleton_", 0), std::string::npos) << "left from the first run: " << name;
    EXPECT_EQ(name.find(".tmp."), std::string::npos) << "temporary left: " << name;
  }
  EXPECT_TRUE(fs::exists(out + "/object.ply"));
  EXPECT_TRUE(fs::exists(out + "/grasps.moveit.yaml"));
  EXPECT_TRUE(fs::exists(out + "/notes.txt"));
  EXPECT_EQ(readJsonFile(out + "/grasps.json")["objects"].size(), 1u);
  // The export belongs to the run that asked for it: a run without --export removes it.
  const CliRun again = runCli("-q run " + dir +
                                  "/scene.pcd --hand sdh --object "
                                  "nearest:0.05,-0.09,0.05 --out " +
                                  out,
                              dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_FALSE(fs::exists(out + "/grasps.moveit.yaml"));
  EXPECT_TRUE(fs::exists(out + "/notes.txt"));
}

}  // namespace
}  // namespace skelgrasp
