// shadow_reference.cpp — see shadow_reference.h.
#include "shadow_reference.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>

#include <atmo_monte_carlo/sampling.h>

#include "mesh.h"

namespace atmo::shadow_reference {

namespace mc = atmo::monte_carlo;
using glm::dvec2;
using glm::dvec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Ray offset per metre of scene scale (see ray_offset_m in the header for why this size).
constexpr double kOffsetPerScale = 1e-9;

dvec3 unit_or_throw(const dvec3& v, const char* what) {
  const double len = glm::length(v);
  if (!(len > 0) || !std::isfinite(len)) throw std::invalid_argument(std::string("shadow_reference: ") + what + " is zero or not finite");
  return v / len;
}

}  // namespace

namespace detail {

// All the meshes' triangles in world space, under one BVH. The signature is what the meshes looked like
// when it was built, so that a stale BVH is noticed (see Scene::prepare).
class MeshBvh {
 public:
  explicit MeshBvh(const std::vector<MeshOccluder>& meshes);

  bool matches(const std::vector<MeshOccluder>& meshes) const;
  // Nearest triangle with 0 < t < t_best (t_best shrinks on a hit); `any`: stop at the first one.
  bool intersect(const dvec3& o, const dvec3& d, double& t_best, Hit* hit, bool any) const;
  double max_abs_coordinate_m() const { return max_abs_m_; }

 private:
  struct Triangle {
    dvec3 v0, e1, e2;
    dvec3 normal;  // unit, outward
    int object;
  };
  struct Node {
    dvec3 lo, hi;
    uint32_t start = 0, count = 0;  // count > 0: a leaf over order_[start, start + count)
    uint32_t right = 0;             // inner node: the left child is the next node
    int axis = 0;
  };
  struct Signature {
    const spheres::TriangleMesh* mesh;
    const void* vertices;
    size_t vertex_count;
    const void* triangles;
    size_t triangle_count;
    glm::dmat4 world_from_object;
    int object;
  };

  uint32_t build(uint32_t start, uint32_t count, const std::vector<dvec3>& centroids);

