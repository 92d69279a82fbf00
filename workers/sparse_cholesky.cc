#include "workers/sparse_cholesky.h"

#include <dlfcn.h>

#include <algorithm>
#include <mutex>
#include <numeric>

#include "Eigen/SparseCholesky"
#include "cholmod.h"

// Debian builds CHOLMOD with OpenMP: its supernodal factorisation opens a parallel region per
// supernode and per update it assembles, about 4,000 per factorisation here, most of them
// with a false `if` clause. libgomp ends every region, even one it runs on a single thread,
// with a barrier wake-up, a futex system call: a 2.2k-vertex drape made 1.19 million of them,
// 30% of its time on this virtual machine (6.9 s with them, 4.9 s without, the same bytes).
// A drape is one core's work and several run side by side, so this definition, which the
// dynamic linker finds in the executable before libgomp's, runs every region of the process
// on its calling thread: the code in it sees one thread (omp_get_num_threads() is 1 outside
// a team), which is how CHOLMOD's regions partition their loops. CHOLMOD calls no other
// entry point that starts threads (nm -D libcholmod.so.3: GOMP_parallel, omp_get_num_threads,
// omp_get_thread_num), and nothing of ours uses OpenMP.
extern "C" void GOMP_parallel(void (*body)(void*), void* data, unsigned /*num_threads*/,
                              unsigned /*flags*/) {
  body(data);
}

namespace fitbase::workers {

using SparseMatrix = Eigen::SparseMatrix<double>;

class SparseCholesky::Impl {
 public:
  virtual ~Impl() = default;
  virtual const std::vector<int>& AnalyzePattern(const SparseMatrix& pattern) = 0;
  virtual int ValueCount() const = 0;
  virtual bool Factorize(const Eigen::VectorXd& values) = 0;
  virtual Eigen::VectorXd Solve(const Eigen::VectorXd& b) const = 0;
};

namespace {

// The values are the pattern's own, in its order.
class SimplicialImpl : public SparseCholesky::Impl {
 public:
  const std::vector<int>& AnalyzePattern(const SparseMatrix& pattern) override {
    matrix_ = pattern;
    matrix_.makeCompressed();
    matrix_.coeffs().setZero();
    slots_.assign(static_cast<size_t>(matrix_.nonZeros()), -1);
    for (Eigen::Index column = 0; column < matrix_.outerSize(); ++column) {
      for (int k = matrix_.outerIndexPtr()[column]; k < matrix_.outerIndexPtr()[column + 1];
           ++k) {
        if (matrix_.innerIndexPtr()[k] >= column) slots_[k] = k;
      }
    }
    solver_.analyzePattern(matrix_);
    return slots_;
  }

  int ValueCount() const override { return static_cast<int>(matrix_.nonZeros()); }

  bool Factorize(const Eigen::VectorXd& values) override {
    if (values.size() != matrix_.nonZeros()) return false;
    matrix_.coeffs() = values;
    solver_.factorize(matrix_);
    return solver_.info() == Eigen::Success;
  }

  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const override { return solver_.solve(b); }

