#include "core/lights/light_clusters.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>

#include "core/clouds/parallel_bands.h"

#include "core/fog/fog_twin.h"

namespace atmo::lights {

namespace {

constexpr double kPi = 3.14159265358979323846;
// The largest e^T G_0 of the surface table (5.9 at T = 2 for g = 0.85; < 7 for any phase): the
// single-scattered term's bound in the ranges.
constexpr double kMaxSurfaceG = 7.0;

// A cone light's sphere test (the spot light against a bounding sphere: whether any point of the sphere
// (centre c relative to the light, radius r) lies inside the cone of half-angle `outer` about `axis`).
bool cone_reaches(const glm::dvec3& c, double r, const glm::dvec3& axis, double cos_outer, float lobes) {
  if (cos_outer < -1.5) return true;
  const double sin_outer = std::sqrt(std::max(1.0 - cos_outer * cos_outer, 0.0));
  const double length2 = glm::dot(c, c);
  for (int lobe = 0; lobe < (lobes > 1.5f ? 2 : 1); ++lobe) {
    const double along = glm::dot(c, lobe ? -axis : axis);
    const double across = std::sqrt(std::max(length2 - along * along, 0.0));
    // Distance from the sphere's centre to the cone's surface (negative inside).
    const double to_surface = cos_outer * across - sin_outer * along;
    if (to_surface <= r && along >= -r) return true;
  }
  return false;
}

// e^(-beta d) in float (the cuts' estimates), 1 in clear air without the call.
double fade(float beta_per_m, double d) { return beta_per_m > 0.0f ? std::exp(-beta_per_m * static_cast<float>(d)) : 1.0; }

// Threads that share a view's clusters (each froxel's work is its own: the result is the same for any count).
const int kThreads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 4u));

// In a band's list, an entry naming the band's own merged light (renumbered when the bands are joined).
constexpr uint32_t kMergedFlag = 0x80000000u;

// An entry of a froxel's list stays out when it brings less than this share of its light (as estimated).
constexpr double kNegligibleShare = 0.005;
// A node whose lights lie within this fraction of its distance from the froxel is shaded as one light; and
// from the far field where it is also farther than kFarRadii of the froxel's radii.
constexpr double kFinalSize = 0.2;
constexpr double kFarRadii = 4.0;
// ... and where the fog on the way dims it by less than this optical thickness.
constexpr double kFarFade = 0.5;
// The rest of the cut is merged into one light per this share of the froxel's light (up to kMergedLights).
constexpr double kShareAGroup = 0.05;

// The diffusion (P1) terms A (fluence / 4) and B (flux / 2, per channel) at x from the tree: a node that
// subtends less than ~35 degrees acts as one light at its centre (the P1 field is smooth).
void add_diffusion(const fog::FogFrame& frame, const LightTree& tree, const glm::dvec3& x, glm::dvec3* a,
                   glm::dmat3* b) {
  const auto one = [&](const glm::dvec3& light, const glm::dvec3& power) {
    const glm::dvec3 to = light - x;
    const double d = glm::length(to);
    const double beta = frame.extinction_per_m *
                        fog::twin::atmo_fog_inside_fraction(float(x.z), float(light.z), frame.top_above_eye_m);
    const glm::vec2 p1 = fog::twin::atmo_fog_diffusion_light(frame.diffusion, float(d), float(beta * d), true);
    *a += 0.25 * double(p1.x) * power;
    if (d > 0.0)
      for (int c = 0; c < 3; ++c) (*b)[c] += 0.5 * double(p1.y) * power[c] * (to / d);
  };
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const LightTree::Node& n = tree.nodes[static_cast<size_t>(stack[--top])];
    const glm::dvec3 c(n.centre);
    if (n.leaf() || double(n.radius_m) < 0.6 * glm::length(c - x) || top + 2 > 128) {
      one(c, glm::dvec3(n.power));
    } else {
      stack[top++] = n.right;
      stack[top++] = n.left;
    }
  }
}

// One froxel's cut of the tree (see the header): appends its entries to *lists (nodes as kMergedFlag | their
// index in *merged) and their ranges to *ranges.
struct Cut {
  const fog::FogFrame& frame;
  const LightTree& tree;
  const SurfaceRange& range;

  struct Entry {
    float weight;  // what it may add at the froxel (a bound for a node, the estimate for a light)
    int32_t node;
  };
  static bool lighter(const Entry& a, const Entry& b) {
    return a.weight != b.weight ? a.weight < b.weight : a.node > b.node;  // max-heap, ties: the lower node first
  }
  enum class Reach { kNone, kBelowThreshold, kReaches };

