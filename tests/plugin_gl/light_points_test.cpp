// The host's lights as points (ATMO_PASS_LIGHT_POINTS) and the light groups
// (set_lights per group, update_lights, set_light_group_pose), through the
// ABI: each drawn light's image holds its illuminance at the eye, Allard's
// law I T / d^2, with T the air's (integrated here by a fine trapezoid sum,
// not the plugin's Gauss-Legendre rule) times the fog's; a light shows where
// that illuminance exceeds the eye's threshold for the sky behind it, and not
// beyond; the host's geometry hides a light behind it; fragile placements
// stay finite; bad input is refused with the light's index named and
// nothing changed.
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <regex>
#include <string>
#include <vector>

#include "atmo_support/image.h"
#include "atmo_support/image_metrics.h"
#include "core/atmosphere/atmosphere_model.h"
#include "core/lights/light_points.h"
#include "plugin_gl_fixture.h"

namespace {

using namespace plugin_gl;

constexpr double kEyeHeightM = 20.0;
constexpr double kNoonUtc = 1718964000.0;           // 2024-06-21 10:00 UTC: the Sun ~60 degrees up
constexpr double kStatuteMileM = 1609.344;

const glm::dmat4 kProjection = glm::perspective(glm::radians(40.0), double(kWidth) / kHeight, 1.0, 1e7);

// Group `group` of lights in the ENU frame at Innsbruck, height 0.
AtmoLightsState lights_of(const std::vector<AtmoLightPoint>& lights, uint32_t group = 0) {
  AtmoLightsState s = atmo::lights_state(group, lights, 47.26, 11.35, 0.0);
  s.lights = lights.empty() ? nullptr : lights.data();
  return s;
}

struct Scene {
  Fixture f;
  std::vector<std::string> log;
  double heading_deg = 0.0, pitch_deg = 0.0;
  GLuint depth_texture = 0;

  static void capture(void* user, int32_t severity, const char* message) {
    auto* lines = static_cast<std::vector<std::string>*>(user);
    if (severity >= ATMO_LOG_WARNING) std::fprintf(stderr, "[atmo] %s\n", message);
    lines->push_back(message);
  }

  explicit Scene(double utc = kJulyNightUtc, double visibility_m = 40000.0) {
    f.services.user = &log;
    f.services.log = &capture;
    f.fresh_context();
    auto air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
    air.visibility_m = visibility_m;
    f.context->set_atmosphere(air);
    f.set_utc(utc);
  }

  AtmoViewState view_state() const {
    AtmoViewState vs = innsbruck_view(kEyeHeightM, heading_deg, pitch_deg, kProjection);
    vs.depth_texture = depth_texture;
    return vs;
  }

  // The points pass over black, exposure 1, linear cd/m^2.
  atmo::support::Image draw(AtmoResult* result = nullptr) {
    f.view->set(view_state());
    f.target->bind();
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    const AtmoResult r = f.view->render(ATMO_PASS_LIGHT_POINTS);
    if (result) *result = r;
    glFinish();
    return f.target->read_color();
  }

  // The numbers of the pass's last debug line: lights, drawn, under the threshold, off screen.
  std::vector<int> last_counts() const {
    static const std::regex re(R"(light points: (\d+) lights, (\d+) drawn, (\d+) under the eye's threshold, (\d+) off)");
    for (auto it = log.rbegin(); it != log.rend(); ++it) {
      std::smatch m;
      if (std::regex_search(*it, m, re)) return {std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4])};
    }
    return {};
  }

  // The window position (x right, y up from the bottom, pixel centres at .5) of an ENU point (relative to the
  // lights' origin), and whether it is in front of the camera.
  glm::dvec2 window_of(const glm::dvec3& enu, bool* in_front = nullptr) const {
    const glm::dvec4 clip = kProjection * look(heading_deg, pitch_deg) * glm::dvec4(enu - glm::dvec3(0, 0, kEyeHeightM), 1.0);
    if (in_front) *in_front = clip.w > 0.0;
    return (glm::dvec2(clip) / clip.w * 0.5 + 0.5) * glm::dvec2(kWidth, kHeight);
  }
};