 private:
  SparseMatrix matrix_;
  std::vector<int> slots_;
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> solver_;
};

// CHOLMOD called directly. Its fill-reducing permutation P is applied once, to the pattern:
// the values are those of the lower triangle of P A P', and CHOLMOD factors that in its natural
// order, as it would have factored A after permuting it itself.
class CholmodImpl : public SparseCholesky::Impl {
 public:
  CholmodImpl() {
    static std::once_flag blas_on_one_thread;
    std::call_once(blas_on_one_thread, [] {
      // OpenBLAS's threaded build (the one scripts/setup.sh selects) splits a product by its
      // thread count, and so its rounding; a drape is one core's work anyway. Looked up, not
      // linked: with another BLAS there is nothing to set. Debian's serial OpenBLAS is not an
      // option: drapes side by side in one process race on its buffers (their bytes differed).
      using SetThreads = void (*)(int);
      if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT,
                                                        "openblas_set_num_threads"))) {
        set(1);
      }
    });
    cholmod_start(&common_);
    common_.supernodal = CHOLMOD_SUPERNODAL;
    common_.final_asis = 1;
    // A matrix that is not positive definite is reported through Factorize's result, not
    // printed.
    common_.print = 0;
  }

  ~CholmodImpl() override {
    cholmod_free_factor(&factor_, &common_);
    cholmod_finish(&common_);
  }

  const std::vector<int>& AnalyzePattern(const SparseMatrix& pattern) override {
    cholmod_free_factor(&factor_, &common_);
    const auto n = static_cast<int>(pattern.rows());
    const int* outer = pattern.outerIndexPtr();
    const int* inner = pattern.innerIndexPtr();
    // One ordering, AMD, instead of CHOLMOD's default of trying AMD and METIS and keeping the
    // one with less fill: the choice could differ between nearby patterns, and METIS is
    // randomised. AMD is within a few percent of METIS on these meshes.
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_AMD;
    common_.postorder = 1;
    cholmod_sparse original = View(n, outer, inner, nullptr);
    // Without an ordering (CHOLMOD out of memory) the layout stays valid and Factorize fails.
    permutation_.resize(n);
    std::iota(permutation_.begin(), permutation_.end(), 0);
    if (cholmod_factor* ordering = cholmod_analyze(&original, &common_)) {
      permutation_.assign(static_cast<int*>(ordering->Perm),
                          static_cast<int*>(ordering->Perm) + n);
      cholmod_free_factor(&ordering, &common_);
    }
    std::vector<int> position(n);  // Of each row of the pattern in P A P'.
    for (int k = 0; k < n; ++k) position[permutation_[k]] = k;
    // Entry (row, column) of the lower triangle goes to the lower triangle of P A P'.
    struct Entry {
      int column;
      int row;
      int source;
    };
    std::vector<Entry> entries;
    slots_.assign(static_cast<size_t>(outer[n]), -1);
    for (int column = 0; column < n; ++column) {
      for (int k = outer[column]; k < outer[column + 1]; ++k) {
        if (inner[k] < column) continue;
        const int a = position[inner[k]];
        const int b = position[column];
        entries.push_back({std::min(a, b), std::max(a, b), k});
      }
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
      return x.column < y.column || (x.column == y.column && x.row < y.row);
    });
    outer_.assign(n + 1, 0);
    inner_.resize(entries.size());
    for (size_t e = 0; e < entries.size(); ++e) {
      ++outer_[entries[e].column + 1];
      inner_[e] = entries[e].row;
      slots_[entries[e].source] = static_cast<int>(e);
    }
    for (int column = 0; column < n; ++column) outer_[column + 1] += outer_[column];
    // P A P' is already ordered and postordered: analysed as it stands it has the symbolic
    // factor A had under P.
    common_.method[0].ordering = CHOLMOD_NATURAL;
    common_.postorder = 0;
    cholmod_sparse permuted = View(n, outer_.data(), inner_.data(), nullptr);
    factor_ = cholmod_analyze(&permuted, &common_);
    return slots_;
  }

  int ValueCount() const override { return static_cast<int>(inner_.size()); }

  bool Factorize(const Eigen::VectorXd& values) override {
    if (factor_ == nullptr || values.size() != ValueCount()) return false;
    const auto n = static_cast<int>(permutation_.size());
    cholmod_sparse permuted = View(n, outer_.data(), inner_.data(), values.data());
    cholmod_factorize(&permuted, factor_, &common_);
    // Not positive definite is a warning, with the failing column in `minor`.
    return common_.status >= CHOLMOD_OK && factor_->minor == factor_->n;
  }

  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const override {
    const auto n = static_cast<Eigen::Index>(permutation_.size());
    Eigen::VectorXd permuted(n);
    for (Eigen::Index k = 0; k < n; ++k) permuted(k) = b(permutation_[k]);
    cholmod_dense rhs{};
    rhs.nrow = static_cast<size_t>(n);
    rhs.ncol = 1;
    rhs.nzmax = rhs.d = static_cast<size_t>(n);
    rhs.x = permuted.data();
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* solution = cholmod_solve(CHOLMOD_A, factor_, &rhs, &common_);
    if (solution == nullptr) return Eigen::VectorXd::Zero(n);
    Eigen::VectorXd x(n);
    const double* y = static_cast<const double*>(solution->x);
    for (Eigen::Index k = 0; k < n; ++k) x(permutation_[k]) = y[k];
    cholmod_free_dense(&solution, &common_);
    return x;
  }

 private:
  // A symmetric matrix with its lower triangle stored (values null: the pattern only).
  static cholmod_sparse View(int n, const int* outer, const int* inner, const double* values) {
    cholmod_sparse view{};
    view.nrow = view.ncol = static_cast<size_t>(n);
    view.nzmax = static_cast<size_t>(outer[n]);
    view.p = const_cast<int*>(outer);
    view.i = const_cast<int*>(inner);
    view.x = const_cast<double*>(values);
    view.stype = -1;
    view.itype = CHOLMOD_INT;
    view.xtype = values == nullptr ? CHOLMOD_PATTERN : CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    view.sorted = 1;
    view.packed = 1;
    return view;
  }

  mutable cholmod_common common_;
  cholmod_factor* factor_ = nullptr;
  std::vector<int> permutation_;  // Row k of P A P' is row permutation_[k] of A.
  std::vector<int> outer_;        // P A P''s lower triangle, compressed by column.
  std::vector<int> inner_;
  std::vector<int> slots_;
};

}  // namespace

SparseCholesky::SparseCholesky(Factorization kind) {
  if (kind == Factorization::kSimplicialLdlt) {
    impl_ = std::make_unique<SimplicialImpl>();
  } else {
    impl_ = std::make_unique<CholmodImpl>();
  }
}

SparseCholesky::~SparseCholesky() = default;

const std::vector<int>& SparseCholesky::AnalyzePattern(const SparseMatrix& pattern) {
  return impl_->AnalyzePattern(pattern);
}

int SparseCholesky::ValueCount() const { return impl_->ValueCount(); }

bool SparseCholesky::Factorize(const Eigen::VectorXd& values) {
  return impl_->Factorize(values);
}

Eigen::VectorXd SparseCholesky::Solve(const Eigen::VectorXd& b) const {
  return impl_->Solve(b);
}

}  // namespace fitbase::workers
