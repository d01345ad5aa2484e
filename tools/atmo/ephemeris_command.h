// ephemeris_command.h — `atmo ephemeris`: where the Sun, the Moon, the five
// naked-eye planets and (optionally) a catalog star are for an observer at a
// time, as the plugin's ephemeris core computes them (core/astro): azimuth,
// elevation with and without refraction, distance, apparent RA/Dec, magnitude,
// illuminated fraction, phase angle, the bright limb's position angle, and the
// time scales used. A human table, or JSON. docs/EPHEMERIS.md documents it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace atmo::ephemeris {

struct Options {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double height_m = 0.0;
  std::string utc;                      // ISO 8601, "...Z" or with an offset
  double dut1_s = 0.0;                  // UT1 - UTC
  std::optional<double> delta_t_s;      // TT - UT1 override
  bool json = false;
  std::optional<std::uint32_t> star_hd;  // HD number in the catalog
  std::string star_name;                 // or its proper name ("Sirius")
  std::string catalog_path;              // star catalog (data/stars/*.tsv)
  bool no_refraction = false;
  std::optional<double> pressure_hpa;    // refraction conditions; default:
  std::optional<double> temperature_c;   // standard atmosphere at the height
};

// 0: printed; 2: bad input (message on stderr).
int run_ephemeris(const Options& options);

}  // namespace atmo::ephemeris
