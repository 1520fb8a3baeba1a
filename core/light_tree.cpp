// light_tree.cpp — building the light BVH (binned SAH with the orientation cost;
// large subtrees in parallel, into slots fixed in advance, so the tree does not
// depend on the threads).
#include "core/light_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/parallel.h"

namespace pmc {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kBuckets = 12;
constexpr int kSahDepth = 36;             // deeper: halve by count (at most 24 more levels for 2^24 lights)
constexpr size_t kParallelLights = 4096;  // nodes of at least this many lights build their children at once

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 v3(const float* f) { return {f[0], f[1], f[2]}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 scale(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
V3 add(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
double clamp1(double c) { return std::max(-1.0, std::min(1.0, c)); }

// A set of directions: within theta of w (empty: no light yet).
struct Cone {
  V3 w{0, 0, 1};
  double theta = 0.0;
  bool empty = true;
};

// The smallest cone (of this construction) holding both (pbrt-v4's DirectionCone Union).
Cone cone_union(const Cone& a, const Cone& b) {
  if (a.empty || b.theta >= kPi) return b;
  if (b.empty || a.theta >= kPi) return a;
  const V3 ab = cross(a.w, b.w);
  const double theta_d = std::atan2(std::sqrt(dot(ab, ab)), dot(a.w, b.w));  // well conditioned near 0 and pi
  if (std::min(theta_d + b.theta, kPi) <= a.theta) return a;
  if (std::min(theta_d + a.theta, kPi) <= b.theta) return b;
  const double theta_o = 0.5 * (a.theta + theta_d + b.theta);
  Cone whole;
  whole.empty = false;
  whole.theta = kPi;
  if (theta_o >= kPi) return whole;
  V3 k = cross(a.w, b.w);
  const double len = std::sqrt(dot(k, k));
  if (!(len > 1e-12)) return whole;
  k = scale(k, 1.0 / len);
  const double theta_r = theta_o - a.theta;  // turn a's axis toward b's about k (Rodrigues, k _|_ a.w)
  V3 w = add(scale(a.w, std::cos(theta_r)), scale(cross(k, a.w), std::sin(theta_r)));
  w = scale(w, 1.0 / std::sqrt(dot(w, w)));
  Cone c;
  c.empty = false;
  c.w = w;
  c.theta = theta_o;
  return c;
}

// Everything below a node.
struct Aggregate {
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  double energy = 0.0;
  Cone cone;
  double theta_e = 0.0;
  bool two_sided = false;

  void add(const LightBounds& b) {
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], double(b.lo[k])), hi[k] = std::max(hi[k], double(b.hi[k]));
    energy += b.energy;
    Cone c;
    c.empty = false;
    c.w = v3(b.axis);
    c.w = scale(c.w, 1.0 / std::sqrt(dot(c.w, c.w)));  // unit in double: angles between near-equal axes hold
    c.theta = std::acos(clamp1(b.cos_theta_o));
    cone = cone_union(cone, c);
    theta_e = std::max(theta_e, std::acos(clamp1(b.cos_theta_e)));
    two_sided = two_sided || b.two_sided;
  }
  void add(const Aggregate& o) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], o.lo[k]), hi[k] = std::max(hi[k], o.hi[k]);
    energy += o.energy;
    cone = cone_union(cone, o.cone);
    theta_e = std::max(theta_e, o.theta_e);
    two_sided = two_sided || o.two_sided;
  }
  double surface_area() const {
    const double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    return 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
  }
  // The measure of the directions the node emits into (the paper's M_Omega).
  double orientation_measure() const {
    const double theta_o = cone.theta, theta_w = std::min(theta_o + theta_e, kPi);
    const double s = std::sin(theta_o), c = std::cos(theta_o);
    return 2.0 * kPi * (1.0 - c) +
           0.5 * kPi * (2.0 * theta_w * s - std::cos(theta_o - 2.0 * theta_w) - 2.0 * theta_o * s + c);
  }
  // The cost of this side of a split (the paper's, without the parent's
  // aspect factor, which the split adds: it is the same for both sides).
  double cost() const { return energy * orientation_measure() * std::max(surface_area(), 1e-30); }
  // How much splitting along `dim` is penalised: the box's longest side over
  // its side along dim (pbrt-v4's Kr; thin slabs make poor children).
  double aspect(int dim) const {
    const double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    const double longest = std::max(d[0], std::max(d[1], d[2]));
    return d[dim] > 0.0 ? longest / d[dim] : 1.0;
  }
};