  // The entry for node `id` at the froxel (centre c, radius r), and whether it reaches it: not at all (a cone
  // that points away), only below the threshold (its range falls short: many such may still add up), or so.
  Entry entry(int32_t id, const glm::dvec3& c, double r, Reach* reach) const {
    const LightTree::Node& n = tree.nodes[static_cast<size_t>(id)];
    if (n.leaf()) {
      const fog::FrameLight& l = frame.lights[tree.order[n.first]];
      const glm::dvec3 to = c - glm::dvec3(l.position_enu_m);
      const double d = glm::length(to);
      if (!cone_reaches(to, r, glm::dvec3(l.axis_enu), l.cos_outer, l.lobes)) {
        *reach = Reach::kNone;
        return {0.0f, id};
      }
      *reach = d > double(range(n.peak)) + r ? Reach::kBelowThreshold : Reach::kReaches;
      // Its irradiance at the froxel's centre (the cone towards it), the distance floored at a quarter of the
      // froxel's radius (a light inside the froxel counts as near, not as infinite).
      const double floor_d = std::max(d, std::max(0.25 * r, 0.5));
      const double cone =
          fog::twin::atmo_fog_cone(l.axis_enu, l.cos_inner, l.cos_outer, l.lobes, glm::vec3(to / std::max(d, 1e-6)));
      const double edge = cone > 0.0 ? cone : 0.05;  // on the cone's edge, part of the froxel is still lit
      return {static_cast<float>(n.peak * edge * fade(l.beta_per_m, d) / (floor_d * floor_d)), id};
    }
    const double d_box = distance_to_box(glm::vec3(c), n.lo, n.hi);
    *reach = d_box > double(range(n.peak)) + r ? Reach::kBelowThreshold : Reach::kReaches;
    const double near = std::max(d_box - r, 0.0), floor_d = std::max(near, std::max(0.25 * r, 0.5));
    return {static_cast<float>(n.peak * fade(n.beta_min, near) / (floor_d * floor_d)), id};
  }

  // Node `id`'s irradiance at c (on a surface facing it), lux per channel: `exact`, its lights' own sum; else
  // its cones as one (node_intensity_towards: the peak channel; the colour is its lights' mean) from its
  // centre, the distance no less than its lights' spread about it (the centre may lie between them), with
  // the spread's second-order gain (node_spread_gain).
  glm::dvec3 node_irradiance(int32_t id, const glm::dvec3& c, bool exact) const {
    const LightTree::Node& n = tree.nodes[static_cast<size_t>(id)];
    glm::dvec3 irradiance(0.0);
    if (exact) {
      for (uint32_t k = n.first; k < n.first + n.count; ++k) irradiance += light_irradiance(tree.order[k], c);
      return irradiance;
    }
    const double colour_peak = std::max({n.power.x, n.power.y, n.power.z});
    if (!(colour_peak > 0.0)) return irradiance;
    const glm::dvec3 to = c - glm::dvec3(n.centre);
    const double d = std::max({glm::length(to), std::sqrt(double(n.variance_m2)), 0.5});
    const double towards = node_intensity_towards(n, glm::vec3(to / d));
    return glm::dvec3(n.power) *
           (towards / colour_peak * node_spread_gain(n, d, n.beta_mean) * fade(n.beta_mean, d) / (d * d));
  }

  // Node `id` as one light of the froxel's own: at its centre, with the intensity that gives its irradiance
  // at the froxel's centre c (node_irradiance).
  fog::FrameLight as_light(int32_t id, const glm::dvec3& c, bool exact) const {
    const LightTree::Node& n = tree.nodes[static_cast<size_t>(id)];
    fog::FrameLight v;
    v.position_enu_m = n.centre;
    v.beta_per_m = n.beta_mean;
    v.extent_m = std::sqrt(n.variance_m2);
    const glm::dvec3 to = c - glm::dvec3(n.centre);
    const double d = std::max({glm::length(to), double(v.extent_m), 0.5});
    const glm::dvec3 irradiance = node_irradiance(id, c, exact);
    // Cone lights of one axis (a row of beams) stay one cone: as one omnidirectional light they would light
    // what lies outside their beams, each cluster differently (blocks on the ground).
    const NodeCone cone = node_cone(n);
    if (n.cone > 0.0f && n.omni < 0.05f * n.cone && cone.agree > 0.9f && (cone.two_way < 0.1f || cone.two_way > 0.9f)) {
      v.axis_enu = cone.axis;
      v.cos_inner = cone.cos_inner;
      v.cos_outer = cone.cos_outer;
      v.lobes = cone.two_way > 0.5f ? 2.0f : 1.0f;
      const double towards = fog::twin::atmo_fog_cone(v.axis_enu, v.cos_inner, v.cos_outer, v.lobes,
                                                      glm::vec3(to / std::max(glm::length(to), 1e-6)));
      if (towards > 0.05) {
        v.intensity_cd = glm::vec3(irradiance * (d * d * std::exp(double(n.beta_mean) * d) / towards));
        return v;
      }
      // Off its beams here: as one omnidirectional light.
      v.axis_enu = glm::vec3(0.0f, 0.0f, 1.0f);
      v.cos_inner = v.cos_outer = -2.0f;
      v.lobes = 1.0f;
    }
    v.intensity_cd = glm::vec3(irradiance * (d * d * std::exp(double(n.beta_mean) * d)));
    return v;
  }

