// cloud_path_tracer.h — the independent reference for the cloud lighting: a
// CPU Monte Carlo path tracer with every scattering order (delta tracking,
// next-event estimation towards the light, ratio tracking), slow but unbiased.
// It shares only the data (CloudVolume) and the phase function
// (twin::cloud_phase) with the real-time model, so the octave approximation's
// error can be measured against it (docs/CLOUDS.md).
//
// What is included: sun/Moon light as a delta light (no disc) through next-event
// estimation, the sky and ground as uniform hemispheres reached by paths that
// escape the grid box after >= 1 scattering, absorption (albedo), all orders up
// to max_scattering_orders. Not included: the background seen straight through
// (reported as transmittance instead), the light's direct beam on a ray that
// never scatters, anything outside the grid box [0, n] (the half voxel of
// trilinear fade past the box is clipped, as cloud_march.glsl clips it).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "atmo_monte_carlo/sampling.h"
#include "core/clouds/cloud_twin.h"
#include "core/clouds/cloud_volume.h"

namespace atmo::clouds::reference {

struct CloudEnvironment {                  // the light, in the scene's ENU frame (z up)
  glm::dvec3 light_direction{0, 0, 1};     // unit, from the cloud towards the sun (or Moon)
  glm::dvec3 light_illuminance_lux{0.0};   // on a surface facing the light, linear RGB, at the cloud
  glm::dvec3 sky_radiance{0.0};            // cd/m^2, uniform over the upper hemisphere (direction z > 0)
  glm::dvec3 ground_radiance{0.0};         // cd/m^2, uniform over the lower hemisphere
};

// Row 0 is the top of the image; one ray per sample through the pixel CENTRE
// (no jitter), so a pixel compares with a marcher's ray through the same point.
struct PinholeCamera {
  glm::dvec3 position_enu_m{0.0};
  glm::dvec3 forward{0, 1, 0}, up{0, 0, 1};  // need not be orthogonal; up is re-orthogonalised
  double vertical_fov_rad = 0.5;
  int width = 0, height = 0;
};

struct PathTraceSettings {
  int samples_per_pixel = 64;
  int max_scattering_orders = 256;
  uint64_t seed = 1;
  int threads = 0;  // 0: hardware. Rows are seeded by their index: the image does not depend on it.
};

struct CloudImage {
  int width = 0, height = 0;
  std::vector<glm::vec3> radiance;   // cd/m^2 in-scattered by the cloud only (background excluded), row-major
  std::vector<float> transmittance;  // of the background through the cloud, per pixel (exact, no noise)
};

// Radiance the cloud scatters towards the camera at each pixel, all scattering orders.
CloudImage path_trace(const CloudVolume& cloud, const CloudEnvironment& env, const PinholeCamera& cam,
                      const PathTraceSettings& s);

// Same, for a single ray (tests): mean in-scattered radiance and its standard
// error over `samples` paths, and the ray's transmittance (exact). Work is split
// in fixed blocks seeded by their index: the result does not depend on threads.
struct RayEstimate {
  glm::dvec3 mean{0.0};
  glm::dvec3 standard_error{0.0};
  double transmittance = 1.0;
};
RayEstimate path_trace_ray(const CloudVolume& cloud, const CloudEnvironment& env, const glm::dvec3& origin_enu_m,
                           const glm::dvec3& direction, int samples, uint64_t seed, int max_scattering_orders = 256);

// Optical depth of the whole ray through the grid box, exact: the trilinear
// density is a cubic along a ray inside one cell of voxel centres, so 2-point
// Gauss-Legendre per cell integrates it exactly. path_trace's transmittance is exp(-this).
double optical_depth(const CloudVolume& cloud, const glm::dvec3& origin_enu_m, const glm::dvec3& direction);

// Ratio-tracking transmittance along the ray (the estimator next-event
// estimation uses towards the light), mean and standard error, for tests.
struct TransmittanceEstimate {
  double mean = 1.0;
  double standard_error = 0.0;
};
TransmittanceEstimate ratio_tracking_transmittance(const CloudVolume& cloud, const glm::dvec3& origin_enu_m,
                                                   const glm::dvec3& direction, int samples, uint64_t seed);

// The tracer's random numbers: xoshiro256** seeded through splitmix64 from
// (seed, stream), 53-bit doubles; one stream per image row or sample block, so
// results never depend on scheduling. Public for the tests.
class PathRng : public monte_carlo::Xoshiro256 {
 public:
  PathRng(uint64_t seed, uint64_t stream) : Xoshiro256(stream_state(seed, stream)) {}

 private:
  static uint64_t stream_state(uint64_t seed, uint64_t stream);
};

// One direction drawn exactly from the droplet phase function around
// `forward` (the current travel direction; cos_theta = dot(forward, direction),
// cloud_phase's convention with both directions reversed), so a path's weight
// is never touched: the HG lobe by inversion with probability 1 - w_draine,
// else the Draine lobe by rejection from HG(g_draine) with acceptance
// (1 + alpha cos^2) / (1 + alpha) (about 0.6 for cloud droplets).
struct PhaseSample {
  glm::dvec3 direction{0.0};
  double cos_theta = 1.0;
};
PhaseSample sample_cloud_phase(const twin::CloudPhase& phase, const glm::dvec3& forward, PathRng& rng);

}  // namespace atmo::clouds::reference
