#include "core/lights/glow_tiles.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "core/clouds/parallel_bands.h"
#include "core/fog/fog_twin.h"

namespace atmo::lights {

namespace {

double peak(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

// Threads that share a view's tiles (each tile's cut is its own: the result is the same for any count).
const int kThreads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 4u));

// A node's glow along a ray (peak channel, per unit albedo): its lights as one at its centre, the
// omnidirectional ones' airlight and the cone lights' as one cone on their mean axis with their mean
// cosines, the more so the more their axes agree (else their mean over the sphere: node_intensity_towards).
double node_glow(const LightTree::Node& n, const fog::FogTable& airlight, const glm::vec3& ray, float min_sin) {
  const float size = static_cast<float>(airlight.width);
  const float d = std::max(glm::length(n.centre), 1e-3f);
  const double omni = fog::twin::atmo_fog_airlight(airlight, size, n.beta_mean, d, glm::dot(ray, n.centre) / d,
                                                   fog::twin::ATMO_FOG_FAR, min_sin);
  if (!(n.cone > 0.0f)) return n.omni * omni;
  const NodeCone c = node_cone(n);
  double as_one_cone = 0.0;
  for (const float lobes : {1.0f, 2.0f}) {
    const float share = lobes > 1.5f ? c.two_way : 1.0f - c.two_way;
    if (share > 0.0f)
      as_one_cone += share * fog::twin::atmo_fog_glow(airlight, size, n.beta_mean, n.centre, ray, c.axis, c.cos_inner,
                                                      c.cos_outer, lobes, fog::twin::ATMO_FOG_FAR, min_sin);
  }
  return n.omni * omni + n.cone * (c.agree * as_one_cone + (1.0 - c.agree) * n.mean_sum / n.cone * omni);
}

}  // namespace

glm::vec4 glow_rectangle(const glm::dmat4& clip_from_enu, const glm::dvec3& towards, double radius) {
  const glm::vec4 whole(-1.0f, -1.0f, 1.0f, 1.0f);
  if (radius >= 0.5 * M_PI) return whole;
  const glm::dvec3 a = std::abs(towards.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(towards, a)), v = glm::cross(towards, u);
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  const double c = std::cos(radius), s = std::sin(radius) / std::cos(M_PI / 16.0);  // the 16-gon holds the circle
  for (int k = 0; k < 16; ++k) {
    const double t = k * (2.0 * M_PI / 16.0);
    const glm::dvec3 d = c * towards + s * (std::cos(t) * u + std::sin(t) * v);
    const glm::dvec4 p = clip_from_enu * glm::dvec4(d, 0.0);
    if (p.w <= 1e-9) return whole;
    for (int i = 0; i < 2; ++i) {
      lo[i] = std::min(lo[i], p[i] / p.w);
      hi[i] = std::max(hi[i], p[i] / p.w);
    }
  }
  return glm::vec4(std::max(lo[0], -1.0), std::max(lo[1], -1.0), std::min(hi[0], 1.0), std::min(hi[1], 1.0));
}