double centroid(const LightBounds& b, int k) { return 0.5 * (double(b.lo[k]) + double(b.hi[k])); }

class Builder {
 public:
  Builder(const std::vector<LightBounds>& lights, LightTree& tree) : lights_(lights), tree_(tree) {
    single_.resize(lights.size());
    for (size_t i = 0; i < lights.size(); ++i) single_[i].add(lights[i]);
  }

  // Builds the node of lights order[begin, end) at `depth` with way `trail`
  // into tree_.nodes[index] and the 2 (end - begin) - 2 slots after it (a
  // subtree over n lights has 2n - 1 nodes, so each child knows its slots in
  // advance, and large siblings build at once on TBB's workers: the same
  // tree as one thread builds); returns its bounds, the union of its
  // children's (so a node's bounds hold its children's, and each is as tight
  // as its own lights allow), and in *deepest its deepest leaf's depth.
  Aggregate build(std::vector<uint32_t>& order, size_t begin, size_t end, int depth, uint64_t trail,
                  size_t index, int* deepest) {
    if (depth >= kMaxLightTreeDepth) fail("light tree: deeper than ", kMaxLightTreeDepth, " levels");
    if (end - begin == 1) {
      const Aggregate& one = single_[order[begin]];
      tree_.nodes[index] = node_of(one);
      tree_.nodes[index].flags |= PMC_TREE_LEAF;
      tree_.nodes[index].second = lights_[order[begin]].light;
      tree_.trails[order[begin]] = trail;
      *deepest = depth;
      return one;
    }
    const size_t mid = split(order, begin, end, depth);
    const size_t second = index + 2 * (mid - begin);
    Aggregate all, other;
    int deep_first = 0, deep_second = 0;
    auto first_child = [&] { all = build(order, begin, mid, depth + 1, trail, index + 1, &deep_first); };
    auto second_child = [&] {
      other = build(order, mid, end, depth + 1, trail | (uint64_t(1) << depth), second, &deep_second);
    };
    if (end - begin >= kParallelLights) {
      parallel_both(first_child, second_child);
    } else {
      first_child();
      second_child();
    }
    all.add(other);
    tree_.nodes[index] = node_of(all);
    tree_.nodes[index].second = uint32_t(second);
    *deepest = std::max(deep_first, deep_second);
    return all;
  }

 private:
  static PmcLightTreeNode node_of(const Aggregate& a) {
    PmcLightTreeNode n{};
    for (int k = 0; k < 3; ++k) n.lo[k] = float(a.lo[k]), n.hi[k] = float(a.hi[k]);
    n.energy = float(a.energy);
    n.axis[0] = float(a.cone.w.x), n.axis[1] = float(a.cone.w.y), n.axis[2] = float(a.cone.w.z);
    // Round the cone outward: a float cosine a hair smaller is a hair wider.
    // (1e-6 radians more: the axis is rounded to float too)
    n.cos_theta_o =
        a.cone.theta >= kPi - 1e-6 ? -1.0f : std::nextafter(float(std::cos(a.cone.theta + 1e-6)), -2.0f);
    n.cos_theta_e = std::nextafter(float(std::cos(a.theta_e)), -2.0f);
    n.flags = a.two_sided ? PMC_TREE_TWO_SIDED : 0u;
    return n;
  }

