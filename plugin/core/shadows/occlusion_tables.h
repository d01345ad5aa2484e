// occlusion_tables.h — what atmo_sky_occlusion.glsl reads besides the
// occluders: its 1D tables (a sphere's log-visibility and form factor by
// angular radius, the optimal-linear exponential by magnitude), made once per
// process at order 4, and the sky's per-frame transfer (the sky radiance's
// triple product with a Lambertian receiver's cosine).
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <string>
#include <vector>

#include "core/shadows/sh.h"

namespace atmo::shadows {

constexpr int kIncludeOrder = 4;  // the include's SH order: 16 coefficients

struct OcclusionTables {
  static constexpr int kSize = 256;  // texels per row
  static constexpr int kRows = 3;
  enum Row { kLogCap = 0, kFormFactor = 1, kOptimalLinear = 2 };
  // RGBA32F, row-major kSize x kRows. Rows kLogCap and kFormFactor hold, at theta = u pi/2 (u = i / (kSize - 1)),
  // the ZH bands 0..3 times sqrt(4 pi / (2l + 1)) (ready to multiply y_lm); kOptimalLinear (a, b, 0, 0) at
  // magnitude u * ol_max_magnitude.
  std::vector<glm::vec4> texels;
  float ol_max_magnitude = 0.0f;
};
// Built on first use (~0.1 s), then shared; thread-safe.
const OcclusionTables& occlusion_tables();
const TripleProduct& include_triple_product();
const OptimalLinearTable& include_optimal_linear();

// The ZH (bands 0..order-1) of the weight with which a sphere of angular radius theta, seen from p,
// averages its surface radiance as a function of its surface normal: the solid angle each visible
// patch subtends at p (cos gamma / distance^2), normalised to a unit integral, so a sphere of constant
// radiance gives that constant back (the thesis's (4.24) weighs by cos gamma alone).
std::vector<double> form_factor_zh(int order, double theta_rad);

// The GLSL body of atmo_occ_square (g * g at order 4, from the triple product's non-zeros); the
// include's copy is checked against it by a test.
std::string sh_square_glsl(const TripleProduct& gamma);

// The sky's light for the include, one frame: uniforms in float, as the host sets them.
struct SkyTransfer {
  // atmo_occ_transfer (vec4[108]): per channel c and cosine coefficient k < 9, the 16 coefficients
  // pi (M_{L_c})_{i k}, i = 0..15, of the sky radiance's product matrix: E_c = sum_k rho_k sum_i pi M_ik V_i.
  std::array<float, 432> transfer{};
  std::array<float, 27> sky_sh9{};     // atmo_occ_sky_sh9: the sky's irradiance SH9 (lux), = the transfer at V = 1
  std::array<float, 27> sun_sh9{};     // atmo_occ_sun_sh9: the Sun's irradiance on an occluder's surface by
                                       // its normal (lux), for its bounce (the sky's is sky_sh9)
};
// From the sky's radiance SH16 (ENU, rgb, cd/m^2 or W m^-2 sr^-1) and the Sun (unit ENU direction,
// illuminance on a surface facing it, lux).
SkyTransfer make_sky_transfer(const std::vector<glm::dvec3>& radiance_sh16, const glm::dvec3& sun_direction_enu,
                              const glm::dvec3& sun_illuminance_lux);

}  // namespace atmo::shadows
