// night_plan.h — what of the night sky can be seen in a view this frame, so
// the passes draw only that: the faintest star that can change a pixel (the
// stars and planets), and whether the Moon's disc, the moonlit sky and the
// faint background (airglow, zodiacal light, Milky Way) can change the
// output at all. Pure (no GL); one decision per frame and view, from the
// scene, the exposure and the output encoding. docs/NIGHT_SKY.md, "What is
// drawn when".
//
// Every decision compares an upper bound of what a term adds to a pixel with
// the smallest increase the output can show on the darkest sky in view
// (estimated erring dark), so a term is skipped only where it is invisible; the stars' limit
// comes from display_limiting_magnitude against an estimate of the darkest
// sky in view that errs dark (more stars than visible are drawn, never fewer).
// As the sky darkens these limits move continuously: stars and the
// background fade in by physics and exposure, not by a switch.
#pragma once

#include "core/scene/scene.h"
#include "core/atmosphere/shader_twin.h"
#include "core/night_sky/background.h"

namespace atmo::core::night {

// The brightest point source the sky can hold: Venus at its greatest
// brilliancy, V = -4.9 (Jupiter -2.9). A limiting magnitude brighter than
// this means no point source can be seen.
constexpr double kBrightestPointSourceMagnitude = -4.9;
// The brightest star, Sirius (V = -1.46; the catalogue's brightest): a
// limiting magnitude brighter than this leaves the planets alone, and the
// plugin then decides from the brightest planet's magnitude (cached) before
// any astrometry is done.
constexpr double kBrightestStarMagnitude = -1.46;

// Its smallest, for the darkest-sky estimate: the airglow at the zenith alone
// (145 S10), through a transmittance of 0.5.
constexpr double kBackgroundMinLuminance = 0.5 * 145.0 * 8.338e-7;

// Upper bound of the moonlit sky's radiance per lux of moonlight, 1/sr: the
// sun's sky-view table reaches ~0.05/sr away from the light in clear air and
// ~0.5/sr in the aureole of hazy air (forward Mie peak); 1/sr bounds both.
constexpr double kMoonlitSkyMaxRadiancePerLux = 1.0;

struct NightPlanInputs {
  double exposure = 1.0;               // output units per cd/m^2
  bool display_encoded = true;         // ATMO_OUTPUT_DISPLAY_SRGB (else LINEAR_HDR)
  double pixel_solid_angle_sr = 1e-6;  // at the image centre
  bool method_has_sky_view = true;     // LUT / ANALYTIC: a moonlit sky-view table can be built
};

// The faintest point source (V) that can change a pixel of a background of
// background_cd_m2 at this exposure and encoding (DISPLAY_SRGB: one display
// step; LINEAR_HDR: visible_increase_cd_m2): display_limiting_magnitude with
// the plan's thresholds. -inf where nothing can show.
double point_limiting_magnitude(double background_cd_m2, const NightPlanInputs& inputs);

struct NightPlan {
  // The smallest output increase that can be seen on black, in exposed
  // linear units (x exposure x cd/m^2): half a display step (0.5/255 through
  // encode_display_srgb), or 1e-4 for a linear HDR target.
  double visible_step_linear = 0.0;
  // The smallest increase (cd/m^2) visible on the darkest sky the Sun leaves
  // in view: what the Moon, moonlit-sky and background bounds are compared with.
  double visible_increase_cd_m2 = 0.0;
  // Estimate of the darkest sky in view (cd/m^2): 0.3 x the zenith's (sun and
  // Moon lit, from the CPU twin's march) plus the background's smallest value.
  double darkest_sky_cd_m2 = 0.0;
  // display_limiting_magnitude against darkest_sky_cd_m2; -inf: nothing.
  double limiting_magnitude = 0.0;
  bool points = false;        // stars and planets: limiting_magnitude >= kBrightestPointSourceMagnitude
  bool moon_disc = false;     // the Moon's disc (above the horizon cut, bright enough)
  bool moonlit_sky = false;   // the sky lit by the Moon (needs a sky-view table method)
  bool background = false;    // airglow, zodiacal light, integrated starlight
  // The Moon above the horizon cut (refracted elevation > -(dip + 0.5°)).
  bool moon_up = false;
  // The zenith's luminance lit by the Sun and by the Moon (cd/m^2, the CPU
  // twin's march; the Moon's only when moonlit_sky). When the Moon's is the
  // larger, the haze over the host's geometry (the aerial-perspective volume)
  // is lit by the Moon instead of the Sun: at night the Sun lights nothing
  // near the ground, and one light keeps the volume's cost.
  double sun_zenith_cd_m2 = 0.0;
  double moon_zenith_cd_m2 = 0.0;
  NightPlanInputs inputs;  // what the plan was made for (the point pass checks planets against their own sky)
  bool moon_lights_haze() const { return moonlit_sky && moon_zenith_cd_m2 > sun_zenith_cd_m2; }
};

// The visible step of the output on black, exposed linear units.
double visible_step_linear(bool display_encoded);
// The smallest increase (cd/m^2) visible on a background of background_cd_m2:
// DISPLAY_SRGB half a display step above the background's encoded value
// (infinite where the display is saturated); LINEAR_HDR the larger of
// visible_step_linear / exposure and 0.5 % of the background (half the
// eye's ~1 % daylight contrast threshold).
double visible_increase_cd_m2(double background_cd_m2, double exposure, bool display_encoded);

// `transmittance` and `multiple_scattering` are the context's tables (the
// darkest-sky estimate marches the zenith on the CPU twin, 16 steps, for
// the Sun and the Moon; not benchmarked on its own).
NightPlan plan_night_sky(const Scene& scene, const twin::Lut2D& transmittance, const twin::Lut2D& multiple_scattering,
                         const NightPlanInputs& inputs);

// The atmosphere with the Moon in the Sun's place: its illuminance outside
// the air (linear sRGB lux) as the light, its angular radius for the disc.
// The sky-view table built with it is the moonlit sky.
twin::AtmosphereParameters moonlit_atmosphere(const twin::AtmosphereParameters& atmosphere, const SkyBodies& bodies);

}  // namespace atmo::core::night
