#include "scenario_setup.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/light_layouts.h"
#include "sphere_json.h"

namespace atmo::render {

namespace hs = atmo::host_scene;
namespace sc = atmo::scenario;

hs::TerrainOptions terrain_of(const sc::Scenario& s) {
  hs::TerrainOptions t;
  if (!s.terrain || s.terrain->kind == sc::TerrainKind::None) {
    t.kind = hs::TerrainOptions::Kind::None;
    return t;
  }
  t.seed = s.terrain->seed;
  t.size_m = s.terrain->size_m;
  t.relief_m = s.terrain->kind == sc::TerrainKind::Flat ? 0.0 : s.terrain->relief_m;
  t.runway_heading_deg = s.terrain->runway_heading_deg;
  // With a "lights" block the plugin has the scenario's lights and draws their points (ATMO_PASS_LIGHT_POINTS):
  // the terrain's own runway points would show them twice, or show runway lights the scenario did not ask for.
  t.draw_light_points = !s.lights;
  return t;
}

hs::Geodetic to_host(const sc::GeodeticPoint& g) { return {g.latitude_deg, g.longitude_deg, g.height_m}; }

hs::Geodetic origin_of(const sc::Scenario& s) { return to_host(s.location); }

hs::AirportSpec airport_spec_of(const sc::AirportLights& a) {
  hs::AirportSpec spec;
  spec.runways.clear();
  for (const sc::AirportRunway& r : a.runways)
    spec.runways.push_back({{r.centre_enu_m[0], r.centre_enu_m[1]}, r.heading_deg, r.length_m, r.width_m});
  spec.taxiway_length_m = a.taxiway_length_m;
  return spec;
}

hs::TownSpec town_spec_of(const sc::TownLights& t) {
  hs::TownSpec spec;
  spec.centre_enu_m = {t.centre_enu_m[0], t.centre_enu_m[1]};
  spec.lights = t.lights;
  spec.lights_per_km2 = t.lights_per_km2;
  spec.seed = t.seed;
  return spec;
}

std::vector<AtmoLightPoint> light_points_of(const sc::Scenario& s, const hs::Terrain& terrain) {
  std::vector<AtmoLightPoint> points;
  if (!s.lights) return points;
  if (s.lights->runway_approach) points = terrain.atmo_light_points();
  if (s.lights->airport) {
    const std::vector<AtmoLightPoint> airport = hs::airport_lights(airport_spec_of(*s.lights->airport));
    points.insert(points.end(), airport.begin(), airport.end());
  }
  if (s.lights->town) {
    const std::vector<AtmoLightPoint> town = hs::town_lights(town_spec_of(*s.lights->town));
    points.insert(points.end(), town.begin(), town.end());
  }
  for (const sc::LightPoint& l : s.lights->points) {
    AtmoLightPoint p{};
    for (int k = 0; k < 3; ++k) {
      p.position_m[k] = l.enu_m[k];
      p.color[k] = l.color[k];
    }
    p.intensity_cd = l.intensity_cd;
    points.push_back(p);
  }
  // set_lights would refuse them all; say which file section asks for too many.
  if (points.size() > ATMO_LIGHTS_MAX)
    throw std::runtime_error("/lights: " + std::to_string(points.size()) +
                             " lights in all (runway, airport, town and points), more than set_lights takes (" +
                             std::to_string(ATMO_LIGHTS_MAX) + ")");
  return points;
}

std::vector<const spheres::TriangleMesh*> ScenarioObjects::mesh_pointers() const {
  std::vector<const spheres::TriangleMesh*> out;
  for (const spheres::TriangleMesh& m : meshes) out.push_back(&m);
  return out;
}

std::vector<AtmoOccluderObject> ScenarioObjects::occluder_objects() const {
  std::vector<AtmoOccluderObject> out;
  for (size_t i = 0; i < instances.size(); ++i) {
    AtmoOccluderObject o{};
    o.spheres = spheres[i].empty() ? nullptr : spheres[i].data();
    o.sphere_count = static_cast<uint32_t>(spheres[i].size());
    o.sphere_size = sizeof(AtmoOccluderSphere);
    for (int c = 0; c < 3; ++c) o.albedo[c] = instances[i].albedo[c];
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) o.world_from_object[c * 4 + r] = instances[i].enu_from_object[c][r];
    out.push_back(o);
  }
  return out;
}

