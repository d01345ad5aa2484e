// fog_frame.h — the fog and its lights as one view's frame needs them: the
// medium (optics and its lookup tables), the lights (in ECEF, double), and per
// view each light relative to the eye, its glow's cull radius and the summed
// diffusion term (docs/FOG.md). Pure; the ABI layer validates the host's
// structs into these, the GL layer draws from FogFrame.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "core/fog/fog_model.h"
#include "core/geo/eye_frame.h"
#include "core/lights/light_set.h"
#include "core/scene/scene.h"
#include "core/sky/sky_lighting.h"

namespace atmo::fog {

// The fog medium: optics and the tables for its phase function.
struct FogMedium {
  FogOptics optics;  // extinction 0: no fog
  static constexpr int kSurfaceTableSize = 32;  // thicknesses and angles
  int airlight_table_size = 64;
  // Tables for the optics' phase function (rebuilt only when it changes).
  double tables_phase_g = NAN;
  int tables_airlight_size = 0;
  FogTable airlight, surface;
  std::unique_ptr<GlowBound> bound;
  uint64_t version = 0;  // bumps when the tables change (the GL copies follow)
  bool enabled() const { return optics.extinction_per_m > 0.0; }
  // Takes new optics; rebuilds the tables when the phase or the size changes.
  void apply(const FogOptics& o, int table_size);
};

// One view's frame: lights relative to the eye in its ENU axes (float), with
// their effective extinction (the part of the eye-light path in the layer),
// glow radius, and the sum of their diffusion terms at the eye.
struct FrameLight {
  glm::vec3 position_enu_m{0.0f};  // relative to the eye
  glm::vec3 intensity_cd{0.0f};
  glm::vec3 axis_enu{0.0f, 0.0f, 1.0f};
  float cos_inner = -2.0f, cos_outer = -2.0f;
  float lobes = 1.0f;               // 2: both ways along the axis (atmo_fog_cone)
  float mean_profile = 1.0f;        // the cone's mean over the sphere (the diffusion term's power)
  float beta_per_m = 0.0f;          // effective extinction on the eye-light path
  float glow_radius_rad = 0.0f;     // where the glow falls under kGlowReachFraction of the threshold (0: nowhere)
  float visible_radius_rad = 0.0f;  // ... and under the threshold itself (its core is drawn to here at most)
  // A merged light (lights::LightClusters) stands for lights spread about its position, this much (m, RMS):
  // its distances are floored at it, as a point between its lights would light what is near it too much.
  float extent_m = 0.0f;
};
struct FogFrame {
  std::vector<FrameLight> lights;   // every light (the glow pass draws those with a radius)
  float top_above_eye_m = kNoTop;
  double extinction_per_m = 0.0;    // the fog's (0: none)
  // Diffusion light at the eye summed over the lights (docs/FOG.md): fluence
  // per channel, and per channel the vector sum of the flux towards the lights.
  glm::vec3 fluence{0.0f};
  glm::mat3 flux_towards_lights{0.0f};  // column c: channel c's vector, ENU
  glm::vec4 diffusion{0.0f};            // (sigma_tr, mu, rate, on) for atmo_fog_diffusion_light
};
// Without fog (fog.enabled() false) the lights are placed all the same,
// with no extinction, glow or diffusion: the light points and the host's
// surfaces still need them.
FogFrame make_fog_frame(const FogMedium& fog, const lights::LightSet& lights, const core::EyeFrame& eye,
                        double threshold_cd_m2);
// The same into *out, reusing its storage (a view's frame, made again each frame).
void make_fog_frame(const FogMedium& fog, const lights::LightSet& lights, const core::EyeFrame& eye,
                    double threshold_cd_m2, FogFrame* out);

// A glow is followed until it falls under this fraction of the threshold: many such glows add up.
constexpr double kGlowReachFraction = 0.1;

// The glow threshold of a frame, cd/m^2: the host's when it set one (> 0),
// else 1/2000 of the view's white (the luminance that maps to 1 at this exposure).
double glow_threshold_cd_m2(double host_threshold_cd_m2, double exposure_scale);

// The smallest sine of the angle to a light that a glow is evaluated at:
// 0.2836 of a pixel (2 tan_half / rows), the glow's 1/gamma core averaged
// over the pixel on the light. `tan_half_fov_y`: the projection's vertical
// half-angle tangent; `rows`: the viewport's height in pixels.
double glow_min_sin(double tan_half_fov_y, double rows);

// The fog's isotropic light from the sky, Sun and Moon, cd/m^2 per channel:
// albedo times the mean radiance around it, the sky above and the ground's
// reflection below (docs/FOG.md: a crude term, right in thin fog and at night).
glm::dvec3 ambient_radiance_cd_m2(const FogOptics& optics, const core::SkyLighting& sky, const core::Scene& scene,
                                  double ground_albedo);

}  // namespace atmo::fog
