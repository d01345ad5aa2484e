#include "cloud_path_tracer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include <glm/gtc/quaternion.hpp>

#include "core/clouds/cloud_optics.h"

namespace atmo::clouds::reference {
namespace {

constexpr double kPi = 3.14159265358979323846;

using monte_carlo::basis;
using monte_carlo::sample_hg_cos;
using monte_carlo::splitmix64;
using Rng = PathRng;

// The cloud in index space: positions and lengths in voxels, extinction per voxel.
struct Medium {
  const DenseGrid* grid = nullptr;
  glm::dvec3 size{0.0};
  double sigma_per_density = 0.0;  // extinction per index unit at density 1
  double majorant = 0.0;           // >= extinction everywhere, per index unit
  double inv_majorant = 0.0;
  double albedo = 1.0;
  glm::dquat to_grid{1, 0, 0, 0};
  glm::dvec3 origin_enu{0.0};
  double inv_voxel = 1.0;
  glm::dvec3 up_grid{0, 0, 1};
  twin::CloudPhase phase{};

  explicit Medium(const CloudVolume& c) {
    grid = &c.density;
    size = glm::dvec3(c.density.nx, c.density.ny, c.density.nz);
    sigma_per_density = static_cast<double>(c.optics.extinction_per_m) * c.voxel_size_m;
    majorant = c.density.empty() ? 0.0 : sigma_per_density * std::max(0.0f, max_density(c.density));
    inv_majorant = majorant > 0.0 ? 1.0 / majorant : 0.0;
    albedo = c.optics.albedo;
    to_grid = glm::conjugate(glm::normalize(c.rotation));
    origin_enu = c.origin_enu_m;
    inv_voxel = 1.0 / c.voxel_size_m;
    up_grid = to_grid * glm::dvec3(0, 0, 1);
    phase = phase_for_droplet(c.optics.droplet_diameter_um);
  }
  glm::dvec3 point_to_index(const glm::dvec3& p_enu) const { return (to_grid * (p_enu - origin_enu)) * inv_voxel; }
  glm::dvec3 dir_to_grid(const glm::dvec3& d_enu) const { return glm::normalize(to_grid * d_enu); }

