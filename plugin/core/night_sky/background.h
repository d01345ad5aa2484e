// background.h — the faint diffuse sky, so a moonless night is not black
// (Jensen et al. 2001 §6 and Fig. 2; constants from Leinert et al. 1998,
// "The 1997 reference of diffuse night sky brightness", A&AS 127, 1):
// airglow, zodiacal light, integrated starlight of the stars too faint for
// the catalogue (the Milky Way), diffuse galactic light and the
// extragalactic ("cosmic") light.
//
// Every function returns luminance in cd/m^2 (and linear sRGB radiance, D65
// white, with the stated colour of each component) OUTSIDE the atmosphere:
// the caller multiplies by the transmittance along the view ray (for the
// airglow, emitted at ~90 km, that is the transmittance of almost the whole
// air column). Directions are unit vectors in ICRS; the caller converts
// (the Sun's ICRS direction for the zodiacal light, the observer's local
// vertical in ICRS for the airglow). Surface brightness conversions are those
// of star_photometry.h (S10, mag/arcsec^2). Sources and figures: docs/NIGHT_SKY.md.
#pragma once

#include <glm/glm.hpp>

namespace atmo::core::night {

// --- Frames -----------------------------------------------------------------------

// Mean obliquity of the ecliptic at J2000, IAU 2006: 84381.406 arcsec.
constexpr double kObliquityJ2000Rad = 84381.406 / 3600.0 * 3.14159265358979323846 / 180.0;
// North ecliptic pole in ICRS (ICRS ~ mean equator and equinox of J2000; the
// 23 mas frame bias is far below what the zodiacal light needs).
glm::dvec3 ecliptic_pole_icrs();
// ICRS -> galactic rotation, IAU 1958 system in the Hipparcos definition (ESA
// 1997, vol. 1, §1.5.3, matrix A_G'): galactic = galactic_from_icrs() * icrs.
// North galactic pole at RA 192.85948°, Dec +27.12825°; l = 0 toward RA
// 266.40500°, Dec -28.93617° (the same matrix as ERFA's eraIcrs2g).
glm::dmat3 galactic_from_icrs();
// Galactic longitude l in [0, 2 pi) (x) and latitude b (y), radians.
glm::dvec2 galactic_lon_lat(const glm::dvec3& dir_icrs);

// --- Settings -----------------------------------------------------------------------

struct BackgroundSettings {
  // Airglow: zenith brightness of the emitting layer seen from the ground,
  // 145 S10 (V) at a dark site near solar minimum: the usual dark-sky budget
  // airglow 145 + zodiacal light 60 + scattered starlight ~15 = 220 S10 =
  // 21.9 mag/arcsec^2 (after Leinert et al. 1998; Benn & Ellison 1998 measure
  // V = 21.9 at the La Palma zenith at solar minimum, airglow : zodiacal light
  // = 2.5 : 1 at high ecliptic latitude). Up to ~2x at solar maximum.
  double airglow_zenith_s10 = 145.0;
  // Emitting layer: the visible airglow lines and continuum come from ~85–100 km
  // (OH 87 km, Na 90 km, O I 557.7 nm 97 km); one layer at 90 km, 10 km thick.
  // Jensen uses 80 km (text: "approximately 110 km").
  double airglow_layer_altitude_m = 90000.0;
  double airglow_layer_thickness_m = 10000.0;
  // Multiplies the zodiacal light (the fit is Leinert's Table 17; the
  // heliocentric-distance factor r^-2.3 and the ±10 % seasonal term are left out).
  double zodiacal_scale = 1.0;
  // Integrated starlight of the stars fainter than the catalogue (V > ~6),
  // S10 (V): pole + excess (1 + k cos b cos l) exp(-|sin b| / width) (cos b
  // cos l is the galactic x component, so the longitude term vanishes at the
  // poles where l is undefined). Anchors: ~30 S10 at the galactic pole and a
  // sky average of ~79 S10, the light of the stars 6 < V < 21 from
  // cumulative star counts (approximate, docs/NIGHT_SKY.md); the excess gives
  // ~230 S10 averaged along the plane, the inner Galaxy (l = 0) 3x the
  // anticentre. A coarse shape: no dust lanes, no Magellanic Clouds.
  double starlight_pole_s10 = 28.0;
  double starlight_plane_excess_s10 = 200.0;
  double starlight_width_sin_b = 0.26;  // ~15° half width (1/e)
  double starlight_longitude_contrast = 0.5;
  // Diffuse galactic light (starlight scattered by interstellar dust): a
  // fraction of the integrated starlight, Jensen's Fig. 2 ratio 9.1e-9 / 3.0e-8.
  double diffuse_galactic_fraction = 0.30;
  // Extragalactic background light, S10 (V): of order 1 (an optical
  // extragalactic background of ~10 nW m^-2 sr^-1 in nu I_nu is ~1.4 S10;
  // Jensen's Fig. 2 ratio cosmic / integrated starlight = 0.03 gives ~1).
  double cosmic_s10 = 1.0;
};

// --- Components ---------------------------------------------------------------------

// Slant factor of the airglow shell along a ray of direction cosine
// `cos_zenith` (to the local vertical) from an eye at `eye_altitude_m` above
// a sphere of `planet_radius_m`: the path length through the emitting shell
// (layer altitude ± thickness/2) before the ray meets the ground, over the
// shell's thickness. 1 at the zenith from the ground; toward the horizon it
// follows van Rhijn, 1 / sqrt(1 - (R/(R+h))^2 sin^2 z) (6.0 at the horizon
// for h = 90 km), capped by the shell's finite thickness; 0 for rays that hit
// the ground first; 2 crossings for an eye above the layer looking down
// through it. Continuous in the eye's altitude (no jump when climbing through
// the layer). Altitudes below 0 count as 0.
double airglow_slant_factor(double cos_zenith, double eye_altitude_m, double planet_radius_m,
                            const BackgroundSettings& settings = {});
double airglow_luminance(double cos_zenith, double eye_altitude_m, double planet_radius_m,
                         const BackgroundSettings& settings = {});

// Zodiacal light, cd/m^2, an analytic fit (docs/NIGHT_SKY.md) to Leinert et
// al. 1998 Table 17 as a function of the elongation from the Sun eps and the
// ecliptic latitude beta, in the table's units (1e-8 W m^-2 sr^-1 um^-1 at 500 nm):
//   I = -44.76 + (149.85 (eps/90°)^-2.459 + 171.0) exp(-(|sin beta| / (1.0635 eps/90°))^0.7259)
//       + 67.28 exp(-((180° - eps) / 36.28°)^2)
// (eps clamped to >= 2°), converted with Leinert's 1 S10 = 1.28 table units.
// Within 14 % of the table for eps >= 40° and 21 % everywhere it is tabulated
// (eps >= 15°); 61 S10 at the ecliptic pole (Leinert: 60), 216 S10 at 90°
// from the Sun on the ecliptic, the Gegenschein 172 S10 at the antisolar point.
double zodiacal_s10(double elongation_rad, double ecliptic_latitude_rad);
double zodiacal_luminance(const glm::dvec3& dir_icrs, const glm::dvec3& sun_icrs,
                          const BackgroundSettings& settings = {});

// Integrated starlight (the Milky Way), cd/m^2, of the stars fainter than the catalogue.
double starlight_s10(double galactic_lon_rad, double galactic_lat_rad, const BackgroundSettings& settings = {});
double starlight_luminance(const glm::dvec3& dir_icrs, const BackgroundSettings& settings = {});

// Colours, linear sRGB normalised to luminance 1:
// airglow: the spectrum of the O I 557.7 nm (250 R), Na D 589.3 nm (50 R)
// and O I 630.0 nm (100 R) lines (typical mid-latitude intensities, after Roach &
// Gordon 1973 and Leinert et al. 1998; each varies by 2x with season and hour) plus a continuum flat in energy that makes up
// the rest of the default zenith brightness, through the CIE 1931 observer;
glm::dvec3 airglow_color_rgb();
// zodiacal light: scattered sunlight, the project's solar spectrum (its
// slight reddening, ~+0.1 in B−V, is left out);
glm::dvec3 zodiacal_color_rgb();
// integrated starlight, diffuse galactic and extragalactic light: a black
// body at the Ballesteros temperature of B−V = 0.8 (~5100 K), about the
// integrated colour of the old disc population (a G8–K0 star).
glm::dvec3 starlight_color_rgb();
constexpr double kStarlightBV = 0.8;

// --- Everything together ------------------------------------------------------------

struct BackgroundLuminance {
  double airglow = 0.0;  // cd/m^2, outside the atmosphere
  double zodiacal = 0.0;
  double starlight = 0.0;
  double diffuse_galactic = 0.0;
  double cosmic = 0.0;
  double total() const { return airglow + zodiacal + starlight + diffuse_galactic + cosmic; }
  // Linear sRGB radiance, cd/m^2, each component with its colour.
  glm::dvec3 rgb() const;
};

// The background in direction `dir_icrs`, for an observer whose local
// vertical is `zenith_icrs` at `eye_altitude_m` on a sphere of
// `planet_radius_m`, with the Sun in direction `sun_icrs`.
BackgroundLuminance night_background(const glm::dvec3& dir_icrs, const glm::dvec3& sun_icrs,
                                     const glm::dvec3& zenith_icrs, double eye_altitude_m,
                                     double planet_radius_m = 6371000.0, const BackgroundSettings& settings = {});

}  // namespace atmo::core::night
