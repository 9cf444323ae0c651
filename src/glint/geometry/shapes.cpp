#include "glint/geometry/shapes.h"

#include <cmath>

namespace glint {

std::optional<double> intersect_plane(const Plane& p, const Ray& ray) {
  const double denom = dot(p.normal, ray.direction);
  if (denom == 0.0) return std::nullopt;
  const double t = dot(p.normal, p.point - ray.origin) / denom;
  if (t > ray.t_min && t < ray.t_max) return t;
  return std::nullopt;
}

std::optional<TriangleHit> intersect_triangle(const Triangle& tri, const Ray& ray) {
  const watertight::ShearedTriangle s = watertight::shear_triangle(tri, ray);
  // Inside when all three edge functions share a sign (zero counts as both).
  if ((s.e0 < 0 || s.e1 < 0 || s.e2 < 0) && (s.e0 > 0 || s.e1 > 0 || s.e2 > 0)) return std::nullopt;
  if (s.det == 0.0 || !std::isfinite(s.det)) return std::nullopt;  // edge-on, or degenerate
  const double inv_det = 1.0 / s.det;
  const double t = s.t_scaled * inv_det;
  if (!(t > ray.t_min && t < ray.t_max)) return std::nullopt;
  return TriangleHit{t, s.e1 * inv_det, s.e2 * inv_det};
}

std::optional<BoxHit> intersect_box(const Box& box, const Ray& ray) {
  double t_near = -kInfinity, t_far = kInfinity;
  int near_face = -1, far_face = -1;
  for (int axis = 0; axis < 3; ++axis) {
    const double o = ray.origin[axis], d = ray.direction[axis];
    if (d == 0.0) {
      if (o < box.lo[axis] || o > box.hi[axis]) return std::nullopt;
      continue;
    }
    double t0 = (box.lo[axis] - o) / d, t1 = (box.hi[axis] - o) / d;
    int f0 = 2 * axis, f1 = 2 * axis + 1;
    if (t0 > t1) {
      std::swap(t0, t1);
      std::swap(f0, f1);
    }
    if (t0 > t_near) {
      t_near = t0;
      near_face = f0;
    }
    if (t1 < t_far) {
      t_far = t1;
      far_face = f1;
    }
    if (t_near > t_far) return std::nullopt;
  }
  if (t_near > ray.t_min && t_near < ray.t_max && near_face >= 0) return BoxHit{t_near, near_face};
  if (t_far > ray.t_min && t_far < ray.t_max && far_face >= 0) return BoxHit{t_far, far_face};
  return std::nullopt;
}

namespace {

// Where a ray is inside an infinite quadric or a slab: [lo, hi], ends may be infinite.
struct Span {
  double lo, hi;
};

// The roots r1 <= r2 of a t^2 + 2 b t + c (a != 0, disc = b^2 - a c >= 0),
// each computed without cancellation.
void stable_roots(double a, double b, double c, double disc, double& r1, double& r2) {
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  r1 = q / a;
  r2 = q != 0.0 ? c / q : r1;
  if (r1 > r2) std::swap(r1, r2);
}

}  // namespace

std::optional<ConeHit> intersect_cone(const Cone& cone, const Ray& ray) {
  const Vec3& a = cone.axis;
  const double len = cone.length;
  const Vec3& d = ray.direction;
  // Solve from the ray's point nearest the shape's middle (t = t0): a far
  // origin would make the coefficients large and cancel away the digits.
  const double dd = dot(d, d);
  if (!(dd > 0.0)) return std::nullopt;
  const double t0 = dot(0.5 * (cone.base + cone.apex) - ray.origin, d) / dd;
  const Vec3 o = (ray.origin + t0 * d) - cone.base;
  // Heights along the axis and offsets across it.
  const double oa = dot(o, a), da = dot(d, a);
  const Vec3 o_r = o - oa * a, d_r = d - da * a;
  // Radius at height h: r(h) = base_radius + k h. Inside: |radial|^2 <= r(h)^2.
  const double k = (cone.apex_radius - cone.base_radius) / len;
  const double r_o = cone.base_radius + k * oa;
  const double qa = dot(d_r, d_r) - k * k * da * da;
  const double qb = dot(o_r, d_r) - k * r_o * da;
  const double qc = dot(o_r, o_r) - r_o * r_o;

  Span spans[2];
  int count = 0;
  if (qa != 0.0) {
    // For a cylinder the discriminant is qa (r^2 - |f|^2), f the axis's
    // offset from the ray line across it: no cancellation at grazing angles.
    double disc;
    if (k == 0.0) {
      const Vec3 f = o_r - (qb / qa) * d_r;
      disc = qa * (r_o * r_o - dot(f, f));
    } else {
      disc = qb * qb - qa * qc;
    }
    if (qa > 0.0) {
      if (disc < 0.0) return std::nullopt;
      double r1, r2;
      stable_roots(qa, qb, qc, disc, r1, r2);
      spans[count++] = {r1, r2};
    } else if (disc < 0.0) {  // a cone's inside all along the ray (both nappes)
      spans[count++] = {-kInfinity, kInfinity};
    } else {  // inside before the first root and after the second
      double r1, r2;
      stable_roots(qa, qb, qc, disc, r1, r2);
      spans[count++] = {-kInfinity, r1};
      spans[count++] = {r2, kInfinity};
    }
  } else if (qb != 0.0) {  // along a cone's slope: 2 qb t + qc <= 0
    const double r = -qc / (2.0 * qb);
    spans[count++] = qb > 0.0 ? Span{-kInfinity, r} : Span{r, kInfinity};
  } else if (qc <= 0.0) {
    spans[count++] = {-kInfinity, kInfinity};
  } else {
    return std::nullopt;
  }

  // The slab 0 <= h <= len, and which cap bounds each of its ends.
  Span slab{-kInfinity, kInfinity};
  int slab_lo_part = kConeBaseCap, slab_hi_part = kConeApexCap;
  if (da != 0.0) {
    const double ta = -oa / da, tb = (len - oa) / da;
    slab = da > 0.0 ? Span{ta, tb} : Span{tb, ta};
    if (da < 0.0) std::swap(slab_lo_part, slab_hi_part);
  } else if (!(oa >= 0.0 && oa <= len)) {
    return std::nullopt;
  }

  // Candidate surface points (ray parameters from t0) and their parts.
  const double t_lo = ray.t_min - t0, t_hi = ray.t_max - t0;
  std::optional<ConeHit> best;
  const auto consider = [&](double t, int part) {
    if (!std::isfinite(t) || !(t > t_lo && t < t_hi)) return;
    if (best && !(t < best->t)) return;
    best = ConeHit{t, part};
  };
  for (int i = 0; i < count; ++i) {
    const Span& s = spans[i];
    const double lo = std::max(s.lo, slab.lo), hi = std::min(s.hi, slab.hi);
    if (!(lo <= hi)) continue;
    if (cone.caps) {
      consider(lo, s.lo >= slab.lo ? kConeSide : slab_lo_part);
      consider(hi, s.hi <= slab.hi ? kConeSide : slab_hi_part);
    } else {
      if (s.lo >= slab.lo) consider(s.lo, kConeSide);
      if (s.hi <= slab.hi) consider(s.hi, kConeSide);
    }
  }
  if (!best) return std::nullopt;
  // Back to the ray's own parameter; the sum can round across an end of the
  // interval, which the caller's interval then decides.
  const double t = t0 + best->t;
  if (!(t > ray.t_min && t < ray.t_max)) return std::nullopt;
  return ConeHit{t, best->part};
}

std::optional<double> intersect_disk(const Disk& disk, const Ray& ray) {
  const double denom = dot(disk.normal, ray.direction);
  if (denom == 0.0) return std::nullopt;
  const Vec3 oc = ray.origin - disk.center;
  const double t = -dot(disk.normal, oc) / denom;
  if (!(t > ray.t_min && t < ray.t_max)) return std::nullopt;
  Vec3 q = oc + t * ray.direction;
  q -= dot(q, disk.normal) * disk.normal;  // in the plane: distances across it only
  const double r2 = dot(q, q);
  if (r2 > disk.radius * disk.radius || r2 < disk.inner_radius * disk.inner_radius) return std::nullopt;
  return t;
}

std::optional<PolygonHit> intersect_polygon(const Polygon& polygon, const Ray& ray) {
  const std::vector<Vec3>& v = polygon.vertices;
  // The plane first: most rays that reach a big polygon's box are out of
  // range there (shadow rays, occluded rays), and then none of its triangles
  // need testing. The margin leaves borderline cases to the triangle test.
  const double denom = dot(polygon.normal, ray.direction);
  const double t_plane = dot(polygon.normal, v[0] - ray.origin) / denom;
  if (std::isfinite(t_plane)) {
    const double slack = 1e-6 * std::abs(t_plane);
    if (!(t_plane >= ray.t_min - slack && t_plane <= ray.t_max + slack)) return std::nullopt;
  }
  // The triangles of a simple planar polygon do not overlap: the first hit
  // is the hit (a ray through a shared edge may find either neighbour).
  const auto test = [&](uint32_t i) -> std::optional<PolygonHit> {
    if (auto h = intersect_triangle(polygon_triangle(polygon, i), ray)) return PolygonHit{h->t, h->b1, h->b2, i};
    return std::nullopt;
  };
  if (polygon.grid && std::isfinite(t_plane)) {
    // Only the triangles near the point p where the ray meets the plane, in
    // the same order: the first hit is the same. A triangle the ray meets is
    // within `margin` of p across the plane: its vertices lie within
    // `deviation` of the plane, which the ray crosses at an angle whose
    // cosine is `cos`; and p and the triangle test round, by far less than
    // 1e-12 of the distances involved.
    const PolygonGrid& g = *polygon.grid;
    const double cos = std::abs(denom) / length(ray.direction);
    const Vec3 p = ray.origin + t_plane * ray.direction;
    const double scale = g.diagonal + length(v[0] - ray.origin) + length(p - ray.origin) +
                         max_abs_component(ray.origin) + max_abs_component(p);
    const double margin = (1.01 * g.deviation + 1e-12 * scale) / cos;
    const double pu = p[g.u], pv = p[g.v];
    if (std::isfinite(margin) && std::isfinite(pu) && std::isfinite(pv)) {
      const auto near = [&](uint32_t i) {
        const std::array<double, 4>& b = g.boxes[i];
        return pu >= b[0] - margin && pv >= b[1] - margin && pu <= b[2] + margin && pv <= b[3] + margin;
      };
      const double u0 = std::floor((pu - margin - g.lo[0]) / g.cell[0]),
                   u1 = std::floor((pu + margin - g.lo[0]) / g.cell[0]);
      const double v0 = std::floor((pv - margin - g.lo[1]) / g.cell[1]),
                   v1 = std::floor((pv + margin - g.lo[1]) / g.cell[1]);
      // Past the grid (which bounds every triangle's box): nothing to hit.
      if (u1 < 0 || v1 < 0 || u0 >= g.cells[0] || v0 >= g.cells[1]) return std::nullopt;
      if (u0 == u1 && v0 == v1) {
        const size_t c = static_cast<size_t>(u0) + static_cast<size_t>(g.cells[0]) * static_cast<size_t>(v0);
        for (uint32_t k = g.first[c]; k < g.first[c + 1]; ++k) {
          const uint32_t i = g.items[k];
          if (!near(i)) continue;
          if (auto h = test(i)) return h;
        }
        return std::nullopt;
      }
      // Near a cell's border: every triangle, boxes first.
      for (uint32_t i = 0; i < polygon.triangles.size(); ++i) {
        if (!near(i)) continue;
        if (auto h = test(i)) return h;
      }
      return std::nullopt;
    }
  }
  for (uint32_t i = 0; i < polygon.triangles.size(); ++i)
    if (auto h = test(i)) return h;
  return std::nullopt;
}

Vec3 cone_normal(const Cone& c, int part, const Vec3& p) {
  if (part == kConeBaseCap) return -c.axis;
  if (part == kConeApexCap) return c.axis;
  const Vec3 rel = p - c.base;
  const Vec3 radial = rel - dot(rel, c.axis) * c.axis;
  const double rl = length(radial);
  const Vec3 out = rl > 0.0 ? radial / rl : c.ref_u;
  return normalize(out - ((c.apex_radius - c.base_radius) / c.length) * c.axis);
}

namespace {

// Box around a disk of radius r centered at c with unit normal n: along axis
// i it reaches r * sqrt(1 - n_i^2), padded a little against rounding so the
// box never cuts the shape.
void extend_disk(Bounds3& b, const Vec3& c, const Vec3& n, double r) {
  Vec3 e;
  for (int i = 0; i < 3; ++i) e[i] = r * std::sqrt(std::max(0.0, 1.0 - n[i] * n[i])) * (1.0 + 1e-12);
  b.extend(c - e);
  b.extend(c + e);
}

}  // namespace

Bounds3 cone_bounds(const Cone& c) {
  Bounds3 b;
  extend_disk(b, c.base, c.axis, c.base_radius);
  extend_disk(b, c.apex, c.axis, c.apex_radius);
  return b;
}

Bounds3 disk_bounds(const Disk& d) {
  Bounds3 b;
  extend_disk(b, d.center, d.normal, d.radius);
  return b;
}

}  // namespace glint
