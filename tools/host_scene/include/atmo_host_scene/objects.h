// objects.h — the host's objects (aircraft, vehicles, hangars) as opaque
// geometry: closed triangle meshes (tools/spheres TriangleMesh, object frame:
// m, x forward, y left, z up) uploaded with flat (per-face) normals and drawn,
// each with its own rigid pose and albedo, in the ENU world frame of camera.h,
// lit by the plugin's sky (get_lighting's SH9 irradiance, clamped at 0) and
// the Sun, as linear radiance (cd/m^2 times the exposure scale), for any
// DepthConvention, writing the depth the plugin's passes read (as terrain.h
// does). Positions go to the GPU relative to the eye (the pose's translation
// minus the eye's, in double on the CPU).
//
// Without an AtmoSkyOcclusion the shading is exactly what
// ATMO_PASS_SKY_OCCLUSION takes as a surface's light without the objects (sky
// SH9 by the normal + the Sun's cosine). With one (get_sky_occlusion, this
// view, this frame) the surfaces are shaded through atmo_sky_occlusion.glsl
// (the host SDK's include, pasted into the shader): the objects' sky shadow,
// Sun shadow and bounce on each other and on themselves, with the meshes' own
// normals. atmo render draws its terrain, runs ATMO_PASS_SKY_OCCLUSION with
// ATMO_PASS_SKY_OCCLUSION_NORMAL_UP over it, then draws the objects so.
#ifndef ATMO_HOST_SCENE_OBJECTS_H
#define ATMO_HOST_SCENE_OBJECTS_H

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmo/atmo.h"
#include "atmo_host_scene/camera.h"
#include "mesh.h"         // tools/spheres: TriangleMesh
#include "sphere_json.h"  // tools/spheres: SphereSet

namespace atmo::host_scene {

// The light an object's surface gets without any object near (ENU at the eye).
struct ObjectLighting {
  std::array<glm::dvec3, 9> sky_irradiance_sh9{};  // AtmoLighting.sky_irradiance_sh9, lux
  glm::dvec3 sun_direction_enu{0.0, 0.0, 1.0};     // unit, towards the Sun
  glm::dvec3 sun_illuminance_lux{0.0};             // on a surface facing the Sun
};

// get_lighting's sky SH9 and Sun (the Sun only: the sky occlusion pass knows no Moon).
ObjectLighting object_lighting_from_atmo(const AtmoLighting& lighting);

// E(n) = max(sum_k sh9_k Y_k(n), 0) + E_sun max(n . sun, 0): what the shader computes, for tests.
glm::dvec3 object_irradiance(const ObjectLighting& lighting, const glm::dvec3& normal);

// A fitted sphere set as the ABI's spheres (set_occluders), in the object's frame.
std::vector<AtmoOccluderSphere> occluder_spheres(const spheres::SphereSet& set);

// One object to draw: which mesh, where, what colour.
struct ObjectInstance {
  size_t mesh = 0;                    // index into the meshes given to ObjectMeshes::gl_init
  glm::dmat4 enu_from_object{1.0};    // rigid: object frame -> the view's ENU world frame
  glm::dvec3 albedo{0.5};             // diffuse reflectance, linear RGB
};

// The rigid pose of an object standing at `position_enu_m` with its x axis (forward) at `heading_deg` from
// true north, clockwise (z stays up).
glm::dmat4 enu_from_object_pose(const glm::dvec3& position_enu_m, double heading_deg);

class ObjectMeshes {
 public:
  ObjectMeshes() = default;
  ~ObjectMeshes() = default;  // GL objects must be released with gl_shutdown() while the context is current
  ObjectMeshes(const ObjectMeshes&) = delete;
  ObjectMeshes& operator=(const ObjectMeshes&) = delete;

  // [gl-current] Uploads the meshes (3 vertices a triangle, the face's normal); false with *error (naming
  // the mesh's index) on failure: an empty mesh, an index out of range, or a GL error.
  bool gl_init(const std::vector<const spheres::TriangleMesh*>& meshes, std::string* error);
  // [gl-current] Deletes them. Idempotent.
  void gl_shutdown();
  bool gl_ready() const { return gl_ready_; }
  size_t mesh_count() const { return meshes_.size(); }

  // [gl-current] Draws the instances into the bound framebuffer with view.depth_convention (set the host
  // depth state with DepthSetup first), back faces culled. Restores the GL state it changes. An instance
  // whose mesh index is out of range is skipped. `occlusion` (with objects: object_count > 0) shades them
  // through atmo_sky_occlusion.glsl, its textures on units first_unit .. first_unit + 4 (restored after).
  void draw(const ViewSetup& view, const ObjectLighting& lighting, const std::vector<ObjectInstance>& instances,
            const AtmoSkyOcclusion* occlusion = nullptr, int first_unit = 0) const;

 private:
  struct Range {
    int first = 0;
    int count = 0;
  };
  std::vector<Range> meshes_;
  bool gl_ready_ = false;
  // [standard/reversed, logarithmic][SH9, sky occlusion, sky occlusion without the bounce]
  unsigned program_[2][3] = {{0, 0, 0}, {0, 0, 0}};
  unsigned vao_ = 0, vbo_ = 0;
};

}  // namespace atmo::host_scene

#endif  // ATMO_HOST_SCENE_OBJECTS_H
