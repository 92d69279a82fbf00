#include "core/matrix_vector.h"

#include <algorithm>
#include <cmath>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define FITBASE_HAS_AVX2_PATH 1
#endif

namespace fitbase::core {
namespace {

// m's column k starts at m + k * stride; factors[k] is column k's coefficient. Every row sums
// the columns in order, each product and sum rounded on its own.
template <typename Entry>
void PortableColumns(const Entry* m, Eigen::Index rows, Eigen::Index cols, Eigen::Index stride,
                     const float* factors, float* out) {
  for (Eigen::Index k = 0; k < cols; ++k) {
    const float s = factors[k];
    const Entry* column = m + k * stride;
    for (Eigen::Index i = 0; i < rows; ++i) out[i] = out[i] + s * static_cast<float>(column[i]);
  }
}

// Column k's factor: x[k] times its scale, rounded once, on both paths.
void Int16Factors(const Int16Columns& m, const float* x, float* factors) {
  for (Eigen::Index k = 0; k < m.cols(); ++k) factors[k] = x[k] * m.scales[k];
}

#ifdef FITBASE_HAS_AVX2_PATH
// Columns in passes of kColumnsPerPass, 32 rows at a time in four registers: a pass reads that
// many column streams (more at once defeat the hardware prefetcher on a large model) and `out`
// once. The rows past the last whole block take the portable loop. Each row still sums its
// columns in order.
constexpr Eigen::Index kColumnsPerPass = 8;

__attribute__((target("avx2"))) inline __m256 LoadEight(const float* p) {
  return _mm256_loadu_ps(p);
}

// Widened to int32, then converted to float: exact, as the portable cast is. Half the bytes to
// load for one more conversion per 8 entries. On male_casualsuit01's basis (25,278 rows by 62
// columns) the product takes about 60 us against the floats' 76 to 83, or 60 to 66 had each
// float column started on a 32-byte boundary (25,278 rows do not give that; the 16-byte loads
// mind it less). Larger bases gain more: 14.6 MB of floats, 233 us against 164. Without AVX2
// (two SSE4.1 widenings and an insert) it took 98 us.
__attribute__((target("avx2"))) inline __m256 LoadEight(const int16_t* p) {
  return _mm256_cvtepi32_ps(
      _mm256_cvtepi16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))));
}

template <typename Entry>
__attribute__((target("avx2"))) void Avx2Columns(const Entry* m, Eigen::Index rows,
                                                 Eigen::Index cols, Eigen::Index stride,
                                                 const float* factors, float* out) {
  const Eigen::Index blocked = rows - rows % 32;
  for (Eigen::Index first = 0; first < cols; first += kColumnsPerPass) {
    const Eigen::Index last = std::min(cols, first + kColumnsPerPass);
    for (Eigen::Index i = 0; i < blocked; i += 32) {
      __m256 a0 = _mm256_loadu_ps(out + i);
      __m256 a1 = _mm256_loadu_ps(out + i + 8);
      __m256 a2 = _mm256_loadu_ps(out + i + 16);
      __m256 a3 = _mm256_loadu_ps(out + i + 24);
      const Entry* p = m + first * stride + i;
      for (Eigen::Index k = first; k < last; ++k, p += stride) {
        const __m256 s = _mm256_broadcast_ss(factors + k);
        a0 = _mm256_add_ps(a0, _mm256_mul_ps(s, LoadEight(p)));
        a1 = _mm256_add_ps(a1, _mm256_mul_ps(s, LoadEight(p + 8)));
        a2 = _mm256_add_ps(a2, _mm256_mul_ps(s, LoadEight(p + 16)));
        a3 = _mm256_add_ps(a3, _mm256_mul_ps(s, LoadEight(p + 24)));
      }
      _mm256_storeu_ps(out + i, a0);
      _mm256_storeu_ps(out + i + 8, a1);
      _mm256_storeu_ps(out + i + 16, a2);
      _mm256_storeu_ps(out + i + 24, a3);
    }
  }
  PortableColumns(m + blocked, rows - blocked, cols, stride, factors, out + blocked);
}
#endif

// The product on this CPU's best path.
template <typename Entry>
void Columns(const Entry* m, Eigen::Index rows, Eigen::Index cols, Eigen::Index stride,
             const float* factors, float* out) {
#ifdef FITBASE_HAS_AVX2_PATH
  if (MultiplyAccumulateUsesAvx2()) {
    Avx2Columns(m, rows, cols, stride, factors, out);
    return;
  }
#endif
  PortableColumns(m, rows, cols, stride, factors, out);
}

}  // namespace

bool MultiplyAccumulateUsesAvx2() {
#ifdef FITBASE_HAS_AVX2_PATH
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
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
  Columns(m.data(), m.rows(), m.cols(), m.outerStride(), x.data(), out.data());
}

Int16Columns QuantizeColumns(const Eigen::Ref<const Eigen::MatrixXf>& m) {
  eigen_assert(m.allFinite());
  Int16Columns q;
  q.values.resize(m.rows(), m.cols());
  q.scales.resize(m.cols());
  for (Eigen::Index k = 0; k < m.cols(); ++k) {
    const float largest = m.rows() > 0 ? m.col(k).cwiseAbs().maxCoeff() : 0.0f;
    // Multiplied, not divided, and rounded half away from zero without a library call or a
    // branch (with them, 3.1 ms of male_casualsuit01's 10 ms load). A column under
    // 32767 / FLT_MAX in magnitude (1e-34) has no finite inverse and is taken as zero.
    const float inverse = largest > 0 ? 32767.0f / largest : 0.0f;
    const float factor = std::isfinite(inverse) ? inverse : 0.0f;
    q.scales[k] = factor > 0 ? largest / 32767.0f : 0.0f;
    const auto column = m.col(k);
    int16_t* values = q.values.col(k).data();
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
      const float steps = column[i] * factor;
      // The product can round a column's largest entry a hair past 32767. Branch-free: the
      // signs of a column's entries follow no pattern a branch predictor could learn.
      const float rounded =
          std::min(std::max(steps + std::copysign(0.5f, steps), -32767.0f), 32767.0f);
      values[i] = static_cast<int16_t>(rounded);
    }
  }
  return q;
}

void MultiplyAccumulatePortable(const Int16Columns& m, const Eigen::Ref<const Eigen::VectorXf>& x,
                                Eigen::Ref<Eigen::VectorXf> out) {
  eigen_assert(m.cols() == x.size() && m.rows() == out.size());
  Eigen::VectorXf factors(m.cols());
  Int16Factors(m, x.data(), factors.data());
  PortableColumns(m.values.data(), m.rows(), m.cols(), m.rows(), factors.data(), out.data());
}

void MultiplyAccumulate(const Int16Columns& m, const Eigen::Ref<const Eigen::VectorXf>& x,
                        Eigen::Ref<Eigen::VectorXf> out) {
  eigen_assert(m.cols() == x.size() && m.rows() == out.size());
  // A fit's columns number tens; the stack keeps the product free of allocation.
  constexpr Eigen::Index kStackFactors = 256;
  float stack[kStackFactors];
  Eigen::VectorXf heap;
  float* factors = stack;
  if (m.cols() > kStackFactors) {
    heap.resize(m.cols());
    factors = heap.data();
  }
  Int16Factors(m, x.data(), factors);
  Columns(m.values.data(), m.rows(), m.cols(), m.rows(), factors, out.data());
}

}  // namespace fitbase::core
