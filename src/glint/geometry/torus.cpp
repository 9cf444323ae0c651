#include "glint/geometry/torus.h"

#include <algorithm>
#include <cmath>

namespace glint {

namespace {

// The torus along the ray as f(s) = A(s)^2 - B(s), s the distance (unit
// direction) from the point of the line nearest the center: A = |q|^2 + R^2
// - r^2 and B = 4 R^2 |q across the axis|^2 are quadratics in s, evaluated as
// they are (no expanded quartic): f keeps its precision near the roots.
struct TorusLine {
  double a2, a1, a0;  // A(s) = a2 s^2 + a1 s + a0 (a2 = 1)
  double b2, b1, b0;  // B(s)
  double f(double s) const {
    const double a = (a2 * s + a1) * s + a0;
    return a * a - ((b2 * s + b1) * s + b0);
  }
  double df(double s) const {
    const double a = (a2 * s + a1) * s + a0;
    return 2.0 * a * (2.0 * a2 * s + a1) - (2.0 * b2 * s + b1);
  }
  // f's expanded coefficients, for the derivatives' roots only.
  void expanded(double c[5]) const {
    c[4] = a2 * a2;
    c[3] = 2 * a2 * a1;
    c[2] = a1 * a1 + 2 * a2 * a0 - b2;
    c[1] = 2 * a1 * a0 - b1;
    c[0] = a0 * a0 - b0;
  }
};

// The root of g in [lo, hi], where g(lo) and g(hi) differ in sign: Newton
// steps kept inside the shrinking bracket, bisection when a step leaves it;
// done when a step moves less than `tol`.
// g_lo and g_hi are g's values at the ends: the first guess is where the
// chord between them crosses zero.
template <class G, class DG>
double bracketed_root(double lo, double hi, double g_lo, double g_hi, double tol, G g, DG dg) {
  const bool lo_negative = g_lo < 0.0;
  double s = lo + (hi - lo) * (g_lo / (g_lo - g_hi));
  if (!(s > lo && s < hi)) s = 0.5 * (lo + hi);
  for (int i = 0; i < 64; ++i) {
    const double gs = g(s);
    if (gs == 0.0) return s;
    ((gs < 0.0) == lo_negative ? lo : hi) = s;
    const double d = dg(s);
    double next = d != 0.0 ? s - gs / d : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - s) <= tol || hi - lo <= tol) return next;
    s = next;
  }
  return s;
}

// The quartic c[0..4] (c[4] = 1) cut into pieces over (lo, hi) on which it
// is monotone: the cuts are the sign changes of its derivative, whose own
// monotone pieces lie between the roots of the second derivative (a
// quadratic, solved in closed form). Returns the number of cuts written
// (lo and hi included).
int monotone_cuts(const double c[5], double lo, double hi, double tol, double* cuts) {
  const double d1[4] = {c[1], 2 * c[2], 3 * c[3], 4 * c[4]};  // f'
  const double d2[3] = {d1[1], 2 * d1[2], 3 * d1[3]};          // f''
  double pieces[4];
  int np = 0;
  pieces[np++] = lo;
  const double disc = d2[1] * d2[1] - 4 * d2[2] * d2[0];
  if (disc > 0.0) {
    const double q = -0.5 * (d2[1] + std::copysign(std::sqrt(disc), d2[1]));
    double r0 = q / d2[2], r1 = q != 0.0 ? d2[0] / q : r0;
    if (r0 > r1) std::swap(r0, r1);
    if (r0 > lo && r0 < hi) pieces[np++] = r0;
    if (r1 > lo && r1 < hi && r1 > r0) pieces[np++] = r1;
  }
  pieces[np++] = hi;
  const auto g = [&](double s) { return ((d1[3] * s + d1[2]) * s + d1[1]) * s + d1[0]; };
  const auto dg = [&](double s) { return (d2[2] * s + d2[1]) * s + d2[0]; };
  int n = 0;
  cuts[n++] = lo;
  for (int k = 0; k + 1 < np; ++k) {
    const double ga = g(pieces[k]), gb = g(pieces[k + 1]);
    if ((ga < 0.0) != (gb < 0.0)) cuts[n++] = bracketed_root(pieces[k], pieces[k + 1], ga, gb, tol, g, dg);
  }
  cuts[n++] = hi;
  return n;
}

}  // namespace

