#pragma once
// Runs the skelgrasp executable (SKELGRASP_CLI_PATH) in a shell and captures what it printed.
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

namespace skelgrasp::test {

struct CliRun {
  int exit_code;
  std::string out;
  std::string err;
};

// `args` go on the command line as they are; stdout and stderr are kept in `dir`.
inline CliRun runCli(const std::string& args, const std::string& dir) {
  const std::string out = dir + "/stdout.txt", err = dir + "/stderr.txt";
  const std::string cmd = std::string(SKELGRASP_CLI_PATH) + " " + args + " > " + out + " 2> " + err;
  const int status = std::system(cmd.c_str());
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  return {WEXITSTATUS(status), slurp(out), slurp(err)};
}

inline int countLines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace skelgrasp::test
