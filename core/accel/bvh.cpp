#include "core/accel/bvh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <limits>

#include "core/base/timing.h"

namespace gs {
namespace {

constexpr int kBins = 16;
constexpr double kTraversalCost = 1.0, kIntersectionCost = 1.0;

struct DBox {
  double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
  void extend(const DBox& b) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], b.lo[a]), hi[a] = std::max(hi[a], b.hi[a]);
  }
  double area() const {
    if (lo[0] > hi[0]) return 0.0;
    const double e[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    return 2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
  }
};

}  // namespace

// Build state: per usable triangle its padded box and centroid; nodes appended in
// depth-first order with siblings adjacent.
struct Bvh::Builder {
  Bvh& bvh;
  std::vector<DBox> boxes;
  std::vector<std::array<double, 3>> centroids;
  std::vector<uint32_t> ids;  // reordered into leaf order
  const std::vector<TriangleVerts>& verts;

  struct Split {
    int axis = -1;
    int bin = 0;  // triangles with bin <= this go left
    double cost = kInf;
    double lo = 0, scale = 0;
  };

  int bin_of(uint32_t id, const Split& s) const {
    return std::clamp(int((centroids[id][s.axis] - s.lo) * s.scale), 0, kBins - 1);
  }

  // The binned SAH over [begin, end): the cheapest split among the 15 bin borders of
  // each axis whose centroids are not all equal.
  Split best_split(uint32_t begin, uint32_t end, double parent_area) const {
    Split best;
    for (int a = 0; a < 3; ++a) {
      double lo = kInf, hi = -kInf;
      for (uint32_t i = begin; i < end; ++i)
        lo = std::min(lo, centroids[ids[i]][a]), hi = std::max(hi, centroids[ids[i]][a]);
      if (!(hi > lo)) continue;
      Split s{a, 0, kInf, lo, kBins / (hi - lo)};
      DBox bins[kBins];
      uint32_t counts[kBins] = {};
      for (uint32_t i = begin; i < end; ++i) {
        const int b = bin_of(ids[i], s);
        bins[b].extend(boxes[ids[i]]), ++counts[b];
      }
      double right_area[kBins];
      uint32_t right_count[kBins];
      DBox right;
      uint32_t n = 0;
      for (int b = kBins - 1; b > 0; --b) {
        right.extend(bins[b]), n += counts[b];
        right_area[b] = right.area(), right_count[b] = n;
      }
      DBox left;
      uint32_t m = 0;
      for (int b = 0; b + 1 < kBins; ++b) {
        left.extend(bins[b]), m += counts[b];
        if (m == 0 || right_count[b + 1] == 0) continue;
        const double cost =
            kTraversalCost + kIntersectionCost *
                                 (left.area() * m + right_area[b + 1] * right_count[b + 1]) /
                                 parent_area;
        if (cost < best.cost) best = s, best.bin = b, best.cost = cost;
      }
    }
    return best;
  }

  // Splits [begin, end) and returns the middle; by the SAH split if there is one, else
  // at the median along the axis where centroids spread most (or in half, when they are
  // all equal: coincident triangles).
  uint32_t partition(uint32_t begin, uint32_t end, const Split& split) {
    if (split.axis >= 0) {
      const auto mid = std::partition(ids.begin() + begin, ids.begin() + end,
                                      [&](uint32_t id) { return bin_of(id, split) <= split.bin; });
      return uint32_t(mid - ids.begin());
    }
    const uint32_t mid = begin + (end - begin) / 2;
    int axis = 0;
    double spread = -1.0;
    for (int a = 0; a < 3; ++a) {
      double lo = kInf, hi = -kInf;
      for (uint32_t i = begin; i < end; ++i)
        lo = std::min(lo, centroids[ids[i]][a]), hi = std::max(hi, centroids[ids[i]][a]);
      if (hi - lo > spread) spread = hi - lo, axis = a;
    }
    std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end,
                     [&](uint32_t x, uint32_t y) {
                       return centroids[x][axis] < centroids[y][axis] ||
                              (centroids[x][axis] == centroids[y][axis] && x < y);
                     });
    return mid;
  }

  // Each triangle lies in exactly one leaf: none needs the mailbox.
  void make_leaf(uint32_t node, uint32_t begin, uint32_t end) {
    std::vector<uint32_t> leaf(ids.begin() + begin, ids.begin() + end);
    for (uint32_t& id : leaf) id |= kOnlyHere;
    bvh.nodes_[node].first = bvh.leaves_.add(leaf, bvh.input_);
    bvh.nodes_[node].count = end - begin;
    ++bvh.leaves_count_;
  }

  void build(uint32_t node, uint32_t begin, uint32_t end, int depth) {
    bvh.deepest_ = std::max(bvh.deepest_, uint64_t(depth));
    DBox box;
    for (uint32_t i = begin; i < end; ++i) box.extend(boxes[ids[i]]);
    for (int a = 0; a < 3; ++a)
      bvh.nodes_[node].lo[a] = float_down(box.lo[a]), bvh.nodes_[node].hi[a] = float_up(box.hi[a]);
    const uint32_t n = end - begin;
    if (n <= 1 || depth + 1 >= bvh.max_depth_) return make_leaf(node, begin, end);
    const Split split = best_split(begin, end, box.area());
    const double leaf_cost = kIntersectionCost * n;
    if (n <= uint32_t(bvh.leaf_size_) && !(split.cost < leaf_cost))
      return make_leaf(node, begin, end);
    // Nodes and leaf headers are what grows with splitting (each triangle is stored once
    // whatever the tree): a split whose two children would exceed the budget is not made.
    // Depth first, so under a tight budget the first subtrees get the nodes.
    if ((bvh.nodes_.size() + 2) * (sizeof(Node) + LeafStore::bytes_for(0)) > bvh.memory_budget_) {
      ++bvh.over_budget_;
      return make_leaf(node, begin, end);
    }
    const uint32_t mid = partition(begin, end, split);
    const uint32_t left = uint32_t(bvh.nodes_.size());
    bvh.nodes_.resize(bvh.nodes_.size() + 2);
    bvh.nodes_[node].first = left;
    bvh.nodes_[node].count = 0;
    build(left, begin, mid, depth + 1);
    build(left + 1, mid, end, depth + 1);
  }
};

