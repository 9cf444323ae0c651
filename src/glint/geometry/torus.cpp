#include "glint/geometry/torus.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace glint {

namespace {

// Newton's steps stop once a step is below kStepTolerance (in units of
// R + r) and the error it leaves (~step^2 g''/2g') below kErrorTolerance.
// Or, in Chebyshev's steps, once a step is below kCubicStep and its error
// (~2 (g''/2g')^2 step^3) below kErrorTolerance.
constexpr double kStepTolerance = 1e-9;
constexpr double kCubicStep = 1e-6;
constexpr double kErrorTolerance = 1e-17;
constexpr int kMaxSteps = 80;

// The torus seen along one ray, in one variable: s is the ray's t less that
// of the line's point nearest the center. Lengths are in units of R + r, so
// every quantity is of order 1 whatever the torus's size or how far the ray
// comes from. The distance from the axis is rho(s) = sqrt(a2 (s - sc)^2 +
// rho2_min), a hyperbola, and the height above the torus's plane z(s) = pz +
// s uz; the direction's length squared is c2 = a2 + uz^2.
struct Line {
  double R, r, r2;
  double a2, sc, rho2_min;
  double pz, uz;
  double c2, half_inv_c2;
  double Ra2rho2;  // R a2 rho2_min: R rho'' = Ra2rho2 / rho^3
  // The stretch about sc between the two convex ones (see line_roots):
  // mid_sigma -1 where g is concave, 0 for the hole (rho < R - r), which
  // holds no root; empty (mid_lo = mid_hi) if g is convex throughout.
  double mid_lo, mid_hi, mid_sigma;
  double step_tol, cubic_step, error_tol;  // the constants above in s's units
};

// g(s) = (rho - R)^2 + z^2 - r^2, the squared distance to the center circle
// less r^2 (negative inside). The quartic is g times (rho + R)^2 + z^2 - r^2,
// which is > 0 everywhere, so g has the same roots; but g keeps its digits
// near them (error ~ eps r^2 against a slope ~ r), which the quartic's
// R^4-sized terms do not. slope_rho = g'(s) rho / 2, which has g''s sign
// and saves Newton a division.
struct Sample {
  double g, slope_rho, rho;
};

inline Sample sample(const Line& l, double s) {
  const double ds = s - l.sc;
  const double rho = std::sqrt(l.a2 * ds * ds + l.rho2_min);
  const double z = l.pz + s * l.uz;
  const double e = rho - l.R;
  return {e * e + (z * z - l.r2), e * (l.a2 * ds) + z * l.uz * rho, rho};
}

// Inside (g < 0) or not: how the stretches' ends are classified, the same
// way at an end that two stretches share.
inline bool inside(const Sample& v) { return v.g < 0.0; }

// Bisection on [a, b] where g has different signs at the ends (the fallback
// when rounding defeats Newton's method near a root).
double bisect(const Line& l, double a, double b) {
  const bool a_inside = inside(sample(l, a));
  for (int i = 0; i < 200; ++i) {
    const double m = 0.5 * (a + b);
    if (m == a || m == b) break;
    (inside(sample(l, m)) == a_inside ? a : b) = m;
  }
  return 0.5 * (a + b);
}

// A safe start for the root nearest x toward y, x outside (g(x) >= 0): rho
// is convex, so its chord over [x, y] lies above it, and g = A - 2 R rho
// (A = rho^2 + z^2 + R^2 - r^2, a quadratic) above the quadratic that uses
// the chord instead; they agree at x and y. Up to where that quadratic first
// reaches 0, g has no root. false if it stays > 0 on [x, y]: then so does g,
// and [x, y] holds no root. For a ray far from the axis the chord is nearly
// rho itself and the start nearly the root.
bool chord_start(const Line& l, double x, const Sample& vx, double y, const Sample& vy, double& start) {
  const double span = std::abs(y - x), dir = y > x ? 1.0 : -1.0;
  const double z = l.pz + x * l.uz;
  // The bound's slope at x along dir; its curvature is 2 c2.
  const double beta = 2.0 * (dir * (l.a2 * (x - l.sc) + l.uz * z) - l.R * (vy.rho - vx.rho) / span);
  const double gamma = vx.g;
  if (!(beta < 0.0)) return false;
  const double disc = beta * beta - 4.0 * l.c2 * gamma;
  if (disc < 0.0) return false;
  // The smaller root. The form with a division would be exact where this
  // one cancels, but a start needs only absolute accuracy, and a start past
  // the root by rounding is caught by approach().
  const double step = std::max(0.0, (-beta - std::sqrt(disc)) * l.half_inv_c2);
  if (!(step <= span)) return false;
  start = x + dir * step;
  return true;
}

// The root of g met first from x toward `end`, on a stretch where g is
// convex (sigma = 1) or concave (sigma = -1), from where sigma g >= 0
// (outside on a convex stretch, inside on a concave one): there Newton's
// step lands between x and that root, so the steps climb toward it
// monotonically and pass neither it nor `end`. On a convex stretch, once g
// is sure to stay monotone over the step (g'' <= 2 c2 bounds how fast g'
// can turn), Chebyshev's step (Newton's plus the curvature's term) is
// taken: cubic convergence, at the risk of passing the root by about its
// tiny error, which one Newton step back from the far side repairs.
// `prev`: a point before x on the same side (x itself, or where a
// chord_start began). Returns false when there is no root before `end` (g
// turns back first, or a step passes end). `sure`: a root is known to lie
// before end (g's sign differs there); rounding's failures of the above then
// fall back to bisection.
bool approach(const Line& l, double prev, bool start_inside, double x, Sample v, double end, double sigma, bool sure,
              double& root) {
  const double dir = end > x ? 1.0 : -1.0;
  // For `sure`: the root between x and end; none visible (the second root
  // of a touching pair, end the first): end itself.
  const auto fallback = [&] {
    root = inside(sample(l, end)) == start_inside ? end : bisect(l, x, end);
    return true;
  };
  double last_newton = kInfinity;
  for (int i = 0; i < kMaxSteps; ++i) {
    if (inside(v) != start_inside) {  // past the root, by a little
      const double inv = 0.5 / v.slope_rho;
      const double newton = v.g * v.rho * inv;
      const double back = x - newton;
      if (!(dir * (back - prev) >= 0.0 && dir * (x - back) >= 0.0)) {
        root = bisect(l, prev, x);
        return true;
      }
      const double half_curvature = (l.c2 * v.rho - l.Ra2rho2 / (v.rho * v.rho)) * inv;
      if (std::abs(newton) <= l.step_tol && std::abs(half_curvature * newton * newton) <= l.error_tol) {
        root = back;
        return true;
      }
      const double past = x;
      x = back;
      v = sample(l, x);
      if (inside(v) != start_inside) {
        root = bisect(l, prev, past);
        return true;
      }
    }
    if (!(sigma * v.slope_rho * dir < 0.0)) return sure && fallback();  // heading away from zero
    const double inv = 0.5 / v.slope_rho;
    const double newton = v.g * v.rho * inv;                                          // g / g'
    const double half_curvature = (l.c2 * v.rho - l.Ra2rho2 / (v.rho * v.rho)) * inv;  // g'' / 2g'
    const double extra = half_curvature * newton * newton;  // about what Newton's step leaves
    double step = newton;
    // Done when the step is small and leaves a negligible error, or (a
    // double root, a tangent ray) stops shrinking fast: then it is as
    // precise as rounding lets such a root be.
    bool done = std::abs(newton) <= l.step_tol &&
                (std::abs(extra) <= l.error_tol || std::abs(newton) > 0.25 * std::abs(last_newton));
    if (sigma > 0.0 && (std::abs(newton) + std::abs(extra)) * v.rho * l.c2 < 0.9 * std::abs(v.slope_rho)) {
      step = newton + extra;
      // Its error is ~2 extra^2 / newton plus g''''s term, ~ newton^3:
      // both negligible past these.
      done = done || (std::abs(newton) <= l.cubic_step && 2.0 * extra * extra <= l.error_tol * std::abs(newton));
    }
    last_newton = newton;
    const double next = x - step;
    if (!(dir * (end - next) > 0.0)) return sure && fallback();  // past the end
    if (done) {
      root = next;
      return true;
    }
    prev = x;
    x = next;
    v = sample(l, x);
  }
  if (sure) root = x;
  return sure;  // ever slower steps: a tangent ray, which may miss
}

// The roots of g in [lo, hi], ascending, into s (room for 8); returns how
// many. lo_outer / hi_outer: that end is the bounding volume's, where g >= 0
// but for rounding; a negative g there is taken as a crossing at the end
// itself, which keeps the count even. first_only: stop at the first root.
//
// g = A - 2 R rho with A quadratic (A'' = 2 c2) and rho'' = a2 rho2_min /
// rho^3, so g'' < 0 just where rho^3 < R a2 rho2_min / c2: a stretch about
// sc (l.mid_lo, l.mid_hi), convex on either side. Each stretch therefore
// holds at most 2 roots, which Newton's method from its right ends finds
// (approach); chord_start gives it a closer start, or proves a stretch empty.
int line_roots(const Line& l, double lo, double hi, bool lo_outer, bool hi_outer, bool first_only, double* s) {
  double cuts[4];
  int n_cuts = 0;
  cuts[n_cuts++] = lo;
  if (l.mid_lo > lo && l.mid_lo < hi) cuts[n_cuts++] = l.mid_lo;
  if (l.mid_hi > lo && l.mid_hi < hi && l.mid_hi > l.mid_lo) cuts[n_cuts++] = l.mid_hi;
  cuts[n_cuts++] = hi;

  int n = 0;
  Sample va = sample(l, lo);
  if (lo_outer && inside(va)) {
    s[n++] = lo;
    if (first_only) return n;
  }
  for (int k = 0; k + 1 < n_cuts; ++k) {
    const double a = cuts[k], b = cuts[k + 1];
    const double mid = 0.5 * (a + b);
    const double sigma = mid > l.mid_lo && mid < l.mid_hi ? l.mid_sigma : 1.0;
    const Sample vb = sample(l, b);
    const bool in_a = inside(va), in_b = inside(vb);
    double r1, r2, start;
    if (sigma == 0.0) {
      // The hole: outside throughout, ends included (g = z^2 there), so an
      // end that rounding puts inside is a crossing there (the ray through
      // the inner equator).
      if (in_a) {
        s[n++] = a;
        if (first_only) return n;
      }
      if (in_b) {
        s[n++] = b;
        if (first_only) return n;
      }
    } else if (sigma > 0.0) {
      if (!in_a) {
        if (chord_start(l, a, va, b, vb, start) &&
            approach(l, a, false, start, sample(l, start), b, 1.0, in_b, r1)) {
          r1 = std::clamp(r1, a, b);
          s[n++] = r1;
          if (first_only) return n;
          if (!in_b) {  // a second root, found the same way from b
            r2 = r1;
            if (chord_start(l, b, vb, a, va, start)) {
              start = std::max(start, r1);
              approach(l, b, false, start, sample(l, start), r1, 1.0, true, r2);
            }
            s[n++] = std::clamp(r2, r1, b);
          }
        } else if (in_b) {  // no root seen, but rounding says there is one
          s[n++] = bisect(l, a, b);
          if (first_only) return n;
        }
      } else if (!in_b) {  // one root, from b
        if (chord_start(l, b, vb, a, va, start)) {
          approach(l, b, false, start, sample(l, start), a, 1.0, true, r1);
        } else {
          approach(l, b, false, b, vb, a, 1.0, true, r1);
        }
        s[n++] = std::clamp(r1, a, b);
        if (first_only) return n;
      }
    } else {  // concave: Newton's method from the inside
      if (in_a) {
        if (approach(l, a, true, a, va, b, -1.0, !in_b, r1)) {
          r1 = std::clamp(r1, a, b);
          s[n++] = r1;
          if (first_only) return n;
          if (in_b) {
            approach(l, b, true, b, vb, r1, -1.0, true, r2);
            s[n++] = std::clamp(r2, r1, b);
          }
        } else if (!in_b) {
          s[n++] = bisect(l, a, b);
          if (first_only) return n;
        }
      } else if (in_b) {
        approach(l, b, true, b, vb, a, -1.0, true, r1);
        s[n++] = std::clamp(r1, a, b);
        if (first_only) return n;
      }
    }
    va = vb;
  }
  if (hi_outer && inside(va)) s[n++] = hi;
  return n;
}

// The ray against the bounding sphere (radius R + r) and the slab |z| <= r
// that hold the torus, reduced to a Line over the stretch [lo, hi] inside
// both. t = t0 + s.
struct Setup {
  Line line;
  double lo, hi;
  double t0;
};

// The line's point nearest the center, f = oc + t_foot d (inv_a = 1 / |d|^2),
// found as intersect_torus (torus.h) finds it, without cancellation for far
// rays; false if the line misses the bounding sphere (also for a zero or
// non-finite direction).
inline bool near_center(const Torus& torus, const Ray& ray, double& inv_a, double& t_foot, Vec3& f) {
  const Vec3 oc = ray.origin - torus.center;
  inv_a = 1.0 / dot(ray.direction, ray.direction);
  t_foot = -dot(oc, ray.direction) * inv_a;
  f = oc + t_foot * ray.direction;
  const double bound = torus.major_radius + torus.minor_radius;
  return dot(f, f) < bound * bound;
}

// The rest, for a line through the bounding sphere; false if it misses the slab.
inline bool setup(const Torus& torus, const Ray& ray, double inv_a, double t_foot, const Vec3& f, Setup& st) {
  const Vec3& d = ray.direction;
  const double a = dot(d, d);
  const double R = torus.major_radius, r = torus.minor_radius, bound = R + r;

  // Lengths in units of R + r; s keeps the ray's own units.
  const Vec3& axis = torus.axis;
  const double k = 1.0 / bound;
  const Vec3 u = d * k;
  const double c2 = a * k * k, inv_c2 = bound * bound * inv_a;
  const double uz = dot(u, axis);
  const Vec3 up = u - uz * axis;
  double a2 = dot(up, up);
  // A line (nearly) along the axis keeps a constant rho.
  if (!(a2 > 1e-200 * c2)) a2 = 0.0;
  const double inv_a2 = a2 > 0.0 ? 1.0 / a2 : 0.0;

  const Vec3 p = f * k;
  const double pz = dot(p, axis), Rk = R * k, rk = r * k;
  const double h = std::sqrt(std::max(0.0, 1.0 - dot(p, p)) * inv_c2);
  double lo = -h, hi = h;
  if (uz != 0.0) {
    const double inv = 1.0 / uz;
    double s1 = (-rk - pz) * inv, s2 = (rk - pz) * inv;
    if (s1 > s2) std::swap(s1, s2);
    lo = std::max(lo, s1);
    hi = std::min(hi, s2);
  } else if (!(std::abs(pz) <= rk)) {
    return false;
  }
  if (!(lo < hi)) return false;

  // The line's point nearest the axis (computed as f above).
  const Vec3 pp = p - pz * axis;
  const double sc = -dot(pp, up) * inv_a2;
  const Vec3 fp = pp + sc * up;
  // A line through the axis has a kink in rho there; keeping it 1e-15 of
  // the torus's size away (below what rounding moved it by already) turns
  // the kink into a short concave stretch whose ends get one-sided slopes.
  const double rho2 = std::max(dot(fp, fp), 1e-30);

  // g is concave where rho^3 < cube, if rho_min is below that. When that
  // stretch lies within the hole (rho < R - r), where g > 0, the hole's own
  // stretch, which needs no cube root, is cut out instead.
  const double Ra2 = Rk * a2 * inv_c2, cube = Ra2 * rho2;
  double mid_lo = 0.0, mid_hi = 0.0, mid_sigma = 0.0;
  if (Ra2 * Ra2 > rho2) {
    const double hole = Rk - rk;
    double rho_end = hole;
    if (cube > hole * hole * hole) {
      rho_end = std::cbrt(cube);
      mid_sigma = -1.0;
    }
    const double w = std::sqrt(std::max(0.0, (rho_end * rho_end - rho2) * inv_a2));
    mid_lo = sc - w;
    mid_hi = sc + w;
  }

  const double unit = std::sqrt(inv_c2);  // one length unit in s
  st.line = Line{Rk,     rk,     rk * rk,   a2,         sc, rho2, pz, uz, c2, 0.5 * inv_c2, Rk * a2 * rho2, mid_lo,
                 mid_hi, mid_sigma, kStepTolerance * unit, kCubicStep * unit, kErrorTolerance * unit};
  st.lo = lo;
  st.hi = hi;
  st.t0 = t_foot;
  return true;
}

// Drops the closest adjacent pair of roots (a touch) until at most `keep`
// remain: the ins and outs still alternate.
int drop_touches(double* s, int n, int keep) {
  while (n > keep) {
    int best = 0;
    for (int k = 1; k + 1 < n; ++k)
      if (s[k + 1] - s[k] < s[best + 1] - s[best]) best = k;
    for (int k = best; k + 2 < n; ++k) s[k] = s[k + 2];
    n -= 2;
  }
  return n;
}

int all_crossings(const Setup& st, double* t) {
  double s[8];
  int n = line_roots(st.line, st.lo, st.hi, true, true, false, s);
  n = drop_touches(s, n, 4);
  for (int k = 0; k < n; ++k) t[k] = st.t0 + s[k];
  return n;
}

}  // namespace

