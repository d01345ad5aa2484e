// runway_fog_night: the fog and glow luminance of the real render (`atmo render
// config/scenarios/runway_fog_night.json`, the EXR of linear cd/m^2 that
// render_scenario_runway_fog_night writes) against the independent reference of
// tools/fog_reference, recomputed here from the scenario's own inputs:
// - the lights the render passed to set_lights (atmo::render::light_points_of:
//   the runway's generated approach, threshold and edge lights with their cones,
//   and the file's two lamp posts), luminance-weighted by their colours;
// - the fog the render passed to set_fog (atmo::render::fog_state_of), its
//   extinction from the visibility by the plugin's own fog::extinction_from_visibility,
//   the plugin's default albedo and phase asymmetry, a slab from the ground to the top;
// - each pixel's view ray from the camera the render used (view_setup_of, the
//   host scene's view and projection matrices), ending on the host's terrain.
// Reference = single scattering by adaptive quadrature (every light) + the
// Monte Carlo's orders >= 2 (every light, fixed seeds), with the Monte Carlo's
// standard error in the tolerance. The render holds the lights' points too
// (ATMO_PASS_LIGHT_POINTS, each light's direct image, not scattered light): they
// are drawn alone here (light_points_only.h) and taken off the render first.
// Which pixels, why, and the measured figures: docs/FOG.md, "The runway
// scenario against the reference".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmo_host_scene/camera.h"
#include "atmo_host_scene/terrain.h"
#include "atmo_scenario/scenario.h"
#include "atmo_support/image.h"
#include "atmo_support/image_metrics.h"
#include "core/fog/fog_model.h"
#include "fog_reference.h"
#include "light_points_only.h"
#include "scenario_setup.h"

