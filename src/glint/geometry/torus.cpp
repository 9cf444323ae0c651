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
// steps kept inside the shrinking bracket, bisection when a step leaves it.
template <class G, class DG>
double bracketed_root(double lo, double hi, G g, DG dg) {
  double glo = g(lo);
  double s = 0.5 * (lo + hi);
  for (int i = 0; i < 100; ++i) {
    const double gs = g(s);
    if (gs == 0.0) return s;
    if ((gs < 0.0) == (glo < 0.0)) {
      lo = s;
      glo = gs;
    } else {
      hi = s;
    }
    const double d = dg(s);
    double next = d != 0.0 ? s - gs / d : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (next == s || hi - lo <= 4e-16 * std::max(std::abs(lo), std::abs(hi))) return next;
    s = next;
  }
  return s;
}

double poly(const double* c, int degree, double s) {
  double v = c[degree];
  for (int k = degree - 1; k >= 0; --k) v = v * s + c[k];
  return v;
}

// The real roots in (lo, hi) of the polynomial c (degree 1 to 4), ascending,
// where it changes sign: the pieces between the derivative's roots are
// monotone, so each holds at most one. Returns the count.
int sign_change_roots(const double* c, int degree, double lo, double hi, double* roots) {
  if (degree == 1) {
    if (c[1] == 0.0) return 0;
    const double r = -c[0] / c[1];
    if (r > lo && r < hi) {
      roots[0] = r;
      return 1;
    }
    return 0;
  }
  double d[4];
  for (int k = 1; k <= degree; ++k) d[k - 1] = k * c[k];
  double cuts[5];
  int n = 0;
  cuts[n++] = lo;
  double inner[3];
  const int m = sign_change_roots(d, degree - 1, lo, hi, inner);
  for (int k = 0; k < m; ++k) cuts[n++] = inner[k];
  cuts[n++] = hi;
  int count = 0;
  const auto g = [&](double s) { return poly(c, degree, s); };
  const auto dg = [&](double s) { return poly(d, degree - 1, s); };
  for (int k = 0; k + 1 < n; ++k) {
    const double a = cuts[k], b = cuts[k + 1];
    const double ga = g(a), gb = g(b);
    if ((ga < 0.0) != (gb < 0.0) && ga != 0.0) roots[count++] = bracketed_root(a, b, g, dg);
  }
  return count;
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
  // Every root lies inside the bounding sphere: |s| < half its chord.
  const double half_chord = std::sqrt(bound * bound - pp) * (1.0 + 1e-9) + 1e-12 * bound;
  double c[5];
  line.expanded(c);
  // The quartic's own critical points split the chord into monotone pieces;
  // each root is then polished on f written as A^2 - B.
  double d1[4];
  for (int k = 1; k <= 4; ++k) d1[k - 1] = k * c[k];
  double cuts[5];
  int n = 0;
  cuts[n++] = -half_chord;
  double crit[3];
  const int m = sign_change_roots(d1, 3, -half_chord, half_chord, crit);
  for (int k = 0; k < m; ++k) cuts[n++] = crit[k];
  cuts[n++] = half_chord;
  const auto f = [&](double s) { return line.f(s); };
  const auto df = [&](double s) { return line.df(s); };
  int count = 0;
  for (int k = 0; k + 1 < n && count < 4; ++k) {
    const double a = cuts[k], b = cuts[k + 1];
    const double fa = f(a), fb = f(b);
    if ((fa < 0.0) != (fb < 0.0)) t[count++] = (sc + bracketed_root(a, b, f, df)) / len;
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
