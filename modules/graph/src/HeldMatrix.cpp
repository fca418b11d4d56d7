#include "HeldMatrix.h"

#include <algorithm>
#include <utility>

namespace budget_slam::graph::held {

void HeldMatrix::change(const HeldRecords& rec, const Held& h, const LinearFactor& lf, double sign,
                        const LinearFactor* old) {
  // A and r are zero past their rows and columns: fixed-size products.
  Eigen::Matrix<double, 6, 6> AtA = sign * (lf.A.transpose() * lf.A);
  Eigen::Matrix<double, 6, 1> Atr = sign * (lf.A.transpose() * lf.r);
  double r2 = sign * lf.r.squaredNorm();
  if (old) {
    AtA.noalias() -= old->A.transpose() * old->A;
    Atr.noalias() -= old->A.transpose() * old->r;
    r2 -= old->r.squaredNorm();
  }
  const double* a = AtA.data();
  const std::size_t m = h.hpos.size();
  if (dying_count == 0) {
    for (std::size_t k = 0; k < m; ++k) Hx[h.hpos[k]] += a[h.hidx[k]];
  } else {
    std::size_t k = 0;
    forEachEntry(rec, h, [&](int r, int c, int, int) {
      double& x = Hx[h.hpos[k]];
      x = dyingRow(rec, r) || dyingRow(rec, c) ? 0.0 : x + a[h.hidx[k]];
      ++k;
    });
  }
  int off = 0;
  for (int j = 0; j < 2 && h.var[j] >= 0; ++j) {
    const Var& v = rec.vars[h.var[j]];
    if (!v.dying) g.segment(v.row, v.dim) += Atr.segment(off, v.dim);
    off += v.dim;
  }
  chi2 += r2;
}

int HeldMatrix::find(int r, int c) const {
  const auto b = Hi.begin() + Hp[c], e = Hi.begin() + Hp[c + 1];
  const auto it = std::lower_bound(b, e, r);
  return it != e && *it == r ? static_cast<int>(it - Hi.begin()) : -1;
}

void HeldMatrix::buildPattern(HeldRecords& rec) {
  const int n = capacity();
  std::vector<int> count(static_cast<std::size_t>(n) + 1, 1);  // the diagonals
  for (const Held& h : rec.factors)
    if (h.alive)
      forEachEntry(rec, h, [&](int r, int c, int, int) {
        if (r != c) ++count[c];
      });
  std::vector<int> start(static_cast<std::size_t>(n) + 1, 0);
  for (int c = 0; c < n; ++c) start[c + 1] = start[c] + count[c];
  std::vector<int> rows(static_cast<std::size_t>(start[n]));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int c = 0; c < n; ++c) rows[fill[c]++] = c;
  for (const Held& h : rec.factors)
    if (h.alive)
      forEachEntry(rec, h, [&](int r, int c, int, int) {
        if (r != c) rows[fill[c]++] = r;
      });
  Hp.assign(static_cast<std::size_t>(n) + 1, 0);
  Hi.clear();
  Hi.reserve(rows.size());
  for (int c = 0; c < n; ++c) {
    std::sort(rows.begin() + start[c], rows.begin() + start[c + 1]);
    const auto e = std::unique(rows.begin() + start[c], rows.begin() + start[c + 1]);
    Hi.insert(Hi.end(), rows.begin() + start[c], e);
    Hp[c + 1] = static_cast<int>(Hi.size());
  }
  for (Held& h : rec.factors)
    if (h.alive) locate(rec, &h);
  assemble(rec);
}

void HeldMatrix::assemble(const HeldRecords& rec) {
  const int n = capacity();
  Hx.assign(Hi.size(), 0.0);
  g.setZero(n);
  chi2 = 0;
  for (const Held& h : rec.factors)
    if (h.alive) add(rec, h, 1.0);
  for (int r = 0; r < n; ++r)
    if (owner[r] < 0) Hx[Hp[r + 1] - 1] = 1.0;  // spare or dead: identity
}

bool HeldMatrix::locate(const HeldRecords& rec, Held* h) const {
  h->hpos.clear();
  h->hidx.clear();
  bool ok = true;
  forEachEntry(rec, *h, [&](int r, int c, int ar, int ac) {
    const int k = find(r, c);
    ok = ok && k >= 0;
    h->hpos.push_back(k);
    h->hidx.push_back(static_cast<std::uint8_t>(6 * ac + ar));
  });
  return ok;
}

bool HeldMatrix::extendPattern(HeldRecords& rec, int first, const std::vector<int>& added) {
  const int n = capacity();
  std::vector<std::pair<int, int>> entries;  // (column, row)
  for (int c = first; c < n; ++c) entries.emplace_back(c, c);
  for (int k : added)
    forEachEntry(rec, rec.factors[k], [&](int r, int c, int, int) {
      if (c >= first && r != c) entries.emplace_back(c, r);
    });
  std::sort(entries.begin(), entries.end());
  entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
  Hi.resize(static_cast<std::size_t>(Hp[first]));
  Hx.resize(static_cast<std::size_t>(Hp[first]));
  Hp.resize(static_cast<std::size_t>(n) + 1);
  std::size_t e = 0;
  for (int c = first; c < n; ++c) {
    for (; e < entries.size() && entries[e].first == c; ++e) {
      Hi.push_back(entries[e].second);
      Hx.push_back(0.0);
    }
    Hp[c + 1] = static_cast<int>(Hi.size());
    if (owner[c] < 0) Hx.back() = 1.0;  // spare: identity
  }
  for (int k : added)
    if (!locate(rec, &rec.factors[k])) return false;
  return true;
}

SparseCholesky::UpperTriangle HeldMatrix::upper(int first) {
  SparseCholesky::UpperTriangle H;
  H.n = capacity();
  if (dead_rows == 0) {
    H.p = Hp.data();
    H.i = Hi.data();
    H.x = Hx.data();
    return H;
  }
  Fp.assign(static_cast<std::size_t>(H.n) + 1, 0);
  Fi.clear();
  Fx.clear();
  // Columns before `first` stay empty (Fp 0 there).
  for (int c = std::max(first, 0); c < H.n; ++c) {
    for (int k = Hp[c]; k < Hp[c + 1]; ++k) {
      const int r = Hi[k];
      if (r != c && (owner[r] < 0 || owner[c] < 0)) continue;
      Fi.push_back(r);
      Fx.push_back(Hx[k]);
    }
    Fp[c + 1] = static_cast<int>(Fi.size());
  }
  H.p = Fp.data();
  H.i = Fi.data();
  H.x = Fx.data();
  return H;
}

}  // namespace budget_slam::graph::held
