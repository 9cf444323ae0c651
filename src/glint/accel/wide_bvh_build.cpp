// The wide BVH's build (wide_bvh.h): binned SAH into a binary tree, then
// collapsed into nodes of kBvhWidth children.
#include "glint/accel/wide_bvh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <future>
#include <memory>
#include <stdexcept>
#include <thread>

namespace glint {

namespace {

constexpr int kBins = 16;
constexpr int kMaxDepth = 60;  // bounds the traversal stack (see wide_bvh.h)
constexpr size_t kParallelMinPrimitives = 4096;

// Float boxes with SSE min/max; lane 3 is unused. Rounded outward from the
// callers' double boxes, so they still contain them.
struct Box4f {
  __m128 lo = _mm_set1_ps(INFINITY), hi = _mm_set1_ps(-INFINITY);
  void extend(__m128 l, __m128 h) {
    lo = _mm_min_ps(lo, l);
    hi = _mm_max_ps(hi, h);
  }
  void extend(const Box4f& b) { extend(b.lo, b.hi); }
  float axis_lo(int a) const {
    alignas(16) float v[4];
    _mm_store_ps(v, lo);
    return v[a];
  }
  float axis_hi(int a) const {
    alignas(16) float v[4];
    _mm_store_ps(v, hi);
    return v[a];
  }
  // Half the surface area (what SAH compares); an empty box gives infinity.
  float half_area() const {
    const __m128 d = _mm_sub_ps(hi, lo);
    const __m128 p = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));  // xy, yz, zx
    alignas(16) float v[4];
    _mm_store_ps(v, p);
    return v[0] + v[1] + v[2];
  }
  Bounds3 to_bounds() const {
    Bounds3 b;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = axis_lo(a);
      b.hi[a] = axis_hi(a);
    }
    return b;
  }
};

// The binary tree the SAH build makes; collapsed into BvhNode afterwards.
// Its boxes are the build's float boxes (36 bytes a node, not 56 in double).
// Left uninitialized on purpose: the arena below is allocated without
// zeroing, so the pages of slots never handed out are never touched.
struct BinaryNode {
  float lo[3], hi[3];
  uint32_t offset;  // leaf: first primitive (of the reordered refs); interior: second child
  uint32_t count;   // 0: interior
  uint32_t first;   // interior: first child
  Bounds3 bounds() const { return Bounds3{Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], hi[1], hi[2])}; }
};

// 32 bytes: the primitive's float box with its id in the lo box's lane 3.
struct alignas(16) PrimRef {
  float lo[3];
  uint32_t id;
  float hi[3];
  float unused;
  __m128 lo4() const { return _mm_load_ps(lo); }
  __m128 hi4() const { return _mm_load_ps(hi); }
  __m128 centroid2() const { return _mm_add_ps(lo4(), hi4()); }  // twice the center: only compared
};

// 32 MB for 1M primitives: huge pages, and not zeroed before they are filled.
using PrimRefs = HugePageVector<PrimRef>;

// Float boxes that always contain the double box: round outward.
float round_down(double v) {
  float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -INFINITY) : f;
}
float round_up(double v) {
  float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, INFINITY) : f;
}

// The binary nodes of one build, shared by its threads: each builder takes
// slots in chunks, so subtrees built on their own threads land in place
// (no copying of finished subtrees into their parents' arrays).
// Its memory comes in huge pages (one fault per 2 MiB instead of 512; the
// system time of a 1M-triangle build went from 59 to 28 ms).
class NodeArena {
 public:
  static constexpr uint32_t kChunk = 1024;
  explicit NodeArena(size_t capacity) : nodes_(HugePageAllocator<BinaryNode>().allocate(capacity)), capacity_(capacity) {}
  ~NodeArena() { HugePageAllocator<BinaryNode>().deallocate(nodes_, capacity_); }
  NodeArena(const NodeArena&) = delete;
  NodeArena& operator=(const NodeArena&) = delete;
  BinaryNode& operator[](uint32_t i) { return nodes_[i]; }
  const BinaryNode& operator[](uint32_t i) const { return nodes_[i]; }
  // The first slot of a fresh chunk.
  uint32_t take_chunk() {
    const size_t first = next_.fetch_add(kChunk, std::memory_order_relaxed);
    if (first + kChunk > capacity_) throw std::logic_error("BVH build: node arena exhausted");
    return static_cast<uint32_t>(first);
  }
  // One past the last slot handed out.
  size_t used() const { return std::min(next_.load(std::memory_order_relaxed), capacity_); }

