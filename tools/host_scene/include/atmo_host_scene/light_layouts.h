// light_layouts.h — the lights of an airport and of a town, as a host would
// send them to set_lights (one AtmoLightPoint each, ENU metres at the
// airfield datum): the night scenes of a qualified simulator hold about
// 15 000 lights (FAA 14 CFR Part 60, Appendix A, Table A1A). Deterministic
// for a seed. Intensities and beams after ICAO Annex 14 Vol. I Appendix 2
// (isocandela figures A2-1..A2-20, rounded): approach and edge lights
// ~10 000-20 000 cd on their beams, centreline and touchdown zone ~5 000 cd,
// taxiway lights ~50-100 cd; the town's after typical luminaires and
// windows (docs/FOG.md "The airport and the town").
#ifndef ATMO_HOST_SCENE_LIGHT_LAYOUTS_H
#define ATMO_HOST_SCENE_LIGHT_LAYOUTS_H

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "atmo/atmo.h"

namespace atmo::host_scene {

struct RunwaySpec {
  glm::dvec2 centre_enu_m{0.0};  // on the datum plane (height 0)
  double heading_deg = 90.0;     // landing direction: the approach end is behind, the approach lights before it
  double length_m = 3000.0;
  double width_m = 45.0;
};

struct AirportSpec {
  std::vector<RunwaySpec> runways = {RunwaySpec{}};
  double taxiway_length_m = 8000.0;  // taxiways parallel to the first runway, 180 m beside it, and stubs
};

// Per runway: edge lights every 60 m both sides (bidirectional beams along
// the runway, 10 000 cd, 7/20 degree cone, 1 degree up); centreline every
// 15 m (bidirectional, 5 000 cd, 5/15 degrees; the last 900 m alternating
// red, the last 300 m red); touchdown zone barrettes of 3 each side every
// 30 m over the first 900 m (5 000 cd towards the approach); threshold (green)
// and end (red) bars of 16; an approach lighting system of 30 barrettes of 5
// every 30 m (20 000 cd towards the approach, 3 degrees up, 10/25 degree
// cone) with a crossbar of 20 at 300 m. Taxiways: blue edge lights every
// 30 m (omni, 50 cd) and green centreline every 15 m (100 cd).
std::vector<AtmoLightPoint> airport_lights(const AirportSpec& spec);

struct TownSpec {
  glm::dvec2 centre_enu_m{0.0, 5000.0};
  uint32_t lights = 10000;       // the layout is filled to exactly this many
  double lights_per_km2 = 1300;  // the density: the town's square grows with the count
  uint64_t seed = 1;
};

// A grid of streets 120 m apart with street lights every 40 m on one side (9 m
// up, 2 500 cd, cut off towards the sky: full within 55 degrees of the nadir,
// none past 85), cars on the streets (headlights 10 000 cd in a 10/30 degree
// beam along the street, red tail lights 10 cd), and lit windows and signs
// (omni, 20-150 cd, 3-30 m up) filling the rest; sodium and white districts.
// The town is a square of side sqrt(lights / lights_per_km2) km.
std::vector<AtmoLightPoint> town_lights(const TownSpec& spec);

}  // namespace atmo::host_scene

#endif  // ATMO_HOST_SCENE_LIGHT_LAYOUTS_H
