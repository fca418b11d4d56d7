#pragma once
// Helpers the reducers share to write their memory into a session state section and read it
// back (docs/OUTPUTS.md "Session state").
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/PlaceGrid.h"
#include "budget_slam/session/SessionSection.h"

namespace budget_slam::reducers {

/// The section name of reducer `name` in a session state: "reducer.<name>".
inline std::string reducerSection(const std::string& name) { return "reducer." + name; }

/// A list of lists as two fields: `<name>_sizes` (one a list) and `<name>` (all values in turn).
template <class T>
void putNested(session::SessionSection& s, const std::string& name,
               const std::vector<std::vector<T>>& lists) {
  std::vector<std::int64_t> sizes, values;
  for (const auto& l : lists) {
    sizes.push_back(static_cast<std::int64_t>(l.size()));
    for (const auto v : l) values.push_back(static_cast<std::int64_t>(v));
  }
  s.putIntegers(name + "_sizes", std::move(sizes));
  s.putIntegers(name, std::move(values));
}

/// The inverse of putNested: `n` lists, values in [lo, hi].
inline std::vector<std::vector<std::int64_t>> nested(const session::SessionSection& s,
                                                     const std::string& name, std::size_t n,
                                                     std::int64_t lo, std::int64_t hi) {
  const auto& sizes = s.integers(name + "_sizes", n, 0, std::int64_t{1} << 40);
  std::size_t total = 0;
  for (const auto k : sizes) total += static_cast<std::size_t>(k);
  const auto& values = s.integers(name, total, lo, hi);
  std::vector<std::vector<std::int64_t>> out(n);
  std::size_t at = 0;
  for (std::size_t i = 0; i < n; ++i) {
    out[i].assign(values.begin() + static_cast<std::ptrdiff_t>(at),
                  values.begin() + static_cast<std::ptrdiff_t>(at + sizes[i]));
    at += static_cast<std::size_t>(sizes[i]);
  }
  return out;
}

/// The place grid as `grid` = {size [m], sectors}, or no values before it is fixed.
inline void putGrid(session::SessionSection& s, const std::optional<PlaceGrid>& grid) {
  s.putReals("grid", grid ? std::vector<double>{grid->size(), double(grid->sectors())}
                          : std::vector<double>{});
}

inline std::optional<PlaceGrid> readGrid(const session::SessionSection& s) {
  const auto& g = s.reals("grid");
  if (g.empty()) return std::nullopt;
  if (g.size() != 2 || !(g[0] > 0) || !(g[1] >= 1 && g[1] <= 360) || g[1] != double(long(g[1])))
    s.fail("grid", "expected a place size > 0 and 1 to 360 heading sectors");
  return PlaceGrid(g[0], static_cast<std::size_t>(g[1]));
}

}  // namespace budget_slam::reducers
