// evaluate --shard + merge driven by the schedulers users run: GNU parallel on one machine and
// Slurm job arrays (scripts/slurm/evaluate-array.sh) on a cluster, with a stand-in sbatch and
// with real Slurm daemons on this machine. The merged directory must
// hold exactly the results of one unsharded evaluate.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "cli_support.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

using test::runCli;

// Few samples, one planner and a fixed hypothesis budget keep each shard short and independent
// of machine speed.
const char* const kFastOptions =
    " --hands sdh --planners skeleton --robustness-samples 4 --robustness-grasps 2 --timeout 0"
    " --vertex-distance 0.01";
constexpr int kShards = 3;

std::vector<nlohmann::json> jsonLines(const std::string& path) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  }
  return out;
}

// Everything except wall-clock times, which differ between runs by nature.
nlohmann::json withoutTimes(nlohmann::json j) {
  for (const char* key : {"planning_s", "regularise_s", "skeleton_s", "robustness_s",
                          "ms_per_valid_grasp", "time_ms", "timed_out"}) {
    j.erase(key);
  }
  return j;
}

bool haveCommand(const std::string& name) {
  return std::system(("command -v " + name + " > /dev/null 2>&1").c_str()) == 0;
}

class SchedulerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::tempDir(std::string("cli_scheduler_") +
                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    objects_ = dir_ + "/objects";
    std::filesystem::create_directories(objects_);
    for (const char* shape : {"capsule", "bottle", "hammer", "mug"}) {
      saveMesh(objects_ + "/" + shape + ".ply", geometry::shapes::makeNamedShape(shape));
    }
    const auto run = runCli(
        "evaluate --objects " + objects_ + " --out " + dir_ + "/single" + kFastOptions, dir_);
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }
  // The merged results equal the single run's, line by line.
  void expectMergedEqualsSingle(const std::string& merged) const {
    for (const char* file : {"/runs.jsonl", "/results.jsonl"}) {
      const auto a = jsonLines(dir_ + "/single" + file), b = jsonLines(merged + file);
      ASSERT_FALSE(a.empty()) << file;
      ASSERT_EQ(a.size(), b.size()) << file;
      for (std::size_t i = 0; i < a.size(); ++i)
        EXPECT_EQ(withoutTimes(a[i]), withoutTimes(b[i])) << file << " line " << i;
    }
    EXPECT_TRUE(std::filesystem::exists(merged + "/summary.md"));
  }
  std::string dir_, objects_;
};

TEST_F(SchedulerTest, ShardsRunThroughGnuParallelMergeToTheSingleRun) {
  if (!haveCommand("parallel")) {
    GTEST_SKIP() << "GNU parallel not installed (Debian package `parallel`; "
                    "scripts/install-deps.sh installs it)";
  }
  const std::string cli = SKELGRASP_CLI_PATH;
  const std::string command = "parallel --will-cite --halt now,fail=1 -j 2 " + cli +
                              " evaluate --objects " + objects_ + " --out " + dir_ +
                              "/shard-{} --shard {}/" + std::to_string(kShards) + kFastOptions +
                              " ::: 0 1 2 > " + dir_ + "/parallel.log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const auto run = runCli("merge " + dir_ + "/shard-0 " + dir_ + "/shard-1 " + dir_ +
                              "/shard-2 --out " + dir_ + "/merged",
                          dir_);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  expectMergedEqualsSingle(dir_ + "/merged");
}

// The Slurm script against a stand-in sbatch that runs each array task and the dependent merge
// right away, in order, with the environment Slurm gives them.
TEST_F(SchedulerTest, TheSlurmArrayScriptShardsAndMergesToTheSingleRun) {
  const std::string script = std::string(SKELGRASP_SOURCE_DIR) + "/scripts/slurm/evaluate-array.sh";
  const std::string bin = dir_ + "/bin";
  std::filesystem::create_directories(bin);
  {
    std::ofstream sbatch(bin + "/sbatch");
    sbatch << "#!/usr/bin/env bash\n"
              "set -e\n"
              "array='' wrap=''\n"
              "for a in \"$@\"; do case \"$a\" in --array=*) array=${a#--array=};;"
              " --wrap=*) wrap=${a#--wrap=};; esac; done\n"
              "echo \"$*\" >> \"$(dirname \"$0\")/calls.log\"\n"
              "if [[ -n $array ]]; then\n"
              "  for i in $(seq 0 ${array#0-}); do SLURM_ARRAY_TASK_ID=$i bash -c \"$wrap\"; done\n"
              "  echo 4242\n"
              "else\n"
              "  bash -c \"$wrap\"; echo 4243\n"
              "fi\n";
  }
  std::filesystem::permissions(bin + "/sbatch", std::filesystem::perms::owner_all);
  const std::string out = dir_ + "/cluster";
  const std::string args = " --shards " + std::to_string(kShards) + " --out " + out +
                           " --skelgrasp " + SKELGRASP_CLI_PATH + " -- --objects " + objects_ +
                           kFastOptions;
  // The dry run prints the two sbatch calls and submits nothing.
  const std::string dry = "bash " + script + " --dry-run" + args + " > " + dir_ + "/dry.txt";
  ASSERT_EQ(std::system(dry.c_str()), 0);
  std::ifstream dry_in(dir_ + "/dry.txt");
  std::string first, second;
  std::getline(dry_in, first);
  std::getline(dry_in, second);
  EXPECT_NE(first.find("--array=0-2"), std::string::npos) << first;
  EXPECT_NE(second.find("--dependency=afterok:"), std::string::npos) << second;
  EXPECT_FALSE(std::filesystem::exists(out));
  const std::string submit =
      "PATH=" + bin + ":$PATH bash " + script + args + " > " + dir_ + "/submit.log 2>&1";
  ASSERT_EQ(std::system(submit.c_str()), 0) << submit;
  std::ifstream calls(bin + "/calls.log");
  std::string call;
  int submitted = 0;
  while (std::getline(calls, call)) ++submitted;
  EXPECT_EQ(submitted, 2);  // one array job, one merge job
  expectMergedEqualsSingle(out + "/merged");
}

