#pragma once
// The checked, atomic file writes live in core (budget_slam/core/FileWrite.h) so that every
// module that writes a file (report's outputs, session's state file) shares them; the report
// names stay for its writers.
#include "budget_slam/core/FileWrite.h"

namespace budget_slam::report {

using budget_slam::cannotWrite;
using budget_slam::LineFile;
using budget_slam::reserveFileSpace;
using budget_slam::writeFileAtomically;

}  // namespace budget_slam::report
