#include "core/matrix_vector.h"

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

}  // namespace
}  // namespace fitbase::core
