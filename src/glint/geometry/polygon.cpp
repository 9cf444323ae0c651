#include "glint/geometry/polygon.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace glint {

namespace {

struct P2 {
  double x, y;
  bool operator==(const P2&) const = default;
};

// Twice the signed area of (a, b, c): > 0 when they turn counterclockwise.
double orient(const P2& a, const P2& b, const P2& c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

bool within_box(const P2& a, const P2& b, const P2& p) {
  return p.x >= std::min(a.x, b.x) && p.x <= std::max(a.x, b.x) && p.y >= std::min(a.y, b.y) &&
         p.y <= std::max(a.y, b.y);
}

// Segments ab and cd cross or touch.
bool segments_meet(const P2& a, const P2& b, const P2& c, const P2& d) {
  const double d1 = orient(c, d, a), d2 = orient(c, d, b), d3 = orient(a, b, c), d4 = orient(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && within_box(c, d, a)) || (d2 == 0 && within_box(c, d, b)) || (d3 == 0 && within_box(a, b, c)) ||
         (d4 == 0 && within_box(a, b, d));
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// The vertices in the polygon's plane, in a frame (e_u, e_v) with
// e_u x e_v = normal, so counterclockwise here is counterclockwise about it.
std::vector<P2> project(const std::vector<Vec3>& vertices, const Vec3& normal) {
  const Vec3 r = std::abs(normal.x) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 e_u = normalize(cross(normal, r)), e_v = cross(normal, e_u);
  std::vector<P2> out;
  out.reserve(vertices.size());
  for (const Vec3& v : vertices) out.push_back({dot(v - vertices[0], e_u), dot(v - vertices[0], e_v)});
  return out;
}

// Vertex indices with repeats of the previous vertex left out (a zero-length
// edge is no edge: it neither turns nor crosses anything).
std::vector<uint32_t> distinct_ring(const std::vector<P2>& p) {
  std::vector<uint32_t> ring;
  for (uint32_t i = 0; i < p.size(); ++i)
    if (ring.empty() || !(p[i] == p[ring.back()])) ring.push_back(i);
  while (ring.size() > 1 && p[ring.back()] == p[ring.front()]) ring.pop_back();
  return ring;
}

// +1 or -1 (the way it winds) when the ring turns the same way at every
// vertex (up to rounding of nearly straight ones) and winds around once; 0 otherwise.
int convex_winding(const std::vector<P2>& p, const std::vector<uint32_t>& ring) {
  const size_t m = ring.size();
  if (m < 3) return 0;
  int left = 0, right = 0;
  double turning = 0;
  for (size_t i = 0; i < m; ++i) {
    const P2& a = p[ring[(i + m - 1) % m]];
    const P2& b = p[ring[i]];
    const P2& c = p[ring[(i + 1) % m]];
    const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - b.x, vy = c.y - b.y;
    const double z = ux * vy - uy * vx, along = ux * vx + uy * vy;
    turning += std::atan2(z, along);
    // Straight within rounding (1e-9 of the edges' lengths) counts as either way.
    const double straight = 1e-9 * std::sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy));
    if (z > straight) ++left;
    if (z < -straight) ++right;
  }
  if (left > 0 && right > 0) return 0;
  if (std::abs(std::abs(turning) - 2 * std::numbers::pi) > 0.5) return 0;  // wound twice (a star), or not at all
  return turning > 0 ? 1 : -1;
}

// Ear clipping of a simple polygon given counterclockwise.
std::vector<std::array<uint32_t, 3>> ear_clip(const std::vector<P2>& p, std::vector<uint32_t> ring) {
  std::vector<std::array<uint32_t, 3>> out;
  if (ring.size() < 3) return out;
  const auto is_ear = [&](size_t m, size_t i) {
    const uint32_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
    if (!(orient(p[a], p[b], p[c]) > 0)) return false;
    for (uint32_t k : ring) {
      if (k == a || k == b || k == c || p[k] == p[a] || p[k] == p[b] || p[k] == p[c]) continue;
      if (orient(p[a], p[b], p[k]) >= 0 && orient(p[b], p[c], p[k]) >= 0 && orient(p[c], p[a], p[k]) >= 0)
        return false;  // another vertex inside (or on) the ear
    }
    return true;
  };
  size_t i = 0, misses = 0;
  while (ring.size() > 3) {
    const size_t m = ring.size();
    i %= m;
    if (!is_ear(m, i)) {
      ++i;
      if (++misses < m) continue;
      // No ear found all the way round: only nearly straight vertices left
      // (rounding). Clip the one that turns left most; its sliver has no area to speak of.
      double best = -kInfinity;
      for (size_t k = 0; k < m; ++k) {
        const double o = orient(p[ring[(k + m - 1) % m]], p[ring[k]], p[ring[(k + 1) % m]]);
        if (o > best) {
          best = o;
          i = k;
        }
      }
    }
    out.push_back({ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]});
    ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
    misses = 0;
    if (i > 0) --i;  // the neighbour before may have become an ear
  }
  out.push_back({ring[0], ring[1], ring[2]});
  return out;
}

