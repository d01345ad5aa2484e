#include "core/shadows/occlusion_frame.h"

#include <algorithm>
#include <cmath>

namespace atmo::shadows {

namespace {

// A sphere holding the spheres [first, last).
glm::dvec4 bound_of(const glm::dvec4* first, const glm::dvec4* last) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const glm::dvec4* s = first; s != last; ++s) {
    lo = glm::min(lo, glm::dvec3(*s) - s->w);
    hi = glm::max(hi, glm::dvec3(*s) + s->w);
  }
  const glm::dvec3 centre = 0.5 * (lo + hi);
  double radius = 0.0;
  for (const glm::dvec4* s = first; s != last; ++s) radius = std::max(radius, glm::length(glm::dvec3(*s) - centre) + s->w);
  return glm::dvec4(centre, radius);
}

// One sphere standing for [first, last): at their volume-weighted centre, of the union's mean projected area
// over 13 directions (axes, face and cube diagonals; Cauchy), a 32 x 32 grid of parallel rays over the bound's
// disc each.
glm::dvec4 proxy_of(const glm::dvec4* first, const glm::dvec4* last, const glm::dvec4& bound) {
  glm::dvec3 weighted(0.0);
  double volume = 0.0;
  for (const glm::dvec4* s = first; s != last; ++s) {
    weighted += glm::dvec3(*s) * (s->w * s->w * s->w);
    volume += s->w * s->w * s->w;
  }
  const glm::dvec3 centre(bound), proxy_centre = volume > 0.0 ? weighted / volume : centre;
  const double radius = bound.w;
  const glm::dvec3 dirs[13] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1},
                               {0, 1, 1}, {0, 1, -1}, {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};
  const int grid = 32;
  double area = 0.0;
  for (const glm::dvec3& raw : dirs) {
    const glm::dvec3 d = glm::normalize(raw);
    const glm::dvec3 u = glm::normalize(std::abs(d.x) < 0.9 ? glm::cross(d, glm::dvec3(1, 0, 0)) : glm::cross(d, glm::dvec3(0, 1, 0)));
    const glm::dvec3 v = glm::cross(d, u);
    int hits = 0;
    for (int a = 0; a < grid; ++a)
      for (int b = 0; b < grid; ++b) {
        const double x = radius * (2.0 * (a + 0.5) / grid - 1.0), y = radius * (2.0 * (b + 0.5) / grid - 1.0);
        const glm::dvec3 point = centre + u * x + v * y;
        for (const glm::dvec4* s = first; s != last; ++s) {
          const glm::dvec3 r = point - glm::dvec3(*s);
          const double along = glm::dot(r, d);
          if (glm::dot(r, r) - along * along <= s->w * s->w) {
            ++hits;
            break;
          }
        }
      }
    area += hits * (2.0 * radius / grid) * (2.0 * radius / grid);
  }
  return glm::dvec4(proxy_centre, std::sqrt(area / 13.0 / M_PI));
}

// Splits [first, last) at the median of the centres along their longest extent until groups hold
// kGroupSpheres at most (stable: equal keys keep their order).
void split_groups(std::vector<glm::dvec4>& spheres, size_t first, size_t last, std::vector<OccluderGroup>* groups) {
  if (last - first <= kGroupSpheres) {
    OccluderGroup g;
    g.first = static_cast<uint32_t>(first);
    g.count = static_cast<uint32_t>(last - first);
    g.bound = bound_of(spheres.data() + first, spheres.data() + last);
    g.proxy = proxy_of(spheres.data() + first, spheres.data() + last, g.bound);
    groups->push_back(g);
    return;
  }
  glm::dvec3 lo(1e300), hi(-1e300);
  for (size_t i = first; i < last; ++i) {
    lo = glm::min(lo, glm::dvec3(spheres[i]));
    hi = glm::max(hi, glm::dvec3(spheres[i]));
  }
  const glm::dvec3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  std::stable_sort(spheres.begin() + first, spheres.begin() + last,
                   [axis](const glm::dvec4& a, const glm::dvec4& b) { return a[axis] < b[axis]; });
  const size_t middle = first + (last - first) / 2;
  split_groups(spheres, first, middle, groups);
  split_groups(spheres, middle, last, groups);
}

}  // namespace

OccluderObject make_occluder_object(std::vector<glm::dvec4> spheres, const glm::dvec3& albedo) {
  OccluderObject o;
  o.spheres = std::move(spheres);
  o.albedo = albedo;
  if (o.spheres.empty()) return o;
  split_groups(o.spheres, 0, o.spheres.size(), &o.groups);
  o.bound = bound_of(o.spheres.data(), o.spheres.data() + o.spheres.size());
  o.proxy = o.groups.size() == 1 ? o.groups[0].proxy : proxy_of(o.spheres.data(), o.spheres.data() + o.spheres.size(), o.bound);
  return o;
}

