// night_sky_inputs.h — the night sky of a view, from the frame: what can be
// seen (core/night_sky/night_plan.h), the astrometry of the eye (cached per
// view), and the stars and planets to draw (the context's StarField, parsed
// from the embedded catalogue on first use). No GL.
#pragma once

#include <string>

#include "abi/objects.h"
#include "core/scene/scene.h"
#include "gl/renderer.h"

namespace atmo::abi {

// The plan for this view and frame (stored in view.night_plan too).
const core::night::NightPlan& plan_night_sky(AtmoContext_T* context, AtmoView_T& view, const core::Scene& scene,
                                             const gl::PassInputs& inputs);

// The view's astrometry at the context's time, rebuilt when the time, DUT1
// or the eye changed; null (and *error) if ERFA refused the time or the eye.
const core::astro::AstrometryFrame* view_astrometry(AtmoContext_T* context, AtmoView_T& view, std::string* error);

// Sets inputs->night (the sky pass's Moon, moonlit sky and background) from
// the view's plan (call plan_night_sky first). The background needs the
// view's astrometry; should it fail, the background stays off.
void add_night_terms(AtmoContext_T* context, AtmoView_T& view, const core::Scene& scene, gl::PassInputs* inputs);

// True when the plan's limit shows that no point source can be seen without
// any astrometry: the limit is brighter than the brightest star and than the
// brightest planet of the last computation (within a day). The daylight case.
bool night_points_invisible(const AtmoContext_T* context, const core::night::NightPlan& plan);

// The aerial-perspective pass: when the view's last plan found the moonlit
// sky brighter than the Sun's (NightPlan::moon_lights_haze), the volume is
// built with the Moon as the light (the Sun then lights nothing near the
// ground). The plan is the one of this view's last sky or night pass, so a
// host calling the sky pass first gets this frame's.
void light_haze_by_the_moon(const AtmoView_T& view, const core::Scene& scene, gl::PassInputs* inputs);

// Fills view.night_points with the stars and planets above the horizon and
// brighter than the plan's limiting magnitude. Returns false (and *error) only
// when the astrometry failed; a catalogue that could not be parsed leaves the
// planets (and logs once).
bool collect_night_points(AtmoContext_T* context, AtmoView_T& view, const core::Scene& scene, std::string* error);

}  // namespace atmo::abi