 private:
  BinaryNode* nodes_;
  size_t capacity_;
  std::atomic<size_t> next_{0};
};

class Builder {
 public:
  Builder(PrimRefs& refs, const BvhBuildOptions& options, NodeArena& nodes, int parallel_depth)
      : refs_(refs), options_(options), nodes_(nodes), parallel_depth_(parallel_depth) {
    while ((1 << block_shift_) < options_.block_size) ++block_shift_;
    options_.block_size = 1 << block_shift_;
  }

  // A node's primitives' box and the box of their centroids (twice the centers).
  struct NodeBoxes {
    Box4f bounds, centroids;
  };

  // `known`: the node's boxes when the parent's split already found them.
  uint32_t build(size_t begin, size_t end, int depth, const NodeBoxes* known = nullptr) {
    const uint32_t index = new_node();
    const NodeBoxes boxes = known ? *known : boxes_of(begin, end);
    const Box4f& bounds = boxes.bounds;
    const Box4f& centroids = boxes.centroids;
    for (int a = 0; a < 3; ++a) {
      nodes_[index].lo[a] = bounds.axis_lo(a);
      nodes_[index].hi[a] = bounds.axis_hi(a);
    }
    const size_t count = end - begin;

    size_t mid = begin;
    alignas(16) float c_lo[4], c_hi[4];
    _mm_store_ps(c_lo, centroids.lo);
    _mm_store_ps(c_hi, centroids.hi);
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (c_hi[a] - c_lo[a] > c_hi[axis] - c_lo[axis]) axis = a;
    if (count == 1) return make_leaf(index, begin, end);
    // One block at most: no split can cost less than its traversal step plus
    // a block (the test below would say leaf), so skip the binning.
    if (count <= static_cast<size_t>(std::min(options_.block_size, options_.max_leaf_size)))
      return make_leaf(index, begin, end);
    if (!(c_hi[axis] > c_lo[axis])) {
      // All centroids coincide: no split separates them, so halve the list
      // when it is too long for one leaf.
      if (count <= static_cast<size_t>(options_.max_leaf_size)) return make_leaf(index, begin, end);
      mid = begin + count / 2;
      return make_interior(index, begin, mid, end, depth);
    }
    if (depth >= kMaxDepth) {
      // Degenerate distribution: an object-median split bounds the depth.
      mid = begin + count / 2;
      std::nth_element(
          refs_.begin() + begin, refs_.begin() + mid, refs_.begin() + end,
          [axis](const PrimRef& a, const PrimRef& b) { return a.lo[axis] + a.hi[axis] < b.lo[axis] + b.hi[axis]; });
      return make_interior(index, begin, mid, end, depth);
    }

    // Binned SAH over all three axes in one pass over the primitives.
    // Small nodes get fewer bins: the sweeps below cost as much as the binning.
    const int bins = static_cast<int>(std::min<size_t>(kBins, std::max<size_t>(count, 4)));
    float scale[3];
    for (int a = 0; a < 3; ++a) scale[a] = c_hi[a] > c_lo[a] ? bins * 0.99999f / (c_hi[a] - c_lo[a]) : 0.0f;
    std::array<std::array<Box4f, kBins>, 3> bin_bounds;
    std::array<std::array<uint32_t, kBins>, 3> bin_count{};
    for (size_t i = begin; i < end; ++i) {
      const PrimRef& r = refs_[i];
      const __m128 l = r.lo4(), h = r.hi4();
      alignas(16) float c[4];
      _mm_store_ps(c, _mm_add_ps(l, h));
      for (int a = 0; a < 3; ++a) {
        const int b = bin_of(c[a], c_lo[a], scale[a], bins);
        bin_count[a][b]++;
        bin_bounds[a][b].extend(l, h);
      }
    }
    double best_cost = kInfinity;
    int best_axis = -1, best_split = -1;
    for (int a = 0; a < 3; ++a) {
      if (scale[a] == 0.0f) continue;
      // Sweep from the right to get the right-side areas, then from the left.
      std::array<double, kBins> right_area{};
      std::array<size_t, kBins> right_count{};
      Box4f acc;
      size_t n = 0;
      for (int b = bins - 1; b > 0; --b) {
        acc.extend(bin_bounds[a][b]);
        n += bin_count[a][b];
        right_area[b] = acc.half_area();
        right_count[b] = n;
      }
      acc = Box4f{};
      n = 0;
      for (int b = 0; b < bins - 1; ++b) {
        acc.extend(bin_bounds[a][b]);
        n += bin_count[a][b];
        if (n == 0 || right_count[b + 1] == 0) continue;
        const double cost = double(acc.half_area()) * blocks(n) + right_area[b + 1] * blocks(right_count[b + 1]);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = a;
          best_split = b;
        }
      }
    }
    // Leaf if splitting does not pay: traversal step costs about one primitive test.
    const double leaf_cost = blocks(count);
    const double area = bounds.half_area();
    const double split_cost = 1.0 + (area > 0 ? best_cost / area : 0.0);
    if (best_axis < 0 || (count <= static_cast<size_t>(options_.max_leaf_size) && leaf_cost <= split_cost))
      return make_leaf(index, begin, end);