OcclusionFrame make_occlusion_frame(const std::vector<const OccluderObject*>& objects,
                                    const std::vector<glm::dmat4>& enu_from_object, const glm::dmat4& clip_from_world,
                                    const glm::dmat3& enu_from_world, int viewport_width, int viewport_height,
                                    const SkyTransfer& sky, const glm::dvec3& sun_direction_enu,
                                    const glm::dvec3& sun_illuminance_lux, const OcclusionLimits& limits) {
  OcclusionFrame f;
  f.tiles_x = std::clamp((viewport_width + OcclusionFrame::kTilePx - 1) / OcclusionFrame::kTilePx, 1, 256);
  f.tiles_y = std::clamp((viewport_height + OcclusionFrame::kTilePx - 1) / OcclusionFrame::kTilePx, 1, 256);
  f.tile_from_position = glm::mat4(clip_from_world);
  f.enu_from_world = glm::mat3(enu_from_world);
  f.sky = sky;
  f.sun = glm::vec4(glm::vec3(sun_direction_enu), 0.0f);
  f.sun_lux = glm::vec3(sun_illuminance_lux);
  f.grid = glm::vec4(f.tiles_x, f.tiles_y, occlusion_tables().ol_max_magnitude,
                     (limits.bounce ? 1.0f : 0.0f) + (limits.hybrid ? 2.0f : 0.0f));
  f.limits = glm::vec4(limits.sin_cull, limits.sin_far, limits.sin_near, limits.sun_radius_rad);
  const glm::dmat4 clip_from_enu = clip_from_world * glm::dmat4(glm::transpose(enu_from_world));

  struct Listed {
    double distance;
    uint32_t object;
    int x0, x1, y0, y1;
  };
  size_t sphere_total = 0;
  for (const OccluderObject* o : objects) sphere_total += o->spheres.size();
  std::vector<glm::vec4> groups;  // appended to the spheres' texels below
  std::vector<Listed> listed;
  for (size_t i = 0; i < objects.size(); ++i) {
    const OccluderObject& o = *objects[i];
    const glm::dmat4& m = enu_from_object[i];
    const uint32_t first = static_cast<uint32_t>(f.spheres.size());
    for (const glm::dvec4& s : o.spheres) f.spheres.emplace_back(glm::vec3(m * glm::dvec4(glm::dvec3(s), 1.0)), s.w);
    const uint32_t first_group = static_cast<uint32_t>(sphere_total + groups.size());
    for (const OccluderGroup& g : o.groups) {
      groups.emplace_back(glm::vec3(m * glm::dvec4(glm::dvec3(g.bound), 1.0)), g.bound.w);
      groups.emplace_back(glm::vec3(m * glm::dvec4(glm::dvec3(g.proxy), 1.0)), g.proxy.w);
      groups.emplace_back(static_cast<float>(first + g.first), static_cast<float>(g.count), 0.0f, 0.0f);
    }
    const glm::dvec3 bound = glm::dvec3(m * glm::dvec4(glm::dvec3(o.bound), 1.0));
    const glm::dvec3 proxy = glm::dvec3(m * glm::dvec4(glm::dvec3(o.proxy), 1.0));
    f.objects.emplace_back(glm::vec3(bound), o.bound.w);
    f.objects.emplace_back(glm::vec3(proxy), o.proxy.w);
    f.objects.emplace_back(glm::vec3(o.albedo), 0.0f);
    f.objects.emplace_back(static_cast<float>(first_group), static_cast<float>(o.groups.size()), 0.0f, 0.0f);
    if (o.spheres.empty()) continue;
    // The receivers it may shade lie within bound / sin_cull of its bound's centre: that box's screen rect.
    const double reach = o.bound.w / limits.sin_cull;
    double x_lo = 1.0, x_hi = -1.0, y_lo = 1.0, y_hi = -1.0;
    bool behind = false;
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 corner = bound + reach * glm::dvec3(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
      const glm::dvec4 clip = clip_from_enu * glm::dvec4(corner, 1.0);
      if (clip.w <= 1e-6) {
        behind = true;
        break;
      }
      x_lo = std::min(x_lo, clip.x / clip.w);
      x_hi = std::max(x_hi, clip.x / clip.w);
      y_lo = std::min(y_lo, clip.y / clip.w);
      y_hi = std::max(y_hi, clip.y / clip.w);
    }
    if (behind) x_lo = y_lo = -1.0, x_hi = y_hi = 1.0;
    if (x_hi < -1.0 || x_lo > 1.0 || y_hi < -1.0 || y_lo > 1.0) continue;
    auto tile = [](double ndc, int n) { return std::clamp(static_cast<int>(std::floor((ndc * 0.5 + 0.5) * n)), 0, n - 1); };
    listed.push_back({glm::length(bound), static_cast<uint32_t>(i), tile(x_lo, f.tiles_x), tile(x_hi, f.tiles_x),
                      tile(y_lo, f.tiles_y), tile(y_hi, f.tiles_y)});
  }
  f.spheres.insert(f.spheres.end(), groups.begin(), groups.end());
  // Nearest first in every tile (the bounce credits a direction to the first sphere that hides it).
  std::sort(listed.begin(), listed.end(), [](const Listed& a, const Listed& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.object < b.object);
  });
  const size_t tiles = static_cast<size_t>(f.tiles_x) * f.tiles_y;
  std::vector<uint32_t> count(tiles, 0);
  for (const Listed& l : listed)
    for (int y = l.y0; y <= l.y1; ++y)
      for (int x = l.x0; x <= l.x1; ++x) ++count[y * f.tiles_x + x];
  f.tiles.resize(tiles);
  uint32_t offset = 0;
  for (size_t t = 0; t < tiles; ++t) {
    f.tiles[t] = glm::uvec2(offset, 0u);
    offset += count[t];
    f.longest_tile_list = std::max(f.longest_tile_list, count[t]);
  }
  f.tile_objects.resize(offset);
  for (const Listed& l : listed)
    for (int y = l.y0; y <= l.y1; ++y)
      for (int x = l.x0; x <= l.x1; ++x) {
        glm::uvec2& t = f.tiles[y * f.tiles_x + x];
        f.tile_objects[t.x + t.y++] = l.object;
      }
  return f;
}

}  // namespace atmo::shadows