namespace fr = atmo::fog_reference;
namespace hs = atmo::host_scene;
namespace sc = atmo::scenario;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The scene as the render saw it, in the ENU frame at the eye (z up there: the plugin takes heights in the
// tangent plane at the eye), and the rendered image.
struct Scene {
  sc::Scenario scenario;
  hs::ViewSetup setup;
  hs::Geodetic eye;
  fr::Medium medium;
  std::vector<fr::Light> lights;  // intensity = cd x luminance of the colour
  std::vector<int> lamp_posts;    // indices in `lights` of the file's own points
  atmo::support::Image image;
  atmo::support::Image points;  // the lights' points alone (ATMO_PASS_LIGHT_POINTS), as the render drew them
  std::unique_ptr<hs::Terrain> terrain;
  double glow_threshold = 0;  // cd/m^2: what atmo render passes to set_lights, 1 / (2000 x the exposure scale)

  // A point of the scenario's ENU frame in the eye's ENU frame.
  glm::dvec3 to_eye(const glm::dvec3& enu) const {
    return hs::enu_from_geodetic(eye, hs::geodetic_from_enu(setup.world_origin, enu));
  }
  // Unit view direction (scenario ENU) through the centre of pixel (x, y), row 0 the top, by the inverse of
  // the host's projection and view matrices.
  glm::dvec3 pixel_direction(double x, double y) const {
    const double ndc_x = 2.0 * (x + 0.5) / setup.viewport[2] - 1.0;
    const double ndc_y = 1.0 - 2.0 * (y + 0.5) / setup.viewport[3];
    const glm::dmat4 world_from_clip = glm::inverse(hs::clip_from_view(setup) * hs::view_from_enu(setup));
    const glm::dvec4 p = world_from_clip * glm::dvec4(ndc_x, ndc_y, 0.5, 1.0);
    return glm::normalize(glm::dvec3(p) / p.w - setup.pose.position_enu_m);
  }
  // Where the ray from the eye along `dir` (scenario ENU) meets the host's terrain (its height minus the
  // curvature drop, as terrain.cpp builds it), m; infinity if not within the far plane.
  double ground_distance(const glm::dvec3& dir) const {
    auto above = [&](double t) {
      const glm::dvec3 p = setup.pose.position_enu_m + t * dir;
      return p.z - (terrain->height_at(p.x, p.y) - hs::curvature_drop_m(p.x, p.y));
    };
    double lo = 0.0, hi = 1.0;
    while (above(hi) > 0.0) {
      lo = hi;
      hi *= 1.5;
      if (hi > setup.far_m) return std::numeric_limits<double>::infinity();
    }
    for (int i = 0; i < 60; ++i) (above(0.5 * (lo + hi)) > 0.0 ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi);
  }
  // The pixel (x right, y down, fractional) where a scenario-ENU point projects.
  glm::dvec2 project(const glm::dvec3& enu) const {
    const glm::dvec4 c = hs::clip_from_view(setup) * hs::view_from_enu(setup) * glm::dvec4(enu, 1.0);
    return {(0.5 * c.x / c.w + 0.5) * setup.viewport[2] - 0.5, (0.5 - 0.5 * c.y / c.w) * setup.viewport[3] - 0.5};
  }
  // The render's scattered light at a pixel: the render less the lights' own points.
  double rendered(int x, int y) const {
    return atmo::support::luminance(image.pixel(x, y)) - atmo::support::luminance(points.pixel(x, y));
  }
  double point(int x, int y) const { return atmo::support::luminance(points.pixel(x, y)); }
};

const Scene& scene() {
  static Scene* s = [] {
    auto* s = new Scene;
    sc::LoadResult loaded = sc::load_scenario_file(ATMO_RUNWAY_FOG_NIGHT_JSON);
    if (!loaded.scenario) throw std::runtime_error(loaded.error);
    s->scenario = *loaded.scenario;
    // The render's own depth convention (the other two are compared with it by depth_*_matches_*).
    s->setup = atmo::render::view_setup_of(s->scenario, 0, hs::DepthConvention::Reversed);
    s->eye = hs::eye_geodetic(s->setup);
    s->terrain = std::make_unique<hs::Terrain>(atmo::render::terrain_of(s->scenario));

    const AtmoFogState fog = atmo::render::fog_state_of(s->scenario);
    s->medium.extinction_per_m = atmo::fog::extinction_from_visibility(fog.visibility_m);
    s->medium.albedo = atmo::fog::kFogAlbedo;  // AtmoFogState.single_scattering_albedo 0: the default
    s->medium.hg_g = atmo::fog::kFogPhaseG;    // AtmoFogState.phase_asymmetry 0: the default
    s->medium.top_m = fog.top_height_m - s->eye.height_m;
    // The fog lies on the ground (flat terrain, the datum's height under the eye to ~0.01 m): a path that
    // reaches it is lost (black ground), as the plugin's diffusion term's boundary assumes.
    s->medium.bottom_m = s->scenario.location.height_m + s->terrain->height_at(0, 0) - s->eye.height_m;

    const std::vector<AtmoLightPoint> points = atmo::render::light_points_of(s->scenario, *s->terrain);
    const size_t own = s->scenario.lights ? s->scenario.lights->points.size() : 0;
    for (size_t i = 0; i < points.size(); ++i) {
      const AtmoLightPoint& p = points[i];
      const float color[3] = {float(p.color[0]), float(p.color[1]), float(p.color[2])};
      const glm::dvec3 at(p.position_m[0], p.position_m[1], p.position_m[2]);
      fr::Light l;
      l.position_m = s->to_eye(at);
      l.intensity = p.intensity_cd * atmo::support::luminance(color);
      if (p.cone_outer_rad > 0.0) {  // atmo.h: cone_outer_rad = 0 is omnidirectional
        const glm::dvec3 axis(p.direction[0], p.direction[1], p.direction[2]);
        l.axis = s->to_eye(at + glm::normalize(axis)) - l.position_m;
        l.cos_inner = std::cos(p.cone_inner_rad);
        l.cos_outer = std::cos(p.cone_outer_rad);
      }
      if (i + own >= points.size()) s->lamp_posts.push_back(static_cast<int>(s->lights.size()));
      s->lights.push_back(l);
    }
    // atmo render's glow threshold, 1/2000 of the camera's white at its EV100 (the camera's own, else the
    // scenario's; this scenario gives one, so the automatic exposure from the Sun is not needed).
    const std::optional<double> ev100 = atmo::render::set_exposure_ev100_of(s->scenario, 0);
    if (!ev100) throw std::runtime_error("runway_fog_night.json: no exposure_ev100");
    s->glow_threshold = atmo::render::glow_threshold_cd_m2_of(hs::exposure_scale_from_ev100(*ev100));
    std::string error;
    if (!atmo::support::read_exr(ATMO_RUNWAY_FOG_NIGHT_EXR, &s->image, &error)) throw std::runtime_error(error);
    atmo::test_render::LightPointsOnly alone(s->scenario, 0, ATMO_PLUGIN_PATH);
    s->points = alone.render(points);  // the same lights
    return s;
  }();
  return *s;
}

struct Reference {
  double single = 0, multiple = 0, multiple_se = 0;  // cd/m^2
  double ground_bound = 0;  // an upper bound of the lit ground's radiance behind the fog (not in single/multiple)
  double d_vp = 0;          // m; infinity: no ground on the ray
  double drawn_single = 0;    // single scattering of the lights whose glow here exceeds the render's glow threshold
  double beamed_multiple = 0;  // the beamed (runway) lights' share of `multiple`
  double total() const { return single + multiple; }
};

// The reference luminance of pixel (x, y): every light's single scattering by quadrature and its orders >= 2
// by the Monte Carlo (`paths` per light, seed `seed` + light index), along the pixel's centre ray.
Reference reference(const Scene& s, int x, int y, uint64_t paths, uint64_t seed) {
  Reference r;
  const glm::dvec3 dir_enu = s.pixel_direction(x, y);
  r.d_vp = s.ground_distance(dir_enu);
  const glm::dvec3 dir = glm::normalize(s.to_eye(s.setup.pose.position_enu_m + 1000.0 * dir_enu));
  const glm::dvec3 eye(0.0);
  double var = 0;
  for (size_t i = 0; i < s.lights.size(); ++i) {
    fr::Light unit = s.lights[i];
    unit.intensity = 1.0;
    const double w = s.lights[i].intensity;
    const double single = w * fr::single_scattering_radiance(s.medium, unit, eye, dir, r.d_vp, 1e-7);
    const fr::MonteCarloResult mc = fr::monte_carlo_radiance(s.medium, unit, eye, dir, r.d_vp, paths, seed + i);
    r.single += single;
    if (single > s.glow_threshold) r.drawn_single += single;
    if (s.lights[i].cos_outer > -1.5) r.beamed_multiple += w * mc.multiple;
    r.multiple += w * mc.multiple;
    var += (w * mc.multiple_std_error) * (w * mc.multiple_std_error);
  }
  r.multiple_se = std::sqrt(var);
  if (std::isfinite(r.d_vp)) {
    // The ground behind: direct irradiance from every light through the fog, times 3 for the light the fog
    // scatters onto it (at most ~2x the direct at the optical distances of the lamp posts' ground,
    // docs/measurements/fog_multiple_scattering.md), times the brightest BRDF the host's terrain uses
    // (albedo <= 0.3, / pi, + gloss 0.03), through the fog to the eye.
    const glm::dvec3 ground = r.d_vp * dir;
    double e = 0;
    for (const fr::Light& l : s.lights) {
      const glm::dvec3 to_light = l.position_m - ground;
      const double d = glm::length(to_light);
      e += l.intensity * fr::light_profile(l, -to_light) * std::exp(-fr::optical_thickness(s.medium, ground, l.position_m)) *
           std::max(to_light.z / d, 0.0) / (d * d);
    }
    r.ground_bound = (0.3 / kPi + 0.03) * 3.0 * e * std::exp(-fr::optical_thickness(s.medium, eye, ground));
  }
  return r;
}

// The pixels: a glow pixel beside each lamp post (kGlowOffsetPx from its image, on the side away from the
// runway's lights, where the lamp's own glow is largest against theirs), and fog pixels away from every
// light, below the horizon (the ray ends on the ground ~400 m away) and above it (the ray leaves the fog
// through its top). Positions only: every luminance is computed.
constexpr double kGlowOffsetPx = 4.0;
struct FogPixel {
  const char* name;
  double u, v;  // as the scenario's luminance_checks: pixel (int(u W), int(v H))
};
constexpr FogPixel kFogPixels[] = {
    {"fog left, below the horizon", 0.1, 0.7},
    {"fog right, below the horizon", 0.9, 0.7},
    {"fog left, above the horizon", 0.15, 0.28},
    {"fog at the top (the scenario's \"night sky\" pixel)", 0.5, 0.03},
};
// Monte Carlo paths per light and pixel (306 lights): the multiple part's standard error is 2-9 % of the
// reference (printed); seeds fixed (kSeed + 1000 pixel + light), so the test is deterministic.
// -DATMO_RUNWAY_FOG_SEED=... draws other paths (the bounds below were checked with three seeds).
constexpr uint64_t kPaths = 1024;
#ifndef ATMO_RUNWAY_FOG_SEED
#define ATMO_RUNWAY_FOG_SEED 18001
#endif
constexpr uint64_t kSeed = ATMO_RUNWAY_FOG_SEED;
// Bounds (docs/FOG.md, "The runway scenario against the reference"); MC noise is taken on the lenient side
// (reference -+ 2 se), as the Monte Carlo's error has a heavy tail (seeds 18001, 9001, 31337 measured).
// - Every pixel, plugin / reference: at most the envelope the fog model claims against the Monte Carlo
//   (2.6, docs/measurements/fog_multiple_scattering.md), and at least 0.8 x the ratio measured at commit
//   time: the plugin is far below the reference here (the beamed lights' multiple scattering, the culled
//   glows; see the docs), so these are regression bounds, to be raised when that is fixed.
constexpr double kEnvelopeHigh = 2.6;
constexpr double kMeasuredGlowLow = 0.31;   // min over seeds of plugin / (reference - 2 se); 0.31-0.51
constexpr double kMeasuredFogLow = 0.024;   // the same for the fog pixels: 0.024-0.056
constexpr double kMargin = 0.8;
// - Glow pixels, against the single scattering alone: at least that of the lights whose glow exceeds the
//   render's glow threshold here (those the plugin certainly draws), at most that of every light, each
//   within the glow's documented accuracy for a beam at the eye (worst 7.9 %, docs/FOG.md "Cone lights"),
//   plus 10 % of the reference's multiple part for the plugin's diffusion term (measured 3-6 % of it at
//   the fog pixels).
constexpr double kGlowAccuracy = 0.079;
constexpr double kDiffusionShare = 0.10;

struct Checked {
  std::string name;
  int x, y;
  bool glow;
};

std::vector<Checked> pixels(const Scene& s) {
  std::vector<Checked> out;
  for (size_t k = 0; k < s.lamp_posts.size(); ++k) {
    const sc::LightPoint& lp = s.scenario.lights->points[k];
    const glm::dvec2 at = s.project(glm::dvec3(lp.enu_m[0], lp.enu_m[1], lp.enu_m[2]));
    const double away = at.x < 0.5 * s.setup.viewport[2] ? -1.0 : 1.0;  // the runway is in the middle
    char name[96];
    std::snprintf(name, sizeof name, "glow %.0f px beside lamp post %zu (%.0f cd)", kGlowOffsetPx, k,
                  lp.intensity_cd);
    out.push_back({name, static_cast<int>(std::lround(at.x + away * kGlowOffsetPx)),
                   static_cast<int>(std::lround(at.y)), true});
  }
  for (const FogPixel& f : kFogPixels)
    out.push_back({f.name, static_cast<int>(f.u * s.setup.viewport[2]), static_cast<int>(f.v * s.setup.viewport[3]),
                   false});
  return out;
}

}  // namespace

