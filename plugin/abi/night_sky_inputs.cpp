#include "abi/night_sky_inputs.h"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "core/astro/observer.h"
#include "core/astro/star_catalog.h"
#include "core/astro/time_scales.h"
#include "core/night_sky/moon_photometry.h"
#include "core/night_sky/night_sky_twin.h"
#include "core/night_sky/star_photometry.h"

namespace atmo::embedded_data {
std::string_view find(std::string_view path);
}

namespace atmo::abi {

namespace {
constexpr const char* kCatalogPath = "stars/hipparcos_v6_6.tsv";

// The solid angle of the pixel at the image centre, from the host's projection.
double centre_pixel_solid_angle_sr(const AtmoViewState& state) {
  const double p11 = std::abs(state.clip_from_view[5]);  // column 1, row 1: 1 / tan(fov_y / 2)
  const double tan_half = p11 > 0.0 ? 1.0 / p11 : 1.0;
  return core::night::pixel_solid_angle_sr(tan_half, static_cast<double>(state.viewport[3]));
}
}  // namespace

const core::night::NightPlan& plan_night_sky(AtmoContext_T* c, AtmoView_T& view, const core::Scene& scene,
                                             const gl::PassInputs& inputs) {
  core::night::NightPlanInputs in;
  in.exposure = inputs.exposure;
  in.display_encoded = inputs.output_encoding == ATMO_OUTPUT_DISPLAY_SRGB;
  in.pixel_solid_angle_sr = centre_pixel_solid_angle_sr(view.state);
  in.method_has_sky_view = inputs.method != gl::SkyMethod::kMarch;
  view.night_plan = core::night::plan_night_sky(scene, c->transmittance, c->multiple_scattering, in);
  return view.night_plan;
}

void add_night_terms(AtmoContext_T* c, AtmoView_T& view, const core::Scene& scene, gl::PassInputs* inputs) {
  const core::night::NightPlan& plan = view.night_plan;
  const core::SkyBodies& b = scene.bodies;
  gl::NightTerms& night = inputs->night;
  night = gl::NightTerms{};
  night.moonlit_sky = plan.moonlit_sky;
  night.moon_disc = plan.moon_disc;
  night.moon_direction_enu = glm::vec3(b.moon_enu);
  const double tan_half = 1.0 / std::max(std::abs(view.state.clip_from_view[5]), 1e-12);
  night.pixel_angle_rad = static_cast<float>(2.0 * tan_half / static_cast<double>(view.state.viewport[3]));
  if (plan.moonlit_sky) night.moonlit_atmosphere = core::night::moonlit_atmosphere(scene.atmosphere, b);
  if (plan.moon_disc) {
    // The Sun as seen from the Moon, from both bodies' positions relative to the eye (geometric, unrefracted).
    constexpr double kAuM = 149597870700.0;
    const glm::dvec3 moon_to_sun = core::night::moon_to_sun_direction(
        b.sun_enu_unrefracted, b.sun_distance_au * kAuM, b.moon_enu_unrefracted, b.moon_distance_m);
    const core::night::MoonDiscLighting lighting =
        core::night::moon_disc_lighting(b.moon_phase_angle_rad, b.moon_distance_m, b.moon_sun_distance_au);
    night.moon = core::night::make_moon_disc(b.moon_enu, b.moon_angular_radius_rad, moon_to_sun,
                                             lighting);
  }
  if (plan.background) {
    std::string error;
    const core::astro::AstrometryFrame* frame = view_astrometry(c, view, &error);
    if (frame) {
      // ICRS ~ CIRS for the diffuse background: they differ by the precession-nutation since J2000 (0.35° in
      // 2024), far below the background's structure (the Milky Way's 15° width, the zodiacal light's 10s of degrees).
      const glm::dmat3 cirs_from_enu = glm::transpose(frame->enu_from_cirs());
      night.sky_background = core::night::make_night_background(cirs_from_enu, cirs_from_enu * b.sun_enu_unrefracted,
                                                                scene.eye_altitude_m,
                                                                static_cast<double>(scene.atmosphere.bottom_radius_m),
                                                                core::night::BackgroundSettings{});
      night.background = true;
    }
  }
}

void light_haze_by_the_moon(const AtmoView_T& view, const core::Scene& scene, gl::PassInputs* inputs) {
  if (!view.night_plan.moon_lights_haze() || inputs->method == gl::SkyMethod::kMarch) return;
  inputs->atmosphere = core::night::moonlit_atmosphere(scene.atmosphere, scene.bodies);
  inputs->sun_direction_enu = glm::vec3(scene.bodies.moon_enu);
}

const core::astro::AstrometryFrame* view_astrometry(AtmoContext_T* c, AtmoView_T& view, std::string* error) {
  if (view.astrometry && view.astrometry_utc_posix_s == c->utc_posix_s && view.astrometry_dut1_s == c->dut1_s &&
      view.astrometry_eye_ecef_m == view.eye.eye_ecef_m) {
    return &*view.astrometry;
  }
  view.astrometry.reset();
  core::astro::TimeScaleOptions time_options;
  time_options.dut1_s = c->dut1_s;
  std::optional<core::astro::TimeScales> time = core::astro::time_scales_from_posix(c->utc_posix_s, time_options, error);
  if (!time) return nullptr;
  const core::Geodetic& g = view.eye.eye;
  std::optional<core::astro::Observer> observer =
      core::astro::observer_from_geodetic(g.latitude_deg, g.longitude_deg, g.height_m, error);
  if (!observer) return nullptr;
  view.astrometry = core::astro::AstrometryFrame::create(*time, *observer, {}, error);
  if (!view.astrometry) return nullptr;
  view.astrometry_utc_posix_s = c->utc_posix_s;
  view.astrometry_dut1_s = c->dut1_s;
  view.astrometry_eye_ecef_m = view.eye.eye_ecef_m;
  return &*view.astrometry;
}

bool night_points_invisible(const AtmoContext_T* c, const core::night::NightPlan& plan) {
  if (!plan.points) return true;
  if (plan.limiting_magnitude >= core::night::kBrightestStarMagnitude) return false;
  // The Sun moves 0.25° a minute: the planets' own skies change little in that time.
  constexpr double kDaylightPlanetCheckS = 60.0;
  return c->have_daylight_planet_check && !c->daylight_planet_visible &&
         std::abs(c->utc_posix_s - c->daylight_planet_check_utc_posix_s) <= kDaylightPlanetCheckS;
}

bool collect_night_points(AtmoContext_T* c, AtmoView_T& view, const core::Scene& scene, std::string* error) {
  view.night_points.clear();
  const core::astro::AstrometryFrame* frame = view_astrometry(c, view, error);
  if (!frame) return false;
  if (!c->star_field) {
    const std::string_view text = embedded_data::find(kCatalogPath);
    core::astro::StarCatalogLoad load = core::astro::parse_star_catalog(text, kCatalogPath);
    if (text.empty()) load.error = std::string("the embedded star catalogue ") + kCatalogPath + " is missing";
    if (!load.error.empty() || load.stars.empty()) {
      c->star_field_error = load.error.empty() ? std::string("the star catalogue is empty") : load.error;
      c->services.log(ATMO_LOG_ERROR, "atmo: night sky: " + c->star_field_error + "; drawing the planets only");
      load.stars.clear();
    }
    c->star_field = std::make_unique<core::night::StarField>(load.stars);  // empty: the planets alone
  }
  core::night::PointSourceCut cut;
  cut.limiting_magnitude = view.night_plan.limiting_magnitude;
  cut.earth_radius_m = static_cast<double>(scene.atmosphere.bottom_radius_m);
  core::night::visible_point_sources(*c->star_field, *frame, cut, nullptr, &view.night_points);
  const core::night::NightPlan& plan = view.night_plan;
  if (plan.limiting_magnitude < core::night::kBrightestStarMagnitude) {
    // Daylight: only planets passed the darkest-sky limit. Each is kept only if it can change a pixel of the sky
    // in its own direction (Venus near the Sun is lost in the aureole), the sky from the CPU twin's march.
    const twin::Lut2D& t = c->transmittance;
    const twin::Lut2D& ms = c->multiple_scattering;
    bool any = false;
    auto hidden = [&](const core::night::PointSource& p) {
      const glm::vec3 sky = twin::sky_radiance(scene.atmosphere, t, glm::vec2(t.width, t.height), ms,
                                               glm::vec2(ms.width, ms.height),
                                               static_cast<float>(std::max(scene.eye_altitude_m, 1.0)),
                                               p.direction_enu, glm::vec3(scene.sun_direction_enu), 16);
      const double local = 0.7 * core::night::rgb_luminance(glm::dvec3(sky));  // erring dark, as the plan
      const bool invisible = double(p.v_mag) > core::night::point_limiting_magnitude(local, plan.inputs);
      any = any || !invisible;
      return invisible;
    };
    view.night_points.erase(std::remove_if(view.night_points.begin(), view.night_points.end(), hidden),
                            view.night_points.end());
    c->have_daylight_planet_check = true;
    c->daylight_planet_visible = any;
    c->daylight_planet_check_utc_posix_s = c->utc_posix_s;
  }
  return true;
}

}  // namespace atmo::abi
