// fog_monte_carlo.cpp — all-orders Monte Carlo reference for a point light in a homogeneous (slab) fog:
// backward path tracing with free-flight sampling and next-event estimation (see fog_reference.h).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

#include "atmo_monte_carlo/sampling.h"
#include "fog_reference.h"

namespace atmo::fog_reference {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr uint64_t kChunk = 1024;  // paths per independently seeded chunk

using monte_carlo::basis;
using monte_carlo::sample_hg_cos;
using monte_carlo::splitmix64;
using Rng = monte_carlo::Xoshiro256;  // seeded from a splitmix64 state

// Part of the ray o + t dir, 0 <= t < limit, inside the slab: [t0, t1). False if empty.
bool slab_interval(const Medium& m, const glm::dvec3& o, const glm::dvec3& dir, double limit, double& t0,
                   double& t1) {
  t0 = 0.0;
  t1 = limit;
  if (dir.z == 0) {
    if (o.z < m.bottom_m || o.z > m.top_m) return false;
  } else {
    double ta = (m.bottom_m - o.z) / dir.z, tb = (m.top_m - o.z) / dir.z;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1;
}

struct ChunkSums {
  double total = 0, total2 = 0, single = 0, single2 = 0, multiple = 0, multiple2 = 0;
  double truncated = 0, vertices = 0;
};

}  // namespace

MonteCarloResult monte_carlo_radiance(const Medium& medium, const Light& light, const glm::dvec3& eye,
                                      const glm::dvec3& view_dir, double d_vp, uint64_t paths, uint64_t seed,
                                      int max_orders, int threads) {
  MonteCarloResult result;
  result.paths = paths;
  const double beta = medium.extinction_per_m;
  const double view_len = glm::length(view_dir);
  if (paths == 0 || max_orders < 1 || !(beta > 0) || !std::isfinite(beta) || !(d_vp > 0) ||
      !(view_len > 0) || !std::isfinite(view_len))
    return result;
  const glm::dvec3 v = view_dir / view_len;
  const double albedo = std::max(medium.albedo, 0.0);
  const double g = std::clamp(medium.hg_g, -0.999999, 0.999999);
  const glm::dvec3 s = light.position_m;
  const double I0 = light.intensity;
  const double transport_mfp = 1.0 / (beta * (1.0 - g));
  const double R0 = glm::length(s - eye) + 5.0 * transport_mfp;  // Russian roulette distance scale
  constexpr double kWeightFloor = 0.1;

  // Light scattered once towards o along the segment o + t dir, t in [t0, t1) inside the medium (the
  // transmittance from o counts from t0), estimated with two samples combined by the balance heuristic
  // (multiple importance sampling): the free-flight sample t_ff (drawn here; it is also the path's next
  // vertex if < t1), whose estimate alone is next-event estimation at that vertex, and an equiangular
  // sample (Kulla & Fajardo 2012, pdf ~ 1/d^2 along the line), which removes the 1/d^2 spike of vertices
  // close to the light (its second moment diverges for vertices spread in 3D).
  auto segment = [&](Rng& rng, const glm::dvec3& o, const glm::dvec3& dir, double t0, double t1,
                     double& t_ff) -> double {
    const glm::dvec3 to_light = s - o;
    const double t_c = glm::dot(to_light, dir);
    const double b = std::max(glm::length(glm::cross(to_light, dir)), 1e-12 * glm::length(to_light));
    const double theta_a = std::atan((t0 - t_c) / b);
    const double theta_b = std::isinf(t1) ? 0.5 * kPi : std::atan((t1 - t_c) / b);
    const double dtheta = theta_b - theta_a;
    // f(t) = sigma_s e^{-beta (t - t0)} p I0 profile e^{-tau_light} / d^2 = F / d^2;  pdf_ea = P / d^2.
    const double P = dtheta > 0 ? b / dtheta : 0.0;
    auto estimate = [&](double t, double z) -> double {
      const glm::dvec3 p = o + t * dir;
      const glm::dvec3 r = p - s;
      const double d2 = z * z + b * b;
      const double len = glm::length(r);
      if (!(len > 0) || !(d2 > 0)) return 0.0;
      const glm::dvec3 wi = r / len;  // the light's propagation direction
      const double profile = light_profile(light, wi);
      if (profile == 0.0) return 0.0;
      const double transmit = std::exp(-beta * (t - t0) - optical_thickness(medium, s, p));
      const double F = beta * albedo * henyey_greenstein(glm::dot(wi, -dir), g) * I0 * profile * transmit;
      const double pdf_ff_d2 = beta * std::exp(-beta * (t - t0)) * d2;
      const double value = F / (P + pdf_ff_d2);
      return std::isfinite(value) ? value : 0.0;
    };
    double sum = 0.0;
    if (dtheta > 0) {
      const double theta = theta_a + rng.uniform() * dtheta;
      const double z = b * std::tan(theta);
      const double t = std::clamp(t_c + z, t0, t1);  // clamps only rounding at the ends
      if (std::isfinite(t)) sum += estimate(t, t == t_c + z ? z : t - t_c);
    }
    t_ff = t0 - std::log1p(-rng.uniform()) / beta;
    if (t_ff < t1) sum += estimate(t_ff, t_ff - t_c);
    return sum;
  };

  auto run_chunk = [&](uint64_t chunk) -> ChunkSums {
    uint64_t seed_state = seed ^ (0xD1B54A32D192ED03ull * (chunk + 1));
    Rng rng(splitmix64(seed_state));
    ChunkSums sums;
    const uint64_t begin = chunk * kChunk, end = std::min(paths, begin + kChunk);
    for (uint64_t i = begin; i < end; ++i) {
      double single = 0, multiple = 0, w = 1.0;  // w: path weight for scattering on the current segment
      glm::dvec3 o = eye, dir = v;
      double limit = d_vp;
      for (int order = 1; order <= max_orders; ++order) {
        double t0, t1;
        if (!slab_interval(medium, o, dir, limit, t0, t1)) break;  // misses the medium: lost
        double t_ff;
        (order == 1 ? single : multiple) += w * segment(rng, o, dir, t0, t1, t_ff);
        if (!(t_ff < t1)) break;  // left the slab or reached the surface at d_vp
        const glm::dvec3 p = o + t_ff * dir;
        sums.vertices += 1;
        w *= albedo;
        if (!(w > 0)) break;
        if (order == max_orders) {  // the cap: this weight would have gone on
          sums.truncated += w;
          break;
        }
        // Russian roulette against a weight floor that grows with the distance to the light.
        const double weight_floor = std::max(kWeightFloor, glm::length(p - s) / R0);
        if (w < weight_floor) {
          if (rng.uniform() * weight_floor >= w) break;
          w = weight_floor;
        }
        glm::dvec3 b1, b2;
        basis(dir, b1, b2);
        const double mu = sample_hg_cos(g, rng.uniform());
        const double phi = 2.0 * kPi * rng.uniform();
        const double sn = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        dir = glm::normalize(mu * dir + sn * (std::cos(phi) * b1 + std::sin(phi) * b2));
        o = p;
        limit = std::numeric_limits<double>::infinity();
      }
      const double total = single + multiple;
      sums.total += total;
      sums.total2 += total * total;
      sums.single += single;
      sums.single2 += single * single;
      sums.multiple += multiple;
      sums.multiple2 += multiple * multiple;
    }
    return sums;
  };

  const uint64_t chunks = (paths + kChunk - 1) / kChunk;
  std::vector<ChunkSums> per_chunk(chunks);
  unsigned n_threads = threads > 0 ? static_cast<unsigned>(threads) : std::thread::hardware_concurrency();
  n_threads = static_cast<unsigned>(std::max<uint64_t>(1, std::min<uint64_t>(std::max(1u, n_threads), chunks)));
  std::atomic<uint64_t> next{0};
  auto worker = [&] {
    for (uint64_t c; (c = next.fetch_add(1)) < chunks;) per_chunk[c] = run_chunk(c);
  };
  if (n_threads == 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < n_threads; ++t) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
  }

  ChunkSums all;  // reduced in chunk order: independent of the thread count
  for (const ChunkSums& c : per_chunk) {
    all.total += c.total;
    all.total2 += c.total2;
    all.single += c.single;
    all.single2 += c.single2;
    all.multiple += c.multiple;
    all.multiple2 += c.multiple2;
    all.truncated += c.truncated;
    all.vertices += c.vertices;
  }
  const double n = static_cast<double>(paths);
  auto std_error = [n](double sum, double sum2) {
    if (n < 2) return 0.0;
    const double mean = sum / n;
    return std::sqrt(std::max(0.0, (sum2 - n * mean * mean) / (n - 1)) / n);
  };
  result.total = all.total / n;
  result.single = all.single / n;
  result.multiple = all.multiple / n;
  result.total_std_error = std_error(all.total, all.total2);
  result.single_std_error = std_error(all.single, all.single2);
  result.multiple_std_error = std_error(all.multiple, all.multiple2);
  result.truncated_weight = all.truncated / n;
  result.mean_vertices = all.vertices / n;
  return result;
}

}  // namespace atmo::fog_reference