  std::vector<Triangle> tris_;
  std::vector<uint32_t> order_;
  std::vector<Node> nodes_;
  std::vector<Signature> signature_;
  double max_abs_m_ = 0;
};

MeshBvh::MeshBvh(const std::vector<MeshOccluder>& meshes) {
  for (const MeshOccluder& m : meshes) {
    signature_.push_back({m.mesh, m.mesh ? m.mesh->vertices.data() : nullptr, m.mesh ? m.mesh->vertices.size() : 0,
                          m.mesh ? m.mesh->triangles.data() : nullptr, m.mesh ? m.mesh->triangles.size() : 0,
                          m.world_from_object, m.object});
    if (!m.mesh) continue;
    std::vector<dvec3> world(m.mesh->vertices.size());
    for (size_t i = 0; i < world.size(); ++i) {
      const glm::dvec4 w = m.world_from_object * glm::dvec4(m.mesh->vertices[i], 1.0);
      world[i] = dvec3(w) / w.w;
    }
    // A mirroring transform turns counter-clockwise into clockwise: flip to keep the normals outward.
    const double flip = glm::determinant(glm::dmat3(m.world_from_object)) < 0 ? -1.0 : 1.0;
    for (const glm::uvec3& t : m.mesh->triangles) {
      if (t.x >= world.size() || t.y >= world.size() || t.z >= world.size())
        throw std::invalid_argument("shadow_reference: a mesh triangle indexes past its vertices");
      const dvec3 v0 = world[t.x], e1 = world[t.y] - v0, e2 = world[t.z] - v0;
      const dvec3 c = glm::cross(e1, e2);
      const double area2 = glm::length(c);
      if (!(area2 > 0) || !std::isfinite(area2)) continue;  // degenerate: never hit, no normal
      tris_.push_back({v0, e1, e2, flip * c / area2, m.object});
      for (const dvec3& v : {v0, world[t.y], world[t.z]})
        max_abs_m_ = std::max({max_abs_m_, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    }
  }
  std::vector<dvec3> centroids(tris_.size());
  for (size_t i = 0; i < tris_.size(); ++i) centroids[i] = tris_[i].v0 + (tris_[i].e1 + tris_[i].e2) / 3.0;
  order_.resize(tris_.size());
  for (size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<uint32_t>(i);
  if (!tris_.empty()) {
    nodes_.reserve(2 * tris_.size() / 4 + 2);
    build(0, static_cast<uint32_t>(tris_.size()), centroids);
  }
}

uint32_t MeshBvh::build(uint32_t start, uint32_t count, const std::vector<dvec3>& centroids) {
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back({});
  dvec3 lo(kInf), hi(-kInf), clo(kInf), chi(-kInf);
  for (uint32_t i = start; i < start + count; ++i) {
    const Triangle& t = tris_[order_[i]];
    for (const dvec3& v : {t.v0, t.v0 + t.e1, t.v0 + t.e2}) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
    clo = glm::min(clo, centroids[order_[i]]);
    chi = glm::max(chi, centroids[order_[i]]);
  }
  const dvec3 extent = chi - clo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  // Median split on the longest centroid axis; a leaf when small or when the centroids coincide.
  if (count <= 4 || !(extent[axis] > 0)) {
    nodes_[index].start = start;
    nodes_[index].count = count;
    return index;
  }
  const uint32_t half = count / 2;
  std::nth_element(order_.begin() + start, order_.begin() + start + half, order_.begin() + start + count,
                   [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  build(start, half, centroids);
  const uint32_t right = build(start + half, count - half, centroids);
  nodes_[index].right = right;
  nodes_[index].axis = axis;
  return index;
}

bool MeshBvh::matches(const std::vector<MeshOccluder>& meshes) const {
  if (meshes.size() != signature_.size()) return false;
  for (size_t i = 0; i < meshes.size(); ++i) {
    const MeshOccluder& m = meshes[i];
    const Signature& s = signature_[i];
    if (m.mesh != s.mesh || m.object != s.object || m.world_from_object != s.world_from_object) return false;
    if (m.mesh && (m.mesh->vertices.data() != s.vertices || m.mesh->vertices.size() != s.vertex_count ||
                   static_cast<const void*>(m.mesh->triangles.data()) != s.triangles ||
                   m.mesh->triangles.size() != s.triangle_count))
      return false;
  }
  return true;
}

bool MeshBvh::intersect(const dvec3& o, const dvec3& d, double& t_best, Hit* hit, bool any) const {
  if (nodes_.empty()) return false;
  const dvec3 inv = 1.0 / d;  // +-inf for a zero component; the slab test below tolerates it
  const Triangle* best = nullptr;
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    // Slab test; fmin/fmax drop the NaN of 0 * inf (origin on a slab plane, direction parallel to it).
    // The far end is widened by a few ulps (as pbrt's gamma(3)) so rounding cannot skip a flat box.
    double t0 = 0, t1 = t_best;
    for (int a = 0; a < 3; ++a) {
      const double ta = (node.lo[a] - o[a]) * inv[a], tb = (node.hi[a] - o[a]) * inv[a];
      t0 = std::fmax(t0, std::fmin(ta, tb));
      t1 = std::fmin(t1, std::fmax(ta, tb) * (1 + 1e-15));
    }
    if (t0 > t1) continue;
    if (node.count > 0) {
      for (uint32_t i = node.start; i < node.start + node.count; ++i) {
        // Moller-Trumbore; edges inclusive, so a ray through a shared edge meets at least one side.
        const Triangle& t = tris_[order_[i]];
        const dvec3 pvec = glm::cross(d, t.e2);
        const double det = glm::dot(t.e1, pvec);
        if (det == 0) continue;
        const double inv_det = 1.0 / det;
        const dvec3 tvec = o - t.v0;
        const double u = glm::dot(tvec, pvec) * inv_det;
        if (u < 0 || u > 1) continue;
        const dvec3 qvec = glm::cross(tvec, t.e1);
        const double v = glm::dot(d, qvec) * inv_det;
        if (v < 0 || u + v > 1) continue;
        const double dist = glm::dot(t.e2, qvec) * inv_det;
        if (!(dist > 0) || !(dist < t_best)) continue;
        t_best = dist;
        best = &t;
        if (any) break;
      }
      if (any && best) break;
    } else {
      // Near child last, so it is popped first.
      const uint32_t left = static_cast<uint32_t>(&node - nodes_.data()) + 1;
      if (d[node.axis] >= 0) {
        stack[top++] = node.right;
        stack[top++] = left;
      } else {
        stack[top++] = left;
        stack[top++] = node.right;
      }
    }
  }
  if (!best) return false;
  hit->distance_m = t_best;
  hit->point_m = o + t_best * d;
  hit->normal = best->normal;
  hit->object = best->object;
  hit->surface = Surface::mesh;
  hit->from_inside = glm::dot(d, best->normal) > 0;
  return true;
}

}  // namespace detail

void Scene::prepare() { mesh_bvh = std::make_shared<const detail::MeshBvh>(meshes); }

namespace {

// The BVH a call traces through: the prepared one when it matches the meshes, else one for this call.
std::shared_ptr<const detail::MeshBvh> bvh_for(const Scene& scene) {
  if (scene.meshes.empty()) return nullptr;
  if (scene.mesh_bvh && scene.mesh_bvh->matches(scene.meshes)) return scene.mesh_bvh;
  return std::make_shared<const detail::MeshBvh>(scene.meshes);
}

// What one call traces against: the scene, a BVH that matches its meshes, and the scene's scale.
class Tracer {
 public:
  Tracer(const Scene& scene, std::shared_ptr<const detail::MeshBvh> bvh) : scene_(scene), bvh_(std::move(bvh)) {
    for (const Sphere& s : scene.spheres)
      if (s.radius_m > 0 && std::isfinite(s.radius_m) && std::isfinite(glm::length(s.centre_m)))
        scale_m_ = std::max(scale_m_, glm::length(s.centre_m) + s.radius_m);
    if (bvh_) scale_m_ = std::max(scale_m_, std::sqrt(3.0) * bvh_->max_abs_coordinate_m());
    if (scene.ground && std::isfinite(scene.ground_height_m)) scale_m_ = std::max(scale_m_, std::abs(scene.ground_height_m));
  }
  explicit Tracer(const Scene& scene) : Tracer(scene, bvh_for(scene)) {}

  double offset_m(const dvec3& p) const {
    const double lp = glm::length(p);
    return kOffsetPerScale * std::max(scale_m_, std::isfinite(lp) ? lp : 0.0);
  }

  // d must be unit.
  bool trace(const dvec3& o, const dvec3& d, Hit* hit, bool any) const {
    double t_best = kInf;
    bool found = false;
    for (const Sphere& s : scene_.spheres) {
      const double r = s.radius_m;
      if (!(r > 0)) continue;
      const dvec3 oc = o - s.centre_m;
      const double b = glm::dot(oc, d);
      const double doc = glm::length(oc);
      const double c = (doc - r) * (doc + r);  // factored: keeps its precision on a 1e7 m sphere
      const bool inside = c < 0;
      if (!inside && b >= 0) continue;  // outside and moving away (or along the surface)
      // Squared half chord from the perpendicular distance to the centre (Ray Tracing Gems ch. 7): no b^2 - c
      // cancellation for a far or huge sphere.
      const double f = glm::length(oc - b * d);
      const double disc = (r - f) * (r + f);
      if (!inside && disc < 0) continue;
      const double sq = std::sqrt(std::max(0.0, disc));
      double t;
      if (inside) {
        t = b > 0 ? c / (-b - sq) : -b + sq;  // far root, without cancellation
      } else {
        t = c / (-b + sq);  // near root (b < 0)
      }
      if (!(t >= 0) || !(t < t_best)) continue;
      t_best = t;
      found = true;
      if (!hit) return true;
      hit->distance_m = t;
      hit->point_m = o + t * d;
      const dvec3 radial = hit->point_m - s.centre_m;
      const double lr = glm::length(radial);
      hit->normal = lr > 0 ? radial / lr : -d;
      hit->object = s.object;
      hit->surface = Surface::sphere;
      hit->from_inside = inside;
      if (any) return true;
    }
    if (scene_.ground) {
      const double h = scene_.ground_height_m;
      double t = kInf;
      bool inside = false;
      if (o.z < h) {
        inside = true;  // below the ground: in the solid; a ray that never rises is blocked at once
        t = d.z > 0 ? (h - o.z) / d.z : 0.0;
      } else if (d.z < 0) {
        t = (h - o.z) / d.z;
      }
      if (t >= 0 && t < t_best) {
        t_best = t;
        found = true;
        if (!hit) return true;
        hit->distance_m = t;
        hit->point_m = o + t * d;
        hit->point_m.z = inside && d.z <= 0 ? o.z : h;
        hit->normal = dvec3(0, 0, 1);
        hit->object = -1;
        hit->surface = Surface::ground;
        hit->from_inside = inside;
        if (any) return true;
      }
    }
    if (bvh_) {
      Hit mesh_hit;
      if (bvh_->intersect(o, d, t_best, &mesh_hit, any)) {
        found = true;
        if (hit) *hit = mesh_hit;
      }
    }
    return found;
  }
  bool blocked(const dvec3& o, const dvec3& d) const { return trace(o, d, nullptr, true); }

  dvec3 sky(const dvec3& d) const { return scene_.sky_radiance ? scene_.sky_radiance(d) : dvec3(0.0); }

 private:
  const Scene& scene_;
  std::shared_ptr<const detail::MeshBvh> bvh_;
  double scale_m_ = 1.0;
};

// Shirley & Chiu's concentric map of [0, 1)^2 onto the unit disc: keeps the strata compact.
dvec2 concentric_disc(double u1, double u2) {
  const double a = 2 * u1 - 1, b = 2 * u2 - 1;
  if (a == 0 && b == 0) return dvec2(0.0);
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4) * (b / a);
  } else {
    r = b;
    phi = kPi / 2 - (kPi / 4) * (a / b);
  }
  return r * dvec2(std::cos(phi), std::sin(phi));
}

struct Frame {
  dvec3 t, b, n;
  explicit Frame(const dvec3& unit_n) : n(unit_n) { mc::basis(unit_n, t, b); }
  dvec3 to_world(const dvec3& l) const { return l.x * t + l.y * b + l.z * n; }
};

// Malley: the disc point lifted to the hemisphere is cosine distributed (pdf cos / pi).
dvec3 cosine_direction(const Frame& f, double u1, double u2) {
  const dvec2 q = concentric_disc(u1, u2);
  return f.to_world(dvec3(q, std::sqrt(std::max(0.0, 1.0 - glm::dot(q, q)))));
}

// The solar disc as a cap of angular radius r about the sun frame's n; equal area: 1 - cos(theta) ~ rho^2.
struct SunCap {
  Frame frame;
  double one_minus_cos_r;
  double mean_cos;  // mean over the cap of cos(angle to the centre), (1 + cos r) / 2
  SunCap(const dvec3& dir, double r)
      : frame(unit_or_throw(dir, "sun_direction")),
        one_minus_cos_r(2 * std::pow(std::sin(std::max(0.0, r) / 2), 2)),  // no 1 - cos cancellation
        mean_cos(1 - 0.5 * one_minus_cos_r) {}
  dvec3 direction(double u1, double u2) const {
    const dvec2 q = concentric_disc(u1, u2);
    const double rho2 = glm::dot(q, q);
    if (!(rho2 > 0)) return frame.n;
    const double h = rho2 * one_minus_cos_r;
    const double sin_t = std::sqrt(std::max(0.0, h * (2 - h)));
    const dvec2 az = q / std::sqrt(rho2);
    return glm::normalize((1 - h) * frame.n + sin_t * (az.x * frame.t + az.y * frame.b));
  }
};

struct Grid {
  long k1 = 1, k2 = 1;
  long count() const { return k1 * k2; }
};

// k1 x k2 <= m with k1 = floor(sqrt(m)).
Grid grid_for(long m) {
  Grid g;
  g.k1 = std::max(1L, static_cast<long>(std::sqrt(static_cast<double>(m))));
  while ((g.k1 + 1) * (g.k1 + 1) <= m) ++g.k1;
  while (g.k1 > 1 && g.k1 * g.k1 > m) --g.k1;
  g.k2 = std::max(1L, m / g.k1);
  return g;
}

// Runs `batch(rng, grid)` (the mean of one batch) for every batch, on threads, and reduces in batch order.
template <class BatchFn>
Estimate run_batches(const Scene& scene, long samples, uint64_t seed, const BatchFn& batch) {
  if (samples < 2) throw std::invalid_argument("shadow_reference: samples must be >= 2 (a standard error needs two batches)");
  const long batches = std::clamp(samples / 4, 2L, 32L);
  const Grid grid = grid_for(samples / batches);
  std::vector<dvec3> means(static_cast<size_t>(batches));
  unsigned threads = scene.threads > 0 ? static_cast<unsigned>(scene.threads) : std::thread::hardware_concurrency();
  threads = std::max(1u, std::min(threads, static_cast<unsigned>(batches)));
  uint64_t seed_state = seed;
  const uint64_t stream_base = mc::splitmix64(seed_state);
  auto run = [&](long b) {
    // Distinct, decorrelated streams: xoshiro seeds itself through splitmix64 from this state.
    mc::Xoshiro256 rng(stream_base ^ (0xD1B54A32D192ED03ull * static_cast<uint64_t>(b + 1)));
    means[static_cast<size_t>(b)] = batch(rng, grid);
  };
  if (threads == 1) {
    for (long b = 0; b < batches; ++b) run(b);
  } else {
    std::atomic<long> next{0};
    std::vector<std::exception_ptr> errors(threads);
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
      pool.emplace_back([&, t] {
        try {
          for (long b; (b = next.fetch_add(1)) < batches;) run(b);
        } catch (...) {
          errors[t] = std::current_exception();
          next = batches;  // the others stop early
        }
      });
    for (std::thread& th : pool) th.join();
    for (const std::exception_ptr& e : errors)
      if (e) std::rethrow_exception(e);
  }
  Estimate est;
  for (const dvec3& m : means) est.value += m;
  est.value /= static_cast<double>(batches);
  dvec3 var(0.0);
  for (const dvec3& m : means) var += (m - est.value) * (m - est.value);
  var /= static_cast<double>(batches - 1);
  est.standard_error = glm::sqrt(var / static_cast<double>(batches));
  est.samples = batches * grid.count();
  return est;
}

}  // namespace

bool intersect(const Scene& scene, const glm::dvec3& origin_m, const glm::dvec3& direction, Hit* hit) {
  std::shared_ptr<const detail::MeshBvh> bvh;
  if (!scene.meshes.empty()) {
    if (!scene.mesh_bvh || !scene.mesh_bvh->matches(scene.meshes))
      throw std::logic_error("shadow_reference::intersect: call Scene::prepare() after changing Scene::meshes");
    bvh = scene.mesh_bvh;
  }
  const double len = glm::length(direction);
  if (!(len > 0) || !std::isfinite(len)) return false;
  Hit h;
  if (!Tracer(scene, bvh).trace(origin_m, direction / len, &h, false)) return false;
  if (hit) *hit = h;
  return true;
}

// The sky's radiance summed over a jittered k1 x k2 grid mapped to the cosine-weighted hemisphere of frame
// about origin (the directions blocked left out when `occluded`): pi * sum / count is the irradiance.
dvec3 jittered_sky_sum(const Tracer& tracer, const Frame& frame, const dvec3& origin, const Grid& g, bool occluded,
                       mc::Xoshiro256& rng) {
  dvec3 sum(0.0);
  for (long i = 0; i < g.k1; ++i)
    for (long j = 0; j < g.k2; ++j) {
      const double u1 = (static_cast<double>(i) + rng.uniform()) / static_cast<double>(g.k1);
      const double u2 = (static_cast<double>(j) + rng.uniform()) / static_cast<double>(g.k2);
      const dvec3 w = cosine_direction(frame, u1, u2);
      if (occluded && tracer.blocked(origin, w)) continue;
      sum += tracer.sky(w);
    }
  return sum;
}

double ray_offset_m(const Scene& scene, const glm::dvec3& p) { return Tracer(scene).offset_m(p); }

Estimate sky_irradiance(const Scene& scene, glm::dvec3 p, glm::dvec3 n, bool occluded, long samples, uint64_t seed) {
  const Frame frame(unit_or_throw(n, "the receiver normal"));
  const Tracer tracer(scene);
  const dvec3 origin = p + frame.n * tracer.offset_m(p);
  return run_batches(scene, samples, seed, [&](mc::Xoshiro256& rng, const Grid& g) {
    const dvec3 sum = jittered_sky_sum(tracer, frame, origin, g, occluded, rng);
    return kPi * sum / static_cast<double>(g.count());  // E = pi * mean(L V) under pdf cos / pi
  });
}

double sun_visibility(const Scene& scene, glm::dvec3 p, long samples) {
  if (samples < 1) throw std::invalid_argument("shadow_reference::sun_visibility: samples must be >= 1");
  const SunCap cap(scene.sun_direction, scene.sun_angular_radius_rad);
  const Tracer tracer(scene);
  const double offset = tracer.offset_m(p);
  const Grid g = grid_for(samples);
  long seen = 0;
  for (long i = 0; i < g.k1; ++i)
    for (long j = 0; j < g.k2; ++j) {
      const dvec3 w = cap.direction((static_cast<double>(i) + 0.5) / static_cast<double>(g.k1),
                                    (static_cast<double>(j) + 0.5) / static_cast<double>(g.k2));
      if (!tracer.blocked(p + w * offset, w)) ++seen;
    }
  return static_cast<double>(seen) / static_cast<double>(g.count());
}

Estimate bounce_irradiance(const Scene& scene, glm::dvec3 p, glm::dvec3 n, BounceMode mode, long samples,
                           long inner_samples, uint64_t seed) {
  const Frame frame(unit_or_throw(n, "the receiver normal"));
  if (inner_samples < 1) throw std::invalid_argument("shadow_reference::bounce_irradiance: inner_samples must be >= 1");
  auto check_object = [&](int object) {
    if (object < 0 || static_cast<size_t>(object) >= scene.object_albedo.size())
      throw std::invalid_argument("shadow_reference::bounce_irradiance: object " + std::to_string(object) +
                                  " has no entry in object_albedo");
  };
  for (const Sphere& s : scene.spheres)
    if (s.radius_m > 0) check_object(s.object);
  for (const MeshOccluder& m : scene.meshes)
    if (m.mesh && !m.mesh->triangles.empty()) check_object(m.object);
  const bool sun = scene.sun_illuminance != dvec3(0.0);
  const SunCap cap(sun ? scene.sun_direction : dvec3(0, 0, 1), scene.sun_angular_radius_rad);
  const bool traced = mode == BounceMode::traced;
  const Tracer tracer(scene);
  const dvec3 origin = p + frame.n * tracer.offset_m(p);
  const Grid inner = grid_for(inner_samples);
  const double inv_inner = 1.0 / static_cast<double>(inner.count());

  // Irradiance at a hit point x with outward normal m: sky (cosine-weighted grid) + Sun (disc grid).
  // The same random numbers are drawn in both modes, whatever is blocked.
  auto hit_irradiance = [&](const dvec3& x, const dvec3& m, mc::Xoshiro256& rng) {
    const Frame hf(m);
    const dvec3 o = x + m * tracer.offset_m(x);
    const dvec3 sky = jittered_sky_sum(tracer, hf, o, inner, traced, rng);
    dvec3 e = kPi * sky * inv_inner;
    if (sun) {
      double cos_sum = 0;
      for (long i = 0; i < inner.k1; ++i)
        for (long j = 0; j < inner.k2; ++j) {
          const double u1 = (static_cast<double>(i) + rng.uniform()) / static_cast<double>(inner.k1);
          const double u2 = (static_cast<double>(j) + rng.uniform()) / static_cast<double>(inner.k2);
          const dvec3 w = cap.direction(u1, u2);
          const double c = glm::dot(m, w);
          if (c <= 0 || (traced && tracer.blocked(o, w))) continue;
          cos_sum += c;
        }
      e += scene.sun_illuminance * (cos_sum * inv_inner / cap.mean_cos);
    }
    return e;
  };

  return run_batches(scene, samples, seed, [&](mc::Xoshiro256& rng, const Grid& g) {
    dvec3 sum(0.0);
    for (long i = 0; i < g.k1; ++i)
      for (long j = 0; j < g.k2; ++j) {
        const double u1 = (static_cast<double>(i) + rng.uniform()) / static_cast<double>(g.k1);
        const double u2 = (static_cast<double>(j) + rng.uniform()) / static_cast<double>(g.k2);
        const dvec3 w = cosine_direction(frame, u1, u2);
        Hit hit;
        if (!tracer.trace(origin, w, &hit, false) || hit.from_inside) continue;  // sky, or the inside of a solid
        const dvec3 albedo = hit.surface == Surface::ground ? scene.ground_albedo
                                                            : scene.object_albedo[static_cast<size_t>(hit.object)];
        // pi * L_hit = pi * (albedo / pi) * E_hit: the estimator of E_b under pdf cos / pi.
        sum += albedo * hit_irradiance(hit.point_m, hit.normal, rng);
      }
    return sum / static_cast<double>(g.count());
  });
}

}  // namespace atmo::shadow_reference
