// OpenSCENARIO (ASAM, 1.0-1.2) import: the Environment of an ".xosc" file as a
// Scenario, so `atmo render` and every scenario reader take it like a JSON
// scenario. docs/OPENSCENARIO.md has the mapping table; in short:
//
//   TimeOfDay@dateTime            -> utc (an offset is honoured; none: taken as UTC, noted)
//   Weather@fractionalCloudCover  -> one procedural cloud layer (cloud_layer_for_oktas)
//   Weather@cloudState (1.0)      -> the same, through an okta count
//   Weather/Fog@visualRange       -> atmosphere.visibility_m (the air's MOR); with a
//                                    BoundingBox, the ground fog layer instead
//   Weather/Sun                   -> compared with the ephemeris, which wins (noted)
//   RoadNetwork/LogicFile         -> location, from the OpenDRIVE geoReference's +lat_0 +lon_0
//   Precipitation, Wind, pressure, temperature, illuminance, DomeImage
//                                 -> accepted, not drawn (Scenario::not_yet_supported)
//
// Errors name the file, the line and column, the element's path and the
// attribute: "f.xosc: line 12, column 8: /OpenSCENARIO/.../Weather/Fog@visualRange:
// expected a distance in metres > 0, found \"-3\"". The first error ends the import.
#ifndef ATMO_SCENARIO_OPENSCENARIO_H
#define ATMO_SCENARIO_OPENSCENARIO_H

#include <string>

#include "atmo_scenario/scenario.h"

namespace atmo::scenario {

// Where the scene is when neither the command line nor a readable
// geoReference says: Munich, at the ellipsoid.
inline constexpr double kImportDefaultLatitudeDeg = 48.137;
inline constexpr double kImportDefaultLongitudeDeg = 11.575;
// The default camera's size, pixels.
inline constexpr int kImportDefaultWidth = 640;
inline constexpr int kImportDefaultHeight = 360;
// A still with no TimeOfDay (optional since 1.2): the June solstice, 11:00 UTC.
inline constexpr const char* kImportDefaultUtc = "2024-06-21T11:00:00Z";

// The cloud layer an okta count becomes (0: none, so coverage_oktas 0):
//   1-4 oktas  cumulus   base 1200 m, top 2200 m (fair-weather heaps)
//   5-7 oktas  stratus   base 1000 m, top 1500 m (a broken deck)
//   8   oktas  overcast  base  600 m, top 1100 m (a closed deck)
// Heights above the ENU origin; seed 1; area: the terrain's 20 km square.
CloudLayer cloud_layer_for_oktas(int oktas);

// Parses and maps `xml_text`; relative files (the OpenDRIVE logic file,
// catalog directories) are read from the directory of `file_label`.
LoadResult parse_openscenario(const std::string& xml_text, const std::string& file_label,
                              const ImportOptions& options = {});
LoadResult load_openscenario_file(const std::string& path, const ImportOptions& options = {});

// +lat_0 and +lon_0 of a PROJ string ("+proj=tmerc +lat_0=48.1 +lon_0=11.5 ..."),
// false when either is missing, not a number or out of range.
bool proj_origin(const std::string& proj, double* latitude_deg, double* longitude_deg);

}  // namespace atmo::scenario

#endif  // ATMO_SCENARIO_OPENSCENARIO_H
