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

// The last non-empty line of `text`, without its newline.
inline std::string lastLine(const std::string& text) {
  const auto end = text.find_last_not_of('\n');
  if (end == std::string::npos) return {};
  const auto start = text.rfind('\n', end);
  const auto from = start == std::string::npos ? 0 : start + 1;
  return text.substr(from, end - from + 1);
}

// A command line that must fail: exit 2 and one error line containing `expected`.
struct BadCliInput {
  std::string name;
  std::string args;  // {dir} stands for the test's folder
  std::string expected;
};

// `args` with every {dir} replaced by `dir`.
inline std::string withDir(std::string args, const std::string& dir) {
  for (std::size_t at; (at = args.find("{dir}")) != std::string::npos;) args.replace(at, 5, dir);
  return args;
}

inline int countLines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace skelgrasp::test
