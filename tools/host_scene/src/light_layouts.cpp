#include "atmo_host_scene/light_layouts.h"

#include <algorithm>
#include <cmath>

namespace atmo::host_scene {

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

AtmoLightPoint light(const glm::dvec3& p, double cd, const glm::dvec3& colour) {
  AtmoLightPoint l{};
  for (int k = 0; k < 3; ++k) {
    l.position_m[k] = p[k];
    l.color[k] = colour[k];
  }
  l.intensity_cd = cd;
  return l;
}

AtmoLightPoint beam(const glm::dvec3& p, double cd, const glm::dvec3& colour, const glm::dvec3& axis, double inner_deg,
                    double outer_deg, bool both_ways = false) {
  AtmoLightPoint l = light(p, cd, colour);
  for (int k = 0; k < 3; ++k) l.direction[k] = axis[k];
  l.cone_inner_rad = inner_deg * kDeg;
  l.cone_outer_rad = outer_deg * kDeg;
  l.flags = both_ways ? uint32_t(ATMO_LIGHT_BIDIRECTIONAL) : 0u;
  return l;
}

const glm::dvec3 kWhite(1.0, 1.0, 1.0), kGreen(0.1, 1.0, 0.45), kRed(1.0, 0.08, 0.05), kBlue(0.15, 0.3, 1.0),
    kYellowWhite(1.0, 0.88, 0.6), kSodium(1.0, 0.55, 0.18), kLed(0.95, 0.95, 1.0);

// splitmix64: a small deterministic stream.
struct Random {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double range(double a, double b) { return a + (b - a) * uniform(); }
};

void runway_lights(const RunwaySpec& r, std::vector<AtmoLightPoint>* out) {
  const double h = r.heading_deg * kDeg;
  const glm::dvec2 along(std::sin(h), std::cos(h)), right(std::cos(h), -std::sin(h));
  const glm::dvec2 threshold = r.centre_enu_m - along * (0.5 * r.length_m);
  const auto at = [&](double s, double t, double up) {  // s along from the threshold, t to the right
    const glm::dvec2 p = threshold + along * s + right * t;
    return glm::dvec3(p, up);
  };
  const glm::dvec3 towards_approach(-along, std::tan(3.0 * kDeg));
  const glm::dvec3 along_runway(along, std::tan(1.0 * kDeg));
  const double half_width = 0.5 * r.width_m + 1.0;
  // Edge lights, both sides, both ends included.
  const int edges = static_cast<int>(std::floor(r.length_m / 60.0));
  for (int i = 0; i <= edges; ++i)
    for (const double side : {-1.0, 1.0})
      out->push_back(beam(at(i * r.length_m / edges, side * half_width, 0.4), 10000.0, kYellowWhite, along_runway, 7.0,
                          20.0, true));
  // Centreline: white, then alternating red and white from 900 m before the end, red over the last 300 m.
  const int centre = static_cast<int>(std::floor(r.length_m / 15.0));
  for (int i = 1; i < centre; ++i) {
    const double s = i * 15.0, to_end = r.length_m - s;
    const glm::dvec3 c = to_end < 300.0 ? kRed : (to_end < 900.0 && i % 2 == 0) ? kRed : kWhite;
    out->push_back(beam(at(s, 0.0, 0.05), 5000.0, c, along_runway, 5.0, 15.0, true));
  }
  // Touchdown zone: barrettes of 3 each side of the centreline, every 30 m over the first 900 m.
  for (int i = 1; i <= 30; ++i)
    for (const double side : {-1.0, 1.0})
      for (int k = 0; k < 3; ++k)
        out->push_back(beam(at(i * 30.0, side * (9.0 + 1.5 * k), 0.05), 5000.0, kWhite, towards_approach, 5.0, 15.0));
  // Threshold (green, towards the approach) and end (red, towards the runway) bars.
  for (int k = 0; k < 16; ++k) {
    const double t = (k / 15.0 - 0.5) * 2.0 * half_width;
    out->push_back(beam(at(-1.0, t, 0.3), 10000.0, kGreen, towards_approach, 7.0, 20.0));
    out->push_back(beam(at(r.length_m + 1.0, t, 0.3), 5000.0, kRed, along_runway, 7.0, 20.0));
  }
  // Approach lighting: 30 barrettes of 5 every 30 m before the threshold, a crossbar of 20 at 300 m.
  for (int i = 1; i <= 30; ++i)
    for (int k = -2; k <= 2; ++k)
      out->push_back(beam(at(-30.0 * i, 1.0 * k, 1.0 + 0.05 * i), 20000.0, kWhite, towards_approach, 10.0, 25.0));
  for (int k = 0; k < 20; ++k) {
    const double t = (k < 10 ? -1.0 : 1.0) * (4.0 + 1.5 * (k % 10));
    out->push_back(beam(at(-300.0, t, 1.0 + 0.5), 20000.0, kWhite, towards_approach, 10.0, 25.0));
  }
}

}  // namespace