// The solid angle of window pixel (x, y) (GL order), sr: the view ray's Jacobian integrated over the pixel by a
// 4 x 4 midpoint rule (independent of the shader's closed form).
double pixel_solid_angle(int x, int y) {
  const glm::dmat4 inverse = glm::inverse(kProjection);
  double sum = 0.0;
  const int n = 4;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::dvec2 w(x + (i + 0.5) / n, y + (j + 0.5) / n);
      auto ray = [&](glm::dvec2 p) {
        const glm::dvec4 v = inverse * glm::dvec4(p.x / kWidth * 2.0 - 1.0, p.y / kHeight * 2.0 - 1.0, -1.0, 1.0);
        return glm::normalize(glm::dvec3(v) / v.w);
      };
      const double h = 1e-3;
      const glm::dvec3 dx = (ray(w + glm::dvec2(h, 0)) - ray(w - glm::dvec2(h, 0))) / (2 * h);
      const glm::dvec3 dy = (ray(w + glm::dvec2(0, h)) - ray(w - glm::dvec2(0, h))) / (2 * h);
      sum += glm::length(glm::cross(dx, dy));
    }
  return sum / (n * n);
}

// The illuminance (lux, luminance-weighted) the image holds within `radius` pixels of window position c.
double image_illuminance(const atmo::support::Image& img, glm::dvec2 c, int radius = 9) {
  double e = 0.0;
  for (int y = int(c.y) - radius; y <= int(c.y) + radius; ++y)
    for (int x = int(c.x) - radius; x <= int(c.x) + radius; ++x) {
      if (x < 0 || y < 0 || x >= kWidth || y >= kHeight) continue;
      e += atmo::support::luminance(img.pixel(x, kHeight - 1 - y)) * pixel_solid_angle(x, y);  // image row 0: top
    }
  return e;
}

// The air's transmittance from the eye to an ENU point (relative to the lights' origin), luminance-weighted:
// the real-time air's extinction integrated by a 20 000-step trapezoid sum over the curved path.
double air_transmittance(double visibility_m, const glm::dvec3& enu) {
  atmo::core::AtmosphereSettings air;
  air.visibility_m = visibility_m;
  const atmo::twin::AtmosphereParameters atm = atmo::core::make_atmosphere_parameters(air, 6371000.0, 1.0);
  const glm::dvec3 to = enu - glm::dvec3(0, 0, kEyeHeightM);
  const glm::dvec3 centre_to_eye(0.0, 0.0, 6371000.0 + kEyeHeightM);
  const int n = 20000;
  glm::dvec3 depth(0.0);
  for (int i = 0; i <= n; ++i) {
    const double t = double(i) / n;
    const double altitude = glm::length(centre_to_eye + t * to) - 6371000.0;
    depth += (i == 0 || i == n ? 0.5 : 1.0) * glm::dvec3(atmo::twin::extinction_at(atm, float(altitude)));
  }
  const glm::dvec3 t = glm::exp(-depth / double(n) * glm::length(to));
  return atmo::lights::luminance(t);
}

double allard_e(double cd, double visibility_m, double fog_beta, const glm::dvec3& enu) {
  const double d = glm::length(enu - glm::dvec3(0, 0, kEyeHeightM));
  return cd * air_transmittance(visibility_m, enu) * std::exp(-fog_beta * d) / (d * d);
}

bool finite_non_negative(const atmo::support::Image& img) {
  for (float v : img.rgba)
    if (!std::isfinite(v) || v < 0.0f) return false;
  return true;
}

