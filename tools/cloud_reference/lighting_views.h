// lighting_views.h — the views on which the real-time cloud lighting
// (shaders/clouds/cloud_functions.glsl, its C++ twin in core/clouds) is
// measured against the path tracer, their stored path-traced references, and
// the comparison. Shared by tests/clouds/octaves_vs_path_tracer_test.cpp (the
// suite's figures, the references' regeneration, the fit of the defaults) and
// bench/clouds_error_cost.cpp (the lighting part of the error-vs-cost chart).
//
// The references (path_traced_references.inc) are of these very clouds,
// suns and cameras: change a number here and regenerate them
// (octaves_vs_path_tracer_test.cpp, DISABLED_RegenerateReferences).
#pragma once

#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "cloud_path_tracer.h"
#include "core/clouds/cloud_volume.h"
#include "core/clouds/cloud_lighting.h"

namespace atmo::clouds::reference {

// The light the references were traced with: the Sun's illuminance (lux) and
// uniform sky and ground radiances (cd/m^2).
constexpr double kViewSunLux = 1e5, kViewSkyCdm2 = 4000.0, kViewGroundCdm2 = 1500.0;

struct LightingView {
  const char* key;
  const char* name;
  std::function<CloudVolume()> cloud;
  glm::dvec3 sun;
  glm::dvec3 eye_offset;       // eye = the cloud's centre + this; the camera looks at the centre
  double fov_deg = 0.0;        // 0: 0.9 x the cloud's bounding sphere
  int res = 16;                // square image
  int spp = 500000;            // reference paths per pixel for the Sun (sky and ground: spp / 16), per half
  float max_transmittance = 0.5f;  // pixels compared: the cloud's body (the edges are noise-dominated)
};

// Development views: the defaults (core/clouds/cloud_optics.cpp) were fitted on them.
const std::vector<LightingView>& development_views();
// Held-out views: defined and path-traced before the model was final, compared once.
const std::vector<LightingView>& held_out_views();

PinholeCamera camera_for(const LightingView& v, const CloudVolume& cloud);
// The path tracer's pixel-centre ray (cloud_path_tracer.h: no jitter).
glm::dvec3 pixel_ray(const PinholeCamera& cam, int row, int col);

struct StoredReference {
  const char* key;
  int res;
  // Per pixel, row-major: Sun, sky, ground radiance (cd/m^2, green, for
  // kViewSunLux, kViewSkyCdm2, kViewGroundCdm2), transmittance, and
  // |a - b| / (a + b) of the two halves' totals.
  const float* data;
};
// nullptr when the view has no stored reference.
const StoredReference* stored_reference(const char* key);

// The model against the stored reference over the view's cloud pixels.
struct LightingErrors {
  double mean = 0.0, bias = 0.0;                // of (model - truth) / truth over the pixels
  double sun = 0.0, ambient = 0.0;              // mean |model - truth| of each part / the pixel's truth
  double sun_ratio = 0.0, ambient_ratio = 0.0;  // summed model / summed truth, per part
  double noise = 0.0;                           // the reference's: mean |a - b| / (a + b)
  int pixels = 0;                               // 0: no stored reference (or none of its size)
};
// What marches the model's rays: the per-cloud march (cloud_march.glsl's
// twin, on the cloud's own grid) or the layer march (cloud_layer_march.glsl's
// twin, through a clipmap of the one cloud centred on the eye's cell, as
// ATMO_CLOUD_DRAW_LAYER draws it), both at 0.5-voxel steps, no step budget.
enum class LightingMarch { PerCloud, Layer };
LightingErrors compare_with_reference(const LightingView& v, const twin::CloudOctaves& octaves,
                                      LightingMarch march = LightingMarch::PerCloud);

// The rays compare_with_reference marches for a view, lit by the Sun, sky and
// ground together as the plugin lights them: what a cost measurement marches.
struct ViewRays {
  CloudVolume cloud;
  LightDepths depths;
  twin::CloudMarch march;
  twin::CloudPhase phase;
  glm::dvec3 eye;
  std::vector<glm::dvec3> directions;
};
ViewRays view_rays(const LightingView& v);

// Downhill simplex (Nelder-Mead) from x0 (initial steps 0.2 |x0_i| + 0.02),
// `iterations` steps: the minimiser of f it found. The fits of the lighting's
// parameters to the views use it.
std::vector<double> nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                                int iterations);

}  // namespace atmo::clouds::reference
