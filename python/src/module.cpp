// The compiled part of the Python package `skelgrasp` (python/skelgrasp/__init__.py re-exports it;
// docs/python.md). Errors become Python exceptions with the message the command line prints
// after "skelgrasp: error: ".
#include <pybind11/pybind11.h>

#include <cstring>

#include "bindings.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/resources.h"

namespace py = pybind11;

PYBIND11_MODULE(_skelgrasp, m) {
  m.doc() = "skelgrasp: skeleton-based grasp planning for multi-fingered hands (docs/python.md).";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const skelgrasp::IoError& e) {
      // A missing file is FileNotFoundError (a subclass of OSError), anything else OSError.
      if (e.problem().rfind("no such file", 0) == 0)  // "no such file" or "... or directory"
        PyErr_SetString(PyExc_FileNotFoundError, e.what());
      else
        PyErr_SetString(PyExc_OSError, e.what());
    } catch (const skelgrasp::ResourceLimitExceeded& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    } catch (const skelgrasp::InvalidArgument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const skelgrasp::InternalError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });

  m.def(
      "set_log_level",
      [](const std::string& level) {
        const auto parsed = spdlog::level::from_str(level);
        if (parsed == spdlog::level::off && level != "off")
          throw skelgrasp::InvalidArgument("log level '" + level +
                                           "' is not trace, debug, info, warn, error or off");
        skelgrasp::setLogLevel(parsed);
      },
      py::arg("level"),
      "Level of the library's log on stderr: 'debug', 'info' (default), 'warn', 'error', 'off'.");

  skelgrasp::python::bindGeometry(m);
  skelgrasp::python::bindOptions(m);
  skelgrasp::python::bindGrasping(m);
  skelgrasp::python::bindScoring(m);
  skelgrasp::python::bindPhysics(m);
  skelgrasp::python::bindPipeline(m);
}