  // Reorders order[begin, end) and returns where the second child starts.
  size_t split(std::vector<uint32_t>& order, size_t begin, size_t end, int depth) {
    double clo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, chi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (size_t i = begin; i < end; ++i)
      for (int k = 0; k < 3; ++k) {
        const double c = centroid(lights_[order[i]], k);
        clo[k] = std::min(clo[k], c), chi[k] = std::max(chi[k], c);
      }
    int widest = 0;
    for (int k = 1; k < 3; ++k)
      if (chi[k] - clo[k] > chi[widest] - clo[widest]) widest = k;
    auto halve = [&](int dim) {
      const size_t mid = begin + (end - begin) / 2;
      std::nth_element(order.begin() + long(begin), order.begin() + long(mid), order.begin() + long(end),
                       [&](uint32_t a, uint32_t b) {
                         const double ca = centroid(lights_[a], dim), cb = centroid(lights_[b], dim);
                         return ca < cb || (ca == cb && a < b);
                       });
      return mid;
    };
    if (depth >= kSahDepth || !(chi[widest] > clo[widest])) return halve(widest);

    double best_cost = HUGE_VAL;
    int best_dim = -1, best_bucket = -1;
    for (int dim = 0; dim < 3; ++dim) {
      const double extent = chi[dim] - clo[dim];
      if (!(extent > 0.0)) continue;
      Aggregate bucket[kBuckets];
      for (size_t i = begin; i < end; ++i)
        bucket[bucket_of(order[i], dim, clo[dim], extent)].add(single_[order[i]]);
      // Costs of every split "buckets [0, s] | (s, end)", from both ends.
      Aggregate below[kBuckets], above[kBuckets];
      for (int s = 0; s < kBuckets; ++s) {
        if (s > 0) below[s] = below[s - 1];
        below[s].add(bucket[s]);
      }
      for (int s = kBuckets - 1; s >= 0; --s) {
        if (s < kBuckets - 1) above[s] = above[s + 1];
        above[s].add(bucket[s]);
      }
      const double kr = below[kBuckets - 1].aspect(dim);  // the whole node's
      for (int s = 0; s + 1 < kBuckets; ++s) {
        if (below[s].lo[0] > below[s].hi[0] || above[s + 1].lo[0] > above[s + 1].hi[0])
          continue;  // one side empty
        const double c = kr * (below[s].cost() + above[s + 1].cost());
        if (c < best_cost) best_cost = c, best_dim = dim, best_bucket = s;
      }
    }
    if (best_dim < 0) return halve(widest);
    const double lo = clo[best_dim], extent = chi[best_dim] - clo[best_dim];
    auto it = std::stable_partition(order.begin() + long(begin), order.begin() + long(end), [&](uint32_t l) {
      return bucket_of(l, best_dim, lo, extent) <= best_bucket;
    });
    const size_t mid = size_t(it - order.begin());
    if (mid == begin || mid == end) return halve(widest);
    return mid;
  }

  int bucket_of(uint32_t light, int dim, double lo, double extent) const {
    const int b = int(double(kBuckets) * (centroid(lights_[light], dim) - lo) / extent);
    return std::max(0, std::min(kBuckets - 1, b));
  }

  const std::vector<LightBounds>& lights_;
  std::vector<Aggregate> single_;  // each light's own bounds (its angles computed once)
  LightTree& tree_;
};

}  // namespace

LightTree build_light_tree(const std::vector<LightBounds>& lights) {
  LightTree tree;
  if (lights.empty()) return tree;
  tree.trails.assign(lights.size(), 0);
  tree.nodes.resize(2 * lights.size() - 1);
  std::vector<uint32_t> order(lights.size());
  std::iota(order.begin(), order.end(), 0u);
  Builder(lights, tree).build(order, 0, order.size(), 0, 0, 0, &tree.depth);
  return tree;
}

}  // namespace pmc
