#include "budget_slam/graph/FactorGraph.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <atomic>
#include <iterator>
#include <stdexcept>
#include <string>

namespace budget_slam::graph {

namespace {
using Triplets = std::vector<Eigen::Triplet<double>>;

/// Adds A_a^T A_b at (ca, cb) into the lower triangle of H. For a == b (ca == cb) only the lower
/// half of the block goes in; for ca > cb the whole block; ca < cb is sent transposed.
template <typename MA, typename MB>
void addBlock(Triplets* t, int ca, const MA& Aa, int cb, const MB& Ab) {
  if (ca < cb) {
    addBlock(t, cb, Ab, ca, Aa);
    return;
  }
  const Eigen::Matrix<double, MA::ColsAtCompileTime, MB::ColsAtCompileTime> blk =
      Aa.transpose() * Ab;
  for (int r = 0; r < blk.rows(); ++r)
    for (int c = 0; c < blk.cols(); ++c)
      if (ca != cb || r >= c) t->emplace_back(ca + r, cb + c, blk(r, c));
}
}  // namespace

void FactorGraph::changed() {
  ++structure_version_;
  ++revision_;
}

std::uint64_t FactorGraph::Lineage::next() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

void FactorGraph::record(GraphChange c) {
  // Bounded: once twice the capacity is reached the older half goes (a reader that far behind
  // starts afresh, changesSince).
  if (journal_.size() >= 2 * kJournalCapacity) {
    journal_.erase(journal_.begin(), journal_.begin() + kJournalCapacity);
    journal_start_ += kJournalCapacity;
  }
  journal_.push_back(std::move(c));
}

void FactorGraph::recordVariable(GraphChange::Kind kind, const VariableKey& v,
                                 VariableIndex index) {
  GraphChange c;
  c.kind = kind;
  c.variable = v;
  c.index = index;
  record(std::move(c));
}

void FactorGraph::recordRemoval(FactorId id) {
  GraphChange c;
  c.kind = GraphChange::Kind::RemoveFactor;
  c.factor.id = id;
  record(std::move(c));
}

GraphFactor FactorGraph::posePriorFactor() const {
  GraphFactor f = GraphFactor::posePrior(prior_id_, poses_.begin()->first, prior_);
  f.vars[0] = poses_.begin()->second.index;
  return f;
}

GraphFactor FactorGraph::odometryFactor(PoseIt from, PoseIt to) const {
  GraphFactor f = GraphFactor::odometry(to->second.odo_id, from->first, to->first, *to->second.odo);
  f.vars = {{from->second.index, to->second.index}};
  return f;
}

GraphFactor FactorGraph::sightingFactor(LandmarkIt l, const Observation& o) const {
  GraphFactor f = GraphFactor::rangeBearing(o.id, o.pose, l->first, o.f);
  f.vars = {{poses_.at(o.pose).index, l->second.index}};
  return f;
}

GraphFactor FactorGraph::landmarkPriorFactor(LandmarkIt l) const {
  GraphFactor f = GraphFactor::landmarkPrior(l->second.prior_id, l->first, *l->second.prior);
  f.vars[0] = l->second.index;
  return f;
}

void FactorGraph::recordAddition(GraphFactor f) {
  GraphChange c;
  c.kind = GraphChange::Kind::AddFactor;
  c.factor = std::move(f);
  record(std::move(c));
}

bool FactorGraph::changesSince(std::uint64_t seq, const GraphChange** first,
                               const GraphChange** last) const {
  if (seq < journal_start_ || seq > changeCount()) return false;
  *first = journal_.data() + (seq - journal_start_);
  *last = journal_.data() + journal_.size();
  return true;
}

std::vector<GraphFactor> FactorGraph::factors() const {
  std::vector<GraphFactor> out;
  // A graph may hold landmarks before its first pose (a session resumed on a saved map: each
  // landmark under its prior); their priors are factors all the same.
  if (!poses_.empty()) {
    out.push_back(posePriorFactor());
    for (auto it = std::next(poses_.begin()); it != poses_.end(); ++it)
      out.push_back(odometryFactor(std::prev(it), it));
  }
  for (auto it = landmarks_.begin(); it != landmarks_.end(); ++it) {
    for (const Observation& o : it->second.obs) out.push_back(sightingFactor(it, o));
    if (it->second.prior) out.push_back(landmarkPriorFactor(it));
  }
  return out;
}

void FactorGraph::addFirstPose(StepIndex step, double t, const Pose2& x, const PriorFactor& prior) {
  if (!poses_.empty()) throw std::logic_error("graph: first pose added twice");
  PoseNode n;
  n.x = x.vector();
  n.t = t;
  n.index = newVariableIndex();
  poses_.emplace(step, n);
  variablesChanged();
  prior_ = prior;
  prior_id_ = next_factor_id_++;
  changed();
  recordVariable(GraphChange::Kind::AddVariable, VariableKey::pose(step), n.index);
  recordAddition(posePriorFactor());
}

void FactorGraph::addPose(StepIndex step, double t, const Pose2& x, const BetweenFactor& odo) {
  if (poses_.empty() || poses_.rbegin()->first >= step)
    throw std::logic_error("graph: pose " + std::to_string(step) + " is not after the last pose");
  PoseNode n;
  n.x = x.vector();
  n.t = t;
  n.odo = odo;
  n.odo_id = next_factor_id_++;
  n.index = newVariableIndex();
  auto it = poses_.emplace_hint(poses_.end(), step, n);
  appendToLayout(&it->second);
  changed();
  recordVariable(GraphChange::Kind::AddVariable, VariableKey::pose(step), n.index);
  recordAddition(odometryFactor(std::prev(it), it));
}

void FactorGraph::addLandmark(LandmarkId id, const Eigen::Vector2d& x) {
  if (landmarks_.count(id))
    throw std::logic_error("graph: landmark " + std::to_string(id) + " exists");
  LandmarkNode n;
  n.x = x;
  n.index = newVariableIndex();
  auto it = landmarks_.emplace(id, n).first;
  insertIntoLayout(&it->second, static_cast<std::size_t>(std::distance(landmarks_.begin(), it)));
  changed();
  recordVariable(GraphChange::Kind::AddVariable, VariableKey::landmark(id), n.index);
}

void FactorGraph::addObservation(StepIndex pose, LandmarkId id, const RangeBearingFactor& f) {
  auto p = poses_.find(pose);
  if (p == poses_.end()) throw std::out_of_range("graph: no pose " + std::to_string(pose));
  auto l = landmarks_.find(id);
  if (l == landmarks_.end()) throw std::out_of_range("graph: no landmark " + std::to_string(id));
  const FactorId fid = next_factor_id_++;
  l->second.obs.push_back({pose, f, fid});
  ++p->second.n_obs;
  changed();
  recordAddition(sightingFactor(l, l->second.obs.back()));
}

void FactorGraph::removeLandmark(LandmarkId id) {
  auto l = landmarks_.find(id);
  if (l == landmarks_.end()) throw std::out_of_range("graph: no landmark " + std::to_string(id));
  for (const Observation& o : l->second.obs) {
    --poses_.at(o.pose).n_obs;
    recordRemoval(o.id);
  }
  if (l->second.prior) recordRemoval(l->second.prior_id);
  const VariableIndex index = l->second.index;
  removeFromLayout(&l->second);
  landmarks_.erase(l);
  freeVariableIndex(index);
  changed();
  recordVariable(GraphChange::Kind::RemoveVariable, VariableKey::landmark(id), index);
}

bool FactorGraph::canMarginalizePose(StepIndex step) const {
  auto p = poses_.find(step);
  if (p == poses_.end() || p == poses_.begin() || p->second.n_obs != 0) return false;
  return std::next(p) != poses_.end();
}

void FactorGraph::marginalizePose(StepIndex step) {
  if (!canMarginalizePose(step))
    throw std::logic_error("graph: pose " + std::to_string(step) + " cannot be marginalized");
  auto p = poses_.find(step);
  auto next = std::next(p);
  const auto prev = std::prev(p);
  recordRemoval(p->second.odo_id);
  recordRemoval(next->second.odo_id);
  next->second.odo = composeBetween(*p->second.odo, *next->second.odo);
  next->second.odo_id = next_factor_id_++;
  const VariableIndex index = p->second.index;
  poses_.erase(p);
  freeVariableIndex(index);
  variablesChanged();
  changed();
  recordVariable(GraphChange::Kind::RemoveVariable, VariableKey::pose(step), index);
  recordAddition(odometryFactor(prev, next));
}

void FactorGraph::dropFirstPoses(std::size_t count, const PriorFactor& next_prior) {
  if (count == 0) return;
  if (count >= poses_.size())
    throw std::logic_error("graph: cannot drop " + std::to_string(count) + " of " +
                           std::to_string(poses_.size()) + " poses");
  auto end = std::next(poses_.begin(), static_cast<std::ptrdiff_t>(count));
  const StepIndex first_kept = end->first;
  for (auto& [id, l] : landmarks_)
    l.obs.erase(std::remove_if(l.obs.begin(), l.obs.end(),
                               [&](const Observation& o) {
                                 if (o.pose >= first_kept) return false;
                                 recordRemoval(o.id);
                                 return true;
                               }),
                l.obs.end());
  recordRemoval(prior_id_);
  for (auto it = poses_.begin(); it != end; ++it) {
    recordRemoval(std::next(it)->second.odo_id);  // every odometry up to the new first pose
    recordVariable(GraphChange::Kind::RemoveVariable, VariableKey::pose(it->first),
                   it->second.index);
    freeVariableIndex(it->second.index);
  }
  poses_.erase(poses_.begin(), end);
  variablesChanged();
  poses_.begin()->second.odo.reset();
  poses_.begin()->second.odo_id = 0;
  prior_ = next_prior;
  prior_id_ = next_factor_id_++;
  changed();
  recordAddition(posePriorFactor());
}

void FactorGraph::setLandmarkPrior(LandmarkId id, const LandmarkPrior& prior) {
  auto l = landmarks_.find(id);
  if (l == landmarks_.end()) throw std::out_of_range("graph: no landmark " + std::to_string(id));
  const bool had = l->second.prior.has_value();
  if (had) recordRemoval(l->second.prior_id);
  l->second.prior = prior;
  l->second.prior_id = next_factor_id_++;
  ++revision_;          // new numbers in H either way
  if (!had) changed();  // a new factor; replacing one keeps the pattern
  recordAddition(landmarkPriorFactor(l));
}

std::size_t FactorGraph::factorCount() const {
  std::size_t n = poses_.empty() ? 0 : poses_.size();  // prior + one odometry per later pose
  for (const auto& [id, l] : landmarks_) n += l.obs.size() + (l.prior ? 1 : 0);
  return n;
}

void FactorGraph::removeFromLayout(const LandmarkNode* landmark) {
  Layout& L = layout_;
  const bool current = L.version == variables_version_;
  variablesChanged();
  if (!current) return;  // rebuilt in full at its next use
  const auto it = std::find(L.landmarks.begin(), L.landmarks.end(), landmark);
  if (it == L.landmarks.end()) return;  // not in the layout: rebuilt at its next use
  const std::size_t k = L.poses.size() + static_cast<std::size_t>(it - L.landmarks.begin());
  for (auto q = std::next(it); q != L.landmarks.end(); ++q) (*q)->col -= 2;
  L.landmarks.erase(it);
  L.starts.erase(L.starts.begin() + static_cast<std::ptrdiff_t>(k));
  for (std::size_t j = k; j < L.starts.size(); ++j) L.starts[j] -= 2;
  L.indices.erase(L.indices.begin() + static_cast<std::ptrdiff_t>(k));
  L.dim -= 2;
  L.version = variables_version_;
}

VariableIndex FactorGraph::newVariableIndex() {
  if (free_indices_.empty()) return next_variable_index_++;
  const VariableIndex v = free_indices_.back();
  free_indices_.pop_back();
  return v;
}

void FactorGraph::freeVariableIndex(VariableIndex v) { free_indices_.push_back(v); }

void FactorGraph::appendToLayout(PoseNode* pose) {
  Layout& L = layout_;
  const bool current = L.version == variables_version_;
  variablesChanged();
  if (!current) return;  // rebuilt in full at its next use
  // A pose after the last one: the columns of the poses before it stay, so the layout grows in
  // place (the landmarks' columns move up by 3).
  const std::size_t k = L.poses.size();  // its place among the variables: after the poses
  pose->col = static_cast<int>(3 * k);
  L.poses.push_back(pose);
  for (LandmarkNode* l : L.landmarks) l->col += 3;
  L.starts.insert(L.starts.begin() + static_cast<std::ptrdiff_t>(k), pose->col);
  for (std::size_t j = k + 1; j < L.starts.size(); ++j) L.starts[j] += 3;
  L.indices.insert(L.indices.begin() + static_cast<std::ptrdiff_t>(k), pose->index);
  const StepIndex step = poses_.rbegin()->first;
  L.by_step.resize(step - L.first_step + 1, nullptr);
  L.by_step.back() = pose;
  L.dim += 3;
  L.version = variables_version_;
}

void FactorGraph::insertIntoLayout(LandmarkNode* landmark, std::size_t position) {
  Layout& L = layout_;
  const bool current = L.version == variables_version_;
  variablesChanged();
  if (!current || position > L.landmarks.size()) return;  // rebuilt in full at its next use
  // The landmarks are in id order after the poses: the new one takes the columns of the one it
  // comes before, and those after it move up by 2.
  const auto at = L.landmarks.begin() + static_cast<std::ptrdiff_t>(position);
  landmark->col = at == L.landmarks.end() ? L.dim : (*at)->col;
  for (auto q = at; q != L.landmarks.end(); ++q) (*q)->col += 2;
  L.landmarks.insert(at, landmark);
  const std::size_t k = L.poses.size() + position;
  L.starts.insert(L.starts.begin() + static_cast<std::ptrdiff_t>(k), landmark->col);
  for (std::size_t j = k + 1; j < L.starts.size(); ++j) L.starts[j] += 2;
  L.indices.insert(L.indices.begin() + static_cast<std::ptrdiff_t>(k), landmark->index);
  L.dim += 2;
  L.version = variables_version_;
}

const FactorGraph::Layout& FactorGraph::layout() const {
  Layout& L = layout_;
  if (L.version == variables_version_) return L;
  L.poses.clear();
  L.landmarks.clear();
  L.starts.clear();
  L.indices.clear();
  L.by_step.clear();
  L.poses.reserve(poses_.size());
  L.landmarks.reserve(landmarks_.size());
  L.starts.reserve(poses_.size() + landmarks_.size() + 1);
  // The nodes belong to this graph; const only because the layout is a cache.
  auto& poses = const_cast<std::map<StepIndex, PoseNode>&>(poses_);
  auto& landmarks = const_cast<std::map<LandmarkId, LandmarkNode>&>(landmarks_);
  int c = 0;
  for (auto& [s, p] : poses) {
    p.col = c;
    L.starts.push_back(c);
    L.indices.push_back(p.index);
    L.poses.push_back(&p);
    c += 3;
  }
  for (auto& [id, l] : landmarks) {
    l.col = c;
    L.starts.push_back(c);
    L.indices.push_back(l.index);
    L.landmarks.push_back(&l);
    c += 2;
  }
  L.starts.push_back(c);
  L.dim = c;
  if (!poses_.empty()) {
    // Steps between kept poses (marginalized ones) are holes: the span is at most the steps the
    // graph covers, 8 bytes a step.
    L.first_step = poses_.begin()->first;
    L.by_step.assign(poses_.rbegin()->first - L.first_step + 1, nullptr);
    for (auto& [s, p] : poses) L.by_step[s - L.first_step] = &p;
  }
  L.version = variables_version_;
  return L;
}

int FactorGraph::dim() const { return layout().dim; }

const std::vector<int>& FactorGraph::variableStarts() const { return layout().starts; }

const std::vector<VariableIndex>& FactorGraph::variableIndices() const { return layout().indices; }

int FactorGraph::column(const VariableKey& v) const {
  layout();
  if (v.kind == VariableKey::Kind::Pose) {
    auto p = poses_.find(static_cast<StepIndex>(v.id));
    if (p == poses_.end()) throw std::out_of_range("graph: no pose " + std::to_string(v.id));
    return p->second.col;
  }
  auto l = landmarks_.find(v.id);
  if (l == landmarks_.end()) throw std::out_of_range("graph: no landmark " + std::to_string(v.id));
  return l->second.col;
}

double FactorGraph::chi2() const {
  if (poses_.empty()) return 0;
  const Layout& L = layout();
  double c = (prior_.sqrt_info * prior_.error(Pose2(L.poses.front()->x))).squaredNorm();
  for (std::size_t k = 1; k < L.poses.size(); ++k) {
    const PoseNode& p = *L.poses[k];
    c += (p.odo->sqrt_info * p.odo->error(Pose2(L.poses[k - 1]->x), Pose2(p.x))).squaredNorm();
  }
  for (const LandmarkNode* l : L.landmarks) {
    for (const Observation& o : l->obs)
      c += (o.f.sqrt_info * o.f.error(Pose2(L.pose(o.pose).x), l->x)).squaredNorm();
    if (l->prior) c += (l->prior->sqrt_info * (l->x - l->prior->mean)).squaredNorm();
  }
  return c;
}

void FactorGraph::linearize(Eigen::SparseMatrix<double>* H, Eigen::VectorXd* g,
                            double* chi2) const {
  const Layout& L = layout();
  // Kept per thread between calls: the list is megabytes on a long run (Victoria Park: 265k
  // entries), and a fresh one is page-faulted in on every linearization.
  thread_local Triplets t;
  t.clear();
  std::size_t n_obs = 0;
  for (const LandmarkNode* l : L.landmarks) n_obs += l->obs.size();
  t.reserve(L.poses.size() * 27 + n_obs * 21);
  g->setZero(L.dim);
  double c2 = 0;
  if (!L.poses.empty()) {
    const PoseNode& p0 = *L.poses.front();
    Eigen::Matrix3d J;
    const Eigen::Vector3d r = prior_.sqrt_info * prior_.error(Pose2(p0.x), &J);
    const Eigen::Matrix3d A = prior_.sqrt_info * J;
    addBlock(&t, p0.col, A, p0.col, A);
    g->segment<3>(p0.col) += A.transpose() * r;
    c2 += r.squaredNorm();
  }
  for (std::size_t k = 1; k < L.poses.size(); ++k) {
    const PoseNode& p = *L.poses[k];
    const PoseNode* prev = L.poses[k - 1];
    Eigen::Matrix3d Ji, Jj;
    const Eigen::Vector3d r = p.odo->sqrt_info * p.odo->error(Pose2(prev->x), Pose2(p.x), &Ji, &Jj);
    const Eigen::Matrix3d Ai = p.odo->sqrt_info * Ji, Aj = p.odo->sqrt_info * Jj;
    addBlock(&t, prev->col, Ai, prev->col, Ai);
    addBlock(&t, p.col, Aj, p.col, Aj);
    addBlock(&t, p.col, Aj, prev->col, Ai);
    g->segment<3>(prev->col) += Ai.transpose() * r;
    g->segment<3>(p.col) += Aj.transpose() * r;
    c2 += r.squaredNorm();
  }
  for (const LandmarkNode* lp : L.landmarks) {
    const LandmarkNode& l = *lp;
    for (const Observation& o : l.obs) {
      const PoseNode& p = L.pose(o.pose);
      Eigen::Matrix<double, 2, 3> Jx;
      Eigen::Matrix2d Jl;
      const Eigen::Vector2d r = o.f.sqrt_info * o.f.error(Pose2(p.x), l.x, &Jx, &Jl);
      const Eigen::Matrix<double, 2, 3> Ax = o.f.sqrt_info * Jx;
      const Eigen::Matrix2d Al = o.f.sqrt_info * Jl;
      addBlock(&t, p.col, Ax, p.col, Ax);
      addBlock(&t, l.col, Al, l.col, Al);
      addBlock(&t, l.col, Al, p.col, Ax);
      g->segment<3>(p.col) += Ax.transpose() * r;
      g->segment<2>(l.col) += Al.transpose() * r;
      c2 += r.squaredNorm();
    }
    if (l.prior) {
      const Eigen::Matrix2d& A = l.prior->sqrt_info;
      const Eigen::Vector2d r = A * (l.x - l.prior->mean);
      addBlock(&t, l.col, A, l.col, A);
      g->segment<2>(l.col) += A.transpose() * r;
      c2 += r.squaredNorm();
    }
  }
  H->resize(L.dim, L.dim);
  H->setFromTriplets(t.begin(), t.end());
  if (chi2) *chi2 = c2;
}

void FactorGraph::retract(const Eigen::VectorXd& dx) {
  const Layout& L = layout();
  for (PoseNode* p : L.poses) {
    p->x += dx.segment<3>(p->col);
    p->x.z() = wrapAngle(p->x.z());
  }
  for (LandmarkNode* l : L.landmarks) l->x += dx.segment<2>(l->col);
  valuesChanged();
}

Eigen::VectorXd FactorGraph::values() const {
  const Layout& L = layout();
  Eigen::VectorXd v(L.dim);
  for (const PoseNode* p : L.poses) v.segment<3>(p->col) = p->x;
  for (const LandmarkNode* l : L.landmarks) v.segment<2>(l->col) = l->x;
  return v;
}

void FactorGraph::setValues(const Eigen::VectorXd& v) {
  const Layout& L = layout();
  if (v.size() != L.dim) throw std::invalid_argument("graph: setValues with a wrong size");
  for (PoseNode* p : L.poses) p->x = v.segment<3>(p->col);
  for (LandmarkNode* l : L.landmarks) l->x = v.segment<2>(l->col);
  valuesChanged();
}

}  // namespace budget_slam::graph