  // Light i's irradiance at c on a surface facing it (its cone and fog), lux per channel.
  glm::dvec3 light_irradiance(uint32_t i, const glm::dvec3& c) const {
    const fog::FrameLight& l = frame.lights[i];
    const glm::dvec3 to = glm::dvec3(l.position_enu_m) - c;
    const double d = std::max(glm::length(to), 0.5);
    const double cone = fog::twin::atmo_fog_cone(l.axis_enu, l.cos_inner, l.cos_outer, l.lobes, glm::vec3(-to / d));
    return glm::dvec3(l.intensity_cd) * (cone * fade(l.beta_per_m, d) / (d * d));
  }

  // What an entry of the cut gives at the froxel's centre c.
  struct Item {
    double estimate = 0.0;       // for the ranking: a light's entry weight, else the irradiance's peak channel
    int32_t node = -1;           // -1: lights under the threshold, together
    glm::dvec3 irradiance{0.0};  // lux per channel (a node's from its cones as one)
    glm::dvec3 position{0.0};    // where it stands (a node's weighted centre)
    double peak = 0.0, beta = 0.0, spread = 0.0;  // summed peak intensity, extinction, reach about `position`
    double rms = 0.0;                             // its lights' RMS distance from `position` (m)
    double second = 0.0;                          // while merging: the weighted sum of |position|^2 + rms^2
    uint32_t count = 0;                           // lights
    glm::dvec3 box_lo{INFINITY}, box_hi{-INFINITY};  // while merging (add_to)
  };

  Item item(const Entry& e, const glm::dvec3& c) const {
    const LightTree::Node& n = tree.nodes[static_cast<size_t>(e.node)];
    Item it;
    it.node = e.node;
    it.position = glm::dvec3(n.centre);
    it.peak = n.peak;
    it.beta = n.beta_mean;
    it.spread = n.radius_m;
    it.rms = std::sqrt(double(n.variance_m2));
    it.count = n.count;
    if (n.leaf()) {
      it.irradiance = light_irradiance(tree.order[n.first], c);
      it.estimate = e.weight;
    } else {
      it.irradiance = node_irradiance(e.node, c, false);
      it.estimate = std::max({it.irradiance.x, it.irradiance.y, it.irradiance.z});
    }
    return it;
  }

  // Items [first, last) as one light of the froxel's own at their weighted centre, with their irradiance at
  // the froxel's centre c; appended with its range.
  void add_merged(Item* const* first, Item* const* last, const glm::dvec3& c, std::vector<uint32_t>* lists,
                  std::vector<float>* ranges, std::vector<fog::FrameLight>* merged, uint64_t* merged_lights) const {
    Item m;
    for (Item* const* it = first; it < last; ++it) add_to(&m, **it);
    finish(&m);
    if (!(m.estimate > 0.0)) return;
    fog::FrameLight v;
    v.position_enu_m = glm::vec3(m.position);
    v.beta_per_m = static_cast<float>(m.beta);
    v.extent_m = static_cast<float>(m.rms);
    const double d = std::max({glm::length(m.position - c), m.rms, 0.5});
    v.intensity_cd = glm::vec3(m.irradiance * (d * d * std::exp(m.beta * d)));
    lists->push_back(kMergedFlag | static_cast<uint32_t>(merged->size()));
    ranges->push_back(range(static_cast<float>(m.peak)) + static_cast<float>(m.spread));
    merged->push_back(v);
    *merged_lights += m.count;
  }