// The render's pixels against the reference. Prints, per pixel, the plugin's scattered luminance (the render
// less the points, which are printed apart), the reference (its single and multiple parts, the Monte Carlo's
// standard error), their ratio, and what the plugin leaves out.
TEST(RunwayFogNight, FogAndGlowLuminanceAgainstTheReference) {
  const Scene& s = scene();
  ASSERT_EQ(s.image.width, s.setup.viewport[2]);
  ASSERT_EQ(s.image.height, s.setup.viewport[3]);
  ASSERT_EQ(s.lamp_posts.size(), 2u);
  std::printf("fog: extinction %.6g 1/m, albedo %.3f, g %.2f, top %.2f m above the eye, ground %.2f m below; "
              "%zu lights; glow threshold %.4g cd/m^2\n",
              s.medium.extinction_per_m, s.medium.albedo, s.medium.hg_g, s.medium.top_m, -s.medium.bottom_m,
              s.lights.size(), s.glow_threshold);
  std::printf("%-50s %9s %5s %9s %9s %9s %9s %7s %9s %6s %9s %9s %8s\n", "pixel", "(x, y)", "d_vp", "plugin",
              "(points)", "reference", "single", "multi", "MC se", "ratio", "drawn SS", "beamed MS", "ground<");
  uint64_t pixel_index = 0;
  for (const Checked& c : pixels(s)) {
    const Reference r = reference(s, c.x, c.y, kPaths, kSeed + 1000 * pixel_index++);
    const double plugin = s.rendered(c.x, c.y);
    const double ratio = plugin / r.total();
    std::printf("%-50s (%3d,%3d) %5.0f %9.4g %9.4g %9.4g %9.4g %7.4g %9.2g %6.3f %9.4g %9.4g %8.2g\n", c.name.c_str(),
                c.x, c.y, r.d_vp, plugin, s.point(c.x, c.y), r.total(), r.single, r.multiple, r.multiple_se, ratio,
                r.drawn_single, r.beamed_multiple, r.ground_bound);
    // The lit ground behind the fog is left out of the reference: it must be negligible.
    EXPECT_LT(r.ground_bound, 0.01 * r.total()) << c.name;
    const double low = kMargin * (c.glow ? kMeasuredGlowLow : kMeasuredFogLow);
    EXPECT_GE(plugin, low * (r.total() - 2.0 * r.multiple_se)) << c.name << ": plugin " << plugin << " cd/m^2";
    EXPECT_LE(plugin, kEnvelopeHigh * (r.total() + 2.0 * r.multiple_se)) << c.name << ": plugin " << plugin << " cd/m^2";
    if (c.glow) {
      std::printf("%-50s plugin / drawn single scattering %.3f, / all single scattering %.3f\n", "", plugin / r.drawn_single,
                  plugin / r.single);
      EXPECT_GE(plugin, (1.0 - kGlowAccuracy) * r.drawn_single) << c.name;
      EXPECT_LE(plugin, (1.0 + kGlowAccuracy) * r.single + kDiffusionShare * (r.multiple + 2.0 * r.multiple_se)) << c.name;
    }
  }
}