    // The children's boxes come out of the split: their bounds from the bins
    // (which hold exactly the primitives each side gets), their centroid
    // boxes from the partition, so they need no pass of their own.
    const float lo = c_lo[best_axis], sc = scale[best_axis];
    auto is_left = [&](const PrimRef& r) {
      return bin_of(r.lo[best_axis] + r.hi[best_axis], lo, sc, bins) <= best_split;
    };
    NodeBoxes left, right;
    for (int b = 0; b < bins; ++b) (b <= best_split ? left : right).bounds.extend(bin_bounds[best_axis][b]);
    size_t i = begin, j = end;
    for (;;) {
      while (i < j && is_left(refs_[i])) {
        const __m128 c = refs_[i++].centroid2();
        left.centroids.extend(c, c);
      }
      while (i < j && !is_left(refs_[j - 1])) {
        const __m128 c = refs_[--j].centroid2();
        right.centroids.extend(c, c);
      }
      if (i >= j) break;
      std::swap(refs_[i], refs_[j - 1]);  // now a left one at i and a right one at j - 1
    }
    mid = i;
    if (mid == begin || mid == end) return make_interior(index, begin, begin + count / 2, end, depth);  // cannot happen
    return make_interior(index, begin, mid, end, depth, &left, &right);
  }

 private:
  NodeBoxes boxes_of(size_t begin, size_t end) const {
    NodeBoxes boxes;
    for (size_t i = begin; i < end; ++i) {
      boxes.bounds.extend(refs_[i].lo4(), refs_[i].hi4());
      const __m128 c = refs_[i].centroid2();
      boxes.centroids.extend(c, c);
    }
    return boxes;
  }

  static int bin_of(float c, float lo, float scale, int bins) {
    return std::clamp(static_cast<int>((c - lo) * scale), 0, bins - 1);
  }

  // Block sizes are powers of two (build_bvh rounds up): a shift, not a
  // division, in the SAH sweep's inner loop (divisions were 6% of a build).
  double blocks(size_t n) const { return static_cast<double>((n + (size_t{1} << block_shift_) - 1) >> block_shift_); }

  uint32_t make_leaf(uint32_t index, size_t begin, size_t end) {
    BinaryNode& n = nodes_[index];
    n.offset = static_cast<uint32_t>(begin);  // refs_[begin, end): the leaf's ids, read out at the end
    n.count = static_cast<uint32_t>(end - begin);
    return index;
  }

  uint32_t make_interior(uint32_t index, size_t begin, size_t mid, size_t end, int depth,
                         const NodeBoxes* left_boxes = nullptr, const NodeBoxes* right_boxes = nullptr) {
    uint32_t first = 0, second = 0;
    if (depth < parallel_depth_ && end - begin >= kParallelMinPrimitives) {
      // The two halves own disjoint ranges of refs_: build them at once.
      auto left_done = std::async(std::launch::async, [&] {
        first = Builder(refs_, options_, nodes_, parallel_depth_).build(begin, mid, depth + 1, left_boxes);
      });
      second = Builder(refs_, options_, nodes_, parallel_depth_).build(mid, end, depth + 1, right_boxes);
      left_done.get();
    } else {
      first = build(begin, mid, depth + 1, left_boxes);
      second = build(mid, end, depth + 1, right_boxes);
    }
    BinaryNode& n = nodes_[index];
    n.first = first;
    n.offset = second;
    n.count = 0;
    return index;
  }

  uint32_t new_node() {
    if (next_slot_ == chunk_end_) {
      next_slot_ = nodes_.take_chunk();
      chunk_end_ = next_slot_ + NodeArena::kChunk;
    }
    return next_slot_++;
  }

  PrimRefs& refs_;
  BvhBuildOptions options_;  // a copy: block_size rounded up to a power of two
  NodeArena& nodes_;
  uint32_t next_slot_ = 0, chunk_end_ = 0;  // this builder's chunk of nodes_
  int block_shift_ = 0;
  int parallel_depth_;  // subtrees above this depth are built on their own threads
};