// Lights spread across the view at 0.3, 2 and 8 km (5 statute miles), omni and beamed (the eye on a cone's
// ramp), in clear night air and in a fog layer: each image holds I T / d^2 within 1 %.
TEST(LightPoints, EachImageHoldsItsIlluminanceAtTheEye) {
  for (const bool fog : {false, true}) {
    Scene s;
    const double fog_beta = fog ? 2.996 / 2000.0 : 0.0;
    if (fog) {
      AtmoFogState fs = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
      fs.visibility_m = 2000.0;
      fs.top_height_m = 300.0;  // the eye and the lights inside it
      s.f.context->set_fog(fs);
    }
    const double d_far = fog ? 2500.0 : 5.0 * kStatuteMileM;
    std::vector<AtmoLightPoint> lights = {atmo::omni_light(-60.0, 300.0, 5.0, 2000.0), atmo::omni_light(0.0, 2000.0, 5.0, 10000.0),
                                          atmo::omni_light(d_far * 0.25, d_far, 5.0, 20000.0)};
    // A beamed light towards the eye, the eye 17.5 degrees off its axis, up the 10-25 degree ramp.
    AtmoLightPoint beam = atmo::omni_light(-400.0, 1000.0, 5.0, 10000.0);
    const glm::dvec3 to_eye = glm::normalize(glm::dvec3(400.0, -1000.0, kEyeHeightM - 5.0));
    const glm::dvec3 side = glm::normalize(glm::cross(to_eye, glm::dvec3(0, 0, 1)));
    const glm::dvec3 axis = std::cos(glm::radians(17.5)) * to_eye + std::sin(glm::radians(17.5)) * side;
    for (int k = 0; k < 3; ++k) beam.direction[k] = axis[k];
    beam.cone_inner_rad = glm::radians(10.0);
    beam.cone_outer_rad = glm::radians(25.0);
    lights.push_back(beam);
    s.f.context->set_lights(lights_of(lights));
    AtmoResult r = ATMO_ERROR_INTERNAL;
    const atmo::support::Image img = s.draw(&r);
    ASSERT_EQ(r, ATMO_SUCCESS);
    ASSERT_TRUE(finite_non_negative(img));
    for (size_t i = 0; i < lights.size(); ++i) {
      const glm::dvec3 p(lights[i].position_m[0], lights[i].position_m[1], lights[i].position_m[2]);
      // The cone's smoothstep in the cosine, 17.5 degrees off the axis of a 10-25 degree ramp.
      const double x = (std::cos(glm::radians(17.5)) - std::cos(glm::radians(25.0))) /
                       (std::cos(glm::radians(10.0)) - std::cos(glm::radians(25.0)));
      const double cone = i == 3 ? x * x * (3.0 - 2.0 * x) : 1.0;
      const double expected = cone * allard_e(lights[i].intensity_cd, 40000.0, fog_beta, p);
      const double got = image_illuminance(img, s.window_of(p));
      std::printf("%s, light %zu at %.0f m: image %.4g lx, I T / d^2 %.4g lx, ratio %.5f\n", fog ? "fog" : "clear", i,
                  glm::length(p), got, expected, got / expected);
      EXPECT_NEAR(got / expected, 1.0, 0.01) << "light " << i;
    }
  }
}

// The eye's threshold illuminance at night, 8e-7 lx (allard_threshold_lux for the night sky): a 10 000 cd
// runway light at 5 statute miles in clear night air is drawn; in RVR 550 m fog it is drawn at 0.9 of its
// Allard range (I T / d^2 = 8e-7 lx, found here by bisection on the reference) and not at 1.1 of it.
TEST(LightPoints, ARunwayLightShowsAtFiveStatuteMilesAndNotBeyondTheFogsAllardRange) {
  {
    Scene s;
    const glm::dvec3 p(0.0, 5.0 * kStatuteMileM, 3.0);
    s.f.context->set_lights(lights_of({atmo::omni_light(p.x, p.y, p.z, 10000.0)}));
    AtmoResult r = ATMO_ERROR_INTERNAL;
    const atmo::support::Image img = s.draw(&r);
    EXPECT_EQ(r, ATMO_SUCCESS);
    const double e = image_illuminance(img, s.window_of(p));
    std::printf("clear night, 10 000 cd at 5 sm: %.3g lx (threshold 8e-7 lx)\n", e);
    EXPECT_GT(e, 8e-7);
  }
  const double beta = 2.996 / 550.0;
  double lo = 100.0, hi = 10000.0;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (allard_e(10000.0, 40000.0, beta, glm::dvec3(0.0, mid, 3.0)) > 8e-7 ? lo : hi) = mid;
  }
  const double range = 0.5 * (lo + hi);
  std::printf("RVR 550 m fog: the Allard range of 10 000 cd at night is %.0f m\n", range);
  for (const double f : {0.9, 1.1}) {
    Scene s;
    AtmoFogState fs = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
    fs.visibility_m = 550.0;
    s.f.context->set_fog(fs);
    const glm::dvec3 p(0.0, f * range, 3.0);
    s.f.context->set_lights(lights_of({atmo::omni_light(p.x, p.y, p.z, 10000.0)}));
    AtmoResult r = ATMO_ERROR_INTERNAL;
    const atmo::support::Image img = s.draw(&r);
    const double e = image_illuminance(img, s.window_of(p));
    std::printf("  at %.1f of it (%.0f m): pass %d, image %.3g lx\n", f, p.y, r, e);
    if (f < 1.0) {
      EXPECT_EQ(r, ATMO_SUCCESS);
      EXPECT_NEAR(e / allard_e(10000.0, 40000.0, beta, p), 1.0, 0.01);
    } else {
      EXPECT_EQ(r, ATMO_STATUS_NOTHING_TO_DRAW);
      EXPECT_EQ(e, 0.0);
    }
  }
}

