// CSDP wrapper for the 3-simplex SDP. With z the degree-2 monomials β_aβ_b
// (a ≤ b) and E = Σ_l (c_lᵀz − d_l)², the moment matrix M2 = X2 X2ᵀ with
// X2 = [1 zᵀ]ᵀ (4.150) (4.152) makes E linear: E = tr(W M2) (4.143) (4.146)
// (4.147). The LMIs are M0 = diag(β_a² − β_b²) ⪰ 0 (the first eigenvector
// dominates), M1 = X1 X1ᵀ ⪰ 0 with X1 = β (4.149) (4.151) and M2 ⪰ 0, tied
// together by equalities between entries that are the same monomial.
#include "moment_sdp.h"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>

extern "C" {
#include <csdp/declarations.h>
}

namespace cone_tracker {
namespace {

// One linear equality Σ coeff · X(block; i, j) = rhs over the moment blocks
// (1-based block and matrix indices, as CSDP wants).
struct Term {
  int block, i, j;
  double coeff;
};
struct Equality {
  std::vector<Term> terms;
  double rhs;
};

template <typename T>
T* Alloc(size_t n) {
  return static_cast<T*>(std::calloc(n, sizeof(T)));
}

// CSDP reads A symmetric: an off-diagonal entry v contributes 2 v X_ij.
struct constraintmatrix MakeConstraint(const Equality& eq, int index, const std::array<int, 4>& block_sizes) {
  struct constraintmatrix m;
  m.blocks = nullptr;
  std::map<int, std::map<std::pair<int, int>, double>> by_block;
  for (const Term& t : eq.terms) {
    const int i = std::min(t.i, t.j), j = std::max(t.i, t.j);
    by_block[t.block][{i, j}] += i == j ? t.coeff : 0.5 * t.coeff;
  }
  for (auto it = by_block.rbegin(); it != by_block.rend(); ++it) {
    auto* b = Alloc<struct sparseblock>(1);
    const int n = static_cast<int>(it->second.size());
    b->blocknum = it->first;
    b->blocksize = block_sizes[it->first];
    b->constraintnum = index;
    b->numentries = n;
    b->issparse = 1;
    b->entries = Alloc<double>(n + 1);
    b->iindices = Alloc<int>(n + 1);
    b->jindices = Alloc<int>(n + 1);
    int k = 1;
    for (const auto& e : it->second) {
      b->iindices[k] = e.first.first;
      b->jindices[k] = e.first.second;
      b->entries[k++] = e.second;
    }
    b->next = m.blocks;
    b->nextbyblock = nullptr;
    m.blocks = b;
  }
  return m;
}

// CSDP prints its iterations to stdout; keep the tool's JSONL output clean.
class QuietStdout {
 public:
  QuietStdout() {
    std::fflush(stdout);
    saved_ = dup(STDOUT_FILENO);
    const int null_fd = open("/dev/null", O_WRONLY);
    if (null_fd >= 0) dup2(null_fd, STDOUT_FILENO), close(null_fd);
  }
  ~QuietStdout() {
    std::fflush(stdout);
    if (saved_ >= 0) dup2(saved_, STDOUT_FILENO), close(saved_);
  }