// Which binary nodes become the slots of each wide node, chosen by the
// surface area heuristic over every way of distributing a subtree over the
// slots (dynamic programming, bottom up, after Ylitie, Karras and Laine's
// compressed wide BVHs, 2017). The greedy rule it replaces (open the
// largest interior child until the node is full) left nodes near the
// leaves with few children: the wide nodes of a 1M terrain held 4.6 of 8
// on average, and there were 35% more of them.
//
// Every leaf is a slot of some wide node whatever the plan, so plans differ
// only in the wide nodes they make, and a ray pays one node test for each
// wide node it enters, which by the heuristic is in proportion to the
// node's area. cost(m, k) is the least summed area of the wide nodes made
// for m's subtree when it may take up to k slots of the node above: m takes
// one slot as a wide node of its own (its area plus its children's best
// split of kBvhWidth slots) or hands j slots to one child and k - j to the
// other.
class CollapsePlan {
 public:
  CollapsePlan(const NodeArena& tree, size_t nodes)
      : tree_(tree), choice_(HugePageAllocator<Choices>().allocate(nodes)), size_(nodes) {}
  ~CollapsePlan() { HugePageAllocator<Choices>().deallocate(choice_, size_); }
  CollapsePlan(const CollapsePlan&) = delete;
  CollapsePlan& operator=(const CollapsePlan&) = delete;

  // Plans the subtree at `root`, its top `parallel_depth` levels' subtrees
  // on threads of their own.
  void plan(uint32_t root, int parallel_depth) {
    Costs costs;
    plan(root, costs, parallel_depth);
  }

  // The binary nodes that become the slots of a wide node at interior node m.
  int slots_of(uint32_t m, uint32_t (&slots)[kBvhWidth]) const {
    const BinaryNode& n = tree_[m];
    int used = 0;
    const int j = choice_[m][0];
    place(n.first, j, slots, used);
    place(n.offset, kBvhWidth - j, slots, used);
    return used;
  }

 private:
  using Costs = std::array<double, kBvhWidth>;  // costs[k - 1] = cost(m, k)
  static constexpr double kWideNodeTieBreak = 1e-300;
  // choices[0]: how many of a wide node's slots go to the first child;
  // choices[k - 1] (k >= 2): the same when m may take k slots, 0 when it
  // takes one slot as a wide node of its own.
  using Choices = std::array<uint8_t, kBvhWidth>;

