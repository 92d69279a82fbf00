#include "core/matrix_vector.h"

#include <cmath>
#include <cstring>

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

// The promise that lets replicas on different CPUs serve the same bytes: the vector path and
// the portable one round alike, on values whose sums do round.
TEST(MatrixVectorTest, GivesThePortableBytesOnThisCpu) {
  for (const Eigen::Index rows : {1, 31, 32, 33, 3 * 2197}) {
    const Eigen::MatrixXf m = Eigen::MatrixXf::Random(rows, 49);
    const Eigen::VectorXf x = Eigen::VectorXf::Random(49) * 1e-2f;
    const Eigen::VectorXf start = Eigen::VectorXf::Random(rows);
    Eigen::VectorXf fast = start;
    Eigen::VectorXf portable = start;
    MultiplyAccumulate(m, x, fast);
    MultiplyAccumulatePortable(m, x, portable);
    EXPECT_EQ(0, std::memcmp(fast.data(), portable.data(), sizeof(float) * rows))
        << rows << " rows, AVX path " << MultiplyAccumulateUsesAvx();
    EXPECT_LT((fast - (start + m * x)).cwiseAbs().maxCoeff(), 1e-5f) << rows;
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
  EXPECT_EQ(q.scales[2], 0.0f);
  EXPECT_EQ(q.values(7, 3), -32767);
  EXPECT_EQ(q.bytes(), 2 * 100 * 4 + 4 * 4u);
  for (Eigen::Index k = 0; k < 4; ++k) {
    const float largest = m.col(k).cwiseAbs().maxCoeff();
    EXPECT_FLOAT_EQ(q.scales[k], largest / 32767.0f) << k;
    for (Eigen::Index i = 0; i < 100; ++i) {
      const float value = static_cast<float>(q.values(i, k)) * q.scales[k];
      EXPECT_LE(std::abs(value - m(i, k)), 0.5f * q.scales[k] * (1 + 1e-5f) + 1e-12f)
          << i << ", " << k;
    }
  }
}

// The 16-bit product on this CPU against the portable one: the same bytes, and the sums of the
// entries as quantized.
TEST(MatrixVectorTest, GivesThePortableBytesFromSixteenBits) {
  for (const Eigen::Index rows : {1, 31, 32, 33, 3 * 2197}) {
    const Int16Columns q = QuantizeColumns(Eigen::MatrixXf::Random(rows, 61) * 0.05f);
    const Eigen::VectorXf x = Eigen::VectorXf::Random(61) * 3.0f;
    const Eigen::VectorXf start = Eigen::VectorXf::Random(rows);
    Eigen::VectorXf fast = start;
    Eigen::VectorXf portable = start;
    MultiplyAccumulate(q, x, fast);
    MultiplyAccumulatePortable(q, x, portable);
    EXPECT_EQ(0, std::memcmp(fast.data(), portable.data(), sizeof(float) * rows))
        << rows << " rows, AVX2 path " << MultiplyAccumulateInt16UsesAvx2();
    const Eigen::MatrixXf entries = q.values.cast<float>() * q.scales.asDiagonal();
    EXPECT_LT((fast - (start + entries * x)).cwiseAbs().maxCoeff(), 1e-5f) << rows;
  }
}

}  // namespace
}  // namespace fitbase::core