  // Items as one: irradiance and counts summed, centre and extinction weighted by the irradiance (add_to each,
  // then finish; until then `position` and `beta` hold weighted sums, `box_lo`/`box_hi` the extent).
  static void add_to(Item* m, const Item& it) {
    const double w = std::max({it.irradiance.x, it.irradiance.y, it.irradiance.z});
    m->irradiance += it.irradiance;
    m->position += w * it.position;
    m->second += w * (glm::dot(it.position, it.position) + it.rms * it.rms);
    m->beta += w * it.beta;
    m->estimate += w;
    m->peak += it.peak;
    m->count += it.count;
    m->box_lo = glm::min(m->box_lo, it.position - it.spread);
    m->box_hi = glm::max(m->box_hi, it.position + it.spread);
  }
  static void finish(Item* m) {
    if (!(m->estimate > 0.0)) return;
    m->position /= m->estimate;
    m->beta /= m->estimate;
    m->rms = std::sqrt(std::max(m->second / m->estimate - glm::dot(m->position, m->position), 0.0));
    m->spread = glm::length(glm::max(m->box_hi - m->position, m->position - m->box_lo));
  }

  // The froxel's list (see the header): best first, the entry that may add the most is opened (a node) or
  // taken (a light: as every node's weight bounds its lights', no light left can add more) until
  // kListLights - kMergedLights lights are taken or kCutOpens nodes opened (what a node opens into that falls
  // short of the threshold alone is kept, together: many may add up); those that add the most are listed one
  // by one, the rest of the cut merged into up to kMergedLights lights (none when they add a negligible
  // share). Appends to *lists (merged lights and nodes as kMergedFlag | their index in
  // *merged) and the entries' ranges to *ranges; returns how many nodes it opened.
  uint64_t list(const glm::dvec3& c, double r, std::vector<uint32_t>* lists, std::vector<float>* ranges,
                std::vector<fog::FrameLight>* merged, uint64_t* merged_lights,
                glm::dvec3 far_faces[LightClusters::kFaces]) const {
    Entry heap[kCutOpensMost + 2];  // each node opened adds at most one entry
    int size = 0;
    Item items[kCutOpensMost + kListLights + 2];
    int taken = 0;
    Item under;  // the lights under the threshold, together (add_to)
    uint64_t opened = 0;
    const auto push = [&](int32_t id) {
      Reach reach;
      const Entry e = entry(id, c, r, &reach);
      if (reach == Reach::kReaches) {
        heap[size++] = e;
        std::push_heap(heap, heap + size, lighter);
      } else if (reach == Reach::kBelowThreshold && id != 0) {
        add_to(&under, item(e, c));
      }
    };
    push(0);
    while (size > 0) {
      const Entry top = heap[0];
      const LightTree::Node& n = tree.nodes[static_cast<size_t>(top.node)];
      // A light, or a node small as seen from anywhere in the froxel (kFinalSize of the distance): as no entry
      // left can add more, it is one of the froxel's most important, and is taken as it is.
      if (n.leaf() || double(n.radius_m) < kFinalSize * (glm::length(glm::dvec3(n.centre) - c) - r)) {
        std::pop_heap(heap, heap + size--, lighter);
        items[taken++] = item(top, c);
        if (taken == kListLights - kMergedLights) break;
        continue;
      }
      if (opened == kCutOpens) break;
      std::pop_heap(heap, heap + size--, lighter);
      ++opened;
      push(n.left);
      push(n.right);
    }
    // A node too near to stand as one light (its lights spread over more than the froxel and more than half
    // its distance) is opened still, up to kCutOpensMost: such nodes are few at each depth.
    for (int k = 0; k < size;) {
      const LightTree::Node& n = tree.nodes[static_cast<size_t>(heap[k].node)];
      const double extent = n.radius_m;
      if (n.leaf() || opened == kCutOpensMost || !(extent > r) ||
          !(extent > 0.5 * glm::length(glm::dvec3(n.centre) - c))) {
        ++k;
        continue;
      }
      ++opened;
      heap[k] = heap[--size];  // the heap's order is no longer needed
      for (const int32_t child : {n.left, n.right}) {
        Reach reach;
        const Entry e = entry(child, c, r, &reach);
        if (reach == Reach::kReaches) {
          heap[size++] = e;
        } else if (reach == Reach::kBelowThreshold) {
          add_to(&under, item(e, c));
        }
      }
    }
    for (int k = 0; k < size; ++k) items[taken++] = item(heap[k], c);
    finish(&under);
    if (under.estimate > 0.0) items[taken++] = under;
    // A node far from the whole froxel, small as seen from it and dimmed little by fog on the way lights it
    // smoothly: its irradiance goes to the far field (the faces of the ambient cube: each face's irradiance
    // from its direction; the include filters it between froxel centres), not the list. (In fog the light
    // falls too fast between froxel centres for the filter, and the neighbour that lists the node instead
    // would count it twice.)
    for (int k = 0; k < taken;) {
      const Item& it = items[k];
      const double d = glm::length(it.position - c);
      if (it.node < 0 || tree.nodes[static_cast<size_t>(it.node)].leaf() || !(d - it.spread > kFarRadii * r) ||
          !(it.spread < kFinalSize * d) || !(it.beta * d < kFarFade)) {
        ++k;
        continue;
      }
      const glm::dvec3 l = (it.position - c) / d;
      for (int axis = 0; axis < 3; ++axis)
        far_faces[2 * axis + (l[axis] < 0.0 ? 1 : 0)] += it.irradiance * std::abs(l[axis]);
      items[k] = items[--taken];
    }
    if (taken == 0) return opened;
    // The entries in pointers (Items are large to move), the one-by-one ones first: the most important (the
    // lights under the threshold only ever merged).
    Item* order[kCutOpensMost + kListLights + 2];
    double total = 0.0;
    for (int k = 0; k < taken; ++k) {
      order[k] = &items[k];
      total += items[k].estimate;
    }
    const auto more_important = [](const Item* a, const Item* b) {
      if ((a->node < 0) != (b->node < 0)) return b->node < 0;
      return a->estimate != b->estimate ? a->estimate > b->estimate : a->node < b->node;
    };
    int one_by_one = std::min(taken, kListLights - kMergedLights);
    std::nth_element(order, order + one_by_one - 1, order + taken, more_important);
    std::sort(order, order + one_by_one, [](const Item* a, const Item* b) {
      return (a->node < 0) != (b->node < 0) ? b->node < 0 : a->node < b->node;
    });
    while (one_by_one > 0 && order[one_by_one - 1]->node < 0) --one_by_one;
    for (int k = 0; k < one_by_one; ++k) {
      if (order[k]->estimate < kNegligibleShare * total) continue;  // each costs every pixel of the froxel
      const LightTree::Node& n = tree.nodes[static_cast<size_t>(order[k]->node)];
      if (n.leaf()) {
        lists->push_back(tree.order[n.first]);
        ranges->push_back(range(n.peak));
      } else {
        lists->push_back(kMergedFlag | static_cast<uint32_t>(merged->size()));
        ranges->push_back(range(n.peak) + n.radius_m);
        merged->push_back(as_light(order[k]->node, c, n.count <= kExactNodeLights));
        *merged_lights += n.count;
      }
    }
    double rest = 0.0;
    for (int k = one_by_one; k < taken; ++k) rest += order[k]->estimate;
    if (one_by_one == taken || rest < kNegligibleShare * total) return opened;
    // The rest, merged: the group whose light is most spread as seen from the centre (its share times its
    // extent over its distance) is split along its longest axis where its light is halved.
    struct Group {
      Item **first, **last;
      double spread;
    };
    const auto group = [&](Item** first, Item** last) {
      glm::dvec3 lo(INFINITY), hi(-INFINITY), centre(0.0);
      double light = 0.0;
      for (Item** it = first; it < last; ++it) {
        lo = glm::min(lo, (*it)->position);
        hi = glm::max(hi, (*it)->position);
        centre += (*it)->estimate * (*it)->position;
        light += (*it)->estimate;
      }
      const double d = light > 0.0 ? std::max(glm::length(centre / light - c), 0.5) : 1.0;
      return Group{first, last, last - first < 2 ? 0.0 : light * glm::length(hi - lo) / d};
    };
    Group groups[kMergedLights] = {group(order + one_by_one, order + taken)};
    int group_count = 1;
    // As many groups as the rest's share asks for: one per kShareAGroup of the froxel's light.
    const int wanted = std::clamp(static_cast<int>(std::ceil(rest / (kShareAGroup * total))), 1, kMergedLights);
    while (group_count < wanted) {
      Group* widest = std::max_element(groups, groups + group_count,
                                       [](const Group& a, const Group& b) { return a.spread < b.spread; });
      if (!(widest->spread > 0.0)) break;
      glm::dvec3 lo(INFINITY), hi(-INFINITY);
      double light = 0.0;
      for (Item** it = widest->first; it < widest->last; ++it) {
        lo = glm::min(lo, (*it)->position);
        hi = glm::max(hi, (*it)->position);
        light += (*it)->estimate;
      }
      const glm::dvec3 extent = hi - lo;
      const int axis = extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
      std::sort(widest->first, widest->last, [&](const Item* a, const Item* b) {
        return a->position[axis] != b->position[axis] ? a->position[axis] < b->position[axis] : a->node < b->node;
      });
      Item** mid = widest->first + 1;
      for (double below = (*widest->first)->estimate;
           mid < widest->last - 1 && below + (*mid)->estimate <= 0.5 * light; ++mid)
        below += (*mid)->estimate;
      Item** const first = widest->first;
      Item** const last = widest->last;
      *widest = group(first, mid);
      groups[group_count++] = group(mid, last);
    }
    for (int g = 0; g < group_count; ++g)
      add_merged(groups[g].first, groups[g].last, c, lists, ranges, merged, merged_lights);
    return opened;
  }

};

