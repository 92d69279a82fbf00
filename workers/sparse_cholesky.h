#ifndef FITBASE_WORKERS_SPARSE_CHOLESKY_H_
#define FITBASE_WORKERS_SPARSE_CHOLESKY_H_

#include <memory>
#include <vector>

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
// (a Newton solve per iteration): the ordering and symbolic analysis are done once. Each
// factorisation takes the matrix's values in the factorisation's own layout, which
// AnalyzePattern gives: the caller writes them there directly, so no factorisation copies or
// permutes the matrix (CHOLMOD, given the lower triangle in the caller's order, transposed it
// twice per factorisation: 9% of a drape). Deterministic with BLAS on one thread: the same
// matrix gives the same bits (CHOLMOD is asked for a single ordering).
class SparseCholesky {
 public:
  explicit SparseCholesky(Factorization kind);
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // `pattern`: n x n, compressed, the lower triangle (row >= column) stored; entries above
  // the diagonal are allowed and ignored. Returns, for each of its stored entries in storage
  // order, the index of that entry's value in the `values` Factorize takes, or -1 for an
  // entry above the diagonal.
  const std::vector<int>& AnalyzePattern(const Eigen::SparseMatrix<double>& pattern);
  // The number of values Factorize takes.
  int ValueCount() const;
  // `values`: ValueCount() entries, placed as AnalyzePattern said. False if the matrix is not
  // positive definite, `values` has another size or the analysis failed (CHOLMOD out of
  // memory); then Solve must not be called.
  bool Factorize(const Eigen::VectorXd& values);
  // x = A^-1 b for the last factorised A; b and x have n rows.
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const;

  // One implementation per Factorization, in the .cc file.
  class Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_SPARSE_CHOLESKY_H_
