#ifndef FITBASE_CORE_MATRIX_VECTOR_H_
#define FITBASE_CORE_MATRIX_VECTOR_H_

#include "Eigen/Core"

namespace fitbase::core {

// out (R) += m (R x C, column-major) * x (C). Each row is summed over the columns in order,
// each product and each sum rounded on its own (no fused multiply-add), so the result is the
// same bytes on every x86-64 CPU, while a CPU with AVX computes 8 rows at a time (runtime
// dispatch: the online fit is this product over the whole garment, and the portable build's
// 4-wide SSE2 takes twice as long). Shapes are the caller's contract (checked in debug builds).
void MultiplyAccumulate(const Eigen::Ref<const Eigen::MatrixXf>& m,
                        const Eigen::Ref<const Eigen::VectorXf>& x, Eigen::Ref<Eigen::VectorXf> out);

// The same sums without AVX, whatever the CPU: the reference the dispatched product is tested
// and benchmarked against.
void MultiplyAccumulatePortable(const Eigen::Ref<const Eigen::MatrixXf>& m,
                                const Eigen::Ref<const Eigen::VectorXf>& x,
                                Eigen::Ref<Eigen::VectorXf> out);

// Whether MultiplyAccumulate takes the AVX path on this CPU.
bool MultiplyAccumulateUsesAvx();

}  // namespace fitbase::core

#endif  // FITBASE_CORE_MATRIX_VECTOR_H_