Bvh::Bvh(const AccelParams& params)
    : leaf_size_(params.leaf_size_or(kDefaultLeafSize)),
      max_depth_(std::min(params.depth_or(kDefaultMaxDepth), kMaxDepthCap)),
      memory_budget_(params.memory_budget),
      kernel_(kernel_for(kernel_isa())) {}

void Bvh::build(const Scene& scene) {
  const auto start = Clock::now();
  input_ = BuildInput(scene);
  nodes_.clear(), leaves_count_ = over_budget_ = deepest_ = 0;
  // Every triangle is stored once, in at most one leaf per triangle.
  // At worst every triangle is a leaf of its own.
  const auto usable = uint32_t(input_.usable.size());
  leaves_.reset(LeafStore::bytes_for(usable) + uint64_t(usable) * LeafStore::bytes_for(0));
  const std::vector<TriangleVerts>& verts = input_.triangles;
  Builder builder{*this, std::vector<DBox>(verts.size()), {}, input_.usable, verts};
  builder.centroids.resize(verts.size());
  for (const uint32_t id : input_.usable) {
    const TriangleBox box = input_.box(id);  // padded: a node never culls a reported hit
    const TriangleVerts& t = verts[id];
    const glm::dvec3 lo = glm::min(t.v0, glm::min(t.v1, t.v2));
    const glm::dvec3 hi = glm::max(t.v0, glm::max(t.v1, t.v2));
    for (int a = 0; a < 3; ++a) {
      builder.boxes[id].lo[a] = box[a];
      builder.boxes[id].hi[a] = box[a + 3];
      builder.centroids[id][a] = 0.5 * (lo[a] + hi[a]);
    }
  }
  if (!builder.ids.empty()) {
    nodes_.reserve(std::min<uint64_t>(2 * builder.ids.size(), memory_budget_ / sizeof(Node) + 1));
    nodes_.resize(1);
    builder.build(0, 0, uint32_t(builder.ids.size()), 0);
  }
  nodes_.shrink_to_fit();
  input_.release_triangles();
  build_seconds_ = seconds_since(start);
}

std::unique_ptr<ThreadContext> Bvh::make_context() const {
  return std::make_unique<MailboxContext>();
}

namespace {

// gamma(3) of Ize's bound: 3u / (1 - 3u), u = 2^-24, rounded up. A slab distance computed in
// float ((plane - origin) * (1 / dir), three roundings) is within a factor 1 +- gamma(3) of
// the exact one, so moving exits away from the entries by 2 gamma(3) of their magnitude
// never loses a crossing, whatever the signs (rays may start at negative t); 3 gamma(3)
// also covers the rounding of the widening itself.
constexpr float kGamma3 = 1.7881409e-7f;

// x moved toward +infinity by `share` of its magnitude (infinities and NaN unchanged).
float widened(float x, float share) { return x * (1 + std::copysign(share, x)); }

}  // namespace

