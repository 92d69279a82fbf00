#include "workers/sparse_cholesky.h"

#include <variant>

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
