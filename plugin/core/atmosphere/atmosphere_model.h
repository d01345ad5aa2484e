// atmosphere_model.h — physical parameters of the air, from the host's
// settings, and the transmittance lookup table the passes sample.
//
// Model: three wavelengths (680, 550, 440 nm) rendered as the R, G, B
// channels (Bruneton 2017): the coefficients of each come from the spectral
// definition of the air (plugin/core/spectral: first-principles Rayleigh with
// the King factor, scale height 8 km; aerosols from the meteorological
// visibility, ln(20)/MOR minus Rayleigh, Angstrom 1.3, albedo 0.9, Cornette-
// Shanks g = 0.8; ozone 300 DU, Serdyuchenko 2014 cross-sections, tent profile
// at 25 km), and the sun of each channel is the linear-sRGB illuminance of the
// solar spectrum (5772 K black body, 1361 W/m^2) through the CIE 1931 observer
// (about 125 klx, slightly warm of D65), so the direct sun's colour is exact.
// Sun's angular radius 0.2666°.
#pragma once

#include <atomic>
#include <functional>

#include "core/atmosphere/shader_twin.h"
#include "core/spectral/spectral_atmosphere.h"

namespace atmo::core {

// The host's settings; the constants of the air (scale heights, phase
// asymmetry, ozone profile, the atmosphere's thickness) are the spectral
// model's (core/spectral/spectral_atmosphere.h), the one source.
struct AtmosphereSettings {
  double visibility_m = 40000.0;
  double aerosol_scale_height_m = spectral::kDefaultAerosolScaleHeightM;
  double ground_albedo = 0.1;
};

using spectral::kAtmosphereThicknessM;
// Linear sRGB illuminance of the sun outside the atmosphere at 1 AU, lux per channel.
glm::dvec3 sun_rgb_illuminance_at_1au_lux();
constexpr double kSunAngularRadiusRad = 0.2666 * 3.14159265358979323846 / 180.0;

twin::AtmosphereParameters make_atmosphere_parameters(const AtmosphereSettings& settings,
                                                      double bottom_radius_m, double sun_distance_au);

// Progress and cancellation of a table build, both optional. The builders
// call `progress` on the calling thread after each row with the fraction of
// rows done, in (0, 1] (the last call is 1), and check `*stop` before each row:
// once it is true they return an empty table (width = height = 0) at once.
// No threads, no logging here: the caller decides what to do with both.
struct TableBuildControl {
  std::function<void(double fraction)> progress;
  const std::atomic<bool>* stop = nullptr;

  bool stopped() const { return stop && stop->load(std::memory_order_relaxed); }
  void report(double fraction) const {
    if (progress) progress(fraction);
  }
};

// Transmittance table T(r, mu) to the top of the atmosphere, integrated in
// double precision with `integration_steps` samples per texel, spaced
// quadratically away from the ray's lowest point.
constexpr int kTransmittanceWidth = 256;
constexpr int kTransmittanceHeight = 64;
twin::Lut2D compute_transmittance_table(const twin::AtmosphereParameters& atm, int width,
                                                     int height, int integration_steps = 256,
                                                     const TableBuildControl& control = {});

// Multiple-scattering table Psi_ms(mu_s, altitude) (Hillaire 2020), per unit
// sun illuminance, from the transmittance table: `directions` rays of `steps`
// samples per texel, through the shared function multiple_scattering_texel.
// 64 texels along mu_s: below the horizon Psi_ms falls steeply, and at 32 the
// linear interpolation between texels made the twilight sky darken in steps
// (a factor 2.6 between two sun elevations 0.25 deg apart at -9.25 deg; 1.6
// at 64 — tests/core/twilight_test.cpp). Altitude needs no more than 32.
constexpr int kMultipleScatteringWidth = 64;   // mu_s
constexpr int kMultipleScatteringHeight = 32;  // altitude
twin::Lut2D compute_multiple_scattering_table(const twin::AtmosphereParameters& atm,
                                              const twin::Lut2D& transmittance,
                                              int width = kMultipleScatteringWidth,
                                              int height = kMultipleScatteringHeight, int directions = 64,
                                              int steps = 20,
                                              const TableBuildControl& control = {});

// The air of `settings` on a sphere of `bottom_radius_m` (Sun at 1 au) and
// its two CPU tables at the default sizes: what tests, benchmarks and tools
// that draw or evaluate one fixed air start from (~0.25 s).
struct ModelTables {
  twin::AtmosphereParameters atmosphere;
  twin::Lut2D transmittance, multiple_scattering;
};
ModelTables compute_model_tables(const AtmosphereSettings& settings, double bottom_radius_m);

}  // namespace atmo::core