  void place(uint32_t m, int k, uint32_t (&slots)[kBvhWidth], int& used) const {
    const BinaryNode& n = tree_[m];
    const int j = n.count > 0 || k == 1 ? 0 : choice_[m][k - 1];
    if (j == 0) {
      slots[used++] = m;
      return;
    }
    place(n.first, j, slots, used);
    place(n.offset, k - j, slots, used);
  }

  void plan(uint32_t m, Costs& costs, int parallel_depth) {
    const BinaryNode& n = tree_[m];
    if (n.count > 0) {
      costs.fill(0.0);  // a leaf: one slot, no wide node
      return;
    }
    // In double: the areas of a huge scene overflow float. (An infinite
    // extent times a zero one is NaN: infinite then.)
    const double dx = double(n.hi[0]) - n.lo[0], dy = double(n.hi[1]) - n.lo[1], dz = double(n.hi[2]) - n.lo[2];
    double area = dx * dy + dy * dz + dz * dx;
    if (std::isnan(area)) area = INFINITY;
    Costs first, second;
    if (parallel_depth > 0) {
      // std::async joins and passes an exception on (a std::thread left
      // joinable by one would terminate the program).
      auto other = std::async(std::launch::async, [&] { plan(n.first, first, parallel_depth - 1); });
      plan(n.offset, second, parallel_depth - 1);
      other.get();
    } else {
      plan(n.first, first, 0);
      plan(n.offset, second, 0);
    }
    Choices& choice = choice_[m];
    // m as a wide node: the best split of its slots between its children.
    double best = INFINITY;
    choice[0] = 1;
    for (int j = 1; j < kBvhWidth; ++j) {
      const double c = first[j - 1] + second[kBvhWidth - j - 1];
      if (c < best) {
        best = c;
        choice[0] = static_cast<uint8_t>(j);
      }
    }
    // A wide node also adds a count too small to matter beside any area: of
    // plans of equal area (a subtree of points, or of segments along an
    // axis, has none) the one with fewer nodes wins.
    costs[0] = area + kWideNodeTieBreak + best;
    for (int k = 2; k <= kBvhWidth; ++k) {
      double cost = costs[0];
      choice[k - 1] = 0;
      for (int j = 1; j < k; ++j) {
        const double c = first[j - 1] + second[k - j - 1];
        if (c < cost) {
          cost = c;
          choice[k - 1] = static_cast<uint8_t>(j);
        }
      }
      costs[k - 1] = cost;
    }
  }

  const NodeArena& tree_;
  Choices* choice_;  // by binary node index; written for interior nodes only
  size_t size_;
};

// Collapses the binary tree into wide nodes, each node's slots as the plan
// says. A first pass counts the wide nodes, so their array is allocated once
// at its size (no over-reserve and copy).
class Collapser {
 public:
  Collapser(const NodeArena& tree, const CollapsePlan& plan, double pad, Bvh& out)
      : tree_(tree), plan_(plan), pad_(pad), out_(out) {}

  size_t count(uint32_t binary_index) const {
    uint32_t slots[kBvhWidth];
    const int used = open_slots(binary_index, slots);
    size_t n = 1;
    for (int i = 0; i < used; ++i)
      if (tree_[slots[i]].count == 0) n += count(slots[i]);
    return n;
  }

  // The whole tree into out.nodes, the root's subtrees on `threads` threads:
  // each subtree's nodes are counted first, so each knows where its range of
  // the array starts, and the layout is the serial collapse's, node for node.
  void collapse_all(uint32_t root, int threads) {
    uint32_t slots[kBvhWidth];
    const int used = open_slots(root, slots);
    size_t size[kBvhWidth] = {};
    for_each_subtree(used, threads, [&](int i) {
      if (tree_[slots[i]].count == 0) size[i] = count(slots[i]);
    });
    size_t total = 1;
    for (int i = 0; i < used; ++i) total += size[i];
    out_.nodes.resize(total);
    uint32_t first[kBvhWidth] = {};
    size_t next = 1;
    for (int i = 0; i < used; ++i) {
      first[i] = static_cast<uint32_t>(next);
      next += size[i];
    }
    write_node(0, slots, used);
    for_each_subtree(used, threads, [&](int i) {
      const BinaryNode& n = tree_[slots[i]];
      if (n.count > 0) return;
      Collapser subtree(tree_, plan_, pad_, out_);
      subtree.next_ = first[i];
      out_.nodes[0].child[i] = subtree.collapse(slots[i]);
    });
  }

