#include "core/lights/light_clusters.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <thread>

#include "core/clouds/parallel_bands.h"

#include "core/fog/fog_twin.h"

namespace atmo::lights {

namespace {

constexpr double kPi = 3.14159265358979323846;
// The largest e^T G_0 of the surface table (5.9 at T = 2 for g = 0.85; < 7 for any phase): the
// single-scattered term's bound in the ranges.
constexpr double kMaxSurfaceG = 7.0;
constexpr double kRangeThresholdFraction = 1.0;

double peak(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

// A cone light's sphere test (the spot light against a bounding sphere: whether any point of the sphere
// (centre c relative to the light, radius r) lies inside the cone of half-angle `outer` about `axis`).
bool cone_reaches(const glm::dvec3& c, double r, const glm::dvec3& axis, double cos_outer, float lobes) {
  if (cos_outer < -1.5) return true;
  const double sin_outer = std::sqrt(std::max(1.0 - cos_outer * cos_outer, 0.0));
  const double length2 = glm::dot(c, c);
  for (int lobe = 0; lobe < (lobes > 1.5f ? 2 : 1); ++lobe) {
    const double along = glm::dot(c, lobe ? -axis : axis);
    const double across = std::sqrt(std::max(length2 - along * along, 0.0));
    // Distance from the sphere's centre to the cone's surface (negative inside).
    const double to_surface = cos_outer * across - sin_outer * along;
    if (to_surface <= r && along >= -r) return true;
  }
  return false;
}

// The diffusion term's aggregate over a subtree of lights (Barnes-Hut: a far subtree acts as one light at
// its power-weighted centre).
struct Node {
  glm::dvec3 centre{0.0};   // power-weighted centre
  double radius = 0.0;      // of the lights about it
  glm::dvec3 power{0.0};    // sum of intensity x the profile's mean (the P1 term's source)
  int first = 0, count = 0; // leaves: the lights order_[first, first + count)
  int left = -1, right = -1;
};

class DiffusionTree {
 public:
  DiffusionTree(const fog::FogFrame& frame) : frame_(frame) {
    order_.resize(frame.lights.size());
    std::iota(order_.begin(), order_.end(), 0u);
    power_.resize(frame.lights.size());
    for (size_t i = 0; i < frame.lights.size(); ++i) {
      const fog::FrameLight& l = frame.lights[i];
      power_[i] = glm::dvec3(l.intensity_cd) * static_cast<double>(l.mean_profile);
    }
    if (!order_.empty()) build(0, static_cast<int>(order_.size()));
  }

  // The far-field terms (A, B per channel) at point x, with the fog's diffusion vector and extinction.
  void add_at(const glm::dvec3& x, double extinction, double top, glm::dvec3* a, glm::dmat3* b) const {
    if (nodes_.empty()) return;
    add(0, x, extinction, top, a, b);
  }

 private:
  int build(int first, int count) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Node n;
    n.first = first;
    n.count = count;
    double weight = 0.0;
    glm::dvec3 lo(1e300), hi(-1e300);
    for (int k = first; k < first + count; ++k) {
      const glm::dvec3 p(frame_.lights[order_[k]].position_enu_m);
      const double w = peak(glm::vec3(power_[order_[k]])) + 1e-30;
      n.centre += w * p;
      weight += w;
      n.power += power_[order_[k]];
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    n.centre /= weight;
    for (int k = first; k < first + count; ++k)
      n.radius = std::max(n.radius, glm::length(glm::dvec3(frame_.lights[order_[k]].position_enu_m) - n.centre));
    if (count > 4) {
      const glm::dvec3 extent = hi - lo;
      const int axis = extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
      const int half = count / 2;
      std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                       [&](uint32_t a, uint32_t b) {
                         return frame_.lights[a].position_enu_m[axis] < frame_.lights[b].position_enu_m[axis];
                       });
      n.left = build(first, half);
      n.right = build(first + half, count - half);
    }
    nodes_[static_cast<size_t>(id)] = n;
    return id;
  }

  void one(const glm::dvec3& x, const glm::dvec3& light, const glm::dvec3& power, double extinction, double top,
           glm::dvec3* a, glm::dmat3* b) const {
    const glm::dvec3 to = light - x;
    const double d = glm::length(to);
    const double beta = extinction * fog::twin::atmo_fog_inside_fraction(float(x.z), float(light.z), float(top));
    const glm::vec2 p1 = fog::twin::atmo_fog_diffusion_light(frame_.diffusion, float(d), float(beta * d), true);
    *a += 0.25 * double(p1.x) * power;
    if (d > 0.0) {
      const glm::dvec3 l = to / d;
      for (int c = 0; c < 3; ++c) (*b)[c] += 0.5 * double(p1.y) * power[c] * l;
    }
  }

  void add(int id, const glm::dvec3& x, double extinction, double top, glm::dvec3* a, glm::dmat3* b) const {
    const Node& n = nodes_[static_cast<size_t>(id)];
    const double d = glm::length(n.centre - x);
    if (n.left < 0) {
      for (int k = n.first; k < n.first + n.count; ++k)
        one(x, glm::dvec3(frame_.lights[order_[k]].position_enu_m), power_[order_[k]], extinction, top, a, b);
    } else if (n.radius < 0.6 * d) {  // the subtree subtends < ~35 degrees: one source (the P1 field is smooth)
      one(x, n.centre, n.power, extinction, top, a, b);
    } else {
      add(n.left, x, extinction, top, a, b);
      add(n.right, x, extinction, top, a, b);
    }
  }

  const fog::FogFrame& frame_;
  std::vector<uint32_t> order_;
  std::vector<glm::dvec3> power_;
  std::vector<Node> nodes_;
};

// Threads that share a view's clusters (each froxel's work is its own: the result is the same for any count).
const int kThreads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 4u));

