// shadow_reference.h — an independent, double-precision, brute-force reference for sky shadows and one
// diffuse bounce near occluders (issue 21): the sky irradiance at a receiver with the occluders'
// visibility, the Sun's visibility, and one bounce of sky + sun light off the occluders. The plugin's
// spherical-harmonic method is measured against it, so it shares nothing with it: every integral is
// taken by ray tracing (spheres in closed form, triangle meshes through a BVH, an optional ground plane)
// and stratified Monte Carlo over directions.
//
// Units: SI, metres and radians; world z is up. Radiance in cd/m^2 (or W m^-2 sr^-1) and irradiance in
// lux (or W m^-2), linear RGB in a glm::dvec3.
//
// Sampling (sky_irradiance, bounce_irradiance): N samples are split into B = clamp(N / 4, 2, 32)
// independent batches; each batch is a jittered k1 x k2 grid on the unit square (k1 = floor(sqrt(N/B)),
// k2 = floor(N/B / k1)), mapped to the disc by Shirley & Chiu's concentric map and lifted to the
// cosine-weighted hemisphere about the normal (Malley's method: pdf = cos / pi, so E = pi * mean(L V)).
// The estimate is the mean of the batch means and its standard error is their standard deviation over
// sqrt(B): honest for the stratified estimator, since the batches are independent and unbiased.
// Estimate::samples is B * k1 * k2: <= N and within B * (sqrt(N/B) + 1) of it.
// Each batch has its own xoshiro256** stream, seeded from (seed, batch index); batches may run on
// several threads but are reduced in batch order, so a result depends on the seed only, never on
// Scene::threads.
//
// Rays from a receiver start at p + n * ray_offset_m(scene, p) (see there); rays that start inside a
// solid (a sphere, a closed mesh from its inside, below the ground) meet its inner surface: blocked.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

namespace atmo::spheres {
struct TriangleMesh;
}

namespace atmo::shadow_reference {

struct Sphere {
  glm::dvec3 centre_m{0.0};
  double radius_m = 0;  // <= 0 (or NaN): no sphere (never hit)
  int object = 0;       // index into Scene::object_albedo
};

// A triangle mesh placed in the world. The mesh is read through the pointer when Scene::prepare() builds
// the BVH (world-space triangles are copied then: the mesh may be freed or moved afterwards, but edits
// need prepare() again). A transform with a negative determinant (a mirror) keeps the normals outward.
struct MeshOccluder {
  const atmo::spheres::TriangleMesh* mesh = nullptr;  // nullptr: nothing
  glm::dmat4 world_from_object{1.0};
  int object = 0;
};

namespace detail {
class MeshBvh;
}

struct Scene {
  std::vector<Sphere> spheres;
  std::vector<MeshOccluder> meshes;
  std::vector<glm::dvec3> object_albedo;  // per object, linear RGB in [0, 1] (bounce_irradiance needs every object's)
  // Optional infinite ground plane z = ground_height_m: a solid half-space below it. It occludes (sky and
  // sun) and, in bounce_irradiance, reflects with ground_albedo.
  bool ground = false;
  double ground_height_m = 0;
  glm::dvec3 ground_albedo{0.2};
  // Sky radiance arriving from `direction` (unit, pointing away from the receiver, z up), over the whole
  // sphere of directions. Where ground = true, directions that meet the ground see the ground instead
  // (blocked for the sky; its reflected light is bounce_irradiance's). An empty function is a black sky.
  // Called from several threads at once (Scene::threads): it must be a pure function.
  std::function<glm::dvec3(const glm::dvec3& direction)> sky_radiance;
  glm::dvec3 sun_direction{0, 0, 1};   // towards the Sun's centre (normalised internally)
  double sun_angular_radius_rad = 0.004654;
  glm::dvec3 sun_illuminance{0};       // lux on a surface facing the Sun, unoccluded (the whole disc)
  int threads = 0;                     // worker threads for the batches; 0: hardware concurrency. Results do not depend on it.

