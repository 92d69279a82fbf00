#include "workers/sparse_cholesky.h"

#include <dlfcn.h>

#include <mutex>
#include <variant>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "Eigen/CholmodSupport"
#include "Eigen/SparseCholesky"

namespace fitbase::workers {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Simplicial = Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower>;
using Supernodal = Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>;

class SparseCholesky::Impl {
 public:
  explicit Impl(Factorization kind) {
    if (kind == Factorization::kSimplicialLdlt) {
      solver_.emplace<Simplicial>();
      return;
    }
    Supernodal& cholmod = solver_.emplace<Supernodal>();
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
    // One ordering, AMD, instead of CHOLMOD's default of trying AMD and METIS and keeping the
    // one with less fill: the choice could differ between nearby patterns, and METIS is
    // randomised. AMD is within a few percent of METIS on these meshes.
    cholmod.cholmod().nmethods = 1;
    cholmod.cholmod().method[0].ordering = CHOLMOD_AMD;
    cholmod.cholmod().postorder = 1;
    // A matrix that is not positive definite is reported through Factorize's result, not
    // printed.
    cholmod.cholmod().print = 0;
  }

  std::variant<Simplicial, Supernodal> solver_;
};

SparseCholesky::SparseCholesky(Factorization kind) : impl_(std::make_unique<Impl>(kind)) {}

SparseCholesky::~SparseCholesky() = default;

void SparseCholesky::AnalyzePattern(const SparseMatrix& pattern) {
  std::visit([&](auto& s) { s.analyzePattern(pattern); }, impl_->solver_);
}

bool SparseCholesky::Factorize(const SparseMatrix& matrix) {
#ifdef _OPENMP
  // CHOLMOD's supernodal factorisation copies its larger blocks in OpenMP regions of four
  // threads (a compile-time count that OMP_NUM_THREADS does not override). A drape is one
  // core's work, several run side by side, and on a busy machine the threads' wake-ups cost
  // far more than the copies: a 2.2k-vertex drape took 13.7 s with them and 4.9 s without,
  // same bytes. No active level makes every region run on the calling thread; the setting
  // belongs to this thread (OpenMP 5), hence here, before each factorisation.
  omp_set_max_active_levels(0);
#endif
  return std::visit(
      [&](auto& s) {
        s.factorize(matrix);
        return s.info() == Eigen::Success;
      },
      impl_->solver_);
}

Eigen::VectorXd SparseCholesky::Solve(const Eigen::VectorXd& b) const {
  return std::visit([&](const auto& s) -> Eigen::VectorXd { return s.solve(b); },
                    impl_->solver_);
}

}  // namespace fitbase::workers
