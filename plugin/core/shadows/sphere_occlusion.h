// sphere_occlusion.h — the sky's irradiance at a receiver behind spheres, at
// any SH order and by each exponential (the direct product of blockers, the
// exact exponential, optimal linear, hybrid), in double: the study behind the
// include's choices (order 4, hybrid; docs/SKY_OCCLUSION.md's chart), and the
// include's twin is tested against it at order 4.
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <vector>

#include "core/shadows/sh.h"

namespace atmo::shadows {

enum class ExpMethod { direct_product, exact, optimal_linear, hybrid };
const char* exp_method_name(ExpMethod method);

// What one order needs: the triple product, the optimal-linear table, the blockers' logs by angle.
class ShOrder {
 public:
  explicit ShOrder(int order);
  int order() const { return gamma_.order(); }
  const TripleProduct& gamma() const { return gamma_; }
  const OptimalLinearTable& optimal_linear() const { return ol_; }
  std::vector<double> log_blocker(double theta_rad) const;  // linear in a 1024-entry table over [0, pi/2]

 private:
  TripleProduct gamma_;
  OptimalLinearTable ol_;
  std::vector<std::vector<double>> log_table_;
};

struct OccludedSky {
  glm::dvec3 sky_lux{0.0};       // with the spheres, clamped to [0, open]
  glm::dvec3 open_lux{0.0};      // without them (the same SH)
  double sky_visibility = 1.0;   // rho . V: cosine-weighted visible fraction of a uniform sky
};

// Spheres as (centre relative to the receiver, radius), m; n unit; radiance_sh: order^2 coefficients
// (rgb). Each sphere is adjusted to the receiver's tangent plane as the include does (atmo_occ_adjust).
OccludedSky occluded_sky(const ShOrder& order, const std::vector<glm::dvec4>& spheres, const glm::dvec3& n,
                         const std::vector<glm::dvec3>& radiance_sh, ExpMethod method);

}  // namespace atmo::shadows