// The grid of a polygon whose triangles are final (see PolygonGrid).
std::shared_ptr<const PolygonGrid> make_grid(const Polygon& polygon) {
  auto g = std::make_shared<PolygonGrid>();
  const Vec3& n = polygon.normal;
  const Vec3 a(std::abs(n.x), std::abs(n.y), std::abs(n.z));
  const int drop = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  g->u = drop == 0 ? 1 : 0;
  g->v = drop == 2 ? 1 : 2;
  Bounds3 box;
  for (const Vec3& v : polygon.vertices) {
    box.extend(v);
    g->deviation = std::max(g->deviation, std::abs(dot(v - polygon.vertices[0], n)));
  }
  g->diagonal = length(box.diagonal());
  const size_t count = polygon.triangles.size();
  g->boxes.reserve(count);
  for (const auto& t : polygon.triangles) {
    const Vec3 &p0 = polygon.vertices[t[0]], &p1 = polygon.vertices[t[1]], &p2 = polygon.vertices[t[2]];
    g->boxes.push_back({std::min({p0[g->u], p1[g->u], p2[g->u]}), std::min({p0[g->v], p1[g->v], p2[g->v]}),
                        std::max({p0[g->u], p1[g->u], p2[g->u]}), std::max({p0[g->v], p1[g->v], p2[g->v]})});
  }
  // About one cell per triangle, square-ish.
  const double extent[2] = {box.hi[g->u] - box.lo[g->u], box.hi[g->v] - box.lo[g->v]};
  const double cells = static_cast<double>(count);
  const double ratio = extent[1] > 0 ? extent[0] / extent[1] : 1.0;
  g->cells[0] = static_cast<int>(std::clamp(std::round(std::sqrt(cells * ratio)), 1.0, 64.0));
  g->cells[1] = static_cast<int>(std::clamp(std::round(cells / g->cells[0]), 1.0, 64.0));
  for (int k = 0; k < 2; ++k) {
    g->lo[k] = k == 0 ? box.lo[g->u] : box.lo[g->v];
    g->cell[k] = extent[k] > 0 ? extent[k] / g->cells[k] : 1.0;
  }
  // Cells overlapped by each box, counted, then filled in triangle order.
  const auto range = [&](const std::array<double, 4>& b, int k) {
    const auto cell = [&](double x) {
      return std::clamp(static_cast<int>(std::floor((x - g->lo[k]) / g->cell[k])), 0, g->cells[k] - 1);
    };
    return std::pair<int, int>(cell(b[k]), cell(b[k + 2]));
  };
  const size_t total = static_cast<size_t>(g->cells[0]) * static_cast<size_t>(g->cells[1]);
  std::vector<uint32_t> count_in(total + 1, 0);
  for (const auto& b : g->boxes) {
    const auto [u0, u1] = range(b, 0);
    const auto [v0, v1] = range(b, 1);
    for (int cv = v0; cv <= v1; ++cv)
      for (int cu = u0; cu <= u1; ++cu) ++count_in[static_cast<size_t>(cu + g->cells[0] * cv) + 1];
  }
  for (size_t c = 0; c < total; ++c) count_in[c + 1] += count_in[c];
  g->first = count_in;
  g->items.resize(count_in[total]);
  for (uint32_t i = 0; i < count; ++i) {
    const auto [u0, u1] = range(g->boxes[i], 0);
    const auto [v0, v1] = range(g->boxes[i], 1);
    for (int cv = v0; cv <= v1; ++cv)
      for (int cu = u0; cu <= u1; ++cu) g->items[count_in[static_cast<size_t>(cu + g->cells[0] * cv)]++] = i;
  }
  return g;
}

}  // namespace