// The lights' diffusion in fog, sampled at the corners of blocks of kBlock x kBlock tiles x 2 slices (it
// reaches kilometres and varies over hundreds of metres, 1 / mu), interpolated to the froxels' centres and
// put on the six faces.
class Diffusion {
 public:
  static constexpr int kBlock = 8;
  template <typename Ray>
  Diffusion(const fog::FogFrame& frame, const LightTree& tree, const ClusterGrid& grid, const Ray& ray)
      : nx_((grid.tiles_x + kBlock - 1) / kBlock + 1),
        ny_((grid.tiles_y + kBlock - 1) / kBlock + 1),
        nk_(ClusterGrid::kSlices / 2 + 1) {
    if (!(frame.diffusion.w > 0.0f) || tree.empty()) return;
    a_.assign(static_cast<size_t>(nx_) * ny_ * nk_, glm::dvec3(0.0));
    b_.assign(a_.size(), glm::dmat3(0.0));
    clouds::for_bands(nk_, kThreads, [&](int k_begin, int k_end) {
      for (int k = k_begin; k < k_end; ++k)
        for (int y = 0; y < ny_; ++y)
          for (int x = 0; x < nx_; ++x) {
            const double ndc_x = std::min(2.0 * x * kBlock / grid.tiles_x - 1.0, 1.0);
            const double ndc_y = std::min(2.0 * y * kBlock / grid.tiles_y - 1.0, 1.0);
            const size_t at = (static_cast<size_t>(k) * ny_ + y) * nx_ + x;
            add_diffusion(frame, tree, ray(ndc_x, ndc_y) * grid.slice_distance(2.0 * k), &a_[at], &b_[at]);
          }
    });
  }