int torus_crossings(const Torus& torus, const Ray& ray, double t[4]) {
  double inv_a, t_foot;
  Vec3 f;
  Setup st;
  if (!near_center(torus, ray, inv_a, t_foot, f) || !setup(torus, ray, inv_a, t_foot, f, st)) return 0;
  return all_crossings(st, t);
}

namespace detail {

std::optional<double> intersect_torus_near(const Torus& torus, const Ray& ray) {
  // Found again here (a few operations) rather than passed: passed through
  // memory, they held up the rest of the set-up by about a tenth of a hit.
  double inv_a, t_foot;
  Vec3 f;
  Setup st;
  if (!near_center(torus, ray, inv_a, t_foot, f) || !setup(torus, ray, inv_a, t_foot, f, st)) return std::nullopt;
  // Only the part of the stretch inside (t_min, t_max), and only its first
  // root: a ray leaving the surface (t_min just past it) costs a sample or two.
  double lo = st.lo, hi = st.hi;
  bool lo_outer = true, hi_outer = true;
  const double s_min = ray.t_min - st.t0, s_max = ray.t_max - st.t0;
  if (s_min > lo) {
    lo = s_min;
    lo_outer = false;
  }
  if (s_max < hi) {
    hi = s_max;
    hi_outer = false;
  }
  if (!(lo < hi)) return std::nullopt;
  double s[8];
  if (line_roots(st.line, lo, hi, lo_outer, hi_outer, true, s) == 0) return std::nullopt;
  const double t = st.t0 + s[0];
  if (t > ray.t_min && t < ray.t_max) return t;
  // Rounding put the root at an end of the interval: decide among all of them.
  double all[4];
  const int n = all_crossings(st, all);
  for (int k = 0; k < n; ++k)
    if (all[k] > ray.t_min && all[k] < ray.t_max) return all[k];
  return std::nullopt;
}

}  // namespace detail