// At noon the sky behind the lights sets the threshold (~5e-5 lx): a 10 cd lamp 1 km away (1e-5 lx) draws
// nothing and costs no GL call; a 10 000 cd runway light there shows.
TEST(LightPoints, ALightDimmerThanTheDaySkyDrawsNothing) {
  Scene s(kNoonUtc);
  s.f.context->set_lights(lights_of({atmo::omni_light(0.0, 1000.0, 3.0, 10.0)}));
  AtmoResult r = ATMO_ERROR_INTERNAL;
  s.draw(&r);
  EXPECT_EQ(r, ATMO_STATUS_NOTHING_TO_DRAW);
  ASSERT_EQ(s.last_counts().size(), 4u);
  EXPECT_EQ(s.last_counts()[2], 1);  // under the eye's threshold
  s.f.context->set_lights(lights_of({atmo::omni_light(0.0, 1000.0, 3.0, 10000.0)}));
  const atmo::support::Image img = s.draw(&r);
  EXPECT_EQ(r, ATMO_SUCCESS);
  EXPECT_GT(image_illuminance(img, s.window_of({0.0, 1000.0, 3.0})), 1e-3);
}

// The host's depth: geometry 100 m away over the lower half of the view hides a light 500 m away behind it;
// a light standing on that geometry (at its depth) and one above it, in the open sky, show.
TEST(LightPoints, HostGeometryHidesALightBehindIt) {
  Scene s;
  s.pitch_deg = 0.0;
  const glm::dvec4 clip = kProjection * glm::dvec4(0.0, 0.0, -100.0, 1.0);
  s.depth_texture = atmo::support::make_split_depth_texture(kWidth, kHeight, float(0.5 * clip.z / clip.w + 0.5));
  // Each at its own bearing, the first two in the view's lower half.
  const glm::dvec3 behind = glm::dvec3(-180.0, 500.0, kEyeHeightM - 100.0);
  const glm::dvec3 on = glm::dvec3(30.0, 100.0, kEyeHeightM - 15.0);
  const glm::dvec3 above = glm::dvec3(200.0, 500.0, kEyeHeightM + 60.0);
  s.f.context->set_lights(lights_of({atmo::omni_light(behind.x, behind.y, behind.z, 5000.0), atmo::omni_light(on.x, on.y, on.z, 5000.0),
                                     atmo::omni_light(above.x, above.y, above.z, 5000.0)}));
  const atmo::support::Image img = s.draw();
  EXPECT_EQ(image_illuminance(img, s.window_of(behind), 2), 0.0);
  EXPECT_GT(image_illuminance(img, s.window_of(on), 2), 0.0);
  EXPECT_GT(image_illuminance(img, s.window_of(above), 2), 0.0);
  glDeleteTextures(1, &s.depth_texture);
}

