// SIMD lanes for the wide BVH's node test: the register the node test uses
// (AVX: 8 floats, else SSE: 4), which sets the node width, and the few
// operations on it. Internal: the layout depends on the compiler's flags.
#pragma once

#include <immintrin.h>

namespace glint {

// The SIMD register the node test uses, and so the node width.
#if defined(__AVX__)
inline constexpr int kBvhWidth = 8;
using FloatLanes = __m256;
inline FloatLanes lanes_set1(float v) { return _mm256_set1_ps(v); }
inline FloatLanes lanes_load(const float* p) { return _mm256_load_ps(p); }
inline void lanes_store(float* p, FloatLanes v) { _mm256_store_ps(p, v); }
inline FloatLanes lanes_sub(FloatLanes a, FloatLanes b) { return _mm256_sub_ps(a, b); }
inline FloatLanes lanes_mul(FloatLanes a, FloatLanes b) { return _mm256_mul_ps(a, b); }
inline FloatLanes lanes_max(FloatLanes a, FloatLanes b) { return _mm256_max_ps(a, b); }
inline FloatLanes lanes_min(FloatLanes a, FloatLanes b) { return _mm256_min_ps(a, b); }
inline int lanes_le_mask(FloatLanes a, FloatLanes b) { return _mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_LE_OQ)); }
// b where `select` is all ones, else a (`select` lanes are all ones or zero).
inline FloatLanes lanes_blend(FloatLanes a, FloatLanes b, FloatLanes select) { return _mm256_blendv_ps(a, b, select); }
#if defined(__FMA__)
inline FloatLanes lanes_fmsub(FloatLanes a, FloatLanes b, FloatLanes c) { return _mm256_fmsub_ps(a, b, c); }
#endif
#else
inline constexpr int kBvhWidth = 4;
using FloatLanes = __m128;
inline FloatLanes lanes_set1(float v) { return _mm_set1_ps(v); }
inline FloatLanes lanes_load(const float* p) { return _mm_load_ps(p); }
inline void lanes_store(float* p, FloatLanes v) { _mm_store_ps(p, v); }
inline FloatLanes lanes_sub(FloatLanes a, FloatLanes b) { return _mm_sub_ps(a, b); }
inline FloatLanes lanes_mul(FloatLanes a, FloatLanes b) { return _mm_mul_ps(a, b); }
inline FloatLanes lanes_max(FloatLanes a, FloatLanes b) { return _mm_max_ps(a, b); }
inline FloatLanes lanes_min(FloatLanes a, FloatLanes b) { return _mm_min_ps(a, b); }
inline int lanes_le_mask(FloatLanes a, FloatLanes b) { return _mm_movemask_ps(_mm_cmple_ps(a, b)); }
inline FloatLanes lanes_blend(FloatLanes a, FloatLanes b, FloatLanes select) {
#if defined(__SSE4_1__)
  return _mm_blendv_ps(a, b, select);
#else
  return _mm_or_ps(_mm_and_ps(select, b), _mm_andnot_ps(select, a));
#endif
}
#if defined(__FMA__)
inline FloatLanes lanes_fmsub(FloatLanes a, FloatLanes b, FloatLanes c) { return _mm_fmsub_ps(a, b, c); }
#endif
#endif

}  // namespace glint
