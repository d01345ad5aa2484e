// star_photometry.h — point sources of the night sky: illuminance from a V
// magnitude, colour from B−V, the sub-pixel-stable footprint a star is drawn
// with, and the limiting magnitude below which a star cannot change a pixel
// (the cull that makes the night passes free in daylight).
//
// Units: illuminance in lux on a surface normal to the source, OUTSIDE the
// atmosphere (the caller multiplies by the transmittance along the line of
// sight); radiance in cd/m^2; colours in linear sRGB / Rec.709 primaries with
// the D65 white, normalised to luminance 1 (Y = 0.2126 R + 0.7152 G +
// 0.0722 B), so a star's RGB illuminance is E_v · rgb. Angles in radians.
// Formulas, sources and measured figures: docs/NIGHT_SKY.md.
#pragma once

#include <glm/glm.hpp>

namespace atmo::core::night {

// --- Magnitudes and photometric units -----------------------------------------------

// Illuminance of a V = 0 source outside the atmosphere, lux: the commonly
// quoted 2.54e-6 lx (after Allen, "Astrophysical Quantities"), i.e.
// V = -13.99 - 2.5 log10(E / lux). Cross-checks (tested): the Sun (V = -26.74)
// gives 126 klx, 0.7 % above the project's solar spectrum through the CIE
// observer (125 klx); Schaefer (1990) writes m = -16.57 - 2.5 log10(I / foot-candle),
// the same zero point to 0.2 % (2.535e-6 lx).
constexpr double kVZeroPointLux = 2.54e-6;

// Solid angle of one square arcsecond, sr: (pi / 648000)^2.
constexpr double kSquareArcsecondSr = 2.350443053909789e-11;
// Solid angle of one square degree, sr: (pi / 180)^2.
constexpr double kSquareDegreeSr = 3.046174197867086e-4;

// E_v = E0 · 10^(-0.4 V), lux.
double illuminance_from_magnitude(double v_magnitude);
// Inverse: V = -2.5 log10(E / E0). E <= 0 gives +infinity.
double magnitude_from_illuminance(double lux);

// Jensen et al. 2001 eq 6: irradiance E_s = 10^(0.4(-V - 19)) W/m^2 (for the
// comparison in the docs; the renderer works in lux). Eq 7 adds the 0.4 mag
// of extinction back: extra_atmospheric = true multiplies by 10^(0.16).
double jensen_irradiance_w_m2(double v_magnitude, bool extra_atmospheric = false);

// Surface brightness: a source of S mag/arcsec^2 has luminance
// L = E0 · 10^(-0.4 S) / (1 arcsec^2) = 1.0807e5 · 10^(-0.4 S) cd/m^2.
double luminance_from_mag_per_arcsec2(double s);
double mag_per_arcsec2_from_luminance(double cd_m2);
// S10 (V): the brightness of one V = 10 star per square degree
// = 27.78 mag/arcsec^2 = 8.34e-7 cd/m^2.
double luminance_from_s10(double s10);
double s10_from_luminance(double cd_m2);

// --- Colour ---------------------------------------------------------------------

// Luminance of a linear sRGB triple: the Y row of the inverse of the project's
// linear_srgb_from_xyz (0.2126, 0.7152, 0.0722).
double rgb_luminance(const glm::dvec3& linear_srgb);

// B−V is clamped to [kMinBV, kMaxBV] before conversion: -0.4 is bluer than
// the hottest O stars' intrinsic colour (about -0.33) and keeps away from the
// poles of both temperature formulas (Ballesteros at B−V = -0.674, Jensen at
// -0.56); 2.0 covers the red giants and supergiants (Betelgeuse 1.85, Antares
// 1.83); redder catalogue values are carbon stars or heavily reddened stars
// whose spectra are no black bodies at all, so a 3180 K black body is as good
// a colour as any.
constexpr double kMinBV = -0.4;
constexpr double kMaxBV = 2.0;

// Ballesteros (2012), EPL 97, 34008, eq 14:
// T = 4600 K · (1 / (0.92 (B−V) + 1.7) + 1 / (0.92 (B−V) + 0.62)). B−V clamped.
double temperature_from_bv_ballesteros(double b_minus_v);
// Jensen et al. 2001 eq 8: T = 7000 K / (B−V + 0.56), for comparison. B−V clamped.
double temperature_from_bv_jensen(double b_minus_v);

// A black body of `kelvin` (Planck's law, 360–830 nm every 5 nm) through the
// project's CIE 1931 2° observer (core/spectral/colorimetry) to linear sRGB
// (D65 white), normalised to luminance 1. Negative components (outside the
// sRGB gamut; none for 3000–40000 K) would be clamped to 0 and the result
// renormalised.
glm::dvec3 blackbody_rgb(double kelvin);
// blackbody_rgb(temperature_from_bv_ballesteros(b_minus_v)).
glm::dvec3 star_rgb_from_bv(double b_minus_v);
// The largest channel of star_rgb_from_bv over the clamped B−V range (1.88,
// the blue channel of the hottest stars): a star of illuminance E adds
// at most E · this to any channel; the cull below uses it to stay conservative.
double star_max_channel_factor();

// --- Footprint: how a star is drawn -------------------------------------------------

// A star is drawn as a Gaussian of standard deviation kStarFootprintSigmaPx
// pixels whose integral is the star's illuminance. Each pixel receives the
// Gaussian integrated over its square (a product of two erf differences), so
// the sum over all pixels is exactly 1 whatever the sub-pixel position of the
// star: its brightness does not flicker when the camera turns slowly. 0.7 px
// keeps the star compact (27.6 % of its light in the central pixel when
// centred on it; 17.9 % in each of four pixels when on their common corner)
// while the pixel-integrated weights vary smoothly with position.
constexpr double kStarFootprintSigmaPx = 0.7;
// Pixels whose centres lie within this many pixels of the star (per axis)
// must be drawn: truncation loses < 0.3 % of the light (tested).
constexpr int kStarFootprintRadiusPx = 3;

// erf(x) by Abramowitz & Stegun 7.1.26 (|error| < 1.5e-7): the formula a GLSL
// shader (which has no erf) uses, so the CPU and the GPU draw the same weights.
double erf_approx(double x);
// Fraction of the star's light that falls in the pixel whose centre is at
// (dx, dy) pixels from the star's centre.
double star_footprint_weight(double dx, double dy, double sigma_px = kStarFootprintSigmaPx);
// The largest weight a pixel can receive: star_footprint_weight(0, 0, sigma).
double star_footprint_peak(double sigma_px = kStarFootprintSigmaPx);

// Solid angle of a pixel of a perspective camera, sr: with a vertical field
// of view 2·atan(tan_half_fov_y) over `viewport_height_px` square pixels, a
// pixel at the image centre subtends (2 tan_half_fov_y / H)^2; off axis (angle
// theta from the optical axis) the solid angle shrinks as cos^3 theta.
double pixel_solid_angle_sr(double tan_half_fov_y, double viewport_height_px, double cos_off_axis = 1.0);
// A star of illuminance E (lux) drawn into a pixel of solid angle omega:
// the luminance the pixel would have if the whole star fell in it, E / omega,
// cd/m^2. The drawn pixel gets this times star_footprint_weight.
double star_pixel_luminance(double illuminance_lux, double pixel_solid_angle_sr);

// --- The limiting-visibility cull -------------------------------------------------

// The display threshold a star must exceed to be drawn.
struct DisplayThreshold {
  enum class Kind {
    kEncodedSdr,  // `step` in the display-encoded value of the project's output
                  // (encode_display_srgb of shaders/atmosphere/functions.glsl:
                  // the filmic curve then the sRGB transfer), e.g. 1/255
    kLinear,      // `step` in linear exposed units (an HDR output's threshold)
  };
  Kind kind = Kind::kEncodedSdr;
  double step = 1.0 / 255.0;
};

// The faintest V magnitude (outside the atmosphere) that can change a pixel
// by at least the threshold. Physically: the star adds to the pixel
// dL = E · transmittance · max_channel · footprint_peak / omega (cd/m^2) on
// top of the sky behind it, `background_cd_m2`; the output is
// exposure · (L_background + dL) (exposure: output units per cd/m^2). The
// smallest dL that moves the output by `threshold` is found on the display
// curve (bisection; for kLinear it is step / exposure), and V_lim is the
// magnitude of E = dL · omega / (transmittance · max_channel · peak).
// Returns -infinity when no star can change the pixel (the output is
// saturated): draw nothing. transmittance = 1 is the conservative choice for
// a whole-pass decision (the atmosphere only dims); the default max_channel
// is star_max_channel_factor().
double display_limiting_magnitude(double background_cd_m2, double exposure, double pixel_solid_angle_sr,
                                  const DisplayThreshold& threshold = {}, double transmittance = 1.0,
                                  double max_channel = -1.0, double sigma_px = kStarFootprintSigmaPx);

// Optional perceptual cut: the naked-eye limiting magnitude against a sky of
// luminance `background_cd_m2`, Schaefer (1990, PASP 102, 212) after Hecht
// (1947) and Garstang (1986): threshold illuminance I = c1 (1 + sqrt(c2 B))^2
// with B in nanolamberts and I in foot-candles; night (rods)
// c1 = 10^-9.8, c2 = 10^-1.9; day (cones) c1 = 10^-8.35, c2 = 10^-5.9; the
// eye uses the more sensitive of the two (Schaefer switches at 1479 nL; the
// minimum differs from the switch by < 0.1 mag and has no jump);
// m = -16.57 - 2.5 log10(I). observer_factor multiplies I (Schaefer's
// F: > 1 for an inexperienced or older observer; 1 = his standard observer).
// The result is the magnitude seen by the eye, so the caller adds the star's
// extinction before comparing.
double naked_eye_limiting_magnitude(double background_cd_m2, double observer_factor = 1.0);

}  // namespace atmo::core::night