ScenarioObjects objects_of(const sc::Scenario& s) {
  ScenarioObjects out;
  std::map<std::string, size_t> mesh_index;  // resolved path -> index into out.meshes
  for (size_t i = 0; i < s.objects.size(); ++i) {
    const sc::SceneObject& o = s.objects[i];
    const std::string at = "/objects/" + std::to_string(i);
    const std::string mesh_path = sc::resolve_path(s, o.mesh);
    auto found = mesh_index.find(mesh_path);
    if (found == mesh_index.end()) {
      try {
        out.meshes.push_back(spheres::read_mesh(mesh_path));
      } catch (const std::exception& e) {
        throw std::runtime_error(at + "/mesh: " + e.what());
      }
      if (out.meshes.back().triangles.empty()) throw std::runtime_error(at + "/mesh: " + mesh_path + ": no triangles");
      found = mesh_index.emplace(mesh_path, out.meshes.size() - 1).first;
    }
    spheres::SphereSet set;
    try {
      set = spheres::read_sphere_set(sc::resolve_path(s, o.spheres));
    } catch (const std::exception& e) {
      throw std::runtime_error(at + "/spheres: " + e.what());
    }
    out.spheres.push_back(hs::occluder_spheres(set));
    hs::ObjectInstance instance;
    instance.mesh = found->second;
    instance.enu_from_object =
        hs::enu_from_object_pose(glm::dvec3(o.position_m[0], o.position_m[1], o.position_m[2]), o.heading_deg);
    instance.albedo = glm::dvec3(o.albedo[0], o.albedo[1], o.albedo[2]);
    out.instances.push_back(instance);
  }
  return out;
}

AtmoOccludersState occluders_state_enu(const hs::Geodetic& origin, const std::vector<AtmoOccluderObject>& objects,
                                       uint32_t flags) {
  AtmoOccludersState state = atmo::make<AtmoOccludersState>(ATMO_TYPE_OCCLUDERS_STATE);
  state.world_frame = ATMO_WORLD_ENU;
  state.object_size = sizeof(AtmoOccluderObject);
  state.world_origin_geodetic[0] = origin.latitude_deg;
  state.world_origin_geodetic[1] = origin.longitude_deg;
  state.world_origin_geodetic[2] = origin.height_m;
  state.objects = objects.empty() ? nullptr : objects.data();
  state.object_count = static_cast<uint32_t>(objects.size());
  state.flags = flags;
  return state;
}

std::vector<AtmoCloudLayer> cloud_layers_of(const sc::Scenario& s, const std::vector<sc::CloudLayer>& layers,
                                            std::vector<std::string>* vdb_paths) {
  const hs::Geodetic origin = origin_of(s);
  std::vector<AtmoCloudLayer> out;
  vdb_paths->assign(layers.size(), std::string());  // no reallocation below: the layers point into it
  for (size_t i = 0; i < layers.size(); ++i) {
    const sc::CloudLayer& c = layers[i];
    AtmoCloudLayer l = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
    switch (c.type) {
      case sc::CloudType::Cumulus: l.type = ATMO_CLOUD_CUMULUS; break;
      case sc::CloudType::Stratus: l.type = ATMO_CLOUD_STRATUS; break;
      case sc::CloudType::Overcast: l.type = ATMO_CLOUD_OVERCAST; break;
      case sc::CloudType::Cirrus: l.type = ATMO_CLOUD_CIRRUS; break;
      case sc::CloudType::Vdb: l.type = ATMO_CLOUD_VDB_FILE; break;
    }
    l.seed = c.seed;
    if (c.type == sc::CloudType::Vdb) {
      (*vdb_paths)[i] = sc::resolve_path(s, c.vdb_file);
      l.vdb_path = (*vdb_paths)[i].c_str();
      const glm::dvec3 p = c.position.kind == sc::Position::Kind::Enu
                               ? glm::dvec3(c.position.enu_m[0], c.position.enu_m[1], c.position.enu_m[2])
                               : hs::enu_from_geodetic(origin, to_host(c.position.geodetic));
      for (int k = 0; k < 3; ++k) l.position_enu_m[k] = p[k];
      l.rotation_deg[0] = c.heading_deg;
      l.metres_per_unit = c.scale;
      l.density_scale = c.density_scale;
    } else {
      l.coverage_oktas = c.coverage_oktas;
      l.base_m = c.base_m;
      l.top_m = c.top_m;
      l.area_size_m = sc::cloud_layer_area_m(s, c);
    }
    out.push_back(l);
  }
  return out;
}

