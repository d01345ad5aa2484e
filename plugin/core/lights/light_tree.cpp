#include "core/lights/light_tree.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/fog/fog_twin.h"

namespace atmo::lights {

namespace {

constexpr int kBitsPerAxis = 18;  // 54-bit Morton codes: a 1 000 km scene in 4-metre cells
constexpr int kKindShift = 3 * kBitsPerAxis;  // the light's kind above them

// A two-way cone's axis, turned to the half-space of a fixed direction (so that like cones agree).
glm::vec3 canonical_axis(const fog::FrameLight& l) {
  return l.lobes > 1.5f && glm::dot(l.axis_enu, glm::vec3(0.31f, 0.53f, 0.79f)) < 0.0f ? -l.axis_enu : l.axis_enu;
}

// 0: omnidirectional; else 1 + the nearest of the 26 directions of a cube's faces, edges and corners to the
// axis (each component to -1, 0 or 1 past sin 22.5 degrees), x2 for two-way, x2 for cones wider than 30 degrees.
uint64_t light_kind(const fog::FrameLight& l) {
  if (l.cos_outer < -1.5f) return 0;
  const glm::vec3 a = canonical_axis(l);
  int cell = 0;
  for (int k = 0; k < 3; ++k) cell = cell * 3 + (a[k] > 0.383f ? 2 : a[k] < -0.383f ? 0 : 1);
  const uint64_t two_way = l.lobes > 1.5f ? 1 : 0, wide = l.cos_outer < 0.866f ? 1 : 0;
  return 1 + static_cast<uint64_t>(cell) + 27 * (two_way + 2 * wide);
}

// The bits of v spread to every third place.
uint64_t spread3(uint64_t v) {
  v &= (uint64_t(1) << kBitsPerAxis) - 1;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

float peak(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

// Stable LSD radix sort of (code, light) by code, 11 bits a pass, passes whose digit is the same for all skipped.
void sort_by_code(std::vector<uint64_t>* codes, std::vector<uint32_t>* order) {
  constexpr int kDigit = 11;
  constexpr uint64_t kMask = (1u << kDigit) - 1;
  const size_t n = codes->size();
  std::vector<uint64_t> code_tmp(n);
  std::vector<uint32_t> order_tmp(n);
  std::vector<uint32_t> count(size_t(1) << kDigit);
  for (int shift = 0; shift < 64; shift += kDigit) {
    std::fill(count.begin(), count.end(), 0u);
    for (uint64_t c : *codes) ++count[(c >> shift) & kMask];
    if (count[((*codes)[0] >> shift) & kMask] == n) continue;  // one digit for all
    uint32_t sum = 0;
    for (uint32_t& c : count) sum += std::exchange(c, sum);
    for (size_t i = 0; i < n; ++i) {
      const uint32_t at = count[((*codes)[i] >> shift) & kMask]++;
      code_tmp[at] = (*codes)[i];
      order_tmp[at] = (*order)[i];
    }
    codes->swap(code_tmp);
    order->swap(order_tmp);
  }
}

// Leaf i (the i-th light in tree order) is node leaves_at + i; the internal nodes come first, in preorder.
struct Builder {
  const std::vector<uint64_t>& codes;
  LightTree* tree;
  int32_t leaves_at;
  int32_t next = 0;

  // The node of order[first, last); returns its index. Splits where the highest bit that differs
  // between the first and last codes turns on (the codes are sorted), at the middle when all are equal.
  int32_t build(uint32_t first, uint32_t last) {
    if (last - first == 1) return leaves_at + static_cast<int32_t>(first);
    const int32_t id = next++;
    LightTree::Node& n = tree->nodes[static_cast<size_t>(id)];
    n.first = first;
    n.count = last - first;
    uint32_t split = first + n.count / 2;
    const uint64_t differ = codes[first] ^ codes[last - 1];
    if (differ) {
      const uint64_t bit = uint64_t(1) << (63 - __builtin_clzll(differ));
      split = static_cast<uint32_t>(
          std::partition_point(codes.begin() + first, codes.begin() + last, [&](uint64_t c) { return !(c & bit); }) -
          codes.begin());
    }
    n.left = build(first, split);
    n.right = build(split, last);
    const LightTree::Node& a = tree->nodes[static_cast<size_t>(n.left)];
    const LightTree::Node& b = tree->nodes[static_cast<size_t>(n.right)];
    n.lo = glm::min(a.lo, b.lo);
    n.hi = glm::max(a.hi, b.hi);
    n.power = a.power + b.power;
    n.peak = a.peak + b.peak;
    n.omni = a.omni + b.omni;
    n.cone = a.cone + b.cone;
    n.axis_sum = a.axis_sum + b.axis_sum;
    n.cos_inner_sum = a.cos_inner_sum + b.cos_inner_sum;
    n.cos_outer_sum = a.cos_outer_sum + b.cos_outer_sum;
    n.two_way = a.two_way + b.two_way;
    n.mean_sum = a.mean_sum + b.mean_sum;
    const float wa = a.peak + 1e-30f, wb = b.peak + 1e-30f;
    n.centre = (wa * a.centre + wb * b.centre) / (wa + wb);
    n.variance_m2 = (wa * (a.variance_m2 + glm::dot(a.centre - n.centre, a.centre - n.centre)) +
                     wb * (b.variance_m2 + glm::dot(b.centre - n.centre, b.centre - n.centre))) /
                    (wa + wb);
    n.beta_min = std::min(a.beta_min, b.beta_min);
    n.beta_mean = (wa * a.beta_mean + wb * b.beta_mean) / (wa + wb);
    const float from_children = std::max(glm::length(n.centre - a.centre) + a.radius_m,
                                         glm::length(n.centre - b.centre) + b.radius_m);
    const float from_box = 0.5f * glm::length(n.hi - n.lo) + glm::length(n.centre - 0.5f * (n.lo + n.hi));
    n.radius_m = std::min(from_children, from_box);
    return id;
  }
};

// Light l as leaf node `i` of the tree (its place in tree order).
LightTree::Node leaf(const fog::FrameLight& l, uint32_t i) {
  LightTree::Node n;
  n.first = i;
  n.count = 1;
  n.lo = n.hi = n.centre = l.position_enu_m;
  n.power = l.intensity_cd * l.mean_profile;
  n.peak = peak(l.intensity_cd);
  n.beta_min = n.beta_mean = l.beta_per_m;
  if (l.cos_outer < -1.5f) {
    n.omni = n.peak;
  } else {
    n.cone = n.peak;
    n.axis_sum = n.peak * canonical_axis(l);
    n.cos_inner_sum = n.peak * l.cos_inner;
    n.cos_outer_sum = n.peak * l.cos_outer;
    n.two_way = l.lobes > 1.5f ? n.peak : 0.0f;
    n.mean_sum = n.peak * l.mean_profile;
  }
  return n;
}

}  // namespace

NodeCone node_cone(const LightTree::Node& n) {
  NodeCone c;
  if (!(n.cone > 0.0f)) return c;
  const float length = glm::length(n.axis_sum);
  c.agree = std::min(length / n.cone, 1.0f);
  if (length > 0.0f) c.axis = n.axis_sum / length;
  c.cos_inner = n.cos_inner_sum / n.cone;
  c.cos_outer = n.cos_outer_sum / n.cone;
  c.two_way = n.two_way / n.cone;
  return c;
}

float node_intensity_towards(const LightTree::Node& n, const glm::vec3& w) {
  if (!(n.cone > 0.0f)) return n.omni;
  const NodeCone c = node_cone(n);
  const float one = fog::twin::atmo_fog_cone(c.axis, c.cos_inner, c.cos_outer, 1.0f, w);
  const float both = fog::twin::atmo_fog_cone(c.axis, c.cos_inner, c.cos_outer, 2.0f, w);
  const float as_one_cone = (1.0f - c.two_way) * one + c.two_way * both;
  return n.omni + n.cone * (c.agree * as_one_cone + (1.0f - c.agree) * n.mean_sum / n.cone);
}

double node_spread_gain(const LightTree::Node& n, double distance_m, double beta_per_m) {
  const double d = std::max(distance_m, 1e-3);
  return std::min(1.0 + n.variance_m2 / 6.0 * (beta_per_m * beta_per_m + 2.0 * beta_per_m / d + 2.0 / (d * d)), 2.0);
}

float distance_to_box(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi) {
  return glm::length(glm::max(glm::max(lo - p, p - hi), glm::vec3(0.0f)));
}

LightTree build_light_tree(const std::vector<fog::FrameLight>& lights) {
  LightTree tree;
  build_light_tree(lights, &tree);
  return tree;
}

void build_light_tree(const std::vector<fog::FrameLight>& lights, LightTree* tree) {
  const size_t n = lights.size();
  tree->nodes.clear();
  tree->order.clear();
  if (n == 0) return;
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const fog::FrameLight& l : lights) {
    lo = glm::min(lo, l.position_enu_m);
    hi = glm::max(hi, l.position_enu_m);
  }
  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-6f});
  const double scale = double((1u << kBitsPerAxis) - 1) / double(extent);
  std::vector<uint64_t> codes(n);
  tree->order.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 q = (glm::dvec3(lights[i].position_enu_m) - glm::dvec3(lo)) * scale;
    codes[i] = spread3(uint64_t(q.x)) | spread3(uint64_t(q.y)) << 1 | spread3(uint64_t(q.z)) << 2 |
               light_kind(lights[i]) << kKindShift;
    tree->order[i] = static_cast<uint32_t>(i);
  }
  sort_by_code(&codes, &tree->order);
  // The leaves in tree order first, in one pass (the lights' reads overlap; the build then reads leaves in
  // order), then the internal nodes over them.
  tree->nodes.resize(2 * n - 1);
  const size_t leaves_at = n - 1;
  tree->dimmest_peak = 0.0f;
  for (size_t i = 0; i < n; ++i) {
    const LightTree::Node& l = tree->nodes[leaves_at + i] = leaf(lights[tree->order[i]], static_cast<uint32_t>(i));
    if (l.peak > 0.0f && (tree->dimmest_peak == 0.0f || l.peak < tree->dimmest_peak)) tree->dimmest_peak = l.peak;
  }
  Builder{codes, tree, static_cast<int32_t>(leaves_at)}.build(0, static_cast<uint32_t>(n));
}

}  // namespace atmo::lights