 private:
  int saved_;
};
std::mutex csdp_mutex;  // CSDP and the stdout redirection are process-global

}  // namespace

bool SolveMomentRelaxation(const std::vector<QuadraticConstraint>& constraints, int count, Eigen::Vector4d* beta,
                           std::string* error) {
  if (count < 2 || count > 4) {
    *error = "simplex-sdp uses 2, 3 or 4 eigenvectors";
    return false;
  }
  // Degree-2 monomials z_k = β_aβ_b, a ≤ b.
  std::vector<std::pair<int, int>> mono;
  for (int a = 0; a < count; ++a)
    for (int b = a; b < count; ++b) mono.push_back({a, b});
  const int K = static_cast<int>(mono.size());
  const auto index_of = [&](int a, int b) {
    for (int k = 0; k < K; ++k)
      if (mono[k] == std::make_pair(std::min(a, b), std::max(a, b))) return k;
    return -1;
  };
  // E = Σ_l (c_lᵀ z − d_l)² = tr(W M2), W = [Σd², −Σd cᵀ; −Σd c, Σ c cᵀ].
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(K + 1, K + 1);
  for (const QuadraticConstraint& q : constraints) {
    Eigen::VectorXd cz(K + 1);
    cz(0) = -q.target;
    for (int k = 0; k < K; ++k)
      cz(k + 1) = (mono[k].first == mono[k].second ? 1.0 : 2.0) * q.Q(mono[k].first, mono[k].second);
    W += cz * cz.transpose();
  }
  W /= std::max(1e-300, W.diagonal().maxCoeff());  // scale for the solver's tolerances

  // Blocks: 1 = M0 (diagonal, count − 1), 2 = M1 (count × count), 3 = M2 (K + 1).
  const std::array<int, 4> sizes{0, count - 1, count, K + 1};
  std::vector<Equality> eqs;
  eqs.push_back({{{3, 1, 1, 1.0}}, 1.0});  // M2(1, 1) = 1
  // M2 entries that are the same degree-4 monomial must agree.
  std::map<std::array<int, 4>, std::pair<int, int>> first;
  for (int i = 0; i < K; ++i)
    for (int j = i; j < K; ++j) {
      std::array<int, 4> key{mono[i].first, mono[i].second, mono[j].first, mono[j].second};
      std::sort(key.begin(), key.end());
      const auto found = first.find(key);
      if (found == first.end()) {
        first[key] = {i + 2, j + 2};
      } else {
        eqs.push_back({{{3, i + 2, j + 2, 1.0}, {3, found->second.first, found->second.second, -1.0}}, 0.0});
      }
    }
  // M1(a, b) = z_ab = M2(1, z_ab) (4.151) (4.152).
  for (int a = 0; a < count; ++a)
    for (int b = a; b < count; ++b) eqs.push_back({{{2, a + 1, b + 1, 1.0}, {3, 1, index_of(a, b) + 2, -1.0}}, 0.0});
  // M0: β_1² − β_a² (4.151).
  for (int a = 1; a < count; ++a)
    eqs.push_back({{{1, a, a, 1.0}, {3, 1, index_of(0, 0) + 2, -1.0}, {3, 1, index_of(a, a) + 2, 1.0}}, 0.0});

  const int n = sizes[1] + sizes[2] + sizes[3], k = static_cast<int>(eqs.size());
  struct blockmatrix C;
  C.nblocks = 3;
  C.blocks = Alloc<struct blockrec>(4);
  C.blocks[1].blockcategory = DIAG;
  C.blocks[1].blocksize = sizes[1];
  C.blocks[1].data.vec = Alloc<double>(sizes[1] + 1);
  for (int b = 2; b <= 3; ++b) {
    C.blocks[b].blockcategory = MATRIX;
    C.blocks[b].blocksize = sizes[b];
    C.blocks[b].data.mat = Alloc<double>(sizes[b] * sizes[b]);
  }
  for (int i = 0; i <= K; ++i)
    for (int j = 0; j <= K; ++j) C.blocks[3].data.mat[j * (K + 1) + i] = -W(i, j);  // CSDP maximises tr(C X)
  double* a = Alloc<double>(k + 1);
  auto* cons = Alloc<struct constraintmatrix>(k + 1);
  for (int e = 0; e < k; ++e) {
    a[e + 1] = eqs[e].rhs;
    cons[e + 1] = MakeConstraint(eqs[e], e + 1, sizes);
  }
  struct blockmatrix X, Z;
  double *y = nullptr, pobj = 0.0, dobj = 0.0;
  int status;
  {
    const std::lock_guard<std::mutex> lock(csdp_mutex);
    const QuietStdout quiet;
    initsoln(n, k, C, a, cons, &X, &y, &Z);
    status = easy_sdp(n, k, C, a, cons, 0.0, &X, &y, &Z, &pobj, &dobj);
  }
  bool ok = status == 0 || status == 3;  // 3: partial success (reduced accuracy)
  if (ok) {
    const double* M2 = X.blocks[3].data.mat;
    const auto z = [&](int a_, int b_) { return M2[(index_of(a_, b_) + 1) * (K + 1)]; };  // M2(1, z_ab)
    beta->setZero();
    (*beta)(0) = std::sqrt(std::max(0.0, z(0, 0)));  // (4.153)
    for (int b = 1; b < count; ++b) (*beta)(b) = (*beta)(0) > 0.0 ? z(0, b) / (*beta)(0) : 0.0;
    ok = beta->allFinite() && (*beta)(0) > 0.0;
    if (!ok) *error = "simplex-sdp: degenerate moment solution";
  } else {
    *error = "simplex-sdp: CSDP returned status " + std::to_string(status);
  }
  free_prob(n, k, C, a, cons, X, y, Z);
  return ok;
}

}  // namespace cone_tracker