// A light reaching a froxel, and how much it matters there.
struct Pair {
  uint32_t froxel, light;
  float importance;
};

// In a band's list, an entry naming the band's own merged light (renumbered when the bands are joined).
constexpr uint32_t kMergedFlag = 0x80000000u;

// A froxel's merged lights stay out of its list when together they bring less than this share of its
// light (as the importances estimate it).
constexpr double kNegligibleShare = 0.005;

// The pairs of light i: the froxels its range reaches (its sphere's footprint in tiles and slices, each
// froxel tested against the sphere and the cone), with its importance in each.
void add_pairs(const fog::FogFrame& frame, const ClusterGrid& grid, const std::vector<glm::dvec3>& centre,
               const std::vector<double>& radius, const std::vector<float>& range, int i, std::vector<Pair>* pairs) {
  const float r = range[static_cast<size_t>(i)];
  if (!(r > 0.0f)) return;
  const fog::FrameLight& l = frame.lights[static_cast<size_t>(i)];
  const glm::dvec3 p(l.position_enu_m);
  const double dp = glm::length(p);
  // The sphere's footprint in tiles: the whole screen when it holds the eye or reaches behind the camera.
  int tx0 = 0, tx1 = grid.tiles_x - 1, ty0 = 0, ty1 = grid.tiles_y - 1;
  if (dp > r * 1.001) {
    double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
    bool behind = false;
    for (int c = 0; c < 8 && !behind; ++c) {
      const glm::dvec3 corner = p + double(r) * glm::dvec3(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
      const glm::dvec4 clip = grid.clip_from_enu * glm::dvec4(corner, 1.0);
      if (!(clip.w > 1e-6)) {
        behind = true;
        break;
      }
      lo_x = std::min(lo_x, clip.x / clip.w);
      hi_x = std::max(hi_x, clip.x / clip.w);
      lo_y = std::min(lo_y, clip.y / clip.w);
      hi_y = std::max(hi_y, clip.y / clip.w);
    }
    if (!behind) {
      if (hi_x < -1.0 || lo_x > 1.0 || hi_y < -1.0 || lo_y > 1.0) return;  // off screen
      tx0 = std::clamp(int(std::floor((lo_x + 1.0) * 0.5 * grid.tiles_x)), 0, grid.tiles_x - 1);
      tx1 = std::clamp(int(std::floor((hi_x + 1.0) * 0.5 * grid.tiles_x)), 0, grid.tiles_x - 1);
      ty0 = std::clamp(int(std::floor((lo_y + 1.0) * 0.5 * grid.tiles_y)), 0, grid.tiles_y - 1);
      ty1 = std::clamp(int(std::floor((hi_y + 1.0) * 0.5 * grid.tiles_y)), 0, grid.tiles_y - 1);
    }
  }
  const int k0 = static_cast<int>(grid.slice_of(std::max(dp - r, 0.0)));
  const int k1 = std::min(static_cast<int>(grid.slice_of(dp + r)), ClusterGrid::kSlices - 1);
  const double intensity = peak(l.intensity_cd);
  for (int k = k0; k <= k1; ++k)
    for (int y = ty0; y <= ty1; ++y)
      for (int x = tx0; x <= tx1; ++x) {
        const uint32_t f = static_cast<uint32_t>(grid.index(x, y, k));
        const glm::dvec3 to = centre[f] - p;
        const double d = glm::length(to);
        if (d > r + radius[f]) continue;
        if (!cone_reaches(to, radius[f], glm::dvec3(l.axis_enu), l.cos_outer, l.lobes)) continue;
        // Its importance: its irradiance at the froxel's centre (the cone towards it), the distance floored
        // at a quarter of the froxel's radius (a light inside the froxel counts as near, not as infinite).
        const double floor_d = std::max(d, std::max(0.25 * radius[f], 0.5));
        const double cone =
            fog::twin::atmo_fog_cone(l.axis_enu, l.cos_inner, l.cos_outer, l.lobes, glm::vec3(to / std::max(d, 1e-6)));
        const double edge = cone > 0.0 ? cone : 0.05;  // on the cone's edge, part of the froxel is still lit
        pairs->push_back({f, static_cast<uint32_t>(i),
                          static_cast<float>(intensity * edge * std::exp(-double(l.beta_per_m) * d) /
                                             (floor_d * floor_d))});
      }
}

// One froxel's list from its pairs [begin, end) (each light once, in index order): the kNearLights most
// important exactly, the rest merged into up to kMergedLights lights (none when they bring a negligible
// share). Appends to *lists (merged lights as kMergedFlag | their index in *merged); returns how many
// lights were merged.
uint64_t froxel_list(const fog::FogFrame& frame, const std::vector<float>& range, const glm::dvec3& centre,
                     double radius, Pair* begin, Pair* end, std::vector<uint32_t>* lists,
                     std::vector<fog::FrameLight>* merged, std::vector<float>* merged_range) {
  const size_t n = static_cast<size_t>(end - begin);
  if (n > static_cast<size_t>(kNearLights)) {
    // The most important first (ties by index: deterministic).
    std::partial_sort(begin, begin + kNearLights, end, [](const Pair& a, const Pair& b) {
      return a.importance != b.importance ? a.importance > b.importance : a.light < b.light;
    });
    std::sort(begin, begin + kNearLights, [](const Pair& a, const Pair& b) { return a.light < b.light; });
  }
  const size_t near = std::min(n, static_cast<size_t>(kNearLights));
  for (size_t k = 0; k < near; ++k) lists->push_back(begin[k].light);
  if (begin + near >= end) return 0;
  double total = 0.0, rest = 0.0;
  for (Pair* p = begin; p < end; ++p) (p < begin + near ? total : rest) += p->importance;
  if (rest < kNegligibleShare * (total + rest)) return 0;
  // The rest, merged: groups split along their longest axis, each one light.
  std::vector<std::pair<Pair*, Pair*>> groups = {{begin + near, end}};
  while (static_cast<int>(groups.size()) < kMergedLights) {
    // Split the group with the most lights (ties: the first) at its median along its longest axis.
    auto largest = std::max_element(groups.begin(), groups.end(), [](const auto& a, const auto& b) {
      return a.second - a.first < b.second - b.first;
    });
    if (largest->second - largest->first < 2) break;
    glm::dvec3 lo(1e300), hi(-1e300);
    for (Pair* p = largest->first; p < largest->second; ++p) {
      lo = glm::min(lo, glm::dvec3(frame.lights[p->light].position_enu_m));
      hi = glm::max(hi, glm::dvec3(frame.lights[p->light].position_enu_m));
    }
    const glm::dvec3 extent = hi - lo;
    const int axis = extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
    Pair* mid = largest->first + (largest->second - largest->first) / 2;
    std::nth_element(largest->first, mid, largest->second, [&](const Pair& a, const Pair& b) {
      const float pa = frame.lights[a.light].position_enu_m[axis], pb = frame.lights[b.light].position_enu_m[axis];
      return pa != pb ? pa < pb : a.light < b.light;
    });
    const std::pair<Pair*, Pair*> right = {mid, largest->second};
    largest->second = mid;
    groups.push_back(right);
  }
  for (const auto& [first, last] : groups) {
    // The group's irradiance magnitude at the froxel's centre, and its intensity-weighted centre.
    glm::dvec3 irradiance(0.0), position(0.0);
    double weight = 0.0;
    float reach = 0.0f, beta = 0.0f;
    for (Pair* p = first; p < last; ++p) {
      const fog::FrameLight& l = frame.lights[p->light];
      const glm::dvec3 to = glm::dvec3(l.position_enu_m) - centre;
      const double d = std::max(glm::length(to), 0.5);
      const double cone = fog::twin::atmo_fog_cone(l.axis_enu, l.cos_inner, l.cos_outer, l.lobes, glm::vec3(-to / d));
      const glm::dvec3 e0 = glm::dvec3(l.intensity_cd) * (cone * std::exp(-double(l.beta_per_m) * d) / (d * d));
      irradiance += e0;
      const double w = peak(glm::vec3(e0));
      position += w * glm::dvec3(l.position_enu_m);
      weight += w;
      reach = std::max(reach, range[p->light]);
      beta = std::max(beta, l.beta_per_m);
    }
    if (!(weight > 0.0)) continue;
    position /= weight;
    fog::FrameLight v;
    v.position_enu_m = glm::vec3(position);
    v.beta_per_m = beta;
    // The intensity that gives the group's irradiance at the centre from where the merged light stands.
    const double d = std::max(glm::length(position - centre), 0.5);
    v.intensity_cd = glm::vec3(irradiance * (d * d * std::exp(double(beta) * d)));
    lists->push_back(kMergedFlag | static_cast<uint32_t>(merged->size()));
    merged->push_back(v);
    merged_range->push_back(reach + static_cast<float>(radius));
  }
  return static_cast<uint64_t>(end - begin - near);
}

// The lights' diffusion in fog, sampled at the corners of blocks of kBlock x kBlock tiles x 2 slices (it
// reaches kilometres and varies over hundreds of metres, 1 / mu), interpolated to the froxels' centres and
// put on the six faces.
class Diffusion {
 public:
  static constexpr int kBlock = 8;
  template <typename Ray>
  Diffusion(const fog::FogFrame& frame, const ClusterGrid& grid, const Ray& ray)
      : nx_((grid.tiles_x + kBlock - 1) / kBlock + 1),
        ny_((grid.tiles_y + kBlock - 1) / kBlock + 1),
        nk_(ClusterGrid::kSlices / 2 + 1) {
    if (!(frame.diffusion.w > 0.0f) || frame.lights.empty()) return;
    const DiffusionTree tree(frame);
    a_.assign(static_cast<size_t>(nx_) * ny_ * nk_, glm::dvec3(0.0));
    b_.assign(a_.size(), glm::dmat3(0.0));
    clouds::for_bands(nk_, kThreads, [&](int k_begin, int k_end) {
      for (int k = k_begin; k < k_end; ++k)
        for (int y = 0; y < ny_; ++y)
          for (int x = 0; x < nx_; ++x) {
            const double ndc_x = std::min(2.0 * x * kBlock / grid.tiles_x - 1.0, 1.0);
            const double ndc_y = std::min(2.0 * y * kBlock / grid.tiles_y - 1.0, 1.0);
            const size_t at = (static_cast<size_t>(k) * ny_ + y) * nx_ + x;
            tree.add_at(ray(ndc_x, ndc_y) * grid.slice_distance(2.0 * k), frame.extinction_per_m,
                        frame.top_above_eye_m, &a_[at], &b_[at]);
          }
    });
  }

  // The P1 irradiance phi / 4 + F . n / 2 on each face of froxel (x, y, k) (clamped per channel, as the
  // include's single light is), added to faces.
  void add_faces(int x, int y, int k, glm::dvec3 faces[LightClusters::kFaces]) const {
    if (a_.empty()) return;
    const double fx = std::min((x + 0.5) / kBlock, nx_ - 1.0), fy = std::min((y + 0.5) / kBlock, ny_ - 1.0),
                 fk = std::min((k + 0.5) / 2.0, nk_ - 1.0);
    const int x0 = std::min(int(fx), nx_ - 2), y0 = std::min(int(fy), ny_ - 2), k0 = std::min(int(fk), nk_ - 2);
    glm::dvec3 a(0.0);
    glm::dmat3 b(0.0);
    for (int c = 0; c < 8; ++c) {
      const int cx = x0 + (c & 1), cy = y0 + ((c >> 1) & 1), ck = k0 + (c >> 2);
      const double w = (c & 1 ? fx - x0 : 1.0 - (fx - x0)) * ((c >> 1) & 1 ? fy - y0 : 1.0 - (fy - y0)) *
                       (c >> 2 ? fk - k0 : 1.0 - (fk - k0));
      const size_t at = (static_cast<size_t>(ck) * ny_ + cy) * nx_ + cx;
      a += w * a_[at];
      b += w * b_[at];
    }
    for (int axis = 0; axis < 3; ++axis)
      for (int sign = 0; sign < 2; ++sign) {
        const glm::dvec3 along(b[0][axis], b[1][axis], b[2][axis]);  // per channel, the flux term along the axis
        faces[2 * axis + sign] += glm::max(a + (sign ? -1.0 : 1.0) * along, glm::dvec3(0.0));
      }
  }

 private:
  int nx_, ny_, nk_;
  std::vector<glm::dvec3> a_;
  std::vector<glm::dmat3> b_;
};

}  // namespace

