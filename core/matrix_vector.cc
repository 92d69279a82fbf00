#include "core/matrix_vector.h"

#include <algorithm>
#include <cmath>

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

// Column k's factor: x[k] times its scale, rounded once, on both paths.
void Int16Factors(const Int16Columns& m, const float* x, float* factors) {
  for (Eigen::Index k = 0; k < m.cols(); ++k) factors[k] = x[k] * m.scales[k];
}

// m's column k starts at m + k * stride.
void PortableInt16Columns(const int16_t* m, Eigen::Index rows, Eigen::Index cols,
                          Eigen::Index stride, const float* factors, float* out) {
  for (Eigen::Index k = 0; k < cols; ++k) {
    const float s = factors[k];
    const int16_t* column = m + k * stride;
    for (Eigen::Index i = 0; i < rows; ++i) out[i] = out[i] + s * static_cast<float>(column[i]);
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

// Eight entries widened to int32, then converted to float: exact, as the portable cast is.
__attribute__((target("avx2"))) inline __m256 LoadInt16(const int16_t* p) {
  return _mm256_cvtepi32_ps(
      _mm256_cvtepi16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))));
}

// AvxColumns' loop over 16-bit entries, widened to floats: half the bytes to load for one more
// conversion per 8 entries. On male_casualsuit01's basis (25,278 rows by 62 columns) it takes
// about 60 us against the floats' 76 to 83, or 60 to 66 had each float column started on a
// 32-byte boundary (25,278 rows do not give that; the 16-bit loads are 16 bytes and mind it
// less). Larger bases gain more: 14.6 MB of floats, 233 us against 164.
__attribute__((target("avx2"))) void Avx2Int16Columns(const int16_t* m, Eigen::Index rows,
                                                      Eigen::Index cols, const float* factors,
                                                      float* out) {
  const Eigen::Index blocked = rows - rows % 32;
  for (Eigen::Index first = 0; first < cols; first += kColumnsPerPass) {
    const Eigen::Index last = std::min(cols, first + kColumnsPerPass);
    for (Eigen::Index i = 0; i < blocked; i += 32) {
      __m256 a0 = _mm256_loadu_ps(out + i);
      __m256 a1 = _mm256_loadu_ps(out + i + 8);
      __m256 a2 = _mm256_loadu_ps(out + i + 16);
      __m256 a3 = _mm256_loadu_ps(out + i + 24);
      const int16_t* p = m + first * rows + i;
      for (Eigen::Index k = first; k < last; ++k, p += rows) {
        const __m256 s = _mm256_broadcast_ss(factors + k);
        a0 = _mm256_add_ps(a0, _mm256_mul_ps(s, LoadInt16(p)));
        a1 = _mm256_add_ps(a1, _mm256_mul_ps(s, LoadInt16(p + 8)));
        a2 = _mm256_add_ps(a2, _mm256_mul_ps(s, LoadInt16(p + 16)));
        a3 = _mm256_add_ps(a3, _mm256_mul_ps(s, LoadInt16(p + 24)));
      }
      _mm256_storeu_ps(out + i, a0);
      _mm256_storeu_ps(out + i + 8, a1);
      _mm256_storeu_ps(out + i + 16, a2);
      _mm256_storeu_ps(out + i + 24, a3);
    }
  }
  PortableInt16Columns(m + blocked, rows - blocked, cols, rows, factors, out + blocked);
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

bool MultiplyAccumulateInt16UsesAvx2() {
#ifdef FITBASE_HAS_AVX_PATH
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
#else
  return false;
#endif
}

Int16Columns QuantizeColumns(const Eigen::Ref<const Eigen::MatrixXf>& m) {
  eigen_assert(m.allFinite());
  Int16Columns q;
  q.values.resize(m.rows(), m.cols());
  q.scales.resize(m.cols());
  for (Eigen::Index k = 0; k < m.cols(); ++k) {
    const float largest = m.rows() > 0 ? m.col(k).cwiseAbs().maxCoeff() : 0.0f;
    const float scale = largest / 32767.0f;
    q.scales[k] = scale;
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
      // The division can round a column's largest entry a hair past 32767.
      const float steps = scale > 0 ? std::nearbyint(m(i, k) / scale) : 0.0f;
      q.values(i, k) = static_cast<int16_t>(std::clamp(steps, -32767.0f, 32767.0f));
    }
  }
  return q;
}

void MultiplyAccumulatePortable(const Int16Columns& m, const Eigen::Ref<const Eigen::VectorXf>& x,
                                Eigen::Ref<Eigen::VectorXf> out) {
  eigen_assert(m.cols() == x.size() && m.rows() == out.size());
  Eigen::VectorXf factors(m.cols());
  Int16Factors(m, x.data(), factors.data());
  PortableInt16Columns(m.values.data(), m.rows(), m.cols(), m.rows(), factors.data(), out.data());
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
#ifdef FITBASE_HAS_AVX_PATH
  if (MultiplyAccumulateInt16UsesAvx2()) {
    Avx2Int16Columns(m.values.data(), m.rows(), m.cols(), factors, out.data());
    return;
  }
#endif
  PortableInt16Columns(m.values.data(), m.rows(), m.cols(), m.rows(), factors, out.data());
}

}  // namespace fitbase::core