  // The P1 irradiance phi / 4 + F . n / 2 on each face of froxel (x, y, k) (clamped per channel, as the
  // include's single light is), added to faces.
  void add_faces(int x, int y, int k, glm::dvec3 faces[LightClusters::kFaces]) const {
    if (a_.empty()) return;
    const double fx = std::min((x + 0.5) / kBlock, nx_ - 1.0), fy = std::min((y + 0.5) / kBlock, ny_ - 1.0),
                 fk = std::min((k + 0.5) / 2.0, nk_ - 1.0);
    const int x0 = std::min(int(fx), nx_ - 2), y0 = std::min(int(fy), ny_ - 2), k0 = std::min(int(fk), nk_ - 2);
    glm::dvec3 a(0.0);
    glm::dmat3 b(0.0);
    for (int c = 0; c < 8; ++c) {
      const int cx = x0 + (c & 1), cy = y0 + ((c >> 1) & 1), ck = k0 + (c >> 2);
      const double w = (c & 1 ? fx - x0 : 1.0 - (fx - x0)) * ((c >> 1) & 1 ? fy - y0 : 1.0 - (fy - y0)) *
                       (c >> 2 ? fk - k0 : 1.0 - (fk - k0));
      const size_t at = (static_cast<size_t>(ck) * ny_ + cy) * nx_ + cx;
      a += w * a_[at];
      b += w * b_[at];
    }
    for (int axis = 0; axis < 3; ++axis)
      for (int sign = 0; sign < 2; ++sign) {
        const glm::dvec3 along(b[0][axis], b[1][axis], b[2][axis]);  // per channel, the flux term along the axis
        faces[2 * axis + sign] += glm::max(a + (sign ? -1.0 : 1.0) * along, glm::dvec3(0.0));
      }
  }

 private:
  int nx_, ny_, nk_;
  std::vector<glm::dvec3> a_;
  std::vector<glm::dmat3> b_;
};

}  // namespace

ClusterGrid ClusterGrid::for_view(const glm::dmat4& clip_from_enu, int viewport_width, int viewport_height,
                                  int tile_px) {
  ClusterGrid g;
  g.clip_from_enu = clip_from_enu;
  const int w = std::max(viewport_width, 1), h = std::max(viewport_height, 1);
  g.tiles_x = std::clamp((w + tile_px - 1) / tile_px, kMinTiles, kMaxTiles);
  const double tile = double(w) / g.tiles_x;  // square tiles
  g.tiles_y = std::clamp(int(std::ceil(h / tile)), 1, kMaxTiles);
  return g;
}

