// light_points.h — which of the host's lights a view shows as points, and how
// bright (ATMO_PASS_LIGHT_POINTS; docs/FOG.md "Light points"). A light's
// image is its illuminance at the eye, Allard's law E = I T / d^2: I its
// intensity towards the eye (the cone), T the air's transmittance along the
// segment times the fog's. It is drawn where E exceeds the eye's threshold
// illuminance for the luminance behind it (night ~8e-7 lx, day ~1e-4 lx), so
// a light dimmer than the sky behind it costs nothing. Pure; the GL layer
// spreads E over the footprint of shaders/night_sky/point_footprint.glsl.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/atmosphere/shader_twin.h"
#include "core/fog/fog_frame.h"

namespace atmo::lights {

// The eye's threshold illuminance for a point light seen against a
// background of luminance B, lux. ICAO (Annex 3, Attachment D; Doc 9328)
// gives four classes: night (B <= 50 cd/m^2) 8e-7 lx, intermediate 1e-5 lx,
// normal day (1 000-12 000 cd/m^2) 1e-4 lx, bright day (sunlit fog) 1e-3
// lx. Here they are joined log-linearly in log B between (50, 8e-7),
// (1 000, 1e-5), (12 000, 1e-4) and (40 000, 1e-3), so a light does not pop
// as the background crosses a class boundary; each class's value holds at or
// below its upper bound.
double allard_threshold_lux(double background_cd_m2);

// The air's transmittance (per channel) along the segment from the eye
// (`eye_altitude_m` above the sphere of atm.bottom_radius_m) to the point
// `to_point_enu_m` away: the extinction of functions.glsl's extinction_at
// (the twin: the same air the passes draw) integrated along the segment's
// altitudes (a curved Earth) by 8-point Gauss-Legendre over parts that span
// at most 400 m of altitude (one part for a light near the eye's height):
// within 1e-4 of a fine trapezoid sum from the ground to 9 km, 10 m to
// 400 km, any elevation (tests/core/light_points_core_test.cpp).
glm::dvec3 air_transmittance(const twin::AtmosphereParameters& atm, double eye_altitude_m,
                             const glm::dvec3& to_point_enu_m);

// What the points need of a view.
struct PointCamera {
  glm::dmat4 clip_from_enu{1.0};  // the host's projection times view-from-ENU-at-the-eye (rotation only)
  int viewport_width = 1, viewport_height = 1;
  double margin_px = 8.0;         // points this far outside the viewport still reach its edge
};

// One drawn point: where it is and what reaches the eye.
struct LightPoint {
  glm::vec3 position_enu_m{0.0f};    // relative to the eye
  glm::vec3 illuminance_lux{0.0f};   // at the eye, per channel (linear Rec.709), after the air and the fog
};

struct LightPointStats {
  uint32_t lights = 0;            // in the frame
  uint32_t off_screen = 0;        // behind the camera or outside the viewport (and its margin)
  uint32_t below_threshold = 0;   // E under the eye's threshold (the cone away from the eye counts here)
  uint32_t drawn = 0;
};

// The lights of a view's frame (fog::make_fog_frame: positions, cones, the
// fog's effective extinction) that show, with their illuminance at the eye.
// threshold_lux: the eye's (allard_threshold_lux, or the host's); a light's
// luminance-weighted E must reach it.
std::vector<LightPoint> visible_light_points(const fog::FogFrame& frame, const twin::AtmosphereParameters& atm,
                                             double eye_altitude_m, const PointCamera& camera, double threshold_lux,
                                             LightPointStats* stats = nullptr);

// Luminance weights of linear Rec.709 RGB (Y of CIE XYZ).
inline double luminance(const glm::dvec3& rgb) { return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z; }

}  // namespace atmo::lights