  double sigma(const glm::dvec3& p) const {
    return sigma_per_density * std::max(0.0f, grid->sample(glm::vec3(p)));
  }
  // Ray against the box [0, size]: the interval [t0, t1] (t0 >= 0), false if empty.
  bool clip(const glm::dvec3& o, const glm::dvec3& d, double& t0, double& t1) const {
    t0 = 0.0;
    t1 = HUGE_VAL;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(d[a]) < 1e-300) {
        if (o[a] < 0.0 || o[a] > size[a]) return false;
        continue;
      }
      const double inv = 1.0 / d[a];
      double ta = (0.0 - o[a]) * inv, tb = (size[a] - o[a]) * inv;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    return t0 < t1;
  }
  double exit_distance(const glm::dvec3& o, const glm::dvec3& d) const {
    double t0, t1;
    return clip(o, d, t0, t1) ? t1 : 0.0;
  }
  // Delta tracking over [0, t_max): true with the distance of the first real collision.
  bool delta_track(const glm::dvec3& o, const glm::dvec3& d, double t_max, Rng& rng, double& t_hit) const {
    if (majorant <= 0.0) return false;
    double t = 0.0;
    for (;;) {
      t += rng.exponential() * inv_majorant;
      if (t >= t_max) return false;
      if (rng.uniform() * majorant < sigma(o + t * d)) {
        t_hit = t;
        return true;
      }
    }
  }
  // Ratio tracking over [0, t_max), with Russian roulette once the estimate is small (unbiased).
  double ratio_track(const glm::dvec3& o, const glm::dvec3& d, double t_max, Rng& rng) const {
    if (majorant <= 0.0) return 1.0;
    double tr = 1.0, t = 0.0;
    for (;;) {
      t += rng.exponential() * inv_majorant;
      if (t >= t_max) return tr;
      tr *= 1.0 - sigma(o + t * d) * inv_majorant;
      if (tr < 0.1) {
        if (tr <= 0.0 || rng.uniform() * 0.1 >= tr) return 0.0;
        tr = 0.1;
      }
    }
  }
  // Exact optical depth over [t0, t1]: split at the planes of voxel centres (k + 0.5).
  double optical_depth(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1) const {
    std::vector<double> ts{t0, t1};
    for (int a = 0; a < 3; ++a) {
      if (std::abs(d[a]) < 1e-12) continue;
      const double c0 = o[a] + t0 * d[a], c1 = o[a] + t1 * d[a];
      const double lo = std::min(c0, c1), hi = std::max(c0, c1);
      for (double k = std::ceil(lo - 0.5); k + 0.5 < hi; k += 1.0) {
        const double t = (k + 0.5 - o[a]) / d[a];
        if (t > t0 && t < t1) ts.push_back(t);
      }
    }
    std::sort(ts.begin(), ts.end());
    const double h = 0.5 / std::sqrt(3.0);
    double tau = 0.0;
    for (size_t i = 1; i < ts.size(); ++i) {
      const double a = ts[i - 1], b = ts[i];
      if (b <= a) continue;
      const double m = 0.5 * (a + b), w = b - a;
      tau += 0.5 * w * (sigma(o + (m - h * w) * d) + sigma(o + (m + h * w) * d));
    }
    return tau;
  }
};

// What one path brings back, per unit of each source, so the colour is applied once.
struct PathResult {
  double light = 0.0;   // times the illuminance, lux -> cd/m^2 (phase is 1/sr)
  double sky = 0.0;     // times the sky radiance
  double ground = 0.0;  // times the ground radiance
};

struct Lighting {
  glm::dvec3 light_grid{0, 0, 1};  // towards the light, grid axes
  bool has_light = false;
  bool has_env = false;
};

// One path from the camera ray's entry into the box (o at t = 0, clipped length t_len).
PathResult trace_path(const Medium& m, const Lighting& lt, const glm::dvec3& o, const glm::dvec3& d, double t_len,
                      int max_orders, Rng& rng) {
  PathResult r;
  double t;
  if (max_orders < 1 || !m.delta_track(o, d, t_len, rng, t)) return r;  // never scattered: background, excluded
  glm::dvec3 x = o + t * d;
  glm::dvec3 dir = d;
  double w = 1.0;
  for (int order = 1;; ++order) {
    w *= m.albedo;  // survival of the real collision
    if (lt.has_light) {
      // Light travels along -light, leaves towards the previous vertex along -dir: cos = dot(light, dir).
      const double tl = m.exit_distance(x, lt.light_grid);
      const double tr = m.ratio_track(x, lt.light_grid, tl, rng);
      if (tr > 0.0)
        r.light += w * tr * twin::cloud_phase(m.phase, static_cast<float>(glm::dot(lt.light_grid, dir)), 1.0f);
    }
    dir = sample_cloud_phase(m.phase, dir, rng).direction;
    const double t_exit = m.exit_distance(x, dir);
    if (!m.delta_track(x, dir, t_exit, rng, t)) {
      if (glm::dot(dir, m.up_grid) > 0.0)
        r.sky += w;
      else
        r.ground += w;
      return r;
    }
    if (order >= max_orders) return r;
    x += t * dir;
    // Russian roulette on low-weight paths (unbiased).
    if (order >= 4 && w < 0.25) {
      if (rng.uniform() * 0.25 >= w) return r;
      w = 0.25;
    }
  }
}

Lighting make_lighting(const Medium& m, const CloudEnvironment& env) {
  Lighting lt;
  lt.has_light = glm::length(env.light_illuminance_lux) > 0.0 && glm::length(env.light_direction) > 0.0;
  if (lt.has_light) lt.light_grid = m.dir_to_grid(env.light_direction);
  lt.has_env = glm::length(env.sky_radiance) > 0.0 || glm::length(env.ground_radiance) > 0.0;
  return lt;
}

glm::dvec3 colour(const PathResult& p, const CloudEnvironment& env) {
  return p.light * env.light_illuminance_lux + p.sky * env.sky_radiance + p.ground * env.ground_radiance;
}

int thread_count(int requested) {
  if (requested > 0) return requested;
  const unsigned h = std::thread::hardware_concurrency();
  return h > 0 ? static_cast<int>(h) : 1;
}

// Runs job(i) for i in [0, n) on `threads` threads; each index is independent.
template <class F>
void parallel_for(int n, int threads, F&& job) {
  threads = std::max(1, std::min(threads, n));
  std::atomic<int> next{0};
  auto worker = [&]() {
    for (int i; (i = next.fetch_add(1)) < n;) job(i);
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < threads; ++k) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
}

}  // namespace

