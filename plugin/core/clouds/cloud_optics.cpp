#include "core/clouds/cloud_optics.h"

#include <algorithm>
#include <cmath>

namespace atmo::clouds {

twin::CloudPhase phase_for_droplet(float droplet_diameter_um) {
  const double d = std::clamp(static_cast<double>(droplet_diameter_um), 5.0, 50.0);
  twin::CloudPhase p{};
  p.g_hg = static_cast<float>(std::exp(-0.0990567 / (d - 1.67154)));
  p.g_draine = static_cast<float>(std::exp(-2.20679 / (d + 3.91029) - 0.428934));
  p.alpha_draine = static_cast<float>(std::exp(3.62489 - 8.29288 / (d + 5.52825)));
  p.w_draine = static_cast<float>(std::exp(-0.599085 / (d - 0.641583) - 0.665888));
  return p;
}

twin::CloudOctaves default_octaves() {
  twin::CloudOctaves o{};
  // Fitted against path-traced references on the development views of
  // tests/clouds/octaves_vs_path_tracer_test.cpp (docs/CLOUDS.md, "Against the
  // path tracer"): the ambient's parameters to the sky's and ground's parts of
  // the images, then the octaves' and the diffusion's to the Sun's part
  // (Nelder-Mead; DISABLED_FitDefaults reruns it); the look-ahead and
  // thin_extinction by a scan. Development views 12.1 %, held-out 14.6 %. At 6
  // octaves, the plugin's default count (4 or 8 octaves: 14-16 %).
  o.count = 6;
  o.extinction_scale = 0.682f;
  o.scattering_scale = 0.75f;
  o.eccentricity_scale = 0.929f;
  o.ambient_extinction = 0.865f;
  o.ambient_loss = 0.0f;
  o.diffusion_strength = 2.55f;
  o.diffusion_extinction = 0.069f;
  o.diffusion_side_escape = 13.5f;
  o.diffusion_anisotropy = 0.462f;
  o.diffusion_buildup_extinction = 2.78f;
  o.diffusion_lookahead = 4.0f;
  o.thin_extinction = 0.2f;
  o.ambient_view_extinction = 0.081f;
  o.up_grid = glm::vec3(0.0f, 0.0f, 1.0f);
  return o;
}

twin::CloudOctaves single_scattering_octaves() {
  twin::CloudOctaves o = default_octaves();
  o.count = 1;
  o.diffusion_strength = 0.0f;
  return o;
}

}  // namespace atmo::clouds
