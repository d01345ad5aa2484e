// scenario_setup.h — what `atmo render` hands the plugin and the host scene for
// a scenario, as plain data: the terrain's options, the light list (the
// runway's generated lights, the airport and town layouts and the file's own
// points), the fog state, the objects (meshes, sphere sets, poses: what
// set_occluders gets) and a camera's view setup. One place, so a test that
// recomputes a render's light from the same inputs
// (tests/render/runway_fog_night_test.cpp, airport_night_test.cpp) uses
// exactly what the render used.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "atmo/atmo.h"
#include "atmo_host_scene/camera.h"
#include "atmo_host_scene/light_layouts.h"
#include "atmo_host_scene/objects.h"
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

// The scenario's objects ("objects"), read from their files: the meshes the
// host draws (one per distinct file), each object's spheres (object frame),
// its pose in the ENU frame at origin_of(s) (host_scene::enu_from_object_pose
// of position_m and heading_deg) and its albedo.
struct ScenarioObjects {
  std::vector<spheres::TriangleMesh> meshes;
  std::vector<std::vector<AtmoOccluderSphere>> spheres;   // per object
  std::vector<host_scene::ObjectInstance> instances;      // per object: mesh index, pose, albedo

  bool empty() const { return instances.empty(); }
  std::vector<const spheres::TriangleMesh*> mesh_pointers() const;
  // set_occluders' objects, pointing into `spheres` (valid while this lives, unchanged).
  std::vector<AtmoOccluderObject> occluder_objects() const;
};

// Reads every object's files (paths resolved against the scenario file); throws std::runtime_error naming the
// element and the file's own error, e.g. "/objects/2/spheres: /x/van.spheres.json: spheres[3].radius_m: ...".
ScenarioObjects objects_of(const scenario::Scenario& s);

// set_occluders' state for `objects` (from ScenarioObjects::occluder_objects, which must outlive the call):
// ENU at `origin`, the poses as given; flags AtmoOcclusionFlags.
AtmoOccludersState occluders_state_enu(const host_scene::Geodetic& origin,
                                       const std::vector<AtmoOccluderObject>& objects, uint32_t flags = 0);

// set_clouds' layers for `layers` (the scenario's "clouds", or a flight event's), in the ENU frame at
// origin_of(s): procedural layers over cloud_layer_area_m, VDB files resolved against the scenario's folder
// (their paths kept in *vdb_paths, one per layer, which must outlive the call that takes the layers).
std::vector<AtmoCloudLayer> cloud_layers_of(const scenario::Scenario& s, const std::vector<scenario::CloudLayer>& layers,
                                            std::vector<std::string>* vdb_paths);
// set_clouds' state over `layers` (from cloud_layers_of, which must outlive the call): ENU at origin_of(s), the
// scenario's render.cloud_draw_mode, the other knobs at the plugin's defaults (setup: ATMO_CLOUD_SETUP_STREAM).
AtmoCloudsState clouds_state_of(const scenario::Scenario& s, const std::vector<AtmoCloudLayer>& layers);

// set_atmosphere's and set_frame's states: the file's air and its UTC.
AtmoAtmosphereState atmosphere_state_of(const scenario::Scenario& s);
// set_atmosphere's state for an atmosphere section (the file's, or a flight event's).
AtmoAtmosphereState atmosphere_state_of(const scenario::Atmosphere& a);
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
