#pragma once
// The parts of budget_slam._core (CoreModule.h), one file each: defineCoreModule (module.cpp)
// calls each define* on the module, after registering the exceptions.
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <vector>

#include "budget_slam/report/ComparisonTable.h"

namespace budget_slam::python {

/// A JSON document as Python objects (through Python's json module: numbers, null, nesting as
/// json.load gives them).
pybind11::object toPython(const nlohmann::json& j);

/// comparison.csv's table from the typed rows compare handed back, column by column in
/// report::comparisonColumns()'s order: a list of (name, kind, values), kind "text" (str values),
/// "integer" (int values) or "number" (float values, NaN where the CSV has an empty field). An
/// integer column holding a missing value is a number column.
pybind11::list comparisonTable(const std::vector<report::ComparisonRow>& rows);

/// run_request, CommandOutcome and localize: the run layer's commands in this process
/// (RunBindings.cpp).
void defineRunBindings(pybind11::module_& m);

/// read_summary, summary_keys and exit_code: the typed outcome's words (OutcomeBindings.cpp).
void defineOutcomeBindings(pybind11::module_& m);

/// reducer_names and registry: the registries' listing (RegistryBindings.cpp).
void defineRegistryBindings(pybind11::module_& m);

/// reducer_scores: a registered reducer's scores on a Gaussian state (ReducerScores.cpp).
void defineReducerScores(pybind11::module_& m);

}  // namespace budget_slam::python
