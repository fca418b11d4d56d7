// Python's progress= callback for the run layer's commands (RunGuard.h).
#include "RunGuard.h"

#include <pybind11/stl.h>

#include <csignal>

namespace py = pybind11;

namespace budget_slam::python {

py::dict progressDict(const ProgressSnapshot& s) {
  py::dict d;
  d["task"] = s.task;
  d["fraction"] = s.fraction;
  d["steps_done"] = s.steps_done;
  d["steps_total"] = s.steps_total ? py::object(py::int_(s.steps_total)) : py::object(py::none());
  d["elapsed_s"] = s.elapsed_s;
  d["steps_per_s"] = s.steps_per_s;
  d["eta_s"] = s.eta_s;
  d["detail"] = s.detail;
  d["finished"] = s.finished;
  return d;
}

ProgressCallback progressCallback(const std::optional<py::function>& progress,
                                  std::optional<py::error_already_set>& error) {
  if (!progress) return {};
  return [progress, &error](const ProgressSnapshot& s) {
    if (error) return;
    py::gil_scoped_acquire gil;
    try {
      (*progress)(progressDict(s));
    } catch (py::error_already_set& e) {
      error.emplace(std::move(e));
      Cancellation::request(SIGINT);
    }
  };
}

}  // namespace budget_slam::python
