// fog_inputs.h — set_fog and set_lights: validation of the host's structs,
// the context's fog (optics and lookup tables) and lights (in ECEF, double),
// and what one view's frame needs from them: each light relative to the eye,
// its glow's cull radius and the summed diffusion term (docs/FOG.md).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "abi/validation.h"
#include "atmo/atmo.h"
#include "core/eye_frame.h"
#include "core/fog/fog_model.h"

namespace atmo::abi {

struct ContextFog {
  fog::FogOptics optics;  // extinction 0: no fog
  int airlight_table_size = 64;
  // Tables for the optics' phase function (rebuilt only when it changes).
  double tables_phase_g = NAN;
  int tables_airlight_size = 0;
  fog::FogTable airlight, surface;
  std::unique_ptr<fog::GlowBound> bound;
  uint64_t version = 0;  // bumps when the tables change (the GL copies follow)
  bool enabled() const { return optics.extinction_per_m > 0.0; }
};

struct FogLight {
  glm::dvec3 position_ecef_m{0.0};
  glm::dvec3 axis_ecef{0.0, 0.0, 1.0};  // unit
  glm::dvec3 intensity_cd{0.0};         // on the axis, per channel (intensity times colour)
  double cos_inner = -2.0, cos_outer = -2.0;  // cos_outer < -1.5: omnidirectional
  double mean_profile = 1.0;            // the cone's mean over the sphere (the diffusion term's power)
};

struct ContextLights {
  std::vector<FogLight> lights;
  double glow_threshold_cd_m2 = 0.0;  // 0: from the view's exposure
};

// Validates and applies; on error nothing changes. Builds tables when the phase changes.
Verdict set_fog_state(const AtmoFogState& s, ContextFog* fog);
// `lights_bytes` is the struct the host passed (its array is read with light_size strides).
Verdict set_lights_state(const AtmoLightsState& s, ContextLights* lights);

// One view's frame: lights relative to the eye in its ENU axes (float), with
// their effective extinction (the part of the eye-light path in the layer),
// glow radius, and the sum of their diffusion terms at the eye.
struct FrameLight {
  glm::vec3 position_enu_m{0.0f};  // relative to the eye
  glm::vec3 intensity_cd{0.0f};
  glm::vec3 axis_enu{0.0f, 0.0f, 1.0f};
  float cos_inner = -2.0f, cos_outer = -2.0f;
  float beta_per_m = 0.0f;          // effective extinction on the eye-light path
  float glow_radius_rad = 0.0f;     // 0: no glow above the threshold
};
struct FogFrame {
  std::vector<FrameLight> lights;   // every light (the glow pass draws those with a radius)
  float top_above_eye_m = fog::kNoTop;
  // Diffusion light at the eye summed over the lights (docs/FOG.md): fluence
  // per channel, and per channel the vector sum of the flux towards the lights.
  glm::vec3 fluence{0.0f};
  glm::mat3 flux_towards_lights{0.0f};  // column c: channel c's vector, ENU
  glm::vec4 diffusion{0.0f};            // (sigma_tr, mu, rate, on) for atmo_fog_diffusion_light
};
FogFrame make_fog_frame(const ContextFog& fog, const ContextLights& lights, const core::EyeFrame& eye,
                        double threshold_cd_m2);

// Per light, the distance beyond which it lights a white Lambertian surface
// (direct, scattered and diffusion terms, facing it) below the threshold:
// the host include skips it there.
std::vector<float> surface_light_ranges(const ContextFog& fog, const FogFrame& frame,
                                        double threshold_cd_m2);

}  // namespace atmo::abi