AtmoCloudsState clouds_state_of(const sc::Scenario& s, const std::vector<AtmoCloudLayer>& layers) {
  AtmoCloudsState state = atmo::clouds_state(s.location.latitude_deg, s.location.longitude_deg, s.location.height_m,
                                             layers.empty() ? nullptr : layers.data(),
                                             static_cast<uint32_t>(layers.size()));
  static_assert(int(sc::CloudDrawMode::Auto) == ATMO_CLOUD_DRAW_AUTO &&
                int(sc::CloudDrawMode::Impostors) == ATMO_CLOUD_DRAW_IMPOSTORS &&
                int(sc::CloudDrawMode::Direct) == ATMO_CLOUD_DRAW_DIRECT &&
                int(sc::CloudDrawMode::Layer) == ATMO_CLOUD_DRAW_LAYER);
  state.draw_mode = static_cast<uint32_t>(s.render.cloud_draw_mode);
  return state;
}

AtmoAtmosphereState atmosphere_state_of(const scenario::Atmosphere& a) {
  auto atmosphere = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
  atmosphere.visibility_m = a.visibility_m;
  atmosphere.aerosol_scale_height_m = a.aerosol_scale_height_m;
  atmosphere.ground_albedo = std::max(a.ground_albedo, 1e-6);
  return atmosphere;
}

AtmoAtmosphereState atmosphere_state_of(const scenario::Scenario& s) { return atmosphere_state_of(s.atmosphere); }

AtmoFrameState frame_state_of(const scenario::Scenario& s) {
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = s.utc_posix_s;
  frame.dut1_s = s.dut1_s;
  return frame;
}

AtmoFogState fog_state_of(const sc::Scenario& s) {
  AtmoFogState fog = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
  if (!s.fog) return fog;
  fog.visibility_m = s.fog->visibility_m;
  fog.top_height_m = s.location.height_m + s.fog->top_m;  // the file's top is above the ENU origin
  return fog;
}

hs::ViewSetup view_setup_of(const sc::Scenario& s, size_t ci, hs::DepthConvention depth) {
  const sc::Camera& cam = s.cameras[ci];
  const hs::Geodetic origin = origin_of(s);
  hs::ViewSetup setup;
  setup.world_origin = origin;
  setup.pose.position_enu_m =
      cam.position.kind == sc::Position::Kind::Enu
          ? glm::dvec3(cam.position.enu_m[0], cam.position.enu_m[1], cam.position.enu_m[2])
          : hs::enu_from_geodetic(origin, to_host(cam.position.geodetic));
  setup.pose.heading_deg = cam.heading_deg;
  setup.pose.pitch_deg = cam.pitch_deg;
  setup.pose.roll_deg = cam.roll_deg;
  setup.vfov_rad = glm::radians(cam.vertical_fov_deg);
  setup.near_m = cam.near_m;
  setup.far_m = cam.far_m;
  setup.depth_convention = depth;
  setup.viewport = {0, 0, cam.width, cam.height};
  setup.output_encoding = ATMO_OUTPUT_LINEAR_HDR;
  setup.exposure_scale = 1.0;  // the frame holds absolute cd/m^2; exposure is applied when writing the PNG
  // The layer march's still (explicit, or AUTO's choice for weather at scale): every pixel every frame.
  if (s.render.cloud_draw_mode == sc::CloudDrawMode::Layer || s.render.cloud_draw_mode == sc::CloudDrawMode::Auto)
    setup.cloud_quality = ATMO_CLOUD_QUALITY_HIGH;
  return setup;
}

std::optional<double> set_exposure_ev100_of(const scenario::Scenario& s, size_t ci) {
  const std::optional<double>& own = s.cameras.at(ci).exposure_ev100;
  return own ? own : s.render.exposure_ev100;
}

double glow_threshold_cd_m2_of(double exposure_scale) { return 1.0 / (2000.0 * exposure_scale); }

}  // namespace atmo::render
