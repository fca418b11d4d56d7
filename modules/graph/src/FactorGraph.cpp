#include "budget_slam/graph/FactorGraph.h"

#include <Eigen/Cholesky>
#include <algorithm>
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

void FactorGraph::addFirstPose(StepIndex step, double t, const Pose2& x, const PriorFactor& prior) {
  if (!poses_.empty()) throw std::logic_error("graph: first pose added twice");
  PoseNode n;
  n.x = x;
  n.t = t;
  poses_.emplace(step, n);
  prior_ = prior;
  changed();
}

void FactorGraph::addPose(StepIndex step, double t, const Pose2& x, const BetweenFactor& odo) {
  if (poses_.empty() || poses_.rbegin()->first >= step)
    throw std::logic_error("graph: pose " + std::to_string(step) + " is not after the last pose");
  PoseNode n;
  n.x = x;
  n.t = t;
  n.odo = odo;
  poses_.emplace_hint(poses_.end(), step, n);
  changed();
}

void FactorGraph::addLandmark(LandmarkId id, const Eigen::Vector2d& x) {
  if (landmarks_.count(id))
    throw std::logic_error("graph: landmark " + std::to_string(id) + " exists");
  LandmarkNode n;
  n.x = x;
  landmarks_.emplace(id, n);
  changed();
}

void FactorGraph::addObservation(StepIndex pose, LandmarkId id, const RangeBearingFactor& f) {
  auto p = poses_.find(pose);
  if (p == poses_.end()) throw std::out_of_range("graph: no pose " + std::to_string(pose));
  auto l = landmarks_.find(id);
  if (l == landmarks_.end()) throw std::out_of_range("graph: no landmark " + std::to_string(id));
  l->second.obs.push_back({pose, f});
  ++p->second.n_obs;
  changed();
}

void FactorGraph::removeLandmark(LandmarkId id) {
  auto l = landmarks_.find(id);
  if (l == landmarks_.end()) throw std::out_of_range("graph: no landmark " + std::to_string(id));
  for (const Observation& o : l->second.obs) --poses_.at(o.pose).n_obs;
  landmarks_.erase(l);
  changed();
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
  next->second.odo = composeBetween(*p->second.odo, *next->second.odo);
  poses_.erase(p);
  changed();
}

LandmarkPrior LandmarkPrior::make(const Eigen::Vector2d& mean, const Eigen::Matrix2d& cov) {
  LandmarkPrior p;
  p.mean = mean;
  // sqrt_info = L^-1 for cov = L L^T: sqrt_info^T sqrt_info = cov^-1.
  const Eigen::LLT<Eigen::Matrix2d> llt(0.5 * (cov + cov.transpose()));
  if (llt.info() != Eigen::Success || !cov.allFinite())
    throw std::invalid_argument("graph: landmark prior covariance is not positive definite");
  p.sqrt_info = llt.matrixL().solve(Eigen::Matrix2d::Identity());
  return p;
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
                               [&](const Observation& o) { return o.pose < first_kept; }),
                l.obs.end());
  poses_.erase(poses_.begin(), end);
  poses_.begin()->second.odo.reset();
  prior_ = next_prior;
  changed();
}

void FactorGraph::setLandmarkPrior(LandmarkId id, const LandmarkPrior& prior) {
  auto l = landmarks_.find(id);
  if (l == landmarks_.end()) throw std::out_of_range("graph: no landmark " + std::to_string(id));
  const bool had = l->second.prior.has_value();
  l->second.prior = prior;
  ++revision_;          // new numbers in H either way
  if (!had) changed();  // a new factor; replacing one keeps the pattern
}

std::size_t FactorGraph::factorCount() const {
  std::size_t n = poses_.empty() ? 0 : poses_.size();  // prior + one odometry per later pose
  for (const auto& [id, l] : landmarks_) n += l.obs.size() + (l.prior ? 1 : 0);
  return n;
}

const FactorGraph::Layout& FactorGraph::layout() const {
  Layout& L = layout_;
  if (L.version == structure_version_) return L;
  L.poses.clear();
  L.landmarks.clear();
  L.starts.clear();
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
    L.poses.push_back(&p);
    c += 3;
  }
  for (auto& [id, l] : landmarks) {
    l.col = c;
    L.starts.push_back(c);
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
  L.version = structure_version_;
  return L;
}

int FactorGraph::dim() const { return layout().dim; }

const std::vector<int>& FactorGraph::variableStarts() const { return layout().starts; }

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
  double c = (prior_.sqrt_info * prior_.error(L.poses.front()->x)).squaredNorm();
  for (std::size_t k = 1; k < L.poses.size(); ++k) {
    const PoseNode& p = *L.poses[k];
    c += (p.odo->sqrt_info * p.odo->error(L.poses[k - 1]->x, p.x)).squaredNorm();
  }
  for (const LandmarkNode* l : L.landmarks) {
    for (const Observation& o : l->obs)
      c += (o.f.sqrt_info * o.f.error(L.pose(o.pose).x, l->x)).squaredNorm();
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
    const Eigen::Vector3d r = prior_.sqrt_info * prior_.error(p0.x, &J);
    const Eigen::Matrix3d A = prior_.sqrt_info * J;
    addBlock(&t, p0.col, A, p0.col, A);
    g->segment<3>(p0.col) += A.transpose() * r;
    c2 += r.squaredNorm();
  }
  for (std::size_t k = 1; k < L.poses.size(); ++k) {
    const PoseNode& p = *L.poses[k];
    const PoseNode* prev = L.poses[k - 1];
    Eigen::Matrix3d Ji, Jj;
    const Eigen::Vector3d r = p.odo->sqrt_info * p.odo->error(prev->x, p.x, &Ji, &Jj);
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
      const Eigen::Vector2d r = o.f.sqrt_info * o.f.error(p.x, l.x, &Jx, &Jl);
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
  ++revision_;
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
  ++revision_;
}

}  // namespace budget_slam::graph