// Where the model is fragile: a light at the eye, right behind it, beside it, 1e6 m away, on a cone's outer
// edge and axis (both ways), in the fog's top plane, with and without fog: the pass succeeds, every pixel
// finite and non-negative.
TEST(LightPoints, FragilePlacementsStayFiniteAndNonNegative) {
  for (const bool fog : {false, true}) {
    Scene s;
    if (fog) {
      AtmoFogState fs = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
      fs.visibility_m = 300.0;
      fs.top_height_m = kEyeHeightM;
      s.f.context->set_fog(fs);
    }
    std::vector<AtmoLightPoint> lights = {atmo::omni_light(0.0, 0.0, kEyeHeightM, 1e8),  atmo::omni_light(0.0, -5.0, kEyeHeightM, 1e4),
                                          atmo::omni_light(1e-3, 1e-3, kEyeHeightM, 1e4), atmo::omni_light(0.0, 1e6, 0.0, 1e8),
                                          atmo::omni_light(0.0, 50.0, kEyeHeightM, 1e4),  atmo::omni_light(5.0, 50.0, kEyeHeightM, 1e4)};
    AtmoLightPoint edge = atmo::omni_light(10.0, 200.0, 5.0, 1e5);
    edge.direction[1] = -1.0;  // towards the eye's side, the eye just outside its outer edge
    edge.cone_inner_rad = 0.0;
    edge.cone_outer_rad = std::atan2(10.0, 200.0);
    lights.push_back(edge);
    AtmoLightPoint both = atmo::omni_light(-10.0, 200.0, kEyeHeightM, 1e5);
    both.direction[1] = 1.0;  // pointing away from the eye: its second lobe faces it
    both.cone_inner_rad = 0.0;
    both.cone_outer_rad = 0.1;
    both.flags = ATMO_LIGHT_BIDIRECTIONAL;
    lights.push_back(both);
    s.f.context->set_lights(lights_of(lights));
    for (const double heading : {0.0, 180.0}) {
      s.heading_deg = heading;
      AtmoResult r = ATMO_ERROR_INTERNAL;
      const atmo::support::Image img = s.draw(&r);
      EXPECT_GE(r, 0) << s.f.context->last_error();
      EXPECT_TRUE(finite_non_negative(img)) << (fog ? "fog" : "clear") << ", heading " << heading;
    }
  }
}

// --- Light groups ------------------------------------------------------------

TEST(LightGroups, EachCallReplacesItsOwnGroupAndNullClearsThemAll) {
  Scene s;
  s.f.context->set_lights(lights_of({atmo::omni_light(0, 500, 5, 1e4), atmo::omni_light(20, 500, 5, 1e4), atmo::omni_light(40, 500, 5, 1e4)}, 0));
  s.f.context->set_lights(lights_of({atmo::omni_light(-20, 600, 5, 1e4), atmo::omni_light(-40, 600, 5, 1e4)}, 7));
  s.draw();
  EXPECT_EQ(s.last_counts(), (std::vector<int>{5, 5, 0, 0}));
  s.f.context->set_lights(lights_of({atmo::omni_light(0, 500, 5, 1e4)}, 0));  // group 0 now holds one
  s.draw();
  EXPECT_EQ(s.last_counts(), (std::vector<int>{3, 3, 0, 0}));
  s.f.context->set_lights(lights_of({}, 7));  // empties group 7
  s.draw();
  EXPECT_EQ(s.last_counts(), (std::vector<int>{1, 1, 0, 0}));
  ASSERT_EQ(s.f.plugin->api().set_lights(s.f.context->handle(), nullptr), ATMO_SUCCESS);
  AtmoResult r = ATMO_ERROR_INTERNAL;
  s.draw(&r);
  EXPECT_EQ(r, ATMO_STATUS_NOTHING_TO_DRAW);
}