Vec3 torus_normal(const Torus& torus, const Vec3& p) {
  const Vec3 q = p - torus.center;
  const Vec3 across = q - dot(q, torus.axis) * torus.axis;
  const double l = length(across);
  Vec3 dir;
  if (l > 0.0) {
    dir = across / l;
  } else {  // on the axis every point of the circle is nearest: any will do
    const Vec3 helper = std::abs(torus.axis.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    dir = normalize(cross(torus.axis, helper));
  }
  // p minus the circle's nearest point, from q (not p): no cancellation
  // against a far center.
  const Vec3 n = q - torus.major_radius * dir;
  const double nl = length(n);
  return nl > 0.0 ? n / nl : dir;  // on the circle itself: outward
}

Bounds3 torus_bounds(const Torus& torus) {
  // The center circle reaches R |e_i across the axis| = R sqrt(1 - a_i^2)
  // along coordinate i (written with the other two components: exact when
  // a_i is near 1), and the tube adds r in every direction. A relative 1e-12
  // on top covers the rounding here and in the intersection test.
  const Vec3& a = torus.axis;
  const double R = torus.major_radius, r = torus.minor_radius;
  const Vec3 e(R * std::sqrt(a.y * a.y + a.z * a.z) + r, R * std::sqrt(a.x * a.x + a.z * a.z) + r,
               R * std::sqrt(a.x * a.x + a.y * a.y) + r);
  const Vec3 margin = e * 1e-12;
  return Bounds3{torus.center - e - margin, torus.center + e + margin};
}

}  // namespace glint
