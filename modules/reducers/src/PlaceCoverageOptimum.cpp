#include "budget_slam/reducers/PlaceCoverageOptimum.h"

#include <glpk.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

namespace budget_slam::reducers {

PlaceCoverageOptimum solvePlaceCoverageOptimum(const std::vector<std::vector<LandmarkId>>& places,
                                               std::size_t k, std::size_t budget,
                                               const PlaceCoverageOptimumLimits& limits) {
  // Distinct landmarks and sightings, in a stable order.
  std::map<LandmarkId, int> column;  // landmark id -> GLPK column of x_L (1-based)
  std::vector<std::vector<LandmarkId>> seen(places.size());
  std::size_t sightings = 0;
  for (std::size_t p = 0; p < places.size(); ++p) {
    seen[p] = places[p];
    std::sort(seen[p].begin(), seen[p].end());
    seen[p].erase(std::unique(seen[p].begin(), seen[p].end()), seen[p].end());
    sightings += seen[p].size();
    if (sightings > limits.max_sightings)
      throw std::length_error("offline optimum: more than " + std::to_string(limits.max_sightings) +
                              " (place, landmark) sightings; the integer program is too large");
    for (const LandmarkId id : seen[p]) column.emplace(id, 0);
  }
  PlaceCoverageOptimum out;
  if (column.empty() || k == 0) return out;
  if (budget >= column.size()) {
    // Everything fits: keep every landmark.
    for (auto& [id, c] : column) out.selection.push_back(id);
    for (const auto& s : seen) out.coverage += static_cast<double>(std::min(s.size(), k));
    out.upper_bound = out.coverage;
    return out;
  }

  std::unique_ptr<glp_prob, void (*)(glp_prob*)> lp(glp_create_prob(), glp_delete_prob);
  glp_term_out(GLP_OFF);
  glp_set_obj_dir(lp.get(), GLP_MAX);
  const int n_x = static_cast<int>(column.size());
  const int n_y = static_cast<int>(seen.size());
  glp_add_cols(lp.get(), n_x + n_y);
  int c = 0;
  for (auto& [id, col] : column) {
    col = ++c;
    glp_set_col_kind(lp.get(), col, GLP_BV);
  }
  for (int p = 0; p < n_y; ++p) {
    glp_set_col_bnds(lp.get(), n_x + 1 + p, GLP_DB, 0.0, static_cast<double>(k));
    glp_set_obj_coef(lp.get(), n_x + 1 + p, 1.0);
  }
  // Rows 1..n_y: y_p - sum x_L <= 0; row n_y + 1: sum x_L <= budget.
  glp_add_rows(lp.get(), n_y + 1);
  std::vector<int> ia(1), ja(1);
  std::vector<double> ar(1);
  for (int p = 0; p < n_y; ++p) {
    glp_set_row_bnds(lp.get(), p + 1, GLP_UP, 0.0, 0.0);
    ia.push_back(p + 1), ja.push_back(n_x + 1 + p), ar.push_back(1.0);
    for (const LandmarkId id : seen[static_cast<std::size_t>(p)])
      ia.push_back(p + 1), ja.push_back(column.at(id)), ar.push_back(-1.0);
  }
  glp_set_row_bnds(lp.get(), n_y + 1, GLP_UP, 0.0, static_cast<double>(budget));
  for (int x = 1; x <= n_x; ++x) ia.push_back(n_y + 1), ja.push_back(x), ar.push_back(1.0);
  glp_load_matrix(lp.get(), static_cast<int>(ia.size()) - 1, ia.data(), ja.data(), ar.data());

  glp_iocp parm;
  glp_init_iocp(&parm);
  parm.presolve = GLP_ON;
  parm.tm_lim = static_cast<int>(std::min(limits.time_limit_s * 1000.0, 2e9));
  const int rc = glp_intopt(lp.get(), &parm);
  const int status = glp_mip_status(lp.get());
  if ((rc != 0 && rc != GLP_ETMLIM) || (status != GLP_OPT && status != GLP_FEAS))
    throw std::runtime_error("offline optimum: GLPK found no solution (glp_intopt code " +
                             std::to_string(rc) + ")");
  out.proven_optimal = status == GLP_OPT;
  for (const auto& [id, col] : column)
    if (glp_mip_col_val(lp.get(), col) > 0.5) out.selection.push_back(id);
  // The value of the selection itself (integer by construction, free of solver round-off).
  for (const auto& s : seen) {
    std::size_t n = 0;
    for (const LandmarkId id : s)
      n += std::binary_search(out.selection.begin(), out.selection.end(), id);
    out.coverage += static_cast<double>(std::min(n, k));
  }
  // Without a proof the LP relaxation bounds the optimum.
  out.upper_bound = out.coverage;
  if (!out.proven_optimal) {
    glp_smcp lp_parm;
    glp_init_smcp(&lp_parm);
    lp_parm.msg_lev = GLP_MSG_OFF;
    if (glp_simplex(lp.get(), &lp_parm) == 0) out.upper_bound = glp_get_obj_val(lp.get());
  }
  return out;
}

}  // namespace budget_slam::reducers