// The ray as the slab test reads it, in float: per axis the near and far planes' index
// (by the direction's sign) and 1 / dir, which is infinite for a zero component. A plane
// the origin lies on then gives 0 * inf = NaN, which the selects below ignore: that axis
// does not constrain the ray, as it should not.
struct Bvh::RayBox {
  float origin[3], inv_dir[3];
  int near[3];  // 0: lo is the near plane, 1: hi
  float t_lo;   // the ray's clipped start, rounded down
  // The node's entry distance when the ray crosses it before t_hi, else +inf.
  float entry(const Node& node, float t_hi) const {
    const float* planes[2] = {node.lo, node.hi};
    float t0 = t_lo, t1 = t_hi;
    for (int a = 0; a < 3; ++a) {
      const float t_near = (planes[near[a]][a] - origin[a]) * inv_dir[a];
      const float t_far = widened((planes[1 - near[a]][a] - origin[a]) * inv_dir[a], 3 * kGamma3);
      t0 = t_near > t0 ? t_near : t0;
      t1 = t_far < t1 ? t_far : t1;
    }
    return t0 <= t1 ? t0 : std::numeric_limits<float>::infinity();
  }
};

Hit Bvh::intersect(const Ray& ray, ThreadContext& context) const {
  return trace<false>(ray, static_cast<MailboxContext&>(context));
}

Hit Bvh::any_hit(const Ray& ray, ThreadContext& context) const {
  return trace<true>(ray, static_cast<MailboxContext&>(context));
}

// Clips as brute does, then walks the tree nearer child first, skipping every node whose
// entry lies beyond the nearest hit so far (ties kept by `closer`, so an equal-t hit in a
// later node still wins by its lower id). `limit` is that stop distance in float, rounded
// up and widened by Ize's bound for the entry's own rounding. The node tests are made on
// the ray's own line in float; from an origin so far away that the line the kernel tests
// lies off it by more than the padding (WalkLine::far), no node is culled.
template <bool AnyHit>
Hit Bvh::trace(const Ray& ray, MailboxContext& context) const {
  Hit best;
  WalkLine line;
  if (nodes_.empty() || !start_walk(input_.clip, ray, line)) return best;
  const RayBoxes boxes(ray, !line.far);
  const BoxFilter filter = BoxFilter::up_to_tmax(boxes, line, ray.tmax);
  RayBox rb;
  for (int a = 0; a < 3; ++a) {
    rb.origin[a] = line.far ? 0.0f : ray.origin[a];
    rb.inv_dir[a] = line.far ? 0.0f : 1.0f / ray.dir[a];
    rb.near[a] = std::signbit(ray.dir[a]) ? 1 : 0;
  }
  constexpr float kNever = std::numeric_limits<float>::infinity();
  rb.t_lo = line.far ? -kNever : float_down(line.shift - line.slack);
  const auto limit_of = [&](float tmax) {
    return line.far ? kNever : widened(float(stop_distance(tmax, line.slack)), 4 * kGamma3);
  };
  const PreparedRay<KernelReal> prepared(ray, line.shift, line.inv_dir);
  float tmax = ray.tmax;
  float limit = limit_of(tmax);
  TraceCounters& counters = context.counters;
  const uint64_t ray_id = context.mailbox.next_ray();
  struct Entry {
    uint32_t node;
    float t;
  };
  Entry stack[kMaxDepthCap + 2];
  int top = 0;
  constexpr float kMiss = std::numeric_limits<float>::infinity();
  const float t_root = rb.entry(nodes_[0], limit);
  if (t_root < kMiss) stack[top++] = {0, t_root};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.t > limit) continue;
    const Node& node = nodes_[e.node];
    ++counters.traversal_steps;
    if (node.count > 0) {
      if (test_leaf<AnyHit>(leaves_.view(node.first), kernel_, prepared, filter, ray_id, tmax, best,
                            context.mailbox, counters)) {
        if (AnyHit) return best;
        limit = limit_of(tmax);
      }
      continue;
    }
    const float ta = rb.entry(nodes_[node.first], limit);
    const float tb = rb.entry(nodes_[node.first + 1], limit);
    const bool a_first = ta <= tb;
    const Entry near{a_first ? node.first : node.first + 1, a_first ? ta : tb};
    const Entry far{a_first ? node.first + 1 : node.first, a_first ? tb : ta};
    if (far.t < kMiss) stack[top++] = far;
    if (near.t < kMiss) stack[top++] = near;
  }
  return best;
}

StructureStats Bvh::stats() const {
  StructureStats s;
  s.nodes = nodes_.size();
  s.leaves = leaves_count_;
  s.voxels_subdivided = nodes_.size() - leaves_count_;
  s.traversal_states = std::nullopt;
  s.depth = deepest_;
  s.memory_bytes = nodes_.size() * sizeof(Node) + leaves_.bytes();
  s.build_seconds = build_seconds_;
  s.voxels_over_budget = over_budget_;
  return s;
}

}  // namespace gs
