// TriangleLeaf: up to four untransformed triangles of one leaf of the
// top-level BVH (triangle objects, and polygons of one triangle), whose
// watertight edge tests run four at a time in double (AVX). Internal.
#pragma once

#include <immintrin.h>

#include <cmath>
#include <cstdint>

#include "glint/geometry/triangle_shear.h"
#include "glint/math/ray.h"

namespace glint {

// Up to four untransformed triangles of one BVH leaf (triangle objects, and
// polygons of one triangle), by vertex and coordinate, for the watertight
// test's edge functions of all of them at once (TriangleLeaf::maybe_hit).
struct alignas(32) TriangleLeaf {
  double v[3][3][4];  // [vertex][axis][lane]
  uint32_t count = 0;

  // Bit i set unless intersect_triangle on triangle i would stop at its
  // edge functions' signs: watertight::shear_triangle_in's operations in the
  // same order, four lanes at a time, so the same decision (a zero edge
  // function, which it recomputes in long double, is left to it).
  int maybe_hit(const Ray& ray) const {
    const int lanes = (1 << count) - 1;
#if defined(__AVX__)
    const Vec3& d = ray.direction;
    const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    if (ax > ay) return lanes & (ax > az ? inside<0>(ray) : inside<2>(ray));
    return lanes & (ay > az ? inside<1>(ray) : inside<2>(ray));
#else
    (void)ray;
    return lanes;
#endif
  }

 private:
#if defined(__AVX__)
  template <int kz>
  int inside(const Ray& ray) const {
    using A = watertight::ShearAxes<kz>;
    const Vec3& d = ray.direction;
    const double sz = 1.0 / A::z(d), sx = -A::x(d) * sz, sy = -A::y(d) * sz;
    const __m256d vsx = _mm256_set1_pd(sx), vsy = _mm256_set1_pd(sy);
    __m256d x2[3], y2[3];
    for (int j = 0; j < 3; ++j) {
      const __m256d px = _mm256_sub_pd(_mm256_load_pd(v[j][A::kx]), _mm256_set1_pd(A::x(ray.origin)));
      const __m256d py = _mm256_sub_pd(_mm256_load_pd(v[j][A::ky]), _mm256_set1_pd(A::y(ray.origin)));
      const __m256d pz = _mm256_sub_pd(_mm256_load_pd(v[j][kz]), _mm256_set1_pd(A::z(ray.origin)));
      x2[j] = _mm256_add_pd(px, _mm256_mul_pd(vsx, pz));
      y2[j] = _mm256_add_pd(py, _mm256_mul_pd(vsy, pz));
    }
    const __m256d e0 = _mm256_sub_pd(_mm256_mul_pd(x2[1], y2[2]), _mm256_mul_pd(y2[1], x2[2]));
    const __m256d e1 = _mm256_sub_pd(_mm256_mul_pd(x2[2], y2[0]), _mm256_mul_pd(y2[2], x2[0]));
    const __m256d e2 = _mm256_sub_pd(_mm256_mul_pd(x2[0], y2[1]), _mm256_mul_pd(y2[0], x2[1]));
    const __m256d zero = _mm256_setzero_pd();
    const auto any = [&](int predicate_lt) {
      const __m256d a = predicate_lt ? _mm256_cmp_pd(e0, zero, _CMP_LT_OQ) : _mm256_cmp_pd(e0, zero, _CMP_GT_OQ);
      const __m256d b = predicate_lt ? _mm256_cmp_pd(e1, zero, _CMP_LT_OQ) : _mm256_cmp_pd(e1, zero, _CMP_GT_OQ);
      const __m256d c = predicate_lt ? _mm256_cmp_pd(e2, zero, _CMP_LT_OQ) : _mm256_cmp_pd(e2, zero, _CMP_GT_OQ);
      return _mm256_movemask_pd(_mm256_or_pd(_mm256_or_pd(a, b), c));
    };
    const int zeros = _mm256_movemask_pd(
        _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(e0, zero, _CMP_EQ_OQ), _mm256_cmp_pd(e1, zero, _CMP_EQ_OQ)),
                     _mm256_cmp_pd(e2, zero, _CMP_EQ_OQ)));
    const int outside = any(1) & any(0) & ~zeros;
    return ~outside;
  }
#endif
};

}  // namespace glint
