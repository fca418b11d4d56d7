#pragma once
#include <cstdint>

#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/session/SessionSection.h"

namespace budget_slam::graph {

/// The whole factor graph in a session state's `[backend.graph]` section (docs/OUTPUTS.md "Session
/// state", docs/GRAPH.md "Resuming a session"): every pose with its timestamp and estimate, the
/// first pose's prior, each later pose's odometry factor from the pose before it (a composed one
/// where poses were marginalized), every landmark's estimate and prior, and every range-bearing
/// factor, each double exact. A graph read back is the saved one factor for factor, so the
/// next session's solves are the one-shot run's: carrying the joint information of the past as the
/// factors it came from is what keeps it exact when the past is relinearized or a landmark's
/// sightings are deleted after the split (a dense prior at one linearization point would be
/// neither).
void writeGraph(const FactorGraph& graph, session::SessionSection& section);

/// True when `section` holds a graph written by writeGraph (a state written before the graph was
/// saved whole holds only the map's marginals).
bool hasGraph(const session::SessionSection& section);

/// The graph of `section`, every value checked: sizes that agree (at most `max_poses` poses),
/// pose steps increasing and below `next_step`, landmark ids increasing and non-negative,
/// coordinates within +-1e9 m, ranges above 0, covariances symmetric and positive definite,
/// landmark prior square roots invertible, every sighting on a saved pose and landmark, every
/// landmark constrained (a sighting or a prior). A bad value is an InputError naming the file,
/// the section and the field.
FactorGraph readGraph(const session::SessionSection& section, std::int64_t next_step,
                      std::size_t max_poses);

}  // namespace budget_slam::graph
