#include "core/fog/fog_frame.h"

#include <algorithm>
#include <cmath>

#include "core/fog/fog_twin.h"

namespace atmo::fog {

void FogMedium::apply(const FogOptics& o, int table_size) {
  if (o.extinction_per_m > 0.0 && (o.phase_g != tables_phase_g || table_size != tables_airlight_size)) {
    const std::shared_ptr<const FogTables> tables = fog_tables(o.phase_g, table_size, kSurfaceTableSize);
    airlight = tables->airlight;
    surface = tables->surface;
    bound = std::make_unique<GlowBound>(o.phase_g);
    tables_phase_g = o.phase_g;
    tables_airlight_size = table_size;
    ++version;
  }
  optics = o;
  airlight_table_size = table_size;
}

FogFrame make_fog_frame(const FogMedium& fog, const lights::LightSet& lights, const core::EyeFrame& eye,
                        double threshold_cd_m2) {
  FogFrame f;
  make_fog_frame(fog, lights, eye, threshold_cd_m2, &f);
  return f;
}

void make_fog_frame(const FogMedium& fog, const lights::LightSet& lights, const core::EyeFrame& eye,
                    double threshold_cd_m2, FogFrame* out) {
  std::vector<FrameLight> storage = std::move(out->lights);
  FogFrame& f = *out;
  f = FogFrame{};
  f.lights = std::move(storage);
  FogOptics o = fog.optics;
  if (!fog.enabled()) o.extinction_per_m = 0.0, o.multiple_scattering = false;
  const double top = std::isfinite(o.top_height_m) ? o.top_height_m - eye.eye.height_m : INFINITY;
  f.top_above_eye_m = std::isfinite(top) ? static_cast<float>(top) : kNoTop;
  f.extinction_per_m = o.extinction_per_m;
  const glm::dmat3 enu_from_ecef = glm::transpose(eye.ecef_from_enu);
  // Every light against the eye, in its ENU axes (double until here).
  f.lights.resize(lights.size());
  std::vector<double> distance(f.lights.size());
  std::vector<glm::dvec3> power(f.lights.size());
  double floor_above_eye = 0.0;
  size_t n = 0;
  lights.for_each_light([&](const glm::dvec3& ecef, const glm::dvec3& axis, const lights::Light& l) {
    const glm::dvec3 rel = enu_from_ecef * (ecef - eye.eye_ecef_m);
    FrameLight& fl = f.lights[n];
    fl = FrameLight{};  // the storage holds last frame's lights
    fl.position_enu_m = glm::vec3(rel);
    fl.intensity_cd = glm::vec3(l.intensity_cd);
    fl.axis_enu = glm::vec3(enu_from_ecef * axis);
    fl.cos_inner = static_cast<float>(l.cos_inner);
    fl.cos_outer = static_cast<float>(l.cos_outer);
    fl.lobes = l.lobes;
    fl.mean_profile = static_cast<float>(l.mean_profile);
    distance[n] = glm::length(rel);
    power[n] = l.intensity_cd * l.mean_profile;
    floor_above_eye = std::min(floor_above_eye, rel.z);
    ++n;
  });
  // The diffusion term's layer: from the ground, taken as the lowest of the eye and the lights (lights stand
  // on the ground), to the top (docs/FOG.md).
  const double depth = std::isfinite(top) ? std::max(top - floor_above_eye, 1.0) : INFINITY;
  const double tr = o.transport_per_m(), mu = o.diffusion_decay_per_m(depth);
  const double cap = !o.multiple_scattering ? 0.0 : std::isfinite(depth) ? o.extinction_per_m * depth : 1e30;
  f.diffusion = glm::vec4(float(tr), float(mu), float(kHandoverRate), float(cap));
  glm::dvec3 fluence(0.0);
  glm::dmat3 flux(0.0);
  if (o.extinction_per_m > 0.0)
    for (size_t i = 0; i < f.lights.size(); ++i) {
      FrameLight& fl = f.lights[i];
      // The part of the eye-light segment inside the layer (heights in the tangent plane at the eye).
      const double beta =
          o.extinction_per_m * twin::atmo_fog_inside_fraction(0.0f, fl.position_enu_m.z, f.top_above_eye_m);
      fl.beta_per_m = static_cast<float>(beta);
      const double d = distance[i];
      const double peak = std::max({fl.intensity_cd.x, fl.intensity_cd.y, fl.intensity_cd.z});
      // Where the glow reaches a tenth of the threshold: glows under it add up over many lights (a town in
      // fog), which the merged glows of a tile keep (core/lights/glow_tiles.h).
      if (fog.bound) {
        fl.glow_radius_rad = static_cast<float>(
            fog.bound->radius_rad(beta, o.albedo, std::max(d, 1e-3), peak, kGlowReachFraction * threshold_cd_m2));
        fl.visible_radius_rad = fl.glow_radius_rad > 0.0f ? static_cast<float>(fog.bound->radius_rad(
                                                                beta, o.albedo, std::max(d, 1e-3), peak, threshold_cd_m2))
                                                          : 0.0f;
      }
      if (o.multiple_scattering && d > 0.0) {
        const glm::vec2 p1 = twin::atmo_fog_diffusion_light(f.diffusion, static_cast<float>(d),
                                                            static_cast<float>(beta * d), false);
        const double phi = p1.x, flux_magnitude = p1.y;
        const glm::dvec3 towards = glm::dvec3(fl.position_enu_m) / d;
        fluence += phi * power[i];
        for (int c = 0; c < 3; ++c) flux[c] += flux_magnitude * power[i][c] * towards;
      }
    }
  f.fluence = glm::vec3(fluence);
  f.flux_towards_lights = glm::mat3(flux);
}

double glow_threshold_cd_m2(double host_threshold_cd_m2, double exposure_scale) {
  if (host_threshold_cd_m2 > 0.0) return host_threshold_cd_m2;
  return 1.0 / (2000.0 * exposure_scale);
}

double glow_min_sin(double tan_half_fov_y, double rows) { return 0.5672 * tan_half_fov_y / rows; }

glm::dvec3 ambient_radiance_cd_m2(const FogOptics& optics, const core::SkyLighting& sky, const core::Scene& scene,
                                  double ground_albedo) {
  const glm::dvec3 sun = glm::dvec3(scene.atmosphere.sun_illuminance_lux) * std::max(scene.sun_direction_enu.z, 0.0);
  const glm::dvec3 moon = scene.bodies.moon_illuminance_rgb_lux * std::max(scene.bodies.moon_enu.z, 0.0);
  const glm::dvec3 horizontal = sky.horizontal_illuminance_lux + sun + moon;
  return optics.albedo * 0.5 * (sky.average_radiance + ground_albedo * horizontal / M_PI);
}

}  // namespace atmo::fog
