// pass_inputs.h — what a GL pass draws with, from the view's scene: the
// method chosen for the view (AtmoSkyMethod resolved to a tier), the
// aerial-perspective volume's reach, and for the analytic tier Preetham's
// coefficients, absolutely calibrated to the LUT model, and its confidence.
// No GL.
#pragma once

#include "abi/objects.h"
#include "core/scene/scene.h"
#include "gl/renderer.h"

namespace atmo::abi {

// `transmittance` and `multiple_scattering` are the context's current tables
// (the analytic tier's calibration evaluates the model's zenith with them).
gl::PassInputs make_pass_inputs(const core::Scene& scene, const AtmoView_T& view, const twin::Lut2D& transmittance,
                                const twin::Lut2D& multiple_scattering);

// The tier that draws: AUTO is LUT; every method hands over to the per-pixel
// march when the eye is above the atmosphere (where the sky-view table's
// horizon parametrisation and the volume's reach were not built for).
gl::SkyMethod resolve_sky_method(uint32_t requested, double eye_altitude_m, double atmosphere_thickness_m);

// Distance the aerial-perspective volume must reach: where a ray grazing the
// Earth leaves the atmosphere (at least 1 km), whatever the projection and its
// far plane, so that every depth convention reads the same volume.
float aerial_volume_range_m(const core::Scene& scene, const AtmoViewState& state, const glm::dmat4& view_from_clip);

}  // namespace atmo::abi