double ClusterGrid::slice_distance(double k) const { return near_m * std::pow(far_m / near_m, k / kSlices); }

double ClusterGrid::slice_of(double distance_m) const {
  const double k = std::log(std::max(distance_m, near_m) / near_m) / std::log(far_m / near_m) * kSlices;
  return std::clamp(k, 0.0, double(kSlices));
}

SurfaceRange::SurfaceRange(const fog::FogFrame& frame, const LightTree& tree, float albedo,
                           double threshold_cd_m2) {
  if (tree.empty() || !(threshold_cd_m2 > 0.0)) return;
  // A white Lambertian surface facing the light: L = E / pi; E <= I (e^-bd / d^2 + albedo b e^-bd G / (2 pi d)),
  // with b the lights' smallest extinction in the attenuation and the fog's in the scattering: a bound for all.
  e_min_ = kPi * threshold_cd_m2;
  beta_lo_ = tree.nodes[0].beta_min;
  scattering_ = albedo * frame.extinction_per_m * kMaxSurfaceG / (2.0 * kPi);
  // From the dimmest light to the sum of all (a node's bound), per bucket of float bit patterns (16 an octave:
  // the patterns of positive floats are in the order of their values), each at its bucket's top.
  if (!(tree.dimmest_peak > 0.0f)) return;
  first_bucket_ = bucket(tree.dimmest_peak);
  const uint32_t last = bucket(tree.nodes[0].peak);
  range_m_.resize(last - first_bucket_ + 1);
  for (uint32_t k = 0; k < range_m_.size(); ++k) {
    const uint32_t top_bits = (first_bucket_ + k + 1) << kBucketShift;
    float top;
    std::memcpy(&top, &top_bits, sizeof(top));
    range_m_[k] = exact(top);
  }
}

uint32_t SurfaceRange::bucket(float intensity_cd) {
  uint32_t bits;
  std::memcpy(&bits, &intensity_cd, sizeof(bits));
  return bits >> kBucketShift;
}

float SurfaceRange::exact(double intensity_cd) const {
  if (!(intensity_cd > 0.0) || !(e_min_ > 0.0)) return 0.0f;
  const auto e = [&](double d) { return intensity_cd * std::exp(-beta_lo_ * d) * (1.0 / (d * d) + scattering_ / d); };
  // e falls with d: bisection in log d between 0.01 m and 1000 km.
  double lo = std::log(0.01), hi = std::log(1e6);
  if (e(std::exp(hi)) >= e_min_) return 1e6f;
  if (e(std::exp(lo)) < e_min_) return 0.0f;
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (lo + hi);
    (e(std::exp(mid)) >= e_min_ ? lo : hi) = mid;
  }
  return static_cast<float>(std::exp(hi));
}

float SurfaceRange::operator()(float intensity_cd) const {
  if (!(intensity_cd > 0.0f) || range_m_.empty()) return 0.0f;
  // Its bucket's top (the range grows with the intensity); past the table, the bisection itself.
  const uint32_t b = bucket(intensity_cd);
  if (b < first_bucket_) return range_m_.front();
  if (b - first_bucket_ >= range_m_.size()) return exact(intensity_cd);
  return range_m_[b - first_bucket_];
}