ClusterGrid ClusterGrid::for_view(const glm::dmat4& clip_from_enu, int viewport_width, int viewport_height,
                                  int tile_px) {
  ClusterGrid g;
  g.clip_from_enu = clip_from_enu;
  const int w = std::max(viewport_width, 1), h = std::max(viewport_height, 1);
  g.tiles_x = std::clamp((w + tile_px - 1) / tile_px, kMinTiles, kMaxTiles);
  const double tile = double(w) / g.tiles_x;  // square tiles
  g.tiles_y = std::clamp(int(std::ceil(h / tile)), 1, kMaxTiles);
  return g;
}

double ClusterGrid::slice_distance(double k) const { return near_m * std::pow(far_m / near_m, k / kSlices); }

double ClusterGrid::slice_of(double distance_m) const {
  const double k = std::log(std::max(distance_m, near_m) / near_m) / std::log(far_m / near_m) * kSlices;
  return std::clamp(k, 0.0, double(kSlices));
}

std::vector<float> surface_ranges(const fog::FogFrame& frame, float albedo, double threshold_cd_m2) {
  std::vector<float> range(frame.lights.size(), 0.0f);
  // A white Lambertian surface facing the light: L = E / pi; E <= I (e^-bd / d^2 + albedo b e^-bd G / (2 pi d)).
  const double e_min = kPi * threshold_cd_m2;
  for (size_t i = 0; i < frame.lights.size(); ++i) {
    const fog::FrameLight& l = frame.lights[i];
    const double intensity = peak(l.intensity_cd), beta = l.beta_per_m;
    if (!(intensity > 0.0) || !(e_min > 0.0)) continue;
    const auto e = [&](double d) {
      return intensity * std::exp(-beta * d) * (1.0 / (d * d) + albedo * beta * kMaxSurfaceG / (2.0 * kPi * d));
    };
    // e falls with d: bisection in log d between 0.01 m and 1000 km.
    double lo = std::log(0.01), hi = std::log(1e6);
    if (e(std::exp(hi)) >= e_min) {
      range[i] = 1e6f;
      continue;
    }
    if (e(std::exp(lo)) < e_min) continue;
    for (int k = 0; k < 30; ++k) {
      const double mid = 0.5 * (lo + hi);
      (e(std::exp(mid)) >= e_min ? lo : hi) = mid;
    }
    range[i] = static_cast<float>(std::exp(hi));
  }
  return range;
}