  uint32_t collapse(uint32_t binary_index) {
    const uint32_t index = next_++;
    uint32_t slots[kBvhWidth];
    const int used = open_slots(binary_index, slots);
    write_node(index, slots, used);
    for (int i = 0; i < used; ++i)
      if (tree_[slots[i]].count == 0) {
        const uint32_t child = collapse(slots[i]);
        out_.nodes[index].child[i] = child;
      }
    return index;
  }

 private:
  // The node's boxes and its leaves; interior children are set by the caller.
  void write_node(uint32_t index, const uint32_t (&slots)[kBvhWidth], int used) {
    BvhNode& node = out_.nodes[index];
    for (int i = 0; i < kBvhWidth; ++i) {
      node.child[i] = 0;
      node.count[i] = 0;
      for (int a = 0; a < 3; ++a) {
        if (i < used) {
          const Bounds3 b = tree_[slots[i]].bounds();
          node.bounds[2 * a][i] = round_down(b.lo[a] - pad_);
          node.bounds[2 * a + 1][i] = round_up(b.hi[a] + pad_);
        } else {
          node.bounds[2 * a][i] = INFINITY;  // empty: never hit
          node.bounds[2 * a + 1][i] = -INFINITY;
        }
      }
    }
    for (int i = 0; i < used; ++i) {
      const BinaryNode& n = tree_[slots[i]];
      if (n.count > 0) {
        node.child[i] = n.offset;
        node.count[i] = n.count;
      }
    }
  }

