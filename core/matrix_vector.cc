#include "core/matrix_vector.h"

#include <algorithm>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define FITBASE_HAS_AVX_PATH 1
#endif

namespace fitbase::core {
namespace {

// m's column k starts at m + k * stride.
void PortableColumns(const float* m, Eigen::Index rows, Eigen::Index cols, Eigen::Index stride,
                     const float* x, float* out) {
  for (Eigen::Index k = 0; k < cols; ++k) {
    const float s = x[k];
    const float* column = m + k * stride;
    for (Eigen::Index i = 0; i < rows; ++i) out[i] = out[i] + s * column[i];
  }
}

#ifdef FITBASE_HAS_AVX_PATH
// Columns in passes of kColumnsPerPass, 32 rows at a time in four registers: a pass reads that
// many column streams (more at once defeat the hardware prefetcher on a large model) and `out`
// once. The rows past the last whole block take the portable loop. Each row still sums its
// columns in order.
constexpr Eigen::Index kColumnsPerPass = 8;

__attribute__((target("avx"))) void AvxColumns(const float* m, Eigen::Index rows,
                                               Eigen::Index cols, Eigen::Index stride,
                                               const float* x, float* out) {
  const Eigen::Index blocked = rows - rows % 32;
  for (Eigen::Index first = 0; first < cols; first += kColumnsPerPass) {
    const Eigen::Index last = std::min(cols, first + kColumnsPerPass);
    for (Eigen::Index i = 0; i < blocked; i += 32) {
      __m256 a0 = _mm256_loadu_ps(out + i);
      __m256 a1 = _mm256_loadu_ps(out + i + 8);
      __m256 a2 = _mm256_loadu_ps(out + i + 16);
      __m256 a3 = _mm256_loadu_ps(out + i + 24);
      const float* p = m + first * stride + i;
      for (Eigen::Index k = first; k < last; ++k, p += stride) {
        const __m256 s = _mm256_broadcast_ss(x + k);
        a0 = _mm256_add_ps(a0, _mm256_mul_ps(s, _mm256_loadu_ps(p)));
        a1 = _mm256_add_ps(a1, _mm256_mul_ps(s, _mm256_loadu_ps(p + 8)));
        a2 = _mm256_add_ps(a2, _mm256_mul_ps(s, _mm256_loadu_ps(p + 16)));
        a3 = _mm256_add_ps(a3, _mm256_mul_ps(s, _mm256_loadu_ps(p + 24)));
      }
      _mm256_storeu_ps(out + i, a0);
      _mm256_storeu_ps(out + i + 8, a1);
      _mm256_storeu_ps(out + i + 16, a2);
      _mm256_storeu_ps(out + i + 24, a3);
    }
  }
  PortableColumns(m + blocked, rows - blocked, cols, stride, x, out + blocked);
}
#endif

}  // namespace

bool MultiplyAccumulateUsesAvx() {
#ifdef FITBASE_HAS_AVX_PATH
  static const bool avx = __builtin_cpu_supports("avx");
  return avx;
#else
  return false;
#endif
}

void MultiplyAccumulatePortable(const Eigen::Ref<const Eigen::MatrixXf>& m,
                                const Eigen::Ref<const Eigen::VectorXf>& x,
                                Eigen::Ref<Eigen::VectorXf> out) {
  eigen_assert(m.cols() == x.size() && m.rows() == out.size());
  PortableColumns(m.data(), m.rows(), m.cols(), m.outerStride(), x.data(), out.data());
}

void MultiplyAccumulate(const Eigen::Ref<const Eigen::MatrixXf>& m,
                        const Eigen::Ref<const Eigen::VectorXf>& x,
                        Eigen::Ref<Eigen::VectorXf> out) {
  eigen_assert(m.cols() == x.size() && m.rows() == out.size());
#ifdef FITBASE_HAS_AVX_PATH
  if (MultiplyAccumulateUsesAvx()) {
    AvxColumns(m.data(), m.rows(), m.cols(), m.outerStride(), x.data(), out.data());
    return;
  }
#endif
  PortableColumns(m.data(), m.rows(), m.cols(), m.outerStride(), x.data(), out.data());
}

}  // namespace fitbase::core
