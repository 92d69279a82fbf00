#include "workers/sparse_cholesky.h"

#include <dlfcn.h>

#include <mutex>
#include <variant>

#include "Eigen/CholmodSupport"
#include "Eigen/SparseCholesky"

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