// A pose moves a group: the same image as its lights set where the pose puts them; update_lights moves one
// light in place.
TEST(LightGroups, APoseMovesAGroupAndAnUpdateMovesItsLights) {
  Scene moved, direct;
  const std::vector<AtmoLightPoint> group = {atmo::omni_light(0, 500, 5, 1e4), atmo::omni_light(250, 700, 5, 1e4)};
  moved.f.context->set_lights(lights_of(group, 3));
  AtmoLightGroupPose pose = atmo::make<AtmoLightGroupPose>(ATMO_TYPE_LIGHT_GROUP_POSE);
  pose.group = 3;
  const glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(-50.0, 100.0, 2.0)) *
                       glm::rotate(glm::dmat4(1.0), glm::radians(10.0), glm::dvec3(0, 0, 1));
  copy(m, pose.world_from_group);
  moved.f.context->set_light_group_pose(pose);
  std::vector<AtmoLightPoint> placed = group;
  for (AtmoLightPoint& l : placed) {
    const glm::dvec3 p(m * glm::dvec4(l.position_m[0], l.position_m[1], l.position_m[2], 1.0));
    for (int k = 0; k < 3; ++k) l.position_m[k] = p[k];
  }
  direct.f.context->set_lights(lights_of(placed, 3));
  const atmo::support::Image a = moved.draw(), b = direct.draw();
  EXPECT_LT(atmo::support::compare_images(a, b, 1.0).max_abs, 1e-4 * 1e4);
  EXPECT_GT(image_illuminance(a, moved.window_of(glm::dvec3(placed[1].position_m[0], placed[1].position_m[1],
                                                            placed[1].position_m[2]))),
            0.0);
  // Replacing the group's lights keeps its pose.
  moved.f.context->set_lights(lights_of(group, 3));
  EXPECT_LT(atmo::support::compare_images(moved.draw(), b, 1.0).max_abs, 1e-4 * 1e4);
  // update_lights: light 1 of the group to where light 0 is, posed.
  AtmoLightsUpdate u = atmo::make<AtmoLightsUpdate>(ATMO_TYPE_LIGHTS_UPDATE);
  u.group = 3;
  u.first = 1;
  u.lights = &group[0];
  u.light_count = 1;
  u.light_size = sizeof(AtmoLightPoint);
  moved.f.context->update_lights(u);
  const atmo::support::Image c = moved.draw();
  const glm::dvec2 w1 = moved.window_of(glm::dvec3(placed[1].position_m[0], placed[1].position_m[1],
                                                   placed[1].position_m[2]));
  EXPECT_EQ(image_illuminance(c, w1, 2), 0.0);
}

