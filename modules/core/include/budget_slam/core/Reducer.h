#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "budget_slam/core/Backend.h"

namespace budget_slam {

/// What a reducer is asked at one drop: the backend (read-only), every landmark in the map,
/// and which of them may be dropped.
struct DropContext {
  const Backend& backend;
  const std::vector<LandmarkView>& landmarks;  ///< all landmarks in the map
  const std::vector<std::size_t>& candidates;  ///< indices into `landmarks`, never empty
  StepIndex step;                              ///< step after which the drop happens
};

/// The landmark a reducer would drop and the score it gave it (lower = less useful; the unit
/// depends on the reducer: bits for mi, 1/m^2 for info-content, ...).
struct ReducerChoice {
  LandmarkId id = kNoLandmarkId;
  double score = 0;
};

/// A rule that picks the landmark to drop (DESIGN.md "Reducers"). Registered by name in a
/// ReducerRegistry; adding one is one file plus one line in reducers/BuiltinReducers.cpp.
class Reducer {
 public:
  virtual ~Reducer() = default;
  virtual std::string name() const = 0;

  /// Returns one of `ctx.candidates`.
  virtual ReducerChoice choose(const DropContext& ctx) = 0;

  /// Writes the reducer's options, MRPT's dumpToTextStream style.
  virtual void dumpOptions(std::ostream& out) const {}
};

}  // namespace budget_slam