std::string firstLineOf(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

// The Slurm script against real slurmctld and slurmd on this machine
// (scripts/slurm/local-cluster.sh: munge, one node, ports on 127.0.0.1): the array job's shards and
// the dependent merge run as a cluster runs them.
TEST_F(SchedulerTest, TheSlurmArrayJobOnALocalClusterMergesToTheSingleRun) {
  constexpr int kJobTimeoutS = 600;
  const std::string scripts = std::string(SKELGRASP_SOURCE_DIR) + "/scripts/slurm";
  const std::string cluster = dir_ + "/slurm";
  // Stops whatever start started, also after a failed start or a failed assertion.
  struct StopCluster {
    std::string command;
    ~StopCluster() { [[maybe_unused]] const int ignored = std::system(command.c_str()); }
  } stop{"bash " + scripts + "/local-cluster.sh stop " + cluster};
  const int started = std::system(("bash " + scripts + "/local-cluster.sh start " + cluster +
                                   " > /dev/null 2> " + dir_ + "/cluster.log")
                                      .c_str());
  if (WEXITSTATUS(started) == 3) {
    GTEST_SKIP() << "Slurm cannot start here: " << firstLineOf(dir_ + "/cluster.log")
                 << " (scripts/install-deps.sh --test installs slurm-wlm and munge)";
  }
  ASSERT_EQ(WEXITSTATUS(started), 0) << firstLineOf(dir_ + "/cluster.log");
  const std::string slurm = "SLURM_CONF=" + cluster + "/slurm.conf ";
  const std::string out = dir_ + "/cluster";
  const std::string submit = slurm + "bash " + scripts + "/evaluate-array.sh --shards " +
                             std::to_string(kShards) + " --time 00:30:00 --out " + out +
                             " --skelgrasp " + SKELGRASP_CLI_PATH + " -- --objects " + objects_ +
                             kFastOptions + " > " + dir_ + "/submit.log 2>&1";
  ASSERT_EQ(std::system(submit.c_str()), 0) << submit;
  // "evaluate-array: submitted 3 shard(s) as job 1, merge as job 2"
  const std::string submitted = firstLineOf(dir_ + "/submit.log");
  const auto at = submitted.find("merge as job ");
  ASSERT_NE(at, std::string::npos) << submitted;
  const std::string merge_job = submitted.substr(at + std::string("merge as job ").size());
  std::string state;
  for (int waited = 0; waited < kJobTimeoutS; ++waited) {
    const std::string show = slurm + "scontrol show job " + merge_job + " > " + dir_ + "/job.txt";
    ASSERT_EQ(std::system(show.c_str()), 0);
    std::ifstream job(dir_ + "/job.txt");
    const std::string text((std::istreambuf_iterator<char>(job)), {});
    const auto from = text.find("JobState=");
    ASSERT_NE(from, std::string::npos) << text;
    state = text.substr(from + 9, text.find(' ', from) - from - 9);
    if (state != "PENDING" && state != "RUNNING" && state != "CONFIGURING" && state != "COMPLETING")
      break;
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
  ASSERT_EQ(state, "COMPLETED") << "merge job " << merge_job << "; logs in " << out << "/logs";
  expectMergedEqualsSingle(out + "/merged");
}

TEST(SlurmScript, RefusesBadArgumentsInOneLineWithExitTwo) {
  const std::string dir = test::tempDir("cli_slurm_bad");
  const std::string script = std::string(SKELGRASP_SOURCE_DIR) + "/scripts/slurm/evaluate-array.sh";
  for (const std::string args : {"--shards 0 --out x -- --objects y", "--shards 2 -- --objects y",
                                 "--shards 2 --out x -- --objects y --shard 1/2",
                                 "--shards 2 --out x", "--shards 2 --out x --bogus"}) {
    const std::string command =
        "bash " + script + " --dry-run " + args + " > " + dir + "/out.txt 2> " + dir + "/err.txt";
    const int status = std::system(command.c_str());
    EXPECT_EQ(WEXITSTATUS(status), 2) << args;
    std::ifstream err(dir + "/err.txt");
    std::string line;
    std::getline(err, line);
    EXPECT_EQ(line.rfind("evaluate-array: error: ", 0), 0u) << args << ": " << line;
  }
}

}  // namespace
}  // namespace skelgrasp
