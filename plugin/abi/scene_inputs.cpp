#include "abi/scene_inputs.h"

#include "abi/validation.h"

namespace atmo::abi {

core::Scene prepare_scene(AtmoContext_T* c, const AtmoView_T& view) {
  core::Scene s = core::make_scene(c->atmosphere, c->utc_posix_s, c->dut1_s, view.eye);
  AtmoContext_T::LutKey key{c->atmosphere.visibility_m, c->atmosphere.aerosol_scale_height_m,
                            c->atmosphere.ground_albedo, s.sphere_radius_m};
  if (!(key == c->lut_key)) {
    c->lut = core::compute_transmittance_table(s.atmosphere, core::kTransmittanceWidth, core::kTransmittanceHeight);
    c->multiple_scattering = core::compute_multiple_scattering_table(s.atmosphere, c->lut);
    c->lut_key = key;
    ++c->lut_version;
  }
  return s;
}

gl::PassInputs make_pass_inputs(const core::Scene& scene, const AtmoView_T& view) {
  gl::PassInputs in;
  const AtmoViewState& v = view.state;
  in.atmosphere = scene.atmosphere;
  in.sun_direction_enu = glm::vec3(scene.sun_direction_enu);
  in.eye_altitude_m = static_cast<float>(scene.eye_altitude_m);
  in.enu_from_view = glm::mat3(view.eye.enu_from_view);
  in.view_from_clip = glm::mat4(view.eye.view_from_clip);
  for (int i = 0; i < 4; ++i) in.viewport[i] = v.viewport[i];
  in.depth_texture = v.depth_texture;
  in.depth_convention = static_cast<int>(v.depth_convention);
  in.log_far_m = static_cast<float>(v.far_plane_m);
  in.log_coefficient = static_cast<float>(v.log_depth_coefficient != 0.0 ? v.log_depth_coefficient : 1.0);
  in.exposure = static_cast<float>(v.exposure_scale != 0.0 ? v.exposure_scale : kDefaultExposureScale);
  in.output_encoding = static_cast<int>(v.output_encoding);
  return in;
}

}  // namespace atmo::abi
