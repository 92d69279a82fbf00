#ifndef FITBASE_CORE_MATRIX_VECTOR_H_
#define FITBASE_CORE_MATRIX_VECTOR_H_

#include <cstddef>
#include <cstdint>

#include "Eigen/Core"

namespace fitbase::core {

// out (R) += m (R x C, column-major) * x (C). Each row is summed over the columns in order,
// each product and each sum rounded on its own (no fused multiply-add), so the result is the
// same bytes on every x86-64 CPU, while a CPU with AVX2 computes 8 rows at a time (runtime
// dispatch: the online fit is this product over the whole garment, and the portable build's
// 4-wide SSE2 takes twice as long). Shapes are the caller's contract (checked in debug builds).
void MultiplyAccumulate(const Eigen::Ref<const Eigen::MatrixXf>& m,
                        const Eigen::Ref<const Eigen::VectorXf>& x, Eigen::Ref<Eigen::VectorXf> out);

// The same sums without AVX2, whatever the CPU: the reference the dispatched product is
// tested and benchmarked against.
void MultiplyAccumulatePortable(const Eigen::Ref<const Eigen::MatrixXf>& m,
                                const Eigen::Ref<const Eigen::VectorXf>& x,
                                Eigen::Ref<Eigen::VectorXf> out);

// Whether MultiplyAccumulate, over floats or 16 bits, takes the AVX2 path on this CPU.
bool MultiplyAccumulateUsesAvx2();

// An R x C matrix in 16 bits per entry: entry (i, k) stands for values(i, k) * scales[k], with
// scales[k] = max_i |m(i, k)| / 32767 of the matrix it was made from, so that it is within
// scales[k] / 2 of it: 1/65534 of the largest magnitude in its column. Half the bytes of
// floats, which is what a product that streams the matrix once per call waits for (the
// online fit, where 8.4k vertices times 62 columns are 6.3 MB as floats).
struct Int16Columns {
  Eigen::Matrix<int16_t, Eigen::Dynamic, Eigen::Dynamic> values;  // R x C, column-major.
  Eigen::VectorXf scales;                                         // C.
  Eigen::Index rows() const { return values.rows(); }
  Eigen::Index cols() const { return values.cols(); }
  size_t bytes() const {
    return sizeof(int16_t) * static_cast<size_t>(values.size()) +
           sizeof(float) * static_cast<size_t>(scales.size());
  }
};

// m: R x C, every entry finite (the caller's contract, checked in debug builds). Each entry
// rounds to the nearest step of its column's scale. A column under 32767 / FLT_MAX (about
// 1e-34) in magnitude, an all-zero one included, has scale 0 and zero entries.
Int16Columns QuantizeColumns(const Eigen::Ref<const Eigen::MatrixXf>& m);

// out (R) += m * x (C), m as its Int16Columns entries stand for. Each column's factor is
// x[k] * scales[k], rounded once, then each row summed over the columns in order with every
// product and sum rounded on its own, as the float product: the same bytes on every x86-64 CPU,
// 32 rows at a time where the CPU has AVX2.
void MultiplyAccumulate(const Int16Columns& m, const Eigen::Ref<const Eigen::VectorXf>& x,
                        Eigen::Ref<Eigen::VectorXf> out);

// The same sums without AVX2, whatever the CPU.
void MultiplyAccumulatePortable(const Int16Columns& m, const Eigen::Ref<const Eigen::VectorXf>& x,
                                Eigen::Ref<Eigen::VectorXf> out);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_MATRIX_VECTOR_H_
