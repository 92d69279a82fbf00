#include "core/matrix_vector.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

// Rows that fill whole 32-row blocks and a remainder, as a garment's 3V coordinates do.
TEST(MatrixVectorTest, AddsTheProductToWhatTheOutputHolds) {
  const Eigen::Index rows = 3 * 35;
  Eigen::MatrixXf m(rows, 3);
  for (Eigen::Index i = 0; i < rows; ++i) m.row(i) << 1.0f, static_cast<float>(i), -0.5f;
  const Eigen::Vector3f x(2.0f, 0.25f, 4.0f);
  Eigen::VectorXf out = Eigen::VectorXf::Constant(rows, 10.0f);
  MultiplyAccumulate(m, x, out);
  for (Eigen::Index i = 0; i < rows; ++i) {
    EXPECT_FLOAT_EQ(out(i), 10.0f + 2.0f + 0.25f * static_cast<float>(i) - 2.0f) << i;
  }
}

// Both products of `matrix` (floats or Int16Columns, whose entries as floats are `entries`)
// from the same start: the dispatched path's bytes against the portable one's, and their sums
// against Eigen's.
template <typename Matrix>
void ExpectThePortableBytes(const Matrix& matrix, const Eigen::MatrixXf& entries,
                            const Eigen::VectorXf& x) {
  const Eigen::Index rows = entries.rows();
  const Eigen::VectorXf start = Eigen::VectorXf::Random(rows);
  Eigen::VectorXf fast = start;
  Eigen::VectorXf portable = start;
  MultiplyAccumulate(matrix, x, fast);
  MultiplyAccumulatePortable(matrix, x, portable);
  EXPECT_EQ(0, std::memcmp(fast.data(), portable.data(), sizeof(float) * rows))
      << rows << " rows, AVX2 path " << MultiplyAccumulateUsesAvx2();
  EXPECT_LT((fast - (start + entries * x)).cwiseAbs().maxCoeff(), 1e-5f) << rows;
}

// A column too small for its inverse to be finite is zero, not infinite steps.
TEST(MatrixVectorTest, QuantizesAColumnBelowAnyScaleToZero) {
  Eigen::MatrixXf m = Eigen::MatrixXf::Random(10, 2);
  m.col(1) *= 1e-38f;
  const Int16Columns q = QuantizeColumns(m);
  EXPECT_EQ(q.scales[1], 0.0f);
  EXPECT_EQ(q.values.col(1).cwiseAbs().maxCoeff(), 0);
  EXPECT_GT(q.scales[0], 0.0f);
}

// The promise that lets replicas on different CPUs serve the same bytes: the vector path and
// the portable one round alike, on values whose sums do round, over floats and 16 bits.
TEST(MatrixVectorTest, GivesThePortableBytesOnThisCpu) {
  for (const Eigen::Index rows : {1, 31, 32, 33, 3 * 2197}) {
    const Eigen::MatrixXf m = Eigen::MatrixXf::Random(rows, 49);
    ExpectThePortableBytes(m, m, Eigen::VectorXf::Random(49) * 1e-2f);
    const Int16Columns q = QuantizeColumns(Eigen::MatrixXf::Random(rows, 61) * 0.05f);
    const Eigen::MatrixXf entries = q.values.cast<float>() * q.scales.asDiagonal();
    ExpectThePortableBytes(q, entries, Eigen::VectorXf::Random(61) * 3.0f);
  }
}

// A block of a larger matrix keeps its column stride.
TEST(MatrixVectorTest, ReadsABlockWithItsColumnStride) {
  const Eigen::MatrixXf big = Eigen::MatrixXf::Random(80, 6);
  const Eigen::VectorXf x = Eigen::VectorXf::Random(4);
  Eigen::VectorXf out = Eigen::VectorXf::Zero(40);
  MultiplyAccumulate(big.block(10, 1, 40, 4), x, out);
  EXPECT_LT((out - big.block(10, 1, 40, 4) * x).cwiseAbs().maxCoeff(), 1e-6f);
}

// Each entry within half a step of its column's scale, the largest magnitude of each column
// kept exactly, and a column of zeros with no scale to divide by.
TEST(MatrixVectorTest, QuantizesEachColumnWithinHalfAStep) {
  Eigen::MatrixXf m = Eigen::MatrixXf::Random(100, 4);
  m.col(1) *= 1e-4f;
  m.col(2).setZero();
  m(7, 3) = -3.0f;
  const Int16Columns q = QuantizeColumns(m);
  ASSERT_EQ(q.rows(), 100);
  ASSERT_EQ(q.cols(), 4);
  EXPECT_EQ(q.values.col(2).cwiseAbs().maxCoeff(), 0);
  EXPECT_EQ(q.scales[2], 0.0f);
  EXPECT_EQ(q.values(7, 3), -32767);
  EXPECT_EQ(q.bytes(), 2 * 100 * 4 + 4 * 4u);
  for (Eigen::Index k = 0; k < 4; ++k) {
    const float largest = m.col(k).cwiseAbs().maxCoeff();
    EXPECT_FLOAT_EQ(q.scales[k], largest / 32767.0f) << k;
    for (Eigen::Index i = 0; i < 100; ++i) {
      const float value = static_cast<float>(q.values(i, k)) * q.scales[k];
      // Half a step, and the float roundings of the division and of the product back.
      const float rounding = 4 * std::numeric_limits<float>::epsilon() * largest;
      EXPECT_LE(std::abs(value - m(i, k)), 0.5f * q.scales[k] + rounding) << i << ", " << k;
    }
  }
}

}  // namespace
}  // namespace fitbase::core
