#include "occlusion_scenes.h"

#include <cmath>

#include "core/shadows/sh.h"

namespace atmo::shadow_reference {

glm::dvec3 test_sky_radiance(const glm::dvec3& d) {
  if (d.z <= 0.0) return glm::dvec3(900.0, 850.0, 800.0);
  const glm::dvec3 towards_sun = glm::normalize(glm::dvec3(0.6, 0.2, 0.77));
  return glm::dvec3(2000.0, 2600.0, 3800.0) * (0.6 + 0.4 * d.z) + glm::dvec3(3000.0, 2800.0, 2400.0) *
                                                                        std::pow(std::max(0.0, glm::dot(d, towards_sun)), 4.0);
}

std::vector<glm::dvec3> test_sky_sh(int order) {
  const int nz = 400, nphi = 800;
  std::vector<glm::dvec3> sh(static_cast<size_t>(order) * order, glm::dvec3(0.0));
  for (int a = 0; a < nz; ++a) {
    const double z = 1.0 - 2.0 * (a + 0.5) / nz, s = std::sqrt(1.0 - z * z);
    for (int b = 0; b < nphi; ++b) {
      const double phi = 2.0 * M_PI * (b + 0.5) / nphi;
      const glm::dvec3 d(s * std::cos(phi), s * std::sin(phi), z);
      const glm::dvec3 l = test_sky_radiance(d);
      const std::vector<double> y = shadows::sh_basis(order, d);
      for (size_t i = 0; i < sh.size(); ++i) sh[i] += l * (y[i] * 4.0 * M_PI / (nz * nphi));
    }
  }
  return sh;
}

std::vector<OcclusionConfig> occlusion_configs() {
  std::vector<OcclusionConfig> out;
  const glm::dvec3 up(0, 0, 1);
  // One sphere overhead and beside, at 10..70 degrees of angular radius from the receiver under it.
  for (double deg : {10.0, 30.0, 50.0, 70.0}) {
    OcclusionConfig c;
    c.name = "one sphere " + std::to_string(static_cast<int>(deg)) + " deg";
    const double d = 10.0, r = d * std::sin(deg * M_PI / 180.0);
    c.spheres = {{0, 0, d, r}};
    for (double x : {0.0, 0.5 * d, d, 2.0 * d}) c.receivers.push_back({{x, 0, 0}, up});
    out.push_back(c);
  }
  {  // Many small spheres: a loose cloud of 40 over the receivers (a tree-like or a scaffold).
    OcclusionConfig c;
    c.name = "40 small spheres";
    uint32_t s = 12345u;
    auto rnd = [&s]() { s = s * 1664525u + 1013904223u; return (s >> 8) / 16777216.0; };
    for (int i = 0; i < 40; ++i) c.spheres.push_back({8.0 * rnd() - 4.0, 8.0 * rnd() - 4.0, 4.0 + 4.0 * rnd(), 0.3 + 0.5 * rnd()});
    for (double x : {-2.0, 0.0, 2.0, 6.0}) c.receivers.push_back({{x, 0.5, 0}, up});
    out.push_back(c);
  }
  {  // Two intersecting spheres of ~25 degrees each.
    OcclusionConfig c;
    c.name = "two intersecting";
    c.spheres = {{-1.5, 0, 8, 3.4}, {1.5, 0, 8, 3.4}};
    for (double x : {0.0, 3.0, 8.0}) c.receivers.push_back({{x, 0, 0}, up});
    out.push_back(c);
  }
  {  // Under a wing: a fuselage of 6 spheres at 4.5 m, a wing of 12 at 4 m, an engine under it.
    OcclusionConfig c;
    c.name = "under a wing";
    for (int i = 0; i < 6; ++i) c.spheres.push_back({-10.0 + 4.0 * i, 0, 4.5, 2.0});
    for (int i = 0; i < 12; ++i) c.spheres.push_back({-2.0 - 0.4 * i, 2.5 + 1.4 * i, 4.0 + 0.05 * i, 0.8});
    c.spheres.push_back({-4.0, 6.0, 2.6, 1.1});
    for (glm::dvec3 p : {glm::dvec3(-3, 4, 0), glm::dvec3(-5, 9, 0), glm::dvec3(-6, 14, 0), glm::dvec3(0, 8, 0),
                         glm::dvec3(-4, 20, 0)})
      c.receivers.push_back({p, up});
    // The fuselage's own underside, facing down: it sees the ground and the sky's low band.
    c.receivers.push_back({{-2.0, 0.0, 2.5}, {0, 0, -1}});
    out.push_back(c);
  }
  {  // Between two vans 3 m apart (6 spheres each), receivers on the ground between and beside.
    OcclusionConfig c;
    c.name = "between two vehicles";
    for (double y : {-2.5, 2.5})
      for (int i = 0; i < 3; ++i) {
        c.spheres.push_back({-1.6 + 1.6 * i, y, 0.9, 0.95});
        c.spheres.push_back({-1.6 + 1.6 * i, y, 1.8, 0.8});
      }
    for (glm::dvec3 p : {glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(2.5, 0, 0), glm::dvec3(0, 4.0, 0)})
      c.receivers.push_back({p, up});
    // A van's side, facing the other van.
    c.receivers.push_back({{0.0, -1.5, 1.2}, {0, 1, 0}});
    out.push_back(c);
  }
  {  // Near a wall 6 m high, 12 m long (a row of 3 x 8 spheres), receivers on the ground beside it and a
     // wall facing it.
    OcclusionConfig c;
    c.name = "near a wall";
    for (int i = 0; i < 8; ++i)
      for (int k = 0; k < 3; ++k) c.spheres.push_back({-6.0 + 12.0 * i / 7.0, 0, 1.0 + 2.0 * k, 1.0});
    for (double y : {1.5, 3.0, 6.0}) c.receivers.push_back({{0, y, 0}, up});
    c.receivers.push_back({{0, 4.0, 2.0}, {0, -1, 0}});
    out.push_back(c);
  }
  return out;
}

}  // namespace atmo::shadow_reference