  // Builds the BVH over every mesh's world-space triangles. The estimators build a temporary one per
  // call when it is missing or does not match `meshes` (same pointers, sizes, transforms, objects);
  // intersect() requires it (throws std::logic_error otherwise). Call again after editing a mesh.
  void prepare();
  std::shared_ptr<const detail::MeshBvh> mesh_bvh;  // set by prepare()
};

struct Estimate {
  glm::dvec3 value{0.0};
  glm::dvec3 standard_error{0.0};
  long samples = 0;  // directions actually used (outer directions for bounce_irradiance)
};

enum class Surface { none, sphere, mesh, ground };

struct Hit {
  double distance_m = std::numeric_limits<double>::infinity();
  glm::dvec3 point_m{0.0};
  glm::dvec3 normal{0.0};  // unit geometric normal, out of the solid (away from it) whichever side the ray came from
  int object = -1;         // the sphere's or mesh's object; -1 for the ground
  Surface surface = Surface::none;
  bool from_inside = false;  // the ray met the surface from inside the solid (a back face)
};

// Nearest surface along origin + t * direction, t >= 0 (t > 0 for triangles; direction normalised internally;
// a zero direction never hits). Spheres in closed form (numerically stable roots; from inside, the far root), meshes by
// Moller-Trumbore through the BVH (median split on the longest centroid axis, <= 4 triangles a leaf),
// the ground plane. A ray starting inside a sphere or below the ground hits it from inside. Needs
// scene.prepare() when scene.meshes is not empty. Returns false (hit untouched) on a miss.
bool intersect(const Scene& scene, const glm::dvec3& origin_m, const glm::dvec3& direction, Hit* hit);

// The offset that rays leave a point by: 1e-9 of the scene's scale, the largest of 1 m, |p|, every
// sphere's |centre| + radius, the meshes' bounds' corners and |ground_height_m|. Double rounding of
// coordinates at that scale is ~2e-16 of it, so the offset clears a surface through p by ~1e6 rounding
// errors (no self-hits, even on a 1e7 m sphere: 1 cm there, 1 nm in a metre-sized scene) while moving
// the receiver by a negligible 1e-9 of the scene.
double ray_offset_m(const Scene& scene, const glm::dvec3& p);

// Sky irradiance at p for the unit normal n (normalised internally; a zero n throws std::invalid_argument):
//   E = integral of L_sky(w) V(p, w) max(0, n.w) dw,
// V = 1 when `occluded` is false (the plain sky integral over n's hemisphere: no occluders, no ground),
// else 0 for directions that meet a sphere, a mesh or the ground. The Sun is not included (sun_visibility).
// Cosine-weighted stratified sampling in batches (see the top); samples >= 2 (else std::invalid_argument).
Estimate sky_irradiance(const Scene& scene, glm::dvec3 p, glm::dvec3 n, bool occluded, long samples,
                        uint64_t seed = 1);

// Fraction (0..1) of the solar disc seen from p: the disc (a cap of sun_angular_radius_rad about
// sun_direction) sampled at the centres of a k1 x k2 grid (k1 = floor(sqrt(samples))) mapped to the cap
// by the concentric map and an equal-area lift, so every sample stands for the same solid angle; one shadow
// ray each from p + w * ray_offset_m. Deterministic (no random numbers); samples >= 1.
double sun_visibility(const Scene& scene, glm::dvec3 p, long samples = 4096);

// One diffuse bounce off the occluders (spheres, meshes and the ground):
//   E_b = integral over the directions from p that hit a surface's outside of (albedo / pi) E_hit max(0, n.w) dw.
// Directions that escape, or that meet a surface from inside a solid, carry nothing. E_hit, the irradiance
// at the hit point's outward normal m, is estimated by nested sampling with inner_samples (>= 1) directions
// cosine-weighted about m (a jittered grid) plus inner_samples points of the solar disc (a jittered grid,
// each standing for sun_illuminance / ((1 + cos r) / 2) * max(0, m.w), so that a surface facing the Sun
// gets sun_illuminance):
//   BounceMode::unshadowed_hit — the sky over m's whole hemisphere and the Sun with no occluders and no
//     ground (what the fast method assumes);
//   BounceMode::traced — the same directions, each with a shadow ray from the hit point (spheres, meshes,
//     ground): the true one-bounce irradiance.
// Both modes draw the same random numbers, so for one seed traced <= unshadowed_hit sample by sample.
// The nested estimator is unbiased; the standard error (from the outer batches) includes the inner noise.
// Needs object_albedo for every object (std::invalid_argument otherwise). Returns lux at p.
enum class BounceMode { unshadowed_hit, traced };
Estimate bounce_irradiance(const Scene& scene, glm::dvec3 p, glm::dvec3 n, BounceMode mode, long samples,
                           long inner_samples, uint64_t seed = 1);

}  // namespace atmo::shadow_reference