std::vector<AtmoLightPoint> airport_lights(const AirportSpec& spec) {
  std::vector<AtmoLightPoint> out;
  for (const RunwaySpec& r : spec.runways) runway_lights(r, &out);
  if (spec.runways.empty() || spec.taxiway_length_m <= 0.0) return out;
  // Taxiways: a parallel one 180 m to the right of the first runway, and stubs to it every 600 m, until the
  // length is used.
  const RunwaySpec& r = spec.runways.front();
  const double h = r.heading_deg * kDeg;
  const glm::dvec2 along(std::sin(h), std::cos(h)), right(std::cos(h), -std::sin(h));
  double left = spec.taxiway_length_m;
  const auto segment = [&](const glm::dvec2& a, const glm::dvec2& b) {
    const double length = std::min(glm::length(b - a), left);
    if (length <= 0.0) return;
    left -= length;
    const glm::dvec2 u = (b - a) / glm::length(b - a), n(u.y, -u.x);
    for (double s = 0.0; s <= length; s += 30.0)
      for (const double side : {-1.0, 1.0}) out.push_back(light(glm::dvec3(a + u * s + n * (side * 12.0), 0.35), 50.0, kBlue));
    for (double s = 7.5; s < length; s += 15.0) out.push_back(light(glm::dvec3(a + u * s, 0.05), 100.0, kGreen));
  };
  const glm::dvec2 parallel = r.centre_enu_m + right * 180.0;
  segment(parallel - along * (0.5 * r.length_m), parallel + along * (0.5 * r.length_m));
  for (double s = -0.5 * r.length_m; s <= 0.5 * r.length_m && left > 0.0; s += 600.0)
    segment(r.centre_enu_m + along * s + right * (0.5 * r.width_m + 15.0), parallel + along * s - right * 12.0);
  return out;
}

std::vector<AtmoLightPoint> town_lights(const TownSpec& spec) {
  std::vector<AtmoLightPoint> out;
  if (spec.lights == 0) return out;
  out.reserve(spec.lights);
  Random rng{spec.seed * 0x2545f4914f6cdd1dull + 1};
  const double side = 1000.0 * std::sqrt(spec.lights / std::max(spec.lights_per_km2, 1.0));
  const glm::dvec2 corner = spec.centre_enu_m - glm::dvec2(0.5 * side);
  const int streets = std::max(1, static_cast<int>(side / 120.0)) + 1;
  const auto colour_at = [&](const glm::dvec2& p) {  // districts 600 m across: sodium or white
    const int cell = static_cast<int>(std::floor((p.x - corner.x) / 600.0)) * 7 +
                     static_cast<int>(std::floor((p.y - corner.y) / 600.0)) * 3;
    return (cell & 1) ? kSodium : kLed;
  };
  // Street lights (about a third), street by street, so a small town still has whole streets.
  const uint32_t street_budget = spec.lights / 3;
  for (int dir = 0; dir < 2 && out.size() < street_budget; ++dir)
    for (int k = 0; k < streets && out.size() < street_budget; ++k)
      for (double s = 0.0; s <= side && out.size() < street_budget; s += 40.0) {
        const glm::dvec2 p = dir == 0 ? corner + glm::dvec2(s, k * 120.0 + 8.0) : corner + glm::dvec2(k * 120.0 + 8.0, s);
        out.push_back(beam(glm::dvec3(p, 9.0), 2500.0, colour_at(p), glm::dvec3(0.0, 0.0, -1.0), 55.0, 85.0));
      }
  // Cars (an eighth): headlights along a street, red tail lights behind.
  const uint32_t car_budget = std::min<uint32_t>(spec.lights, static_cast<uint32_t>(out.size()) + spec.lights / 8);
  while (out.size() + 4 <= car_budget) {
    const bool east = rng.uniform() < 0.5;
    const int k = static_cast<int>(rng.uniform() * streets);
    const double s = rng.range(0.0, side), way = rng.uniform() < 0.5 ? 1.0 : -1.0;
    const glm::dvec2 u = east ? glm::dvec2(way, 0.0) : glm::dvec2(0.0, way), n(u.y, -u.x);
    const glm::dvec2 c = east ? corner + glm::dvec2(s, k * 120.0 - 2.0 * way) : corner + glm::dvec2(k * 120.0 + 2.0 * way, s);
    for (const double t : {-0.7, 0.7}) {
      out.push_back(beam(glm::dvec3(c + u * 2.0 + n * t, 0.7), 10000.0, kLed, glm::dvec3(u, -0.03), 10.0, 30.0));
      out.push_back(beam(glm::dvec3(c - u * 2.2 + n * t, 0.9), 10.0, kRed, glm::dvec3(-u, 0.0), 30.0, 80.0));
    }
  }
  // Windows and signs fill the rest, inside the blocks.
  while (out.size() < spec.lights) {
    const glm::dvec2 p = corner + glm::dvec2(rng.range(0.0, side), rng.range(0.0, side));
    const double cd = 20.0 * std::pow(7.5, rng.uniform());  // 20-150 cd
    const glm::dvec3 warm(1.0, rng.range(0.7, 0.95), rng.range(0.4, 0.8));
    out.push_back(light(glm::dvec3(p, rng.range(3.0, 30.0)), cd, warm));
  }
  return out;
}

}  // namespace atmo::host_scene
