#ifndef FITBASE_WORKERS_SPARSE_CHOLESKY_H_
#define FITBASE_WORKERS_SPARSE_CHOLESKY_H_

#include <memory>

#include "Eigen/Core"
#include "Eigen/SparseCore"

namespace fitbase::workers {

// How the cloth solver factors its Newton systems.
enum class Factorization {
  // Eigen's SimplicialLDLT (AMD ordering): one column at a time, no dense kernels. The first
  // solver, kept as the speed baseline (bench/drape_bench --speed).
  kSimplicialLdlt,
  // CHOLMOD's supernodal LL^T (SuiteSparse, AMD ordering, on the calling thread): columns with
  // the same sparsity are factored together as dense blocks through BLAS. With
  // OpenBLAS on one thread 6.2x faster than kSimplicialLdlt on an 8.4k-vertex garment; with
  // Debian's reference BLAS about as fast.
  kSupernodalCholmod,
};

// Factorises symmetric positive definite matrices of one fixed sparsity pattern, many times
// (a Newton solve per iteration): the ordering and symbolic analysis are done once. Reads only
// the lower triangle. Deterministic with BLAS on one thread: the same matrix gives the
// same bits (CHOLMOD is asked for a single ordering).
class SparseCholesky {
 public:
  explicit SparseCholesky(Factorization kind);
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // `pattern` (n x n, compressed, lower triangle stored).
  void AnalyzePattern(const Eigen::SparseMatrix<double>& pattern);
  // False if the matrix is not positive definite (then Solve must not be called).
  bool Factorize(const Eigen::SparseMatrix<double>& matrix);
  // x = A^-1 b for the last factorised A; b and x have n rows.
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_SPARSE_CHOLESKY_H_
