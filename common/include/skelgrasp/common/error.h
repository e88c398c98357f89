#pragma once
// Error handling conventions (see README, "Conventions"):
//  - caller mistakes (bad parameters, unreadable files) throw an exception derived from Error;
//  - expected data failures (an open mesh, no grasp found) are reported in a stage's Status;
//  - broken internal invariants trip SKELGRASP_DEMAND, which throws InternalError.
#include <stdexcept>
#include <string>

namespace skelgrasp {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A parameter or argument the caller passed is invalid.
class InvalidArgument : public Error {
 public:
  using Error::Error;
};

// A file is missing, unreadable or malformed. The message starts with the path.
class IoError : public Error {
 public:
  IoError(const std::string& path, const std::string& problem)
      : Error(path + ": " + problem), path_(path), problem_(problem) {}
  const std::string& path() const { return path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string path_;
  std::string problem_;
};

// An internal invariant does not hold: a bug in skelgrasp, not in the caller's data.
class InternalError : public Error {
 public:
  using Error::Error;
};

enum class StatusCode {
  kOk,
  kInvalidInput,  // the data cannot be processed by this stage (e.g. mesh not closed)
  kNoResult,      // the stage ran but found nothing (e.g. no grasp)
  kTimeout,       // stopped by a time limit; partial results are kept
  kFailed,        // a library the stage relies on failed
};

const char* toString(StatusCode code);

struct Status {
  StatusCode code = StatusCode::kOk;
  std::string message;

  bool ok() const { return code == StatusCode::kOk; }
  static Status Ok() { return {}; }
  static Status Make(StatusCode c, std::string msg) { return {c, std::move(msg)}; }
};

[[noreturn]] void throwInternalError(const char* condition, const char* file, int line);

}  // namespace skelgrasp

// Always-on invariant check (also in Release builds).
#define SKELGRASP_DEMAND(condition)   \
  ((condition) ? static_cast<void>(0) \
               : ::skelgrasp::throwInternalError(#condition, __FILE__, __LINE__))