bool polygon_is_convex(const std::vector<Vec3>& vertices, const Vec3& normal) {
  const std::vector<P2> p = project(vertices, normal);
  return convex_winding(p, distinct_ring(p)) != 0;
}

PolygonBuild make_polygon(std::vector<Vec3> vertices, std::vector<Vec3> normals) {
  PolygonBuild out;
  const size_t n = vertices.size();
  if (n < 3) {
    out.error = "a polygon needs at least three vertices (got " + std::to_string(n) + ")";
    return out;
  }
  const Vec3 e1 = vertices[1] - vertices[0], e2 = vertices[2] - vertices[0];
  const Vec3 c = cross(e1, e2);
  const double area = length(c);
  if (!(area > 1e-12 * length(e1) * length(e2)) || !std::isfinite(area)) {
    out.error = "the first three vertices are collinear (degenerate polygon: they define its normal)";
    return out;
  }
  const Vec3 normal = c / area;
  Bounds3 box;
  for (const Vec3& v : vertices) box.extend(v);
  const double limit = kPolygonPlanarity * length(box.diagonal());
  for (size_t i = 3; i < n; ++i) {
    const double off = std::abs(dot(vertices[i] - vertices[0], normal));
    if (!(off <= limit)) {
      out.error = "not planar: vertex " + std::to_string(i) + " is " + number(off) +
                  " from the plane of the first three vertices (at most " + number(limit) +
                  " is allowed: 1e-5 of the bounding box diagonal)";
      return out;
    }
  }
  const std::vector<P2> p = project(vertices, normal);
  const std::vector<uint32_t> ring = distinct_ring(p);
  const int winding = convex_winding(p, ring);
  Polygon& polygon = out.polygon;
  if (winding != 0) {
    // The fan (0, i, i+1) of the contract, whose triangles also carry the
    // vertex normals; zero-area ones (repeated vertices) are left out.
    for (uint32_t i = 1; i + 1 < n; ++i)
      if (orient(p[0], p[i], p[i + 1]) != 0) polygon.triangles.push_back({0, i, i + 1});
  } else {
    if (!normals.empty()) {
      out.error = "a polygon with normals must be convex (this one is not; leave out \"normals\" for flat shading)";
      out.error_at_normals = true;
      return out;
    }
    const size_t m = ring.size();
    if (m > kMaxNonConvexPolygonVertices) {
      out.error = "a non-convex polygon may have at most " + std::to_string(kMaxNonConvexPolygonVertices) +
                  " vertices (got " + std::to_string(m) + ")";
      return out;
    }
    // Every edge against every edge it does not share a vertex with.
    std::vector<double> lo_x(m), hi_x(m);
    for (size_t i = 0; i < m; ++i) {
      lo_x[i] = std::min(p[ring[i]].x, p[ring[(i + 1) % m]].x);
      hi_x[i] = std::max(p[ring[i]].x, p[ring[(i + 1) % m]].x);
    }
    for (size_t i = 0; i < m; ++i) {
      for (size_t j = i + 2; j < m; ++j) {
        if (i == 0 && j == m - 1) continue;  // neighbours around the end
        if (hi_x[i] < lo_x[j] || hi_x[j] < lo_x[i]) continue;
        if (segments_meet(p[ring[i]], p[ring[(i + 1) % m]], p[ring[j]], p[ring[(j + 1) % m]])) {
          out.error = "self-intersecting: the edge from vertex " + std::to_string(ring[i]) + " to " +
                      std::to_string(ring[(i + 1) % m]) + " meets the edge from vertex " + std::to_string(ring[j]) +
                      " to " + std::to_string(ring[(j + 1) % m]);
          return out;
        }
      }
    }
    // Ear clipping wants counterclockwise: the sign of the shoelace area.
    double twice_area = 0;
    for (size_t i = 0; i < m; ++i) {
      const P2& a = p[ring[i]];
      const P2& b = p[ring[(i + 1) % m]];
      twice_area += a.x * b.y - a.y * b.x;
    }
    std::vector<uint32_t> ccw = ring;
    if (twice_area < 0) std::reverse(ccw.begin(), ccw.end());
    polygon.triangles = ear_clip(p, std::move(ccw));
  }
  polygon.vertices = std::move(vertices);
  polygon.normals = std::move(normals);
  polygon.normal = normal;
  if (polygon.triangles.size() >= kPolygonGridMinTriangles) polygon.grid = make_grid(polygon);
  return out;
}

}  // namespace glint