uint64_t PathRng::stream_state(uint64_t seed, uint64_t stream) {
  uint64_t x = seed;
  const uint64_t h = splitmix64(x);
  return h ^ (stream * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull);
}

PhaseSample sample_cloud_phase(const twin::CloudPhase& ph, const glm::dvec3& forward, PathRng& rng) {
  double c;
  if (rng.uniform() >= ph.w_draine) {
    c = sample_hg_cos(ph.g_hg, rng.uniform());
  } else {
    // Draine = HG(g) (1 + alpha c^2) / norm: HG proposals accepted with (1 + alpha c^2) / (1 + alpha).
    const double alpha = std::max(0.0f, ph.alpha_draine);
    do {
      c = sample_hg_cos(ph.g_draine, rng.uniform());
    } while (rng.uniform() * (1.0 + alpha) >= 1.0 + alpha * c * c);
  }
  PhaseSample s;
  s.cos_theta = c;
  const double sn = std::sqrt(std::max(0.0, 1.0 - c * c)), phi = 2.0 * kPi * rng.uniform();
  glm::dvec3 b1, b2;
  basis(forward, b1, b2);
  s.direction = glm::normalize(c * forward + sn * (std::cos(phi) * b1 + std::sin(phi) * b2));
  return s;
}

double optical_depth(const CloudVolume& cloud, const glm::dvec3& origin_enu_m, const glm::dvec3& direction) {
  const Medium m(cloud);
  const glm::dvec3 o = m.point_to_index(origin_enu_m), d = m.dir_to_grid(direction);
  double t0, t1;
  if (m.majorant <= 0.0 || !m.clip(o, d, t0, t1)) return 0.0;
  return m.optical_depth(o, d, t0, t1);
}

TransmittanceEstimate ratio_tracking_transmittance(const CloudVolume& cloud, const glm::dvec3& origin_enu_m,
                                                   const glm::dvec3& direction, int samples, uint64_t seed) {
  const Medium m(cloud);
  const glm::dvec3 o = m.point_to_index(origin_enu_m), d = m.dir_to_grid(direction);
  TransmittanceEstimate e;
  double t0, t1;
  if (samples <= 0 || !m.clip(o, d, t0, t1)) return e;
  Rng rng(seed, 0x7261746Full);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < samples; ++i) {
    const double tr = m.ratio_track(o + t0 * d, d, t1 - t0, rng);
    sum += tr;
    sum2 += tr * tr;
  }
  e.mean = sum / samples;
  e.standard_error = samples > 1 ? std::sqrt(std::max(0.0, sum2 / samples - e.mean * e.mean) / (samples - 1)) : 0.0;
  return e;
}