int torus_crossings(const Torus& torus, const Ray& ray, double t[4]) {
  const double len = length(ray.direction);
  if (!(len > 0.0) || !std::isfinite(len)) return 0;
  const Vec3 d = ray.direction / len;
  const Vec3 o = ray.origin - torus.center;
  const double R = torus.major_radius, r = torus.minor_radius, bound = R + r;
  // The line's nearest point to the center; a line that passes the
  // bounding sphere by misses.
  const double sc = -dot(o, d);
  const Vec3 p = o + sc * d;
  const double pp = dot(p, p);
  if (!(pp < bound * bound)) return 0;
  const double pb = dot(p, d);  // ~0, kept for exactness
  const double pa = dot(p, torus.axis), da = dot(d, torus.axis);
  const double four_r2 = 4.0 * R * R;
  TorusLine line{1.0, 2.0 * pb, pp + R * R - r * r,
                 four_r2 * (1.0 - da * da), four_r2 * 2.0 * (pb - pa * da), four_r2 * (pp - pa * pa)};
  // Every root lies inside the bounding sphere (|s| < half its chord) and
  // in the slab |q.axis| <= r.
  const double slack = 1e-9 * bound;
  const double half_chord = std::sqrt(bound * bound - pp) + slack;
  double lo = -half_chord, hi = half_chord;
  if (std::abs(da) > 1e-12) {
    double s0 = (-r - pa) / da, s1 = (r - pa) / da;
    if (s0 > s1) std::swap(s0, s1);
    lo = std::max(lo, s0 - slack);
    hi = std::min(hi, s1 + slack);
    if (!(lo < hi)) return 0;
  } else if (std::abs(pa) > r) {
    return 0;
  }
  double c[5];
  line.expanded(c);
  // The quartic's critical points split [lo, hi] into monotone pieces; the
  // root of each piece whose ends differ in sign is polished on f written
  // as A^2 - B.
  double cuts[5];
  const int n = monotone_cuts(c, lo, hi, 1e-8 * bound, cuts);
  const auto f = [&](double s) { return line.f(s); };
  const auto df = [&](double s) { return line.df(s); };
  int count = 0;
  double f_prev = f(cuts[0]);
  for (int k = 0; k + 1 < n && count < 4; ++k) {
    const double f_next = f(cuts[k + 1]);
    if ((f_prev < 0.0) != (f_next < 0.0))
      t[count++] = (sc + bracketed_root(cuts[k], cuts[k + 1], f_prev, f_next, 1e-15 * bound, f, df)) / len;
    f_prev = f_next;
  }
  if (count % 2 != 0) --count;  // a touch that rounding split unevenly: not a crossing
  return count;
}

std::optional<double> intersect_torus(const Torus& torus, const Ray& ray) {
  double t[4];
  const int n = torus_crossings(torus, ray, t);
  for (int k = 0; k < n; ++k)
    if (t[k] > ray.t_min && t[k] < ray.t_max) return t[k];
  return std::nullopt;
}

Vec3 torus_normal(const Torus& torus, const Vec3& p) {
  const Vec3 q = p - torus.center;
  const Vec3 across = q - dot(q, torus.axis) * torus.axis;
  const double l = length(across);
  // On the axis every point of the circle is nearest: any will do.
  Vec3 dir = l > 0.0 ? across / l : Vec3(0.0);
  if (!(l > 0.0)) {
    const Vec3 helper = std::abs(torus.axis.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    dir = normalize(cross(torus.axis, helper));
  }
  const Vec3 n = q - torus.major_radius * dir;
  const double nl = length(n);
  return nl > 0.0 ? n / nl : dir;
}

Bounds3 torus_bounds(const Torus& torus) {
  // The center circle's box (R sqrt(1 - a_i^2) along axis i) grown by r.
  Vec3 e;
  for (int i = 0; i < 3; ++i)
    e[i] = (torus.major_radius * std::sqrt(std::max(0.0, 1.0 - torus.axis[i] * torus.axis[i])) + torus.minor_radius) *
           (1.0 + 1e-12);
  return Bounds3{torus.center - e, torus.center + e};
}

}  // namespace glint
