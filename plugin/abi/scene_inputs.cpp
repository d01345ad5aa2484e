#include "abi/scene_inputs.h"

#include <algorithm>
#include <cmath>

#include "abi/validation.h"
#include "core/solar_position.h"

namespace atmo::abi {

namespace {
// The sphere radius is rounded so channels at nearby latitudes share a table;
// 10 km is 0.16 % of the radius.
constexpr double kRadiusQuantumM = 10000.0;
}

SceneInputs prepare_scene(AtmoContext_T* c, const AtmoView_T& view) {
  SceneInputs s;
  const double radius = std::round(core::local_earth_radius_m(view.eye.eye.latitude_deg) / kRadiusQuantumM) *
                        kRadiusQuantumM;
  core::SunPosition sun = core::solar_position(c->utc_posix_s, c->dut1_s);
  s.atmosphere = core::make_atmosphere_parameters(c->atmosphere, radius, sun.distance_au);

  AtmoContext_T::LutKey key{c->atmosphere.visibility_m, c->atmosphere.aerosol_scale_height_m,
                            c->atmosphere.ground_albedo, radius};
  if (!(key == c->lut_key)) {
    c->lut = core::compute_transmittance_table(s.atmosphere, core::kTransmittanceWidth, core::kTransmittanceHeight);
    c->lut_key = key;
    ++c->lut_version;
  }
  s.sun_direction_ecef = sun.direction_ecef;
  s.sun_direction_enu = core::enu_from_ecef_direction(view.eye, sun.direction_ecef);
  s.eye_altitude_m = std::max(view.eye.eye.height_m, 1.0);
  return s;
}

gl::PassInputs make_pass_inputs(const SceneInputs& scene, const AtmoView_T& view) {
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
