#include "core/lights/light_set.h"

namespace atmo::lights {

double mean_cone_profile(double cos_inner, double cos_outer, double lobes) {
  if (cos_outer < kOmni) return 1.0;
  return lobes * (2.0 - cos_inner - cos_outer) / 4.0;
}

size_t LightSet::size() const {
  size_t n = 0;
  for (const auto& [id, g] : groups) n += g.lights.size();
  return n;
}

}  // namespace atmo::lights
