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

// `matrix`'s stored values placed as `cholesky` wants them.
Eigen::VectorXd Values(SparseCholesky& cholesky, const Eigen::SparseMatrix<double>& matrix) {
  const std::vector<int>& slots = cholesky.AnalyzePattern(matrix);
  EXPECT_EQ(slots.size(), static_cast<size_t>(matrix.nonZeros()));
  Eigen::VectorXd values = Eigen::VectorXd::Zero(cholesky.ValueCount());
  for (size_t k = 0; k < slots.size(); ++k) {
    if (slots[k] >= 0) values(slots[k]) += matrix.valuePtr()[k];
  }
  return values;
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
    ASSERT_TRUE(cholesky.Factorize(Values(cholesky, a)));
    solutions.push_back(cholesky.Solve(b));
    EXPECT_LT((full * solutions.back() - b).norm(), 1e-9 * b.norm());
  }
  EXPECT_LT((solutions[0] - solutions[1]).norm(), 1e-9 * solutions[0].norm());
}

// The cloth solver's pattern stores its vertex blocks whole; the factorisation must read the
// lower triangle only, and give the entries above the diagonal no place.
TEST(SparseCholeskyTest, IgnoresEntriesAboveTheDiagonalAndRefusesAWrongValueCount) {
  const Eigen::SparseMatrix<double> lower = GridMatrix(12, 0.5);
  Eigen::SparseMatrix<double> both = lower.selfadjointView<Eigen::Lower>();
  both.makeCompressed();
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(lower.rows(), 1.0, -3.0);
  for (Factorization kind : {Factorization::kSimplicialLdlt, Factorization::kSupernodalCholmod}) {
    SparseCholesky from_lower(kind);
    ASSERT_TRUE(from_lower.Factorize(Values(from_lower, lower)));
    SparseCholesky from_both(kind);
    const std::vector<int> slots = from_both.AnalyzePattern(both);
    const Eigen::VectorXd values = Values(from_both, both);
    int ignored = 0;
    for (Eigen::Index column = 0; column < both.outerSize(); ++column) {
      for (int k = both.outerIndexPtr()[column]; k < both.outerIndexPtr()[column + 1]; ++k) {
        const bool above = both.innerIndexPtr()[k] < column;
        EXPECT_EQ(slots[k] < 0, above) << k;
        ignored += above ? 1 : 0;
      }
    }
    EXPECT_EQ(ignored, (both.nonZeros() - both.rows()) / 2);
    ASSERT_TRUE(from_both.Factorize(values));
    EXPECT_EQ(from_both.Solve(b), from_lower.Solve(b)) << static_cast<int>(kind);
    EXPECT_FALSE(from_both.Factorize(Eigen::VectorXd::Ones(from_both.ValueCount() + 1)));
  }
}

TEST(SparseCholeskyTest, ReportsAMatrixThatIsNotPositiveDefinite) {
  const Eigen::SparseMatrix<double> a = GridMatrix(10, -5.0);
  for (Factorization kind : {Factorization::kSimplicialLdlt, Factorization::kSupernodalCholmod}) {
    SparseCholesky cholesky(kind);
    EXPECT_FALSE(cholesky.Factorize(Values(cholesky, a))) << static_cast<int>(kind);
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
  ASSERT_TRUE(cholesky.Factorize(Values(cholesky, a)));
  const Eigen::VectorXd x = cholesky.Solve(Eigen::VectorXd::Ones(a.rows()));
  const Eigen::SparseMatrix<double> full = a.selfadjointView<Eigen::Lower>();
  EXPECT_LT((full * x - Eigen::VectorXd::Ones(a.rows())).norm(),
            1e-9 * std::sqrt(static_cast<double>(a.rows())));
  EXPECT_EQ(ThreadCount(), threads);
}

}  // namespace
}  // namespace fitbase::workers