GlowTiles bin_glows(const fog::FogFrame& frame, const LightTree& tree, const fog::FogTable& airlight,
                    const glm::dmat4& clip_from_enu, int viewport_width, int viewport_height, double min_sin,
                    const GlowBudget& budget) {
  GlowTiles out;
  out.grid = ClusterGrid::for_view(clip_from_enu, viewport_width, viewport_height, ClusterGrid::kGlowTilePx);
  const ClusterGrid& g = out.grid;
  const int tiles = g.tiles_x * g.tiles_y;
  // min_sin is 0.2836 of a pixel's angle; the core reaches kCorePixels of the smooth image's pixels.
  const double pixel_rad = min_sin / 0.2836;
  const double core_rad = kCorePixels * kGlowDivisor * pixel_rad;
  out.core_sin = static_cast<float>(std::sin(core_rad));
  // Each tile's centre direction and half-angle.
  const glm::dmat4 enu_from_clip = glm::inverse(clip_from_enu);
  const auto ray = [&](double x, double y) {
    const glm::dvec4 p = enu_from_clip * glm::dvec4(x, y, 0.5, 1.0);
    return glm::normalize(glm::dvec3(p) / p.w);
  };
  std::vector<glm::dvec3> centre(static_cast<size_t>(tiles));
  std::vector<double> half(static_cast<size_t>(tiles));
  for (int y = 0; y < g.tiles_y; ++y)
    for (int x = 0; x < g.tiles_x; ++x) {
      const double x0 = 2.0 * x / g.tiles_x - 1.0, x1 = 2.0 * (x + 1) / g.tiles_x - 1.0;
      const double y0 = 2.0 * y / g.tiles_y - 1.0, y1 = 2.0 * (y + 1) / g.tiles_y - 1.0;
      const glm::dvec3 mid = ray(0.5 * (x0 + x1), 0.5 * (y0 + y1));
      double spread = 0.0;
      for (const glm::dvec3& corner : {ray(x0, y0), ray(x1, y0), ray(x0, y1), ray(x1, y1)})
        spread = std::max(spread, std::acos(std::clamp(glm::dot(corner, mid), -1.0, 1.0)));
      centre[static_cast<size_t>(y * g.tiles_x + x)] = mid;
      half[static_cast<size_t>(y * g.tiles_x + x)] = spread;
    }

  // Each light: its core (drawn per light, at full resolution, where it shows above the threshold itself) and
  // its far glow's weight I cone e^(-beta D) / D (0: its smooth part is under the threshold everywhere).
  std::vector<double> weight(frame.lights.size(), 0.0);
  for (size_t i = 0; i < frame.lights.size(); ++i) {
    const fog::FrameLight& l = frame.lights[i];
    if (!(l.glow_radius_rad > min_sin)) continue;
    const glm::dvec3 p(l.position_enu_m);
    const double d = glm::length(p);
    if (!(d > 0.0)) continue;
    const glm::dvec3 towards = p / d;
    if (l.visible_radius_rad > min_sin) {
      const double radius = std::min(double(l.visible_radius_rad), core_rad);
      const glm::vec4 r = glow_rectangle(clip_from_enu, towards, radius);
      if (r.x < r.z && r.y < r.w) {  // on screen
        out.cores.push_back(static_cast<uint32_t>(i));
        out.core_radius_rad.push_back(static_cast<float>(radius));
      }
    }
    if (!(l.glow_radius_rad > core_rad)) continue;
    const double cone = fog::twin::atmo_fog_cone(l.axis_enu, l.cos_inner, l.cos_outer, l.lobes, glm::vec3(-towards));
    weight[i] = peak(l.intensity_cd) * std::max(cone, 0.05) * std::exp(-double(l.beta_per_m) * d) / d;
  }
  if (tree.empty()) {
    out.offset.assign(static_cast<size_t>(tiles), 0);
    out.count.assign(static_cast<size_t>(tiles), 0);
    return out;
  }
  // Per node of the tree: how far from its lights' directions a glow of its reaches (the largest glow radius
  // of its lights whose smooth part shows; < 0: none), and its angular radius seen from the eye. Children
  // follow their parent in `nodes`, so one pass from the end fills the parents.
  const size_t node_count = tree.nodes.size();
  std::vector<float> reach(node_count, -1.0f), angular(node_count, 0.0f);
  for (size_t k = node_count; k-- > 0;) {
    const LightTree::Node& n = tree.nodes[k];
    if (n.leaf()) {
      const uint32_t i = tree.order[n.first];
      reach[k] = weight[i] > 0.0 ? frame.lights[i].glow_radius_rad : -1.0f;
    } else {
      reach[k] = std::max(reach[static_cast<size_t>(n.left)], reach[static_cast<size_t>(n.right)]);
    }
    const double d = glm::length(glm::dvec3(n.centre));
    angular[k] = d > double(n.radius_m) ? static_cast<float>(std::asin(double(n.radius_m) / d)) : float(M_PI);
  }

  // Each tile's cut of the tree (lightcuts): best first, the entry whose glow may be largest on the tile is
  // opened (a node) or taken (a light), until budget.exact lights are taken or budget.opens nodes opened; the
  // rest of the cut is merged.
  struct Entry {
    float importance;  // a bound on its glow over the tile (a light's: its estimate)
    int32_t node;
  };
  const auto lighter = [](const Entry& a, const Entry& b) {
    return a.importance != b.importance ? a.importance < b.importance : a.node > b.node;
  };
  struct TileOut {
    std::vector<uint32_t> exact;
    std::vector<fog::FrameLight> merged;
    uint64_t visited = 0, rest = 0;
  };
  std::vector<TileOut> per_tile(static_cast<size_t>(tiles));
  const float size = static_cast<float>(airlight.width);
  clouds::for_bands(tiles, kThreads, [&](int begin, int end) {
    std::vector<Entry> heap;
    std::vector<Entry> rest;
    for (int t = begin; t < end; ++t) {
      TileOut& o = per_tile[static_cast<size_t>(t)];
      const glm::dvec3& c = centre[static_cast<size_t>(t)];
      const double h = half[static_cast<size_t>(t)];
      // Node k's entry, or none where no glow of its reaches the tile.
      const auto entry = [&](int32_t k, Entry* e) {
        const LightTree::Node& n = tree.nodes[static_cast<size_t>(k)];
        if (!(reach[static_cast<size_t>(k)] > 0.0f)) return false;
        ++o.visited;
        if (n.leaf()) {
          const uint32_t i = tree.order[n.first];
          const glm::dvec3 p(frame.lights[i].position_enu_m);
          const double angle = std::acos(std::clamp(glm::dot(c, glm::normalize(p)), -1.0, 1.0));
          const double gamma = std::max(angle - h, core_rad);
          if (gamma > frame.lights[i].glow_radius_rad) return false;
          // The glow's bound falls as 1 / sin gamma near the light.
          *e = {static_cast<float>(weight[i] / std::sin(std::min(gamma, 0.5 * M_PI))), k};
          return true;
        }
        const glm::dvec3 p(n.centre);
        const double d = glm::length(p);
        const double angle = d > 0.0 ? std::acos(std::clamp(glm::dot(c, p / d), -1.0, 1.0)) : 0.0;
        const double gamma = std::max(angle - double(angular[static_cast<size_t>(k)]) - h, core_rad);
        if (gamma > reach[static_cast<size_t>(k)]) return false;
        const double near = std::max(d - double(n.radius_m), 1e-3);
        *e = {static_cast<float>(double(n.peak) * std::exp(-double(n.beta_min) * near) / near /
                                 std::sin(std::min(gamma, 0.5 * M_PI))),
              k};
        return true;
      };
      heap.clear();
      rest.clear();
      Entry e;
      if (entry(0, &e)) heap.push_back(e);
      int opened = 0;
      while (!heap.empty() && o.exact.size() < static_cast<size_t>(budget.exact)) {
        const Entry top = heap.front();
        const LightTree::Node& n = tree.nodes[static_cast<size_t>(top.node)];
        if (!n.leaf() && opened == budget.opens) break;
        std::pop_heap(heap.begin(), heap.end(), lighter);
        heap.pop_back();
        if (n.leaf()) {
          o.exact.push_back(tree.order[n.first]);
          continue;
        }
        ++opened;
        for (const int32_t child : {n.left, n.right})
          if (entry(child, &e)) {
            heap.push_back(e);
            std::push_heap(heap.begin(), heap.end(), lighter);
          }
      }
      std::sort(o.exact.begin(), o.exact.end());
      o.rest = heap.size();
      if (heap.empty() || budget.merged <= 0) continue;  // (a budget without merging drops the rest)
      // The rest of the cut, merged: split along the largest extent of the direction (radians) or of the log
      // distance (half weight: e^(-beta D) D^-1 varies slowly in it) into up to budget.merged groups.
      const auto coordinate = [&](const Entry& x, int axis) {
        const glm::vec3 p = tree.nodes[static_cast<size_t>(x.node)].centre;
        const float d = std::max(glm::length(p), 1e-3f);
        return axis < 3 ? p[axis] / d : 0.5f * std::log(d);
      };
      std::vector<std::pair<Entry*, Entry*>> groups = {{heap.data(), heap.data() + heap.size()}};
      while (static_cast<int>(groups.size()) < budget.merged) {
        auto largest = std::max_element(groups.begin(), groups.end(), [](const auto& x, const auto& y) {
          return x.second - x.first < y.second - y.first;
        });
        if (largest->second - largest->first < 2) break;
        float lo[4] = {1e30f, 1e30f, 1e30f, 1e30f}, hi[4] = {-1e30f, -1e30f, -1e30f, -1e30f};
        for (Entry* x = largest->first; x < largest->second; ++x)
          for (int k = 0; k < 4; ++k) {
            lo[k] = std::min(lo[k], coordinate(*x, k));
            hi[k] = std::max(hi[k], coordinate(*x, k));
          }
        int axis = 0;
        for (int k = 1; k < 4; ++k)
          if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
        Entry* mid = largest->first + (largest->second - largest->first) / 2;
        std::nth_element(largest->first, mid, largest->second, [&](const Entry& x, const Entry& y) {
          const float px = coordinate(x, axis), py = coordinate(y, axis);
          return px != py ? px < py : x.node < y.node;
        });
        const std::pair<Entry*, Entry*> right = {mid, largest->second};
        largest->second = mid;
        groups.push_back(right);
      }
      const glm::vec3 ray(c);
      for (const auto& [first, last] : groups) {
        // The group's glow along the tile's central ray (a light's whole glow, its cone's too; a node's as one
        // light at its centre with its cones as one towards the eye), and its centre and extinction weighted
        // by the entries' bounds; the merged light gives that glow from where it stands.
        glm::dvec3 position(0.0), glow(0.0);
        double w = 0.0, beta = 0.0;
        for (Entry* x = first; x < last; ++x) {
          const LightTree::Node& n = tree.nodes[static_cast<size_t>(x->node)];
          const double wi = x->importance;
          position += wi * glm::dvec3(n.centre);
          beta += wi * n.beta_mean;
          w += wi;
          if (n.leaf()) {
            const fog::FrameLight& l = frame.lights[tree.order[n.first]];
            glow += glm::dvec3(l.intensity_cd) *
                    double(fog::twin::atmo_fog_glow(airlight, size, l.beta_per_m, l.position_enu_m, ray, l.axis_enu,
                                                    l.cos_inner, l.cos_outer, l.lobes, fog::twin::ATMO_FOG_FAR,
                                                    out.core_sin));
          } else {
            const double colour_peak = std::max({n.power.x, n.power.y, n.power.z});
            if (colour_peak > 0.0) glow += glm::dvec3(n.power) / colour_peak * node_glow(n, airlight, ray, out.core_sin);
          }
        }
        if (!(w > 0.0)) continue;
        position /= w;
        beta /= w;
        const float d = std::max(static_cast<float>(glm::length(position)), 1e-3f);
        const double unit = fog::twin::atmo_fog_airlight(airlight, size, static_cast<float>(beta), d,
                                                         glm::dot(ray, glm::vec3(position)) / d,
                                                         fog::twin::ATMO_FOG_FAR, out.core_sin);
        if (!(unit > 0.0)) continue;
        fog::FrameLight m;
        m.position_enu_m = glm::vec3(position);
        m.beta_per_m = static_cast<float>(beta);
        m.intensity_cd = glm::vec3(glow / unit);
        o.merged.push_back(m);
      }
    }
  });
  out.offset.assign(static_cast<size_t>(tiles), 0);
  out.count.assign(static_cast<size_t>(tiles), 0);
  for (int t = 0; t < tiles; ++t) {
    const TileOut& o = per_tile[static_cast<size_t>(t)];
    out.offset[t] = static_cast<uint32_t>(out.lists.size());
    out.lists.insert(out.lists.end(), o.exact.begin(), o.exact.end());
    for (const fog::FrameLight& m : o.merged) {
      out.lists.push_back(static_cast<uint32_t>(frame.lights.size() + out.merged.size()));
      out.merged.push_back(m);
    }
    out.count[t] = static_cast<uint32_t>(out.lists.size() - out.offset[t]);
    out.longest_list = std::max(out.longest_list, out.count[t]);
    out.weighed += o.visited;
    out.merged_entries += o.rest;
  }
  return out;
}

}  // namespace atmo::lights
