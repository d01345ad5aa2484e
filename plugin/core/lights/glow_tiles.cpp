#include "core/lights/glow_tiles.h"

#include <algorithm>
#include <cmath>

#include "core/fog/fog_twin.h"

namespace atmo::lights {

namespace {

double peak(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

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

GlowTiles bin_glows(const fog::FogFrame& frame, const fog::FogTable& airlight, const glm::dmat4& clip_from_enu,
                    int viewport_width, int viewport_height, double min_sin) {
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

  struct Pair {
    uint32_t tile, light;
    float importance;
  };
  std::vector<Pair> pairs;
  std::vector<double> weight(frame.lights.size(), 0.0);  // the far glow's weight I cone e^(-beta D) / D
  for (size_t i = 0; i < frame.lights.size(); ++i) {
    const fog::FrameLight& l = frame.lights[i];
    if (!(l.glow_radius_rad > min_sin)) continue;
    const glm::dvec3 p(l.position_enu_m);
    const double d = glm::length(p);
    if (!(d > 0.0)) continue;
    const glm::dvec3 towards = p / d;
    const glm::vec4 r = glow_rectangle(clip_from_enu, towards, l.glow_radius_rad);
    if (r.x >= r.z || r.y >= r.w) continue;  // off screen
    // The core where it shows (above the threshold itself: it is drawn per light, at full resolution).
    if (l.visible_radius_rad > min_sin) {
      out.cores.push_back(static_cast<uint32_t>(i));
      out.core_radius_rad.push_back(static_cast<float>(std::min(double(l.visible_radius_rad), core_rad)));
    }
    if (!(l.glow_radius_rad > core_rad)) continue;  // the smooth part is under the threshold everywhere
    const double cone = fog::twin::atmo_fog_cone(l.axis_enu, l.cos_inner, l.cos_outer, l.lobes, glm::vec3(-towards));
    weight[i] = peak(l.intensity_cd) * std::max(cone, 0.05) * std::exp(-double(l.beta_per_m) * d) / d;
    const int tx0 = std::clamp(int(std::floor((r.x + 1.0) * 0.5 * g.tiles_x)), 0, g.tiles_x - 1);
    const int tx1 = std::clamp(int(std::floor((r.z + 1.0) * 0.5 * g.tiles_x)), 0, g.tiles_x - 1);
    const int ty0 = std::clamp(int(std::floor((r.y + 1.0) * 0.5 * g.tiles_y)), 0, g.tiles_y - 1);
    const int ty1 = std::clamp(int(std::floor((r.w + 1.0) * 0.5 * g.tiles_y)), 0, g.tiles_y - 1);
    for (int y = ty0; y <= ty1; ++y)
      for (int x = tx0; x <= tx1; ++x) {
        const size_t t = static_cast<size_t>(y * g.tiles_x + x);
        const double angle = std::acos(std::clamp(glm::dot(centre[t], towards), -1.0, 1.0));
        const double gamma = std::max(angle - half[t], core_rad);
        if (gamma > l.glow_radius_rad) continue;
        // The glow's bound falls as 1 / sin gamma near the light.
        pairs.push_back({static_cast<uint32_t>(t), static_cast<uint32_t>(i),
                         static_cast<float>(weight[i] / std::sin(std::min(gamma, 0.5 * M_PI)))});
      }
  }
  out.pairs = pairs.size();

  std::vector<uint32_t> start(static_cast<size_t>(tiles) + 1, 0);
  for (const Pair& p : pairs) ++start[p.tile + 1];
  for (int t = 0; t < tiles; ++t) start[t + 1] += start[t];
  std::vector<Pair> grouped(pairs.size());
  {
    std::vector<uint32_t> at(start.begin(), start.end() - 1);
    for (const Pair& p : pairs) grouped[at[p.tile]++] = p;
  }
  out.offset.assign(static_cast<size_t>(tiles), 0);
  out.count.assign(static_cast<size_t>(tiles), 0);
  for (int t = 0; t < tiles; ++t) {
    Pair* begin = grouped.data() + start[t];
    Pair* end = grouped.data() + start[t + 1];
    const size_t n = static_cast<size_t>(end - begin);
    if (n > static_cast<size_t>(kExactGlows)) {
      std::partial_sort(begin, begin + kExactGlows, end, [](const Pair& a, const Pair& b) {
        return a.importance != b.importance ? a.importance > b.importance : a.light < b.light;
      });
      std::sort(begin, begin + kExactGlows, [](const Pair& a, const Pair& b) { return a.light < b.light; });
    }
    const size_t exact = std::min(n, static_cast<size_t>(kExactGlows));
    out.offset[t] = static_cast<uint32_t>(out.lists.size());
    for (size_t k = 0; k < exact; ++k) out.lists.push_back(begin[k].light);
    out.count[t] = static_cast<uint32_t>(exact);
    if (begin + exact < end) {
      out.overflow += static_cast<uint64_t>(end - begin - exact);
      std::vector<std::pair<Pair*, Pair*>> groups = {{begin + exact, end}};
      while (static_cast<int>(groups.size()) < kMergedGlows) {
        auto largest = std::max_element(groups.begin(), groups.end(), [](const auto& a, const auto& b) {
          return a.second - a.first < b.second - b.first;
        });
        if (largest->second - largest->first < 2) break;
        // A glow's shape follows the light's direction and optical distance: split along the largest extent of
        // the direction (radians) or of the log distance (half weight: e^(-beta D) D^-1 varies slowly in it).
        const auto coordinate = [&](uint32_t light, int axis) {
          const glm::vec3 p = frame.lights[light].position_enu_m;
          const float d = std::max(glm::length(p), 1e-3f);
          return axis < 3 ? p[axis] / d : 0.5f * std::log(d);
        };
        float lo[4] = {1e30f, 1e30f, 1e30f, 1e30f}, hi[4] = {-1e30f, -1e30f, -1e30f, -1e30f};
        for (Pair* p = largest->first; p < largest->second; ++p)
          for (int k = 0; k < 4; ++k) {
            lo[k] = std::min(lo[k], coordinate(p->light, k));
            hi[k] = std::max(hi[k], coordinate(p->light, k));
          }
        int axis = 0;
        for (int k = 1; k < 4; ++k)
          if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
        Pair* mid = largest->first + (largest->second - largest->first) / 2;
        std::nth_element(largest->first, mid, largest->second, [&](const Pair& a, const Pair& b) {
          const float pa = coordinate(a.light, axis), pb = coordinate(b.light, axis);
          return pa != pb ? pa < pb : a.light < b.light;
        });
        const std::pair<Pair*, Pair*> right = {mid, largest->second};
        largest->second = mid;
        groups.push_back(right);
      }
      const glm::vec3 ray = glm::vec3(centre[static_cast<size_t>(t)]);
      const float size = static_cast<float>(airlight.width);
      for (const auto& [first, last] : groups) {
        // The group's glow along the tile's central ray (each member's whole glow, its cone's too), and its
        // weighted centre and extinction; the merged light gives that glow from where it stands.
        glm::dvec3 position(0.0), glow(0.0);
        double w = 0.0, beta = 0.0;
        for (Pair* p = first; p < last; ++p) {
          const fog::FrameLight& l = frame.lights[p->light];
          const double wi = weight[p->light];
          position += wi * glm::dvec3(l.position_enu_m);
          beta += wi * l.beta_per_m;
          w += wi;
          glow += glm::dvec3(l.intensity_cd) *
                  double(fog::twin::atmo_fog_glow(airlight, size, l.beta_per_m, l.position_enu_m, ray, l.axis_enu,
                                                  l.cos_inner, l.cos_outer, l.lobes, fog::twin::ATMO_FOG_FAR,
                                                  out.core_sin));
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
        out.lists.push_back(static_cast<uint32_t>(frame.lights.size() + out.merged.size()));
        ++out.count[t];
        out.merged.push_back(m);
      }
    }
    out.longest_list = std::max(out.longest_list, out.count[t]);
  }
  return out;
}

}  // namespace atmo::lights
