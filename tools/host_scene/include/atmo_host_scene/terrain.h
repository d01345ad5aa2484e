// terrain.h — the host's opaque geometry: a procedural heightfield with a
// runway and approach/runway light points, in the ENU world frame of camera.h,
// drawn with its own GLSL 330 shaders as linear radiance (cd/m^2 times the
// exposure scale) into the bound framebuffer, for any DepthConvention.
//
// Layout: the runway's centre is the ENU origin (the airfield datum), its axis
// along runway_heading_deg. The approach end (threshold lights, approach
// lights) is the end the runway heading points away from: an aircraft landing
// on heading runway_heading_deg flies over the approach lights first.
#ifndef ATMO_HOST_SCENE_TERRAIN_H
#define ATMO_HOST_SCENE_TERRAIN_H

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmo/atmo.h"
#include "atmo_host_scene/camera.h"

namespace atmo::host_scene {

constexpr double kEarthRadiusM = 6371000.0;

// Drop of the Earth's surface below the tangent plane at horizontal distance d
// from the ENU origin: d^2 / (2 R).
double curvature_drop_m(double east_m, double north_m);

// Light for the host's own shading, all in ENU at the eye.
struct SceneLighting {
  glm::dvec3 sun_direction_enu{0.0, 0.0, 1.0};  // unit, towards the sun
  glm::dvec3 sun_illuminance_lux{0.0};          // linear RGB, on a surface facing the sun
  glm::dvec3 sky_ambient_lux{0.0};              // linear RGB, on a horizontal surface
};

// The directional light from the plugin's get_lighting: the Sun, or the Moon
// when it gives more light (a host with one directional light); the ambient
// is the plugin's sky illuminance on a horizontal surface plus a 1 mlx floor.
SceneLighting lighting_from_atmo(const AtmoLighting& lighting);

struct LightPoint {
  glm::dvec3 position_enu_m{0.0};
  glm::vec3 color{1.0f};   // linear RGB, scaled by intensity_cd
  float intensity_cd = 0;  // towards the viewer (omnidirectional here)
};

// set_lights' state for `points` in the ENU frame at `origin` (points must
// outlive the call it is passed to); threshold 0: the plugin's default.
AtmoLightsState lights_state_enu(const Geodetic& origin, const std::vector<AtmoLightPoint>& points,
                                 double glow_threshold_cd_m2 = 0.0);

struct TerrainOptions {
  enum class Kind {
    Hills,  // fBm value-noise heightfield, flat around the runway, low under its approaches
    None,   // no geometry and no lights: draw() draws nothing
  };
  Kind kind = Kind::Hills;
  uint64_t seed = 1;
  double size_m = 40000.0;        // side of the square, centred on the origin
  double relief_m = 300.0;        // highest hills above the runway
  int grid = 256;                 // vertices per side
  double runway_heading_deg = 90.0;
  double runway_length_m = 3000.0;
  double runway_width_m = 45.0;
  // The runway lights as the host's own 2-pixel points; false where the plugin's ATMO_PASS_LIGHT_POINTS
  // draws them (they would show twice).
  bool draw_light_points = true;
};

// Light-point layout (counts are fixed by these numbers):
//   approach lights: kApproachBars barrettes of kApproachBarLights white lights,
//     every kApproachBarSpacingM before the threshold, plus a crossbar of
//     kCrossbarLights at 300 m;
//   threshold: kThresholdLights green across the approach end;
//   runway end: kThresholdLights red across the far end;
//   edge lights: white every kEdgeLightSpacingM along both edges, both ends included.
constexpr int kApproachBars = 30;
constexpr int kApproachBarLights = 5;
constexpr double kApproachBarSpacingM = 30.0;
constexpr int kCrossbarLights = 20;
constexpr int kThresholdLights = 16;
constexpr double kEdgeLightSpacingM = 60.0;

class Terrain {
 public:
  explicit Terrain(const TerrainOptions& options = TerrainOptions());
  // GL objects must be released with gl_shutdown() while the context is current.
  ~Terrain() = default;
  Terrain(const Terrain&) = delete;
  Terrain& operator=(const Terrain&) = delete;

  const TerrainOptions& options() const { return options_; }

  // Terrain height above the airfield datum (the ENU origin's height), before
  // the curvature drop; bilinear in the grid. 0 outside the terrain or for Kind::None.
  double height_at(double east_m, double north_m) const;
  // Grid heights, row-major (north rows, east columns), before the curvature drop.
  const std::vector<float>& heights() const { return heights_; }
  int grid() const { return grid_; }

  const std::vector<LightPoint>& light_points() const { return lights_; }
  // The light points for the plugin's set_lights (ENU at the terrain's
  // origin). Runway lights are beamed at the approaching aircraft: along the
  // approach, 3 degrees up, full within 10 degrees and none beyond 25 (their
  // rated intensity is on that axis; docs/FOG.md).
  std::vector<AtmoLightPoint> atmo_light_points() const;

  // [gl-current] Creates programs and buffers; false with *error on failure.
  bool gl_init(std::string* error);
  // [gl-current] Deletes them. Idempotent.
  void gl_shutdown();
  bool gl_ready() const { return gl_ready_; }

  // [gl-current] Draws terrain, runway and light points into the bound
  // framebuffer with view.depth_convention (set the host depth state with
  // DepthSetup first). Restores the GL state it changes. With `fog` (from
  // get_fog_lighting; light_count > 0) the surfaces are lit by the plugin's
  // lights in its fog through atmo_fog_lights.glsl.
  void draw(const ViewSetup& view, const SceneLighting& lighting, const AtmoFogLighting* fog = nullptr) const;

 private:
  struct Vertex {
    float position_hi[3];  // ENU relative to the origin, split high/low for precision
    float position_lo[3];
    float normal[3];
    float albedo[3];
  };

  void build_heights();
  void build_mesh();
  void build_runway();
  void build_lights();
  double raw_height(double east_m, double north_m) const;
  Vertex make_vertex(const glm::dvec3& p, const glm::dvec3& n, const glm::vec3& albedo) const;
  void add_runway_quad(double u0, double u1, double v0, double v1, double lift_m, const glm::vec3& albedo);
  glm::dvec3 runway_to_enu(double along_m, double across_m, double up_m) const;

  TerrainOptions options_;
  int grid_ = 0;
  std::vector<float> heights_;
  std::vector<Vertex> terrain_vertices_;
  std::vector<uint32_t> terrain_indices_;
  std::vector<Vertex> runway_vertices_;  // triangles: asphalt first, then markings
  size_t asphalt_vertex_count_ = 0;
  std::vector<LightPoint> lights_;

  bool gl_ready_ = false;
  // GL objects; [0] standard/reversed variant, [1] logarithmic-depth variant.
  unsigned surface_program_[2] = {0, 0};
  unsigned point_program_[2] = {0, 0};
  unsigned fog_program_[2] = {0, 0};  // the surface program with atmo_fog_lights.glsl
  unsigned terrain_vao_ = 0, terrain_vbo_ = 0, terrain_ibo_ = 0;
  unsigned runway_vao_ = 0, runway_vbo_ = 0;
  unsigned light_vao_ = 0, light_vbo_ = 0;
};

}  // namespace atmo::host_scene

#endif  // ATMO_HOST_SCENE_TERRAIN_H
