// moon_photometry.h — the Moon as a light (illuminance at the observer) and as
// a disc (radiance of each point), after Jensen et al. 2001 §4 (the
// Hapke–Lommel–Seeliger BRDF, eqs 1–5), with the measured phase law of
// Krisciunas & Schaefer (1991) setting the absolute level.
//
// Geometry comes in as arguments (the ephemeris is core/astro): the phase
// angle phi (Sun–Moon–observer, radians in [0, pi]; 0 = full), the
// observer–Moon distance in metres and the Sun–Moon distance in au.
// Illuminance in lux OUTSIDE the atmosphere, on a surface facing the Moon;
// radiance in cd/m^2; colours in linear sRGB (D65 white) normalised to
// luminance 1. Formulas, sources and measured figures: docs/NIGHT_SKY.md.
#pragma once

#include <glm/glm.hpp>

namespace atmo::core::night {

constexpr double kMoonRadiusM = 1737.4e3;         // IAU mean radius
constexpr double kMoonMeanDistanceM = 384400.0e3;  // the reference distance of the phase law
constexpr double kJensenMoonAlbedo = 0.072;        // Jensen's C, "mean albedo of the Moon"
constexpr double kHapkeG = 0.6;                    // Jensen eq 3: surface density (0.4 rays .. 0.8 craters)
constexpr double kHapkeT = 0.1;                    // Jensen eq 4: forward scattering, fit to Rougier
// Jensen's Sun at the Moon, W/m^2, the unit of his earthshine (eq 1: 0.19 W/m^2 "full earthshine").
constexpr double kJensenSunAtMoonWm2 = 1905.0;
constexpr double kJensenFullEarthshineWm2 = 0.19;

// --- The pieces of the model (all finite on [0, pi]) ---------------------------------

// Integrated Lommel–Seeliger phase function of a sphere, normalised to 1 at
// full phase: 1 - sin(phi/2) tan(phi/2) ln(cot(phi/4)). Its analytic limits
// are 1 at phi = 0 and 0 at phi = pi, where the formula is 0·inf: both ends
// are guarded (1e-6 rad) and the result clamped to [0, 1].
double lommel_seeliger_phase(double phase_rad);
// Jensen eq 3, retrodirective (opposition) function B(phi, g): 2 at phi = 0,
// 1 for phi >= pi/2; g / tan(phi) is guarded at phi -> 0.
double hapke_retrodirective(double phase_rad, double g = kHapkeG);
// Jensen eq 4, scattering law S(phi) = [sin|phi| + (pi - |phi|) cos|phi|] / pi + t (1 - cos|phi| / 2)^2.
double hapke_scattering(double phase_rad, double t = kHapkeT);
// Jensen eq 2 without the albedo: f = 2/(3 pi) B S / (1 + cos_r / cos_i), the
// radiance per unit albedo and per unit illuminance at normal incidence (see
// the docs: L = C · f · E_normal). 0 when cos_i <= 0 (unlit) or cos_r <= 0 (not visible).
double hapke_brdf(double cos_incidence, double cos_reflection, double phase_rad);

// Jensen eq 1, earthshine at the Moon as a fraction of the sunlight at the Moon:
// 0.19 · 0.5 · lommel_seeliger_phase(pi - phi) / 1905 (the Earth's phase is pi - phi).
double earthshine_fraction(double moon_phase_rad);

// Luminous illuminance of the Sun at 1 au outside the atmosphere, lux: the
// project's solar spectrum (5772 K black body, 1361 W/m^2) through the CIE
// 1931 observer (the luminance of core::sun_rgb_illuminance_at_1au_lux(), about 125 klx).
double sun_illuminance_at_1au_lux();

// Linear sRGB colour of moonlight and of the lunar disc, luminance 1: the
// project's solar spectrum times Jensen's lunar reddening ramp (a linear
// albedo ramp from 70 % at 340 nm to 135 % at 740 nm, held constant beyond
// its ends), through the CIE 1931 observer. Only the chromaticity is taken
// from the ramp; the luminous albedo stays C.
glm::dvec3 moon_color_rgb();

// --- The Moon as a light ----------------------------------------------------------

// Krisciunas & Schaefer (1991, PASP 103, 1033) phase law (after Allen):
// V = -12.73 + 0.026 |phi_deg| + 4e-9 phi_deg^4 at 384 400 km and 1 au, plus
// 5 log10((d / 384 400 km) · r_au) for the inverse squares.
double moon_magnitude_krisciunas_schaefer(double phase_rad, double observer_distance_m = kMoonMeanDistanceM,
                                          double sun_distance_au = 1.0);

// Jensen eq 5 (integrated Lommel–Seeliger, C = 0.072) with the earthshine of eq 1:
// E = 2/3 · C (r_m/d)^2 · [E_em + E_sm · lommel_seeliger_phase(phi)], lux.
double moon_illuminance_jensen_lux(double phase_rad, double observer_distance_m = kMoonMeanDistanceM,
                                   double sun_distance_au = 1.0, double albedo = kJensenMoonAlbedo);

// The closed-form disc integral of the radiance of moon_disc_luminance (the
// Hapke BRDF of eqs 2–4 with a constant albedo C):
// E = 1/3 (r_m/d)^2 · [C_sun B(phi) S(phi) lommel_seeliger_phase(phi) E_sm + C_earth B(0) S(0) E_em].
// Sun and earthshine terms separately, lux.
struct MoonIlluminance {
  double sun_lux = 0.0;
  double earthshine_lux = 0.0;
  double total() const { return sun_lux + earthshine_lux; }
};
MoonIlluminance moon_illuminance_hapke(double phase_rad, double observer_distance_m, double sun_distance_au,
                                       double sun_albedo, double earthshine_albedo);

// The illuminance used for the Moon as a light (what the host receives):
// the measured phase law (Krisciunas & Schaefer) for the sunlit part plus the
// earthshine of eq 1 on the disc at phase 0 with the albedo calibrated on the
// full Moon (see moon_calibrated_albedo). Lux, outside the atmosphere.
MoonIlluminance moon_illuminance(double phase_rad, double observer_distance_m = kMoonMeanDistanceM,
                                 double sun_distance_au = 1.0);

// The albedo C that makes the disc integral of the Hapke radiance equal the
// Krisciunas & Schaefer law at phase phi: C(phi) = E_KS(phi) / E_Hapke(phi; C = 1),
// independent of the distances. 0.18 at full Moon, 0.16–0.22 up to 150°
// (the Hapke phase curve with one albedo follows the measured one within
// 21 %, tests/core/night_photometry_test.cpp); beyond
// kMoonPhaseLawLimitRad the law rises unphysically (at 179° it would need
// C = 10: it gives V = -4 for a Moon that shows no sunlit part), so C is
// held at its 150° value there and the Hapke phase curve takes the light to 0
// at new Moon. Jensen's 0.072 makes the full Moon 0.13 lx, one magnitude too
// faint (docs/NIGHT_SKY.md).
constexpr double kMoonPhaseLawLimitRad = 150.0 * 3.14159265358979323846 / 180.0;
double moon_calibrated_albedo(double phase_rad);

// --- The Moon as a disc -------------------------------------------------------------

enum class MoonCalibration {
  kMagnitudeLaw,  // albedo moon_calibrated_albedo(phi): the disc integrates to moon_illuminance()
  kJensen,        // albedo 0.072 (Jensen as published)
};

// Per-frame uniforms of the Moon pass.
struct MoonDiscLighting {
  double phase_rad = 0.0;
  // Albedo times illuminance at normal incidence at the Moon, lux: the Sun's
  // and the Earth's (earthshine, eq 1).
  double sun_albedo_lux = 0.0;
  double earthshine_albedo_lux = 0.0;
  double sun_bs = 0.0;         // B(phi) S(phi)
  double earthshine_bs = 0.0;  // B(0) S(0): the Earth is at the observer, phase 0
  glm::dvec3 color_rgb{1.0};   // moon_color_rgb()
};
MoonDiscLighting moon_disc_lighting(double phase_rad, double observer_distance_m = kMoonMeanDistanceM,
                                    double sun_distance_au = 1.0,
                                    MoonCalibration calibration = MoonCalibration::kMagnitudeLaw);

// The outward normal of the lunar surface seen at disc position (x, y) (unit
// disc, x along `disc_right`, y along `disc_up`; both perpendicular to
// `to_observer` and to each other): x·right + y·up + sqrt(1 - x^2 - y^2)·to_observer
// (orthographic: the Moon subtends 0.5°, the hemisphere seen from 60 Earth
// radii is 0.3 % short of a half). Points outside the unit disc are pulled to the limb.
glm::dvec3 moon_disc_normal(const glm::dvec2& disc_xy, const glm::dvec3& to_observer, const glm::dvec3& disc_right,
                            const glm::dvec3& disc_up);

// Luminance of the lunar surface point with outward normal `normal`, lit by
// the Sun in direction `to_sun` (from the Moon) and by the Earth (earthshine,
// from `to_observer`), seen from `to_observer` (unit vectors, any frame):
// L = 2/(3 pi) [C_s E_s B(phi) S(phi) mu0 / (mu0 + mu) + C_e E_e B(0) S(0) / 2], cd/m^2,
// mu0 = n·to_sun, mu = n·to_observer. 0 where mu <= 0 (the far side); the
// sunlit term is 0 where mu0 <= 0 (beyond the terminator). No limb darkening.
double moon_disc_luminance(const MoonDiscLighting& lighting, const glm::dvec3& normal, const glm::dvec3& to_sun,
                           const glm::dvec3& to_observer);
// moon_disc_luminance · color_rgb: linear sRGB radiance, cd/m^2.
glm::dvec3 moon_disc_radiance_rgb(const MoonDiscLighting& lighting, const glm::dvec3& normal,
                                  const glm::dvec3& to_sun, const glm::dvec3& to_observer);

// The disc's radiance (linear sRGB, cd/m^2, outside the air) seen in
// direction `dir` for a Moon whose centre is in direction `centre`, of
// angular radius `angular_radius_rad`, lit from `to_sun` (Moon -> Sun): 0 off
// the disc (a hard edge). Vectors need not be unit. The double-precision
// reference the GLSL disc (shaders/night_sky/moon_disc.glsl) is tested against.
glm::dvec3 moon_disc_radiance_toward(const MoonDiscLighting& lighting, const glm::dvec3& centre,
                                     double angular_radius_rad, const glm::dvec3& to_sun, const glm::dvec3& dir);

}  // namespace atmo::core::night
