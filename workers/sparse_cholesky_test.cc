#include "workers/sparse_cholesky.h"

#include <dlfcn.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "Eigen/SparseCore"
#include "gtest/gtest.h"

extern "C" void GOMP_parallel(void (*body)(void*), void* data, unsigned num_threads,
                              unsigned flags);

namespace fitbase::workers {
namespace {

// A grid Laplacian plus `diagonal` on a side x side grid, the lower triangle stored: positive
// definite for diagonal > 0.
Eigen::SparseMatrix<double> GridMatrix(int side, double diagonal) {
  std::vector<Eigen::Triplet<double>> entries;
  auto index = [side](int i, int j) { return i * side + j; };
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      const int k = index(i, j);
      entries.emplace_back(k, k, 4.0 + diagonal);
      if (i > 0) entries.emplace_back(k, index(i - 1, j), -1.0);
      if (j > 0) entries.emplace_back(k, index(i, j - 1), -1.0);
    }
  }
  Eigen::SparseMatrix<double> matrix(side * side, side * side);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

int ThreadCount() {
  int count = 0;
  for ([[maybe_unused]] const auto& task :
       std::filesystem::directory_iterator("/proc/self/task")) {
    ++count;
  }
  return count;
}

TEST(SparseCholeskyTest, BothFactorizationsSolveTheSameSystem) {
  const Eigen::SparseMatrix<double> a = GridMatrix(30, 0.01);
  const Eigen::SparseMatrix<double> full = a.selfadjointView<Eigen::Lower>();
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  std::vector<Eigen::VectorXd> solutions;
  for (Factorization kind : {Factorization::kSimplicialLdlt, Factorization::kSupernodalCholmod}) {
    SparseCholesky cholesky(kind);
    cholesky.AnalyzePattern(a);
    ASSERT_TRUE(cholesky.Factorize(a));
    solutions.push_back(cholesky.Solve(b));
    EXPECT_LT((full * solutions.back() - b).norm(), 1e-9 * b.norm());
  }
  EXPECT_LT((solutions[0] - solutions[1]).norm(), 1e-9 * solutions[0].norm());
}

TEST(SparseCholeskyTest, ReportsAMatrixThatIsNotPositiveDefinite) {
  const Eigen::SparseMatrix<double> a = GridMatrix(10, -5.0);
  for (Factorization kind : {Factorization::kSimplicialLdlt, Factorization::kSupernodalCholmod}) {
    SparseCholesky cholesky(kind);
    cholesky.AnalyzePattern(a);
    EXPECT_FALSE(cholesky.Factorize(a)) << static_cast<int>(kind);
  }
}

TEST(SparseCholeskyTest, CholmodsParallelRegionsRunOnTheCallingThread) {
  // The process's GOMP_parallel is ours, so libcholmod's calls bind to it, not to libgomp's.
  EXPECT_EQ(dlsym(RTLD_DEFAULT, "GOMP_parallel"), reinterpret_cast<void*>(&GOMP_parallel));
  const int threads = ThreadCount();
  // Large enough that libgomp, had it run CHOLMOD's regions, would have started its threads
  // (2 threads before, 5 after, measured with the definition taken out).
  const Eigen::SparseMatrix<double> a = GridMatrix(150, 0.01);
  SparseCholesky cholesky(Factorization::kSupernodalCholmod);
  cholesky.AnalyzePattern(a);
  ASSERT_TRUE(cholesky.Factorize(a));
  const Eigen::VectorXd x = cholesky.Solve(Eigen::VectorXd::Ones(a.rows()));
  const Eigen::SparseMatrix<double> full = a.selfadjointView<Eigen::Lower>();
  EXPECT_LT((full * x - Eigen::VectorXd::Ones(a.rows())).norm(),
            1e-9 * std::sqrt(static_cast<double>(a.rows())));
  EXPECT_EQ(ThreadCount(), threads);
}

}  // namespace
}  // namespace fitbase::workers
