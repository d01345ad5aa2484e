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
  // From the sweep in tests/clouds/octaves_vs_path_tracer_test.cpp (mean
  // relative error against the path tracer 33-36 %, single scattering 80 %):
  // the approximation still misses the diffuse light deep in thick clouds.
  o.count = 8;
  o.extinction_scale = 0.3f;
  o.scattering_scale = 0.5f;
  o.eccentricity_scale = 0.5f;
  o.ambient_extinction = 0.5f;
  return o;
}

twin::CloudOctaves single_scattering_octaves() {
  twin::CloudOctaves o = default_octaves();
  o.count = 1;
  return o;
}

}  // namespace atmo::clouds