  template <class Task>
  static void for_each_subtree(int used, int threads, const Task& task) {
    std::atomic<int> next{0};
    auto worker = [&] {
      for (int i = next++; i < used; i = next++) task(i);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < std::min(threads, used); ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
  }

  // The binary nodes that become the wide node's children.
  int open_slots(uint32_t binary_index, uint32_t (&slots)[kBvhWidth]) const {
    if (tree_[binary_index].count > 0) {
      slots[0] = binary_index;  // a root that is a leaf: one leaf slot
      return 1;
    }
    return plan_.slots_of(binary_index, slots);
  }

  const NodeArena& tree_;
  const CollapsePlan& plan_;
  double pad_;
  Bvh& out_;
  uint32_t next_ = 0;
};

int build_threads(const BvhBuildOptions& options) {
  return options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

bool is_finite_box(const Bounds3& b) { return !b.empty() && is_finite(b.lo) && is_finite(b.hi); }

// The build from float boxes (`refs`) and the scene's box in double.
Bvh build_from_refs(PrimRefs refs, const Bounds3& scene, const BvhBuildOptions& options,
                    const Vec3& origin_hint) {
  Bvh bvh;
  if (refs.empty()) return bvh;
  // 2^d subtrees for d levels of threads: a few per core balances uneven splits.
  const int threads = build_threads(options);
  int parallel_depth = 0;
  while (threads > 1 && (1 << parallel_depth) < 4 * threads && parallel_depth < 8) ++parallel_depth;
  // A binary tree over n primitives has at most 2n - 1 nodes; each builder
  // (fewer than 2^(d+1)) may leave part of its last chunk unused.
  NodeArena tree(2 * refs.size() + (size_t{2} << parallel_depth) * NodeArena::kChunk);
  const uint32_t root = Builder(refs, options, tree, parallel_depth).build(0, refs.size(), 0);
  // Leaves name ranges of the reordered refs: their ids, in order, are the
  // primitive list.
  bvh.primitives.resize(refs.size());
  for (size_t i = 0; i < refs.size(); ++i) bvh.primitives[i] = refs[i].id;
  const size_t refs_count = refs.size();
  refs = PrimRefs();  // freed before the collapse (`= {}` would keep the capacity)
  // Rays are tested in float: pad boxes by more than the float rounding of
  // coordinates as large as the scene's (and the camera's) farthest point.
  const double extent =
      std::max({max_abs_component(scene.lo), max_abs_component(scene.hi), max_abs_component(origin_hint), 1e-30});
  const double pad = extent * 0x1p-20;
  const bool parallel = refs_count >= kParallelMinPrimitives;
  CollapsePlan plan(tree, tree.used());
  plan.plan(root, parallel ? std::min(parallel_depth, 3) : 0);  // 8 subtrees: the plan is a small part of the build
  Collapser(tree, plan, pad, bvh).collapse_all(root, parallel ? threads : 1);
  return bvh;
}

}  // namespace

Bvh build_bvh(std::span<const Bounds3> bounds, const BvhBuildOptions& options, const Vec3& origin_hint) {
  PrimRefs refs;
  refs.reserve(bounds.size());
  Bounds3 scene;
  for (size_t i = 0; i < bounds.size(); ++i) {
    if (!is_finite_box(bounds[i])) continue;
    const Bounds3& b = bounds[i];
    refs.push_back(PrimRef{{round_down(b.lo.x), round_down(b.lo.y), round_down(b.lo.z)},
                           static_cast<uint32_t>(i),
                           {round_up(b.hi.x), round_up(b.hi.y), round_up(b.hi.z)},
                           0.0f});
    scene.extend(b);
  }
  return build_from_refs(std::move(refs), scene, options, origin_hint);
}

Bvh build_bvh_over_float_boxes(size_t count, const std::function<void(size_t, size_t, FloatBox*)>& boxes_of,
                               const BvhBuildOptions& options, const Vec3& origin_hint) {
  // Each thread fills its own range of refs (primitives with a non-finite or
  // empty box left out) and its part of the scene's box, in float: the same
  // values build_bvh's double box would hold. The ranges are then closed up,
  // which moves nothing when every box is finite.
  const size_t threads = count < kParallelMinPrimitives ? 1 : static_cast<size_t>(build_threads(options));
  PrimRefs refs(count);
  std::vector<size_t> kept(threads, 0);
  std::vector<Box4f> scene_part(threads);
  auto fill = [&](size_t part) {
    const size_t begin = count * part / threads, end = count * (part + 1) / threads;
    size_t out = begin;
    Box4f scene;
    FloatBox boxes[kFloatBoxRange];
    for (size_t range = begin; range < end; range += kFloatBoxRange) {
      const size_t range_end = std::min(end, range + kFloatBoxRange);
      boxes_of(range, range_end, boxes);
      for (size_t i = range; i < range_end; ++i) {
        const FloatBox& b = boxes[i - range];
        bool finite = true;
        for (int a = 0; a < 3; ++a)
          finite = finite && std::isfinite(b.lo[a]) && std::isfinite(b.hi[a]) && b.lo[a] <= b.hi[a];
        if (!finite) continue;
        refs[out] = PrimRef{{b.lo[0], b.lo[1], b.lo[2]}, static_cast<uint32_t>(i), {b.hi[0], b.hi[1], b.hi[2]}, 0.0f};
        scene.extend(refs[out].lo4(), refs[out].hi4());
        ++out;
      }
    }
    kept[part] = out - begin;
    scene_part[part] = scene;
  };
  {
    std::vector<std::thread> pool;
    for (size_t part = 1; part < threads; ++part) pool.emplace_back(fill, part);
    fill(0);
    for (std::thread& t : pool) t.join();
  }
  size_t total = kept[0];
  Box4f scene = scene_part[0];
  for (size_t part = 1; part < threads; ++part) {
    const size_t begin = count * part / threads;
    if (total != begin) std::copy(refs.begin() + begin, refs.begin() + begin + kept[part], refs.begin() + total);
    total += kept[part];
    scene.extend(scene_part[part]);
  }
  refs.resize(total);
  const Bounds3 scene_bounds = scene.to_bounds();
  return build_from_refs(std::move(refs), scene_bounds, options, origin_hint);
}

}  // namespace glint
