#include "PluginHost.h"

#include <pybind11/embed.h>

#include <filesystem>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace budget_slam::python {
namespace {

/// The budget_slam package of this build: build/python beside build/bin (the executable's
/// folder), when it is there.
std::string packageFolder() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  const fs::path dir = exe.parent_path().parent_path() / "python";
  return fs::exists(dir / "budget_slam" / "__init__.py", ec) ? dir.string() : "";
}

std::string lastLine(const py::error_already_set& e) {
  try {
    const py::list lines =
        py::module_::import("traceback").attr("format_exception_only")(e.type(), e.value());
    std::string last =
        lines.empty() ? std::string() : py::str(lines[lines.size() - 1]).cast<std::string>();
    while (!last.empty() && (last.back() == '\n' || last.back() == '\r' || last.back() == ' '))
      last.pop_back();
    return last.empty() ? std::string("an exception without a message") : printable(last);
  } catch (...) {
    return "an exception that cannot be printed";
  }
}

}  // namespace

std::vector<std::string> takePluginFlags(std::vector<std::string>& args) {
  std::vector<std::string> files, rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (i > 0 && a == "--plugin") {
      if (i + 1 >= args.size())
        throw UsageError("--plugin: give a Python file (--plugin FILE.py); see docs/PYTHON.md");
      files.push_back(args[++i]);
    } else if (i > 0 && a.rfind("--plugin=", 0) == 0) {
      files.push_back(a.substr(9));
    } else {
      rest.push_back(a);
    }
  }
  for (const auto& f : files)
    if (f.empty()) throw UsageError("--plugin: empty value; give a Python file (--plugin FILE.py)");
  args = std::move(rest);
  return files;
}

void loadPlugins(const std::vector<std::string>& files) {
  if (files.empty()) return;
  py::initialize_interpreter(false);  // no signal handlers: SIGINT stays the stop request's
  {
    const std::string folder = packageFolder();
    py::module_ sys = py::module_::import("sys");
    if (!folder.empty()) sys.attr("path").attr("insert")(0, folder);
    // budget_slam/__init__.py imports its C++ half as budget_slam._core: the one built into this
    // executable (its registry is the one the runs read), never a separate _core.so.
    sys.attr("modules")["budget_slam._core"] = py::module_::import("_core");
    py::module_ package;
    try {
      package = py::module_::import("budget_slam");
    } catch (const py::error_already_set& e) {
      throw UsageError("--plugin: cannot import the budget_slam package (" + lastLine(e) +
                       "): build it (python/) or set PYTHONPATH");
    }
    for (const auto& f : files) {
      std::error_code ec;
      if (!fs::is_regular_file(f, ec))
        throw UsageError("--plugin " + printable(f) + ": no such file");
      try {
        package.attr("load_plugin")(f);
      } catch (const py::error_already_set& e) {
        throw UsageError("--plugin " + printable(f) + ": " + lastLine(e));
      }
    }
  }
  // The runs take the GIL back at each call into a plugin (PythonReducer.cpp); it is never taken
  // back here: Python stays up, unfinalized, until the process ends.
  PyEval_SaveThread();
}

}  // namespace budget_slam::python