LightClusters cluster_lights(const fog::FogFrame& frame, const LightTree& tree, const ClusterGrid& grid,
                             float fog_albedo, double threshold_cd_m2) {
  LightClusters out;
  out.grid = grid;
  const int froxels = grid.froxels();
  const SurfaceRange range(frame, tree, fog_albedo, threshold_cd_m2);
  const glm::dmat4 enu_from_clip = glm::inverse(grid.clip_from_enu);
  // Each froxel's centre (ENU relative to the eye) and bounding radius.
  std::vector<glm::dvec3> centre(static_cast<size_t>(froxels));
  std::vector<double> radius(static_cast<size_t>(froxels));
  // The eye is the origin (clip_from_enu holds no translation): a pixel's ray is the direction of any point
  // on it, here at NDC depth 0.5, which is finite for every depth convention (an infinite reversed-Z far
  // plane is at 0).
  const auto ray = [&](double ndc_x, double ndc_y) {
    const glm::dvec4 p = enu_from_clip * glm::dvec4(ndc_x, ndc_y, 0.5, 1.0);
    return glm::normalize(glm::dvec3(p) / p.w);
  };
  for (int y = 0; y < grid.tiles_y; ++y)
    for (int x = 0; x < grid.tiles_x; ++x) {
      const double x0 = 2.0 * x / grid.tiles_x - 1.0, x1 = 2.0 * (x + 1) / grid.tiles_x - 1.0;
      const double y0 = 2.0 * y / grid.tiles_y - 1.0, y1 = 2.0 * (y + 1) / grid.tiles_y - 1.0;
      const glm::dvec3 mid = ray(0.5 * (x0 + x1), 0.5 * (y0 + y1));
      double spread = 0.0;  // the tile's half-angle
      for (const glm::dvec3& corner : {ray(x0, y0), ray(x1, y0), ray(x0, y1), ray(x1, y1)})
        spread = std::max(spread, std::acos(std::clamp(glm::dot(corner, mid), -1.0, 1.0)));
      for (int k = 0; k < ClusterGrid::kSlices; ++k) {
        const double d0 = grid.slice_distance(k), d1 = grid.slice_distance(k + 1), dm = 0.5 * (d0 + d1);
        const size_t f = static_cast<size_t>(grid.index(x, y, k));
        centre[f] = mid * dm;
        const double across = std::tan(std::min(spread, 1.5)) * d1;
        radius[f] = std::sqrt(across * across + 0.25 * (d1 - d0) * (d1 - d0));
      }
    }

  // The lights' diffusion in fog reaches kilometres and varies over hundreds of metres (1 / mu): sampled
  // at the corners of blocks of kDiffusionBlock x kDiffusionBlock tiles x 2 slices and interpolated to the
  // froxels' centres.
  const Diffusion diffusion(frame, tree, grid, ray);

  // Each froxel's list and far field, in bands of froxels; a band's lists and merged lights are joined in
  // froxel order.
  struct Band {
    std::vector<uint32_t> lists;  // merged lights as kMergedFlag | their index in `merged`
    std::vector<float> ranges;
    std::vector<fog::FrameLight> merged;
    uint64_t opened = 0, merged_lights = 0;
  };
  // Each band takes every band_total-th line of tiles (a row at one slice): near slices hold few lights and
  // far ones many, so contiguous bands would leave threads idle.
  const int lines = grid.tiles_y * ClusterGrid::kSlices;
  const int band_total = clouds::band_count(lines, kThreads);
  std::vector<Band> bands(static_cast<size_t>(band_total));
  out.offset.assign(static_cast<size_t>(froxels), 0);
  out.count.assign(static_cast<size_t>(froxels), 0);
  for (std::vector<glm::vec3>& face : out.far) face.assign(static_cast<size_t>(froxels), glm::vec3(0.0f));
  const Cut cut{frame, tree, range};
  const auto each_froxel_of = [&](int b, auto&& fn) {
    for (int line = b; line < lines; line += band_total)
      for (int f = line * grid.tiles_x; f < (line + 1) * grid.tiles_x; ++f) fn(static_cast<size_t>(f));
  };
  clouds::for_numbered_bands(band_total, band_total, [&](int b, int, int) {
    Band& band = bands[static_cast<size_t>(b)];
    each_froxel_of(b, [&](size_t f) {
      const size_t first = band.lists.size();
      glm::dvec3 faces[LightClusters::kFaces] = {};
      if (!tree.empty())
        band.opened += cut.list(centre[f], radius[f], &band.lists, &band.ranges, &band.merged, &band.merged_lights,
                                faces);
      out.offset[f] = static_cast<uint32_t>(first);  // band-relative until joined
      out.count[f] = static_cast<uint32_t>(band.lists.size() - first);
      const int i = static_cast<int>(f);
      diffusion.add_faces(i % grid.tiles_x, (i / grid.tiles_x) % grid.tiles_y, i / (grid.tiles_x * grid.tiles_y),
                          faces);
      for (int face = 0; face < LightClusters::kFaces; ++face) out.far[face][f] = glm::vec3(faces[face]);
    });
  });
  for (int b = 0; b < band_total; ++b) {
    Band& band = bands[static_cast<size_t>(b)];
    const uint32_t list_base = static_cast<uint32_t>(out.lists.size());
    const uint32_t merged_base = static_cast<uint32_t>(frame.lights.size() + out.merged.size());
    for (uint32_t entry : band.lists)
      out.lists.push_back(entry & kMergedFlag ? merged_base + (entry & ~kMergedFlag) : entry);
    out.list_range_m.insert(out.list_range_m.end(), band.ranges.begin(), band.ranges.end());
    out.merged.insert(out.merged.end(), band.merged.begin(), band.merged.end());
    out.opened += band.opened;
    out.merged_lights += band.merged_lights;
    each_froxel_of(b, [&](size_t f) {
      out.offset[f] += list_base;
      out.longest_list = std::max(out.longest_list, out.count[f]);
    });
  }
  return out;
}

}  // namespace atmo::lights