TEST(LightGroups, BadInputIsRefusedWithTheLightNamedAndNothingChanges) {
  Scene s;
  const auto& api = s.f.plugin->api();
  AtmoContext ctx = s.f.context->handle();
  const auto set = [&](const AtmoLightsState& st) { return api.set_lights(ctx, &st); };
  std::vector<AtmoLightPoint> good = {atmo::omni_light(0, 500, 5, 1e4), atmo::omni_light(20, 500, 5, 1e4)};
  ASSERT_EQ(set(lights_of(good, 2)), ATMO_SUCCESS);
  const atmo::support::Image before = s.draw();
  auto refused = [&](AtmoResult r, AtmoResult expected, const std::string& needle) {
    EXPECT_EQ(r, expected);
    const std::string message = api.last_error(ctx);
    EXPECT_NE(message.find(needle), std::string::npos) << message;
    EXPECT_EQ(atmo::support::compare_images(s.draw(), before, 1.0).max_abs, 0.0) << needle;
  };
  std::vector<AtmoLightPoint> bad = good;
  bad.push_back(atmo::omni_light(0, 0, 0, 1e4));
  bad[2].position_m[1] = NAN;
  refused(set(lights_of(bad, 2)), ATMO_ERROR_NON_FINITE_VALUE, "AtmoLightsState.lights[2]");
  bad[2] = atmo::omni_light(0, 0, 0, 1e4);
  bad[2].flags = ATMO_LIGHT_BIDIRECTIONAL;  // no cone
  refused(set(lights_of(bad, 2)), ATMO_ERROR_INVALID_ARGUMENT, "AtmoLightsState.lights[2].flags");
  bad[2].cone_outer_rad = 2.0;  // bidirectional cones that overlap
  bad[2].direction[2] = 1.0;
  refused(set(lights_of(bad, 2)), ATMO_ERROR_OUT_OF_RANGE,
          "AtmoLightsState.lights[2].cone_outer_rad");
  refused(set(lights_of(good, 4096)), ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsState.group = 4096");
  // All groups together: at most ATMO_LIGHTS_MAX.
  std::vector<AtmoLightPoint> many(ATMO_LIGHTS_MAX - 1, atmo::omni_light(0, 500, 5, 1.0));
  refused(set(lights_of(many, 9)), ATMO_ERROR_OUT_OF_RANGE, "65536");
  // update_lights: a group with no lights, a range past the group's end, a bad light (index named).
  AtmoLightsUpdate u = atmo::make<AtmoLightsUpdate>(ATMO_TYPE_LIGHTS_UPDATE);
  u.group = 5;
  u.lights = good.data();
  u.light_count = 1;
  refused(api.update_lights(ctx, &u), ATMO_ERROR_OUT_OF_RANGE, "group = 5");
  u.group = 2;
  u.first = 1;
  u.light_count = 2;
  refused(api.update_lights(ctx, &u), ATMO_ERROR_OUT_OF_RANGE, "[1, 3)");
  std::vector<AtmoLightPoint> one_bad = {good[0], good[1]};
  one_bad[1].intensity_cd = -1.0;
  u.first = 0;
  u.lights = one_bad.data();
  u.light_size = sizeof(AtmoLightPoint);
  refused(api.update_lights(ctx, &u), ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsUpdate.lights[1].intensity_cd");
  // set_light_group_pose: not rigid, NaN, a group with no lights.
  AtmoLightGroupPose pose = atmo::make<AtmoLightGroupPose>(ATMO_TYPE_LIGHT_GROUP_POSE);
  pose.group = 2;
  copy(glm::scale(glm::dmat4(1.0), glm::dvec3(2.0)), pose.world_from_group);
  refused(api.set_light_group_pose(ctx, &pose), ATMO_ERROR_OUT_OF_RANGE, "not a rotation");
  copy(glm::dmat4(1.0), pose.world_from_group);
  pose.world_from_group[13] = INFINITY;
  refused(api.set_light_group_pose(ctx, &pose), ATMO_ERROR_NON_FINITE_VALUE, "world_from_group[13]");
  pose.world_from_group[13] = 0.0;
  pose.group = 8;
  refused(api.set_light_group_pose(ctx, &pose), ATMO_ERROR_OUT_OF_RANGE, "group = 8");
}

// A 96-byte light (the version-1 stride) reads no flags: the plugin copies no byte past it.
TEST(LightGroups, VersionOneLightsReadNoFlags) {
  Scene s;
  std::vector<unsigned char> bytes(2 * 96, 0);
  AtmoLightPoint a = atmo::omni_light(0, 500, 5, 1e4), b = atmo::omni_light(20, 500, 5, 1e4);
  std::memcpy(bytes.data(), &a, 96);
  std::memcpy(bytes.data() + 96, &b, 96);
  AtmoLightsState st = lights_of({});
  st.lights = reinterpret_cast<const AtmoLightPoint*>(bytes.data());
  st.light_count = 2;
  st.light_size = 96;
  ASSERT_EQ(s.f.plugin->api().set_lights(s.f.context->handle(), &st), ATMO_SUCCESS);
  s.draw();
  EXPECT_EQ(s.last_counts(), (std::vector<int>{2, 2, 0, 0}));
}

// A bidirectional beam pointing away from the eye shows its second lobe: the same image as the one-way beam
// turned towards the eye.
TEST(LightGroups, ABidirectionalBeamShinesBothWays) {
  Scene both, towards;
  AtmoLightPoint l = atmo::omni_light(0.0, 800.0, 5.0, 1e4);
  l.cone_inner_rad = 0.05;
  l.cone_outer_rad = 0.3;
  l.direction[1] = 1.0;  // away from the eye
  l.flags = ATMO_LIGHT_BIDIRECTIONAL;
  both.f.context->set_lights(lights_of({l}));
  l.direction[1] = -1.0;
  l.flags = 0;
  towards.f.context->set_lights(lights_of({l}));
  const atmo::support::Image a = both.draw(), b = towards.draw();
  EXPECT_GT(image_illuminance(a, both.window_of({0.0, 800.0, 5.0})), 0.0);
  EXPECT_EQ(atmo::support::compare_images(a, b, 1.0).max_abs, 0.0);
}

}  // namespace
