// atmosphere_model.h — physical parameters of the air, from the host's
// settings, and the transmittance lookup table the passes sample.
//
// Model (issue 2, single scattering, three channels at 680/550/440 nm):
//  - Rayleigh: sea-level scattering (5.802, 13.558, 33.100) x 1e-6 /m, scale height 8 km.
//  - Aerosols: extinction at 550 nm from the meteorological optical range
//    (Koschmieder, 5 % contrast): beta_total = ln(20) / MOR = 2.996 / MOR; the
//    aerosol part is beta_total minus Rayleigh at 550 nm (floored at 2e-7 /m),
//    single-scattering albedo 0.9, Angstrom exponent 1.3, scale height from
//    the settings, Cornette-Shanks phase with g = 0.8.
//  - Ozone: absorption (0.650, 1.881, 0.085) x 1e-6 /m at the 25 km peak, tent profile of 15 km half width.
//  - Sun: 128 000 lux at 1 AU outside the atmosphere (solar constant 1361 W/m^2
//    times 94 lm/W), white in Rec.709/D65; angular radius 0.2666°.
#pragma once

#include "core/shader_twin.h"

namespace atmo::core {

struct AtmosphereSettings {
  double visibility_m = 40000.0;
  double aerosol_scale_height_m = 1200.0;
  double ground_albedo = 0.1;
};

constexpr double kAtmosphereThicknessM = 100000.0;
constexpr double kSunIlluminanceAt1AuLux = 128000.0;
constexpr double kSunAngularRadiusRad = 0.2666 * 3.14159265358979323846 / 180.0;

twin::AtmosphereParameters make_atmosphere_parameters(const AtmosphereSettings& settings,
                                                      double bottom_radius_m, double sun_distance_au);

// Transmittance table T(r, mu) to the top of the atmosphere, integrated in
// double precision with `integration_steps` midpoint samples per texel.
constexpr int kTransmittanceWidth = 256;
constexpr int kTransmittanceHeight = 64;
twin::Lut2D compute_transmittance_table(const twin::AtmosphereParameters& atm, int width,
                                                     int height, int integration_steps = 256);

// Multiple-scattering table Psi_ms(mu_s, altitude) (Hillaire 2020), per unit
// sun illuminance, from the transmittance table: `directions` rays of `steps`
// samples per texel, through the shared function multiple_scattering_texel.
constexpr int kMultipleScatteringSize = 32;
twin::Lut2D compute_multiple_scattering_table(const twin::AtmosphereParameters& atm,
                                              const twin::Lut2D& transmittance, int size = kMultipleScatteringSize,
                                              int directions = 64, int steps = 20);

}  // namespace atmo::core
