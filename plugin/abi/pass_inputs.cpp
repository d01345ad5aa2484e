#include "abi/pass_inputs.h"

#include <algorithm>
#include <cmath>

#include "abi/validation.h"
#include "core/sky/analytic_tier.h"

namespace atmo::abi {

gl::SkyMethod resolve_sky_method(uint32_t requested, double eye_altitude_m, double atmosphere_thickness_m) {
  if (requested == ATMO_SKY_METHOD_MARCH || eye_altitude_m >= atmosphere_thickness_m) return gl::SkyMethod::kMarch;
  if (requested == ATMO_SKY_METHOD_ANALYTIC) return gl::SkyMethod::kAnalytic;
  return gl::SkyMethod::kLut;
}

// The highest ground on Earth (Everest, 8 849 m): no terrain farther than the eye's horizon plus this summit's
// horizon can be seen.
constexpr double kHighestGroundM = 8849.0;

// The range does not depend on the projection: clamped to a finite far
// plane, the slices fell elsewhere than with reversed Z's infinite one, and the
// three depth conventions gave different images (issue 18: sunset_haze p95
// 0.57 %, overcast_dusk 3.8 % even with the two-slice reading; with one range
// 7.6e-5). The projection stays in the signature for its callers.
float aerial_volume_range_m(const core::Scene& scene, const AtmoViewState& state,
                            const glm::dmat4& /*view_from_clip*/) {
  if (state.aerial_range_m != 0.0) return static_cast<float>(state.aerial_range_m);  // the host's (validated)
  const auto& atm = scene.atmosphere;
  // The end of the air along the horizon, and the farthest ground in sight.
  double range = twin::aerial_geometric_range(atm, static_cast<float>(scene.eye_altitude_m));
  const double r0 = atm.bottom_radius_m, r = r0 + std::max(scene.eye_altitude_m, 0.0);
  const double summit = r0 + kHighestGroundM;
  const double ground_m = std::sqrt(r * r - r0 * r0) + std::sqrt(summit * summit - r0 * r0);
  range = std::min(range, ground_m);
  return static_cast<float>(std::max(range, 1000.0));
}

gl::PassInputs make_pass_inputs(const core::Scene& scene, const AtmoView_T& view, const twin::Lut2D& transmittance,
                                const twin::Lut2D& multiple_scattering) {
  gl::PassInputs in;
  const AtmoViewState& v = view.state;
  in.atmosphere = scene.atmosphere;
  in.sun_direction_enu = glm::vec3(scene.sun_direction_enu);
  in.eye_altitude_m = static_cast<float>(scene.eye_altitude_m);
  in.enu_from_view = glm::mat3(view.eye.enu_from_view);
  in.view_from_clip = glm::mat4(view.eye.view_from_clip);
  for (int i = 0; i < 4; ++i) in.viewport[i] = v.viewport[i];
  in.depth_texture = v.depth_texture;
  if (v.depth_origin == ATMO_DEPTH_ORIGIN_VIEWPORT) {
    in.depth_origin[0] = v.viewport[0];
    in.depth_origin[1] = v.viewport[1];
  }
  in.depth_convention = static_cast<int>(v.depth_convention);
  in.log_far_m = static_cast<float>(v.far_plane_m);
  in.log_coefficient = static_cast<float>(v.log_depth_coefficient != 0.0 ? v.log_depth_coefficient : 1.0);
  in.exposure = static_cast<float>(v.exposure_scale != 0.0 ? v.exposure_scale : kDefaultExposureScale);
  in.output_encoding = static_cast<int>(v.output_encoding);
  const double thickness_m = static_cast<double>(scene.atmosphere.top_radius_m - scene.atmosphere.bottom_radius_m);
  in.method = resolve_sky_method(v.sky_method, scene.eye_altitude_m, thickness_m);
  in.aerial_range_m = aerial_volume_range_m(scene, v, view.eye.view_from_clip);
  auto or_default = [](uint32_t value, int fallback) { return value != 0 ? static_cast<int>(value) : fallback; };
  in.table_sizes.sky_view_width = or_default(v.sky_view_table_size[0], in.table_sizes.sky_view_width);
  in.table_sizes.sky_view_height = or_default(v.sky_view_table_size[1], in.table_sizes.sky_view_height);
  in.table_sizes.aerial_width = or_default(v.aerial_volume_size[0], in.table_sizes.aerial_width);
  in.table_sizes.aerial_height = or_default(v.aerial_volume_size[1], in.table_sizes.aerial_height);
  in.table_sizes.aerial_slices = or_default(v.aerial_volume_size[2], in.table_sizes.aerial_slices);

  if (in.method == gl::SkyMethod::kAnalytic) {
    const core::AnalyticTier tier = core::analytic_tier(view.context->atmosphere, in.atmosphere, transmittance,
                                                        multiple_scattering, in.sun_direction_enu, in.eye_altitude_m);
    in.preetham = tier.coefficients;
    in.analytic_weight = tier.weight;
    // Where Preetham has no say, draw with the LUT program: it does not evaluate Preetham at all.
    if (tier.weight <= 0.0f) in.method = gl::SkyMethod::kLut;
  }
  return in;
}

}  // namespace atmo::abi