RayEstimate path_trace_ray(const CloudVolume& cloud, const CloudEnvironment& env, const glm::dvec3& origin_enu_m,
                           const glm::dvec3& direction, int samples, uint64_t seed, int max_scattering_orders) {
  const Medium m(cloud);
  const Lighting lt = make_lighting(m, env);
  const glm::dvec3 o = m.point_to_index(origin_enu_m), d = m.dir_to_grid(direction);
  RayEstimate e;
  double t0, t1;
  if (m.majorant <= 0.0 || !m.clip(o, d, t0, t1)) return e;
  e.transmittance = std::exp(-m.optical_depth(o, d, t0, t1));
  if (samples <= 0 || (!lt.has_light && !lt.has_env)) return e;
  // Fixed blocks, each its own stream; summed in block order.
  constexpr int kBlock = 4096;
  const int blocks = (samples + kBlock - 1) / kBlock;
  struct Sums {
    glm::dvec3 sum{0.0}, sum2{0.0};
  };
  std::vector<Sums> sums(blocks);
  const glm::dvec3 entry = o + t0 * d;
  parallel_for(blocks, thread_count(0), [&](int b) {
    Rng rng(seed, static_cast<uint64_t>(b) + (1ull << 40));
    const int n = std::min(kBlock, samples - b * kBlock);
    Sums s;
    for (int i = 0; i < n; ++i) {
      const glm::dvec3 v = colour(trace_path(m, lt, entry, d, t1 - t0, max_scattering_orders, rng), env);
      s.sum += v;
      s.sum2 += v * v;
    }
    sums[b] = s;
  });
  Sums total;
  for (const Sums& s : sums) {
    total.sum += s.sum;
    total.sum2 += s.sum2;
  }
  const double n = samples;
  e.mean = total.sum / n;
  if (samples > 1)
    e.standard_error = glm::sqrt(glm::max(glm::dvec3(0.0), total.sum2 / n - e.mean * e.mean) / (n - 1.0));
  return e;
}

CloudImage path_trace(const CloudVolume& cloud, const CloudEnvironment& env, const PinholeCamera& cam,
                      const PathTraceSettings& s) {
  CloudImage img;
  img.width = std::max(0, cam.width);
  img.height = std::max(0, cam.height);
  const size_t count = static_cast<size_t>(img.width) * img.height;
  img.radiance.assign(count, glm::vec3(0.0f));
  img.transmittance.assign(count, 1.0f);
  if (count == 0) return img;
  const Medium m(cloud);
  const Lighting lt = make_lighting(m, env);
  const glm::dvec3 fwd = glm::normalize(cam.forward);
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, cam.up));
  const glm::dvec3 up = glm::cross(right, fwd);
  const double th = std::tan(0.5 * cam.vertical_fov_rad);
  const double aspect = static_cast<double>(img.width) / img.height;
  const glm::dvec3 o = m.point_to_index(cam.position_enu_m);
  const int spp = std::max(0, s.samples_per_pixel);
  parallel_for(img.height, thread_count(s.threads), [&](int row) {
    Rng rng(s.seed, static_cast<uint64_t>(row));
    const double y = (1.0 - 2.0 * (row + 0.5) / img.height) * th;
    for (int col = 0; col < img.width; ++col) {
      const double x = (2.0 * (col + 0.5) / img.width - 1.0) * th * aspect;
      const glm::dvec3 d = m.dir_to_grid(glm::normalize(fwd + x * right + y * up));
      const size_t idx = static_cast<size_t>(row) * img.width + col;
      double t0, t1;
      if (m.majorant <= 0.0 || !m.clip(o, d, t0, t1)) continue;
      img.transmittance[idx] = static_cast<float>(std::exp(-m.optical_depth(o, d, t0, t1)));
      if (spp == 0 || (!lt.has_light && !lt.has_env)) continue;
      glm::dvec3 sum(0.0);
      const glm::dvec3 entry = o + t0 * d;
      for (int i = 0; i < spp; ++i)
        sum += colour(trace_path(m, lt, entry, d, t1 - t0, s.max_scattering_orders, rng), env);
      img.radiance[idx] = glm::vec3(sum / static_cast<double>(spp));
    }
  });
  return img;
}

}  // namespace atmo::clouds::reference
