#include "glint/geometry/csg.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "glint/geometry/shapes.h"
#include "glint/geometry/torus.h"

namespace glint {

namespace {

// Where a span starts or ends: which leaf's surface, which part of it.
struct Boundary {
  double t;
  uint32_t leaf;
  int part;
  bool flip;
};
struct Span {
  Boundary in, out;
};

// A short list on the stack that spills to the heap: most rays meet a few
// spans, and a per-ray allocation would cost more than the whole test.
template <class T, size_t N>
class ShortList {
 public:
  void push_back(const T& x) {
    if (size_ < N) items_[size_] = x;
    else {
      if (spill_.empty()) spill_.assign(items_.begin(), items_.end());
      spill_.push_back(x);
    }
    ++size_;
  }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T* begin() { return size_ <= N ? items_.data() : spill_.data(); }
  T* end() { return begin() + size_; }
  T& operator[](size_t i) { return begin()[i]; }

 private:
  std::array<T, N> items_;
  std::vector<T> spill_;
  size_t size_ = 0;
};
using Spans = ShortList<Span, 8>;

Ray to_leaf(const CsgLeaf& leaf, const Ray& ray) {
  if (!leaf.transform) return ray;
  Ray r = ray;
  r.origin = leaf.transform->inverse_point(ray.origin);
  r.direction = leaf.transform->inverse_vector(ray.direction);
  return r;
}

// A convex solid's span from its nearest-hit test asked twice over the
// whole line: the entry, then the exit beyond it.
template <class Test>
void convex_span(uint32_t index, Ray ray, Test test, Spans& out) {
  ray.t_min = -kInfinity;
  ray.t_max = kInfinity;
  const auto entry = test(ray);
  if (!entry) return;
  ray.t_min = entry->first;
  const auto exit = test(ray);
  if (!exit) return;
  out.push_back({{entry->first, index, entry->second, false}, {exit->first, index, exit->second, false}});
}

void leaf_spans(const Csg& csg, uint32_t index, const Ray& world, Spans& out) {
  const CsgLeaf& leaf = csg.leaves[index];
  const Ray ray = to_leaf(leaf, world);
  using Found = std::optional<std::pair<double, int>>;
  switch (leaf.type) {
    case CsgLeafType::sphere: {
      // Both roots at once, with intersect_sphere's stable arithmetic.
      const Vec3 oc = ray.origin - leaf.sphere.center;
      const double a = dot(ray.direction, ray.direction);
      const double b = dot(oc, ray.direction);
      const Vec3 f = oc - (b / a) * ray.direction;
      const double r2 = leaf.sphere.radius * leaf.sphere.radius;
      const double disc = a * (r2 - dot(f, f));
      if (!(disc > 0.0)) return;
      const double c = dot(oc, oc) - r2;
      const double q = -(b + std::copysign(std::sqrt(disc), b));
      double t0 = q / a, t1 = q != 0.0 ? c / q : t0;
      if (t0 > t1) std::swap(t0, t1);
      if (t0 < t1) out.push_back({{t0, index, 0, false}, {t1, index, 0, false}});
      return;
    }
    case CsgLeafType::box:
      convex_span(index, ray, [&](const Ray& r) -> Found {
        if (auto h = intersect_box(leaf.box, r)) return std::pair{h->t, h->face};
        return std::nullopt;
      }, out);
      return;
    case CsgLeafType::cone:
      convex_span(index, ray, [&](const Ray& r) -> Found {
        if (auto h = intersect_cone(leaf.cone, r)) return std::pair{h->t, h->part};
        return std::nullopt;
      }, out);
      return;
    case CsgLeafType::torus: {
      double t[4];
      const int n = torus_crossings(leaf.torus, ray, t);
      for (int k = 0; k + 1 < n; k += 2)
        if (t[k] < t[k + 1]) out.push_back({{t[k], index, 0, false}, {t[k + 1], index, 0, false}});
      return;
    }
  }
}

// A span thinner than this (relative to where it is) is two coincident
// faces that rounding set apart, not a solid: it is dropped.
bool thin(const Span& s) {
  const double scale = std::max({1.0, std::abs(s.in.t), std::abs(s.out.t)});
  return s.out.t - s.in.t <= 1e-9 * scale;
}

void node_spans(const Csg& csg, uint32_t node_index, const Ray& ray, Spans& out);

// An operation's spans: its children's span ends swept in order of t, the
// combined inside-ness decided after all ends at the same t, so that faces
// two children share are settled by the operation.
void operation_spans(const Csg& csg, const CsgNode& node, const Ray& ray, Spans& out) {
  struct End {
    double t;
    uint32_t child;
    bool entering;
    Boundary boundary;
  };
  ShortList<End, 16> ends;
  for (uint32_t k = 0; k < node.count; ++k) {
    Spans spans;
    node_spans(csg, csg.child_nodes[node.first + k], ray, spans);
    // Nothing of the first solid: no difference; nothing of one: no intersection.
    if (spans.empty() && (node.op == CsgOp::intersection || (node.op == CsgOp::difference && k == 0))) return;
    for (const Span& s : spans) {
      ends.push_back({s.in.t, k, true, s.in});
      ends.push_back({s.out.t, k, false, s.out});
    }
  }
  // A few ends, mostly in order already: insertion sort.
  for (size_t i = 1; i < ends.size(); ++i)
    for (size_t j = i; j > 0 && ends[j].t < ends[j - 1].t; --j) std::swap(ends[j], ends[j - 1]);
  // Children inside at the sweep's point: all of them, or the first and
  // no other, by the operation.
  uint32_t inside = 0, first_inside = 0;
  const auto combined = [&] {
    switch (node.op) {
      case CsgOp::union_of: return inside > 0;
      case CsgOp::intersection: return inside == node.count;
      case CsgOp::difference: return first_inside == 1 && inside == 1;
    }
    return false;
  };
  const auto subtracted = [&](uint32_t child) { return node.op == CsgOp::difference && child > 0; };
  bool state = false;
  Boundary open{};
  for (size_t i = 0; i < ends.size();) {
    size_t j = i + 1;  // the ends at ends[i].t are [i, j) (always one: a NaN equals nothing)
    while (j < ends.size() && ends[j].t == ends[i].t) ++j;
    for (size_t k = i; k < j; ++k) {
      const End& e = ends[k];
      inside += e.entering ? 1 : 0;
      inside -= e.entering ? 0 : 1;
      if (e.child == 0) first_inside = e.entering ? 1 : 0;
    }
    const bool now = combined();
    if (now != state) {
      // The surface of the change: an end whose own crossing made it (a
      // solid entered or a subtracted one left, for an entry).
      Boundary b = ends[i].boundary;
      uint32_t from = ends[i].child;
      for (size_t k = i; k < j; ++k)
        if ((ends[k].entering != subtracted(ends[k].child)) == now) {
          b = ends[k].boundary;
          from = ends[k].child;
          break;
        }
      b.flip = b.flip != subtracted(from);
      if (now) {
        open = b;
      } else {
        const Span s{open, b};
        if (!thin(s)) out.push_back(s);
      }
      state = now;
    }
    i = j;
  }
}

void node_spans(const Csg& csg, uint32_t node_index, const Ray& ray, Spans& out) {
  const CsgNode& node = csg.nodes[node_index];
  if (node.leaf) leaf_spans(csg, node.index, ray, out);
  else operation_spans(csg, node, ray, out);
}

}  // namespace

std::optional<CsgHit> intersect_csg(const Csg& csg, const Ray& ray) {
  Spans spans;
  node_spans(csg, 0, ray, spans);
  for (const Span& s : spans) {
    for (const Boundary& b : {s.in, s.out}) {
      if (b.t >= ray.t_max) return std::nullopt;
      if (b.t > ray.t_min) return CsgHit{b.t, b.leaf, b.part, b.flip};
    }
  }
  return std::nullopt;
}

Vec3 csg_leaf_normal(const CsgLeaf& leaf, int part, const Vec3& p) {
  switch (leaf.type) {
    case CsgLeafType::sphere: return normalize(p - leaf.sphere.center);
    case CsgLeafType::box: return box_face_normal(part);
    case CsgLeafType::cone: return cone_normal(leaf.cone, part, p);
    case CsgLeafType::torus: return torus_normal(leaf.torus, p);
  }
  return {0, 1, 0};
}

Bounds3 csg_leaf_bounds(const CsgLeaf& leaf) {
  Bounds3 b;
  switch (leaf.type) {
    case CsgLeafType::sphere:
      b = Bounds3{leaf.sphere.center - Vec3(leaf.sphere.radius), leaf.sphere.center + Vec3(leaf.sphere.radius)};
      break;
    case CsgLeafType::box: b = Bounds3{leaf.box.lo, leaf.box.hi}; break;
    case CsgLeafType::cone: b = cone_bounds(leaf.cone); break;
    case CsgLeafType::torus: b = torus_bounds(leaf.torus); break;
  }
  return leaf.transform ? leaf.transform->bounds(b) : b;
}

namespace {

Bounds3 node_bounds(const Csg& csg, uint32_t index) {
  const CsgNode& node = csg.nodes[index];
  if (node.leaf) return csg_leaf_bounds(csg.leaves[node.index]);
  Bounds3 b = node_bounds(csg, csg.child_nodes[node.first]);
  if (node.op == CsgOp::difference) return b;
  for (uint32_t k = 1; k < node.count; ++k) {
    const Bounds3 c = node_bounds(csg, csg.child_nodes[node.first + k]);
    if (node.op == CsgOp::union_of) {
      b = Bounds3{min(b.lo, c.lo), max(b.hi, c.hi)};
    } else {
      b = Bounds3{max(b.lo, c.lo), min(b.hi, c.hi)};
    }
  }
  // Children that do not overlap: an empty solid, kept as a point's box
  // so the accelerators need no special case.
  if (!(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z)) b = Bounds3{b.lo, b.lo};
  return b;
}

}  // namespace

Bounds3 csg_bounds(const Csg& csg) { return node_bounds(csg, 0); }

}  // namespace glint