LightClusters cluster_lights(const fog::FogFrame& frame, const ClusterGrid& grid, float fog_albedo,
                             double threshold_cd_m2) {
  LightClusters out;
  out.grid = grid;
  const int froxels = grid.froxels();
  // Ranges at a tenth of the threshold: a light under the threshold alone still counts in a merged light,
  // where many of them add up (a town seen from its edge).
  out.range_m = surface_ranges(frame, fog_albedo, kRangeThresholdFraction * threshold_cd_m2);
  const glm::dmat4 enu_from_clip = glm::inverse(grid.clip_from_enu);
  // Each froxel's centre (ENU relative to the eye) and bounding radius.
  std::vector<glm::dvec3> centre(static_cast<size_t>(froxels));
  std::vector<double> radius(static_cast<size_t>(froxels));
  // The eye is the origin (clip_from_enu holds no translation): a pixel's ray is the direction of any point
  // on it, here at NDC depth 0.5, which is finite for every depth convention (an infinite reversed-Z far
  // plane is at 0).
  const auto ray = [&](double ndc_x, double ndc_y) {
    const glm::dvec4 p = enu_from_clip * glm::dvec4(ndc_x, ndc_y, 0.5, 1.0);
    return glm::normalize(glm::dvec3(p) / p.w);
  };
  for (int y = 0; y < grid.tiles_y; ++y)
    for (int x = 0; x < grid.tiles_x; ++x) {
      const double x0 = 2.0 * x / grid.tiles_x - 1.0, x1 = 2.0 * (x + 1) / grid.tiles_x - 1.0;
      const double y0 = 2.0 * y / grid.tiles_y - 1.0, y1 = 2.0 * (y + 1) / grid.tiles_y - 1.0;
      const glm::dvec3 mid = ray(0.5 * (x0 + x1), 0.5 * (y0 + y1));
      double spread = 0.0;  // the tile's half-angle
      for (const glm::dvec3& corner : {ray(x0, y0), ray(x1, y0), ray(x0, y1), ray(x1, y1)})
        spread = std::max(spread, std::acos(std::clamp(glm::dot(corner, mid), -1.0, 1.0)));
      for (int k = 0; k < ClusterGrid::kSlices; ++k) {
        const double d0 = grid.slice_distance(k), d1 = grid.slice_distance(k + 1), dm = 0.5 * (d0 + d1);
        const size_t f = static_cast<size_t>(grid.index(x, y, k));
        centre[f] = mid * dm;
        const double across = std::tan(std::min(spread, 1.5)) * d1;
        radius[f] = std::sqrt(across * across + 0.25 * (d1 - d0) * (d1 - d0));
      }
    }

  // Every (light, froxel) pair where the light reaches the froxel, with the light's bound there; the lights
  // in bands on up to kThreads threads, the bands' pairs joined in order (the same for any thread count).
  const int light_count = static_cast<int>(frame.lights.size());
  std::vector<std::vector<Pair>> band_pairs(static_cast<size_t>(clouds::band_count(light_count, kThreads)));
  clouds::for_numbered_bands(light_count, kThreads, [&](int b, int begin, int end) {
    for (int i = begin; i < end; ++i)
      add_pairs(frame, grid, centre, radius, out.range_m, i, &band_pairs[static_cast<size_t>(b)]);
  });
  std::vector<uint32_t> start(static_cast<size_t>(froxels) + 1, 0);
  for (const std::vector<Pair>& pairs : band_pairs)
    for (const Pair& p : pairs) ++start[p.froxel + 1];
  for (int f = 0; f < froxels; ++f) start[f + 1] += start[f];
  std::vector<Pair> grouped(start[static_cast<size_t>(froxels)]);
  {
    // Grouped by froxel, each froxel's lights in index order (counting sort, stable).
    std::vector<uint32_t> at(start.begin(), start.end() - 1);
    for (const std::vector<Pair>& pairs : band_pairs)
      for (const Pair& p : pairs) grouped[at[p.froxel]++] = p;
  }
  band_pairs.clear();
  out.pairs = grouped.size();

  // The lights' diffusion in fog reaches kilometres and varies over hundreds of metres (1 / mu): sampled
  // at the corners of blocks of kDiffusionBlock x kDiffusionBlock tiles x 2 slices and interpolated to the
  // froxels' centres.
  const Diffusion diffusion(frame, grid, ray);

  // Each froxel's list and far field, in bands of froxels; a band's lists and merged lights are joined in
  // froxel order.
  struct Band {
    std::vector<uint32_t> lists;  // merged lights as kMergedFlag | their index in `merged`
    std::vector<fog::FrameLight> merged;
    std::vector<float> merged_range_m;
    uint64_t overflow = 0;
  };
  const int band_total = clouds::band_count(froxels, kThreads);
  std::vector<Band> bands(static_cast<size_t>(band_total));
  out.offset.assign(static_cast<size_t>(froxels), 0);
  out.count.assign(static_cast<size_t>(froxels), 0);
  for (std::vector<glm::vec3>& face : out.far) face.assign(static_cast<size_t>(froxels), glm::vec3(0.0f));
  clouds::for_numbered_bands(froxels, kThreads, [&](int b, int begin, int end) {
    Band& band = bands[static_cast<size_t>(b)];
    for (int f = begin; f < end; ++f) {
      const size_t first = band.lists.size();
      band.overflow += froxel_list(frame, out.range_m, centre[static_cast<size_t>(f)], radius[static_cast<size_t>(f)],
                                   grouped.data() + start[static_cast<size_t>(f)],
                                   grouped.data() + start[static_cast<size_t>(f) + 1], &band.lists, &band.merged,
                                   &band.merged_range_m);
      out.offset[static_cast<size_t>(f)] = static_cast<uint32_t>(first);  // band-relative until joined
      out.count[static_cast<size_t>(f)] = static_cast<uint32_t>(band.lists.size() - first);
      glm::dvec3 faces[LightClusters::kFaces] = {};
      diffusion.add_faces(f % grid.tiles_x, (f / grid.tiles_x) % grid.tiles_y, f / (grid.tiles_x * grid.tiles_y),
                          faces);
      for (int face = 0; face < LightClusters::kFaces; ++face)
        out.far[face][static_cast<size_t>(f)] = glm::vec3(faces[face]);
    }
  });
  for (int b = 0, f = 0; b < band_total; ++b) {
    Band& band = bands[static_cast<size_t>(b)];
    const uint32_t list_base = static_cast<uint32_t>(out.lists.size());
    const uint32_t merged_base = static_cast<uint32_t>(frame.lights.size() + out.merged.size());
    for (uint32_t entry : band.lists)
      out.lists.push_back(entry & kMergedFlag ? merged_base + (entry & ~kMergedFlag) : entry);
    out.merged.insert(out.merged.end(), band.merged.begin(), band.merged.end());
    out.merged_range_m.insert(out.merged_range_m.end(), band.merged_range_m.begin(), band.merged_range_m.end());
    out.overflow += band.overflow;
    // The band's froxels: [b * froxels / bands, (b + 1) * froxels / bands) (for_numbered_bands' split).
    for (const int end = (b + 1) * froxels / band_total; f < end; ++f) {
      out.offset[static_cast<size_t>(f)] += list_base;
      out.longest_list = std::max(out.longest_list, out.count[static_cast<size_t>(f)]);
    }
  }
  return out;
}

}  // namespace atmo::lights
