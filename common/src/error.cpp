#include "skelgrasp/common/error.h"

namespace skelgrasp {

const char* toString(StatusCode code) {
  switch (code) {
    case StatusCode::kOk:
      return "ok";
    case StatusCode::kInvalidInput:
      return "invalid_input";
    case StatusCode::kNoResult:
      return "no_result";
    case StatusCode::kTimeout:
      return "timeout";
    case StatusCode::kFailed:
      return "failed";
  }
  return "unknown";
}

void throwInternalError(const char* condition, const char* file, int line) {
  throw InternalError(std::string("internal invariant violated: ") + condition + " (" + file + ":" +
                      std::to_string(line) + ")");
}

}  // namespace skelgrasp
