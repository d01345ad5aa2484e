// scenario_setup.h — what `atmo render` hands the plugin and the host scene for
// a scenario, as plain data: the terrain's options, the light list (the
// runway's generated lights, the airport and town layouts and the file's own
// points), the fog state and a camera's view setup. One place, so a test that
// recomputes a render's light from the same inputs
// (tests/render/runway_fog_night_test.cpp, airport_night_test.cpp) uses
// exactly what the render used.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "atmo/atmo.h"
#include "atmo_host_scene/camera.h"
#include "atmo_host_scene/light_layouts.h"
#include "atmo_host_scene/terrain.h"
#include "atmo_scenario/scenario.h"

namespace atmo::render {

// The scenario's terrain (Kind::None without one); its own runway points drawn only without a "lights" block.
host_scene::TerrainOptions terrain_of(const scenario::Scenario& s);

host_scene::Geodetic to_host(const scenario::GeodeticPoint& g);
// The ENU origin of the scenario's world frame.
host_scene::Geodetic origin_of(const scenario::Scenario& s);

// The host-scene layouts a scenario's "lights" block asks for.
host_scene::AirportSpec airport_spec_of(const scenario::AirportLights& a);
host_scene::TownSpec town_spec_of(const scenario::TownLights& t);

// set_lights' light list, ENU at origin_of(s): the terrain runway's approach,
// threshold and edge lights when asked for (beamed along the approach), the
// airport's lights, the town's, then the file's own points (omnidirectional).
// Empty without a "lights" block; throws (naming /lights) past ATMO_LIGHTS_MAX.
std::vector<AtmoLightPoint> light_points_of(const scenario::Scenario& s, const host_scene::Terrain& terrain);

// set_atmosphere's and set_frame's states: the file's air and its UTC.
AtmoAtmosphereState atmosphere_state_of(const scenario::Scenario& s);
AtmoFrameState frame_state_of(const scenario::Scenario& s);

// set_fog's state: the file's visibility, and its top (above the ENU origin)
// as a height above the ellipsoid. Only meaningful when s.fog is set.
AtmoFogState fog_state_of(const scenario::Scenario& s);

// Camera `ci`'s exposure as set in the file: its own EV100, else the
// scenario's; none means automatic (scenario::auto_exposure_ev100 of the Sun).
std::optional<double> set_exposure_ev100_of(const scenario::Scenario& s, size_t ci);

// The glow threshold `atmo render` passes to set_lights: 1/2000 of the camera's
// white (the luminance that maps to 1 at this exposure scale), cd/m^2.
double glow_threshold_cd_m2_of(double exposure_scale);

// Camera `ci`'s view: pose in ENU at origin_of(s), field of view, near/far,
// the whole target as viewport; no depth texture, linear HDR output, exposure 1.
host_scene::ViewSetup view_setup_of(const scenario::Scenario& s, size_t ci, host_scene::DepthConvention depth);

}  // namespace atmo::render
