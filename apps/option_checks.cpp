#include "option_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <thread>

#include "skelgrasp/common/logging.h"

namespace skelgrasp::cli {
namespace {

// Shortest text of a range bound: 1000, 0.5, 1e+06.
std::string bound(double value) {
  return fmt::format("{:g}", value);
}

// True when `text` is, in full, a finite number (then in `value`); else `problem` says why.
bool parseFloating(const std::string& text, double& value, std::string& problem) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  value = std::strtod(begin, &end);
  if (text.empty() || end != begin + text.size() ||
      std::isspace(static_cast<unsigned char>(text[0]))) {
    problem = "'" + text + "' is not a number";
    return false;
  }
  if (!std::isfinite(value)) {
    problem = "'" + text + "' is not a finite number";
    return false;
  }
  return true;
}

// `range` is the interval as shown: "[0, 1000]" or "(0, 1000]".
CLI::Validator floatingRange(double min, bool min_open, double max, std::string range) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0;
        std::string problem;
        if (!parseFloating(text, value, problem)) return problem + ", expected one in " + range;
        const bool low = min_open ? !(value > min) : !(value >= min);
        if (low || value > max) return text + " is outside " + range;
        return {};
      },
      "in " + range);
}

std::string countDescription(std::uint64_t min, std::uint64_t max) {
  if (max == std::numeric_limits<std::uint64_t>::max()) return fmt::format(">= {}", min);
  return fmt::format("in [{}, {}]", min, max);
}

// Checks a whole decimal number in [min, max]; drops its leading zeros. Empty on success.
std::string checkCount(std::string& text, std::uint64_t min, std::uint64_t max) {
  const std::string expected = "a whole number " + countDescription(min, max);
  const bool digits = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c));
  });
  if (!digits) return "'" + text + "' is not " + expected;
  const auto first = text.find_first_not_of('0');
  text = first == std::string::npos ? "0" : text.substr(first);
  errno = 0;
  const std::uint64_t value = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE || value < min || value > max) {
    return fmt::format("{} is outside [{}, {}]", text, min, max);
  }
  return {};
}

}  // namespace

CLI::Validator finiteIn(double min, double max) {
  return floatingRange(min, false, max, "[" + bound(min) + ", " + bound(max) + "]");
}

CLI::Validator positiveFinite(double max) {
  return floatingRange(0, true, max, "(0, " + bound(max) + "]");
}

CLI::Validator lengthOrZero() {
  return finiteIn(0, kMaxOptionLengthM);
}

CLI::Validator positiveLength() {
  return positiveFinite(kMaxOptionLengthM);
}

CLI::Validator countIn(std::uint64_t min, std::uint64_t max) {
  return CLI::Validator([=](std::string& text) { return checkCount(text, min, max); },
                        countDescription(min, max));
}

CLI::Validator vertexCountOrZero() {
  constexpr std::uint64_t kMinClosedMeshVertices = 4;  // a tetrahedron
  return CLI::Validator(
      [](std::string& text) {
        std::string error = checkCount(text, 0, kMaxCount);
        if (error.empty() && text != "0" && std::stoull(text) < kMinClosedMeshVertices)
          error = "a vertex budget must be 0 (never) or at least 4, not " + text;
        return error;
      },
      "0 or [4, " + std::to_string(kMaxCount) + "]");
}

int hardwareThreads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

CLI::Validator threadCount(int min) {
  const int cores = hardwareThreads();
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        std::string problem = checkCount(text, static_cast<std::uint64_t>(min), kMaxCount);
        if (!problem.empty()) return problem;
        if (std::stoull(text) > static_cast<std::uint64_t>(cores)) {
          log().warn("{} threads requested, this machine has {}: using {}", text, cores, cores);
          text = std::to_string(cores);
        }
        return {};
      },
      fmt::format(">= {}, at most the {} cores", min, cores));
}

void checkParsedNumbers(const CLI::App& app) {
  for (const CLI::Option* option : app.get_options()) {
    if (option->count() == 0) continue;
    const std::string type = option->get_type_name();
    const std::string base = type.substr(0, type.find(':'));
    for (const std::string& text : option->results()) {
      if (base == "FLOAT") {
        double value = 0;
        std::string problem;
        if (!parseFloating(text, value, problem))
          throw CLI::ValidationError(option->get_name(), problem);
      } else if (base == "UINT") {
        const auto first = text.find_first_not_of(" \t");
        if (first != std::string::npos && text[first] == '-') {
          throw CLI::ValidationError(option->get_name(),
                                     "'" + text + "' is negative, expected a whole number >= 0");
        }
      }
    }
  }
  for (const CLI::App* sub : app.get_subcommands()) checkParsedNumbers(*sub);
}

void checkDefaults(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    const std::string fallback = option->get_default_str();
    if (fallback.empty()) continue;
    for (int index = 0;; ++index) {
      CLI::Validator* check = nullptr;
      try {
        check = option->get_validator(index);
      } catch (const CLI::OptionNotFound&) {
        break;
      }
      std::string text = fallback;
      const std::string problem = (*check)(text);
      if (!problem.empty()) {
        throw std::logic_error(app.get_name() + " " + option->get_name() + ": default " + fallback +
                               " fails its own check: " + problem);
      }
    }
  }
  for (CLI::App* sub : app.get_subcommands({})) checkDefaults(*sub);
}

std::string oneLine(const std::string& message) {
  std::string line = message;
  std::replace(line.begin(), line.end(), '\n', ' ');
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line;
}

}  // namespace skelgrasp::cli
