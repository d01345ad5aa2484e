// Fog and point lights through the ABI: set_fog / set_lights validation (each
// bad field named, nothing changed), no fog or no light -> no cost, and
// finite, non-negative output (the glows against every light's exact glow:
// fog_glow_test.cpp; the host include: fog_host_include_test.cpp)
// where the model is fragile (a light at the eye, very thin and very dense
// fog, the eye above the fog top, lights far away).
#include <glad/gl.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "atmo_support/image.h"
#include "atmo_support/image_metrics.h"
#include "plugin_gl_fixture.h"

namespace {

using namespace plugin_gl;

constexpr double kEyeHeightM = 2.0;

AtmoFogState fog_of(double visibility_m, uint32_t scattering = ATMO_FOG_SCATTERING_SINGLE) {
  AtmoFogState s = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
  s.visibility_m = visibility_m;
  s.scattering = scattering;
  return s;
}

// Lights in the ENU frame at Innsbruck, height 0 (the eye is kEyeHeightM above its origin).
AtmoLightsState lights_of(const std::vector<AtmoLightPoint>& lights, double threshold = 0.0) {
  AtmoLightsState s = atmo::make<AtmoLightsState>(ATMO_TYPE_LIGHTS_STATE);
  s.world_frame = ATMO_WORLD_ENU;
  s.light_size = sizeof(AtmoLightPoint);
  s.world_origin_geodetic[0] = 47.26;
  s.world_origin_geodetic[1] = 11.35;
  s.lights = lights.empty() ? nullptr : lights.data();
  s.light_count = static_cast<uint32_t>(lights.size());
  s.glow_threshold_cd_m2 = threshold;
  return s;
}

const glm::dmat4 kProjection = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1e5);

void set_night_view(Fixture& f, double height_m, double heading_deg, double pitch_deg) {
  f.set_utc(kJulyNightUtc);
  f.view->set(innsbruck_view(height_m, heading_deg, pitch_deg, kProjection));
}

// The LIGHT_GLOWS pass over black; returns its result.
AtmoResult draw_glows(Fixture& f, atmo::support::Image* out) {
  f.target->bind();
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  const AtmoResult r = f.view->render(ATMO_PASS_LIGHT_GLOWS);
  glFinish();
  *out = f.target->read_color();
  return r;
}

AtmoResult raw_set_fog(Fixture& f, const AtmoFogState* s) { return f.plugin->api().set_fog(f.context->handle(), s); }
AtmoResult raw_set_lights(Fixture& f, const AtmoLightsState* s) {
  return f.plugin->api().set_lights(f.context->handle(), s);
}

TEST(FogPass, NoFogOrNoLightsCostNothing) {
  Fixture f;
  set_night_view(f, kEyeHeightM, 0.0, 0.0);
  atmo::support::Image img;
  // No fog: no glow pass, with or without lights. No lights: no host lighting.
  EXPECT_EQ(draw_glows(f, &img), ATMO_STATUS_NOTHING_TO_DRAW);
  AtmoFogLighting fl = atmo::make<AtmoFogLighting>(ATMO_TYPE_FOG_LIGHTING);
  EXPECT_EQ(f.plugin->api().get_fog_lighting(f.view->handle(), &fl), ATMO_STATUS_NOTHING_TO_DRAW);
  EXPECT_EQ(fl.light_count, 0u);
  const std::vector<AtmoLightPoint> one = {atmo::omni_light(0.0, 100.0, 5.0, 1e4)};
  f.context->set_lights(lights_of(one));
  EXPECT_EQ(draw_glows(f, &img), ATMO_STATUS_NOTHING_TO_DRAW);
  EXPECT_EQ(atmo::support::count_nonfinite(img), 0u);
  // Lights in clear air light the host's surfaces (their direct light: no extinction).
  EXPECT_EQ(f.plugin->api().get_fog_lighting(f.view->handle(), &fl), ATMO_SUCCESS);
  EXPECT_EQ(fl.light_count, 1u);
  EXPECT_EQ(fl.medium[0], 0.0);
  // Fog without lights: the fog is drawn, but the host has no lights to shade with.
  f.context->set_lights(lights_of({}));
  f.context->set_fog(fog_of(200.0));
  EXPECT_EQ(draw_glows(f, &img), ATMO_SUCCESS);
  EXPECT_EQ(f.plugin->api().get_fog_lighting(f.view->handle(), &fl), ATMO_STATUS_NOTHING_TO_DRAW);
  EXPECT_EQ(fl.light_count, 0u);
  // Fog removed again (NULL): nothing to draw.
  EXPECT_EQ(raw_set_fog(f, nullptr), ATMO_SUCCESS);
  EXPECT_EQ(draw_glows(f, &img), ATMO_STATUS_NOTHING_TO_DRAW);
}

TEST(FogPass, InvalidStatesAreRejectedWithTheFieldNamed) {
  Fixture f;
  set_night_view(f, kEyeHeightM, 0.0, 0.0);
  struct FogCase {
    const char* what;
    AtmoFogState s;
    AtmoResult code;
    const char* message;
  };
  std::vector<FogCase> fogs;
  AtmoFogState s = fog_of(200.0);
  s.visibility_m = std::nan("");
  fogs.push_back({"NaN visibility", s, ATMO_ERROR_NON_FINITE_VALUE, "visibility_m is nan"});
  s = fog_of(200.0);
  s.visibility_m = 5.0;
  fogs.push_back({"visibility too short", s, ATMO_ERROR_OUT_OF_RANGE, "visibility_m = 5"});
  s = fog_of(0.0);
  s.extinction_per_m = -0.01;
  fogs.push_back({"negative extinction", s, ATMO_ERROR_OUT_OF_RANGE, "extinction_per_m = -0.01"});
  s = fog_of(200.0);
  s.phase_asymmetry = 0.99;
  fogs.push_back({"g out of range", s, ATMO_ERROR_OUT_OF_RANGE, "phase_asymmetry = 0.99"});
  s = fog_of(200.0);
  s.single_scattering_albedo = 1.5;
  fogs.push_back({"albedo above 1", s, ATMO_ERROR_OUT_OF_RANGE, "single_scattering_albedo = 1.5"});
  s = fog_of(200.0);
  s.scattering = 7;
  fogs.push_back({"bad scattering", s, ATMO_ERROR_INVALID_ARGUMENT, "scattering = 7"});
  s = fog_of(200.0);
  s.airlight_table_size = 4;
  fogs.push_back({"table too small", s, ATMO_ERROR_OUT_OF_RANGE, "airlight_table_size = 4"});
  s = fog_of(200.0);
  s.top_height_m = INFINITY;
  fogs.push_back({"infinite top", s, ATMO_ERROR_NON_FINITE_VALUE, "top_height_m is inf"});
  s = fog_of(200.0);
  s.header.struct_size = 16;
  fogs.push_back({"undersized struct", s, ATMO_ERROR_STRUCT_TOO_SMALL, "struct_size is 16"});
  s = fog_of(200.0);
  s.header.type = ATMO_TYPE_LIGHTS_STATE;
  fogs.push_back({"wrong type", s, ATMO_ERROR_WRONG_STRUCT_TYPE, "AtmoFogState"});
  for (const FogCase& c : fogs) {
    EXPECT_EQ(raw_set_fog(f, &c.s), c.code) << c.what;
    EXPECT_NE(f.context->last_error().find(c.message), std::string::npos) << c.what << ": " << f.context->last_error();
  }
  atmo::support::Image img;
  EXPECT_EQ(draw_glows(f, &img), ATMO_STATUS_NOTHING_TO_DRAW) << "a rejected set_fog changed the fog";

  // Lights, with fog on so that a wrongly accepted light would show.
  f.context->set_fog(fog_of(200.0));
  struct LightCase {
    const char* what;
    std::vector<AtmoLightPoint> lights;
    AtmoLightsState s;
    AtmoResult code;
    const char* message;
  };
  const AtmoLightPoint good = atmo::omni_light(0.0, 100.0, 5.0, 1e4);
  std::vector<LightCase> cases;
  auto add = [&](const char* what, AtmoLightPoint p, AtmoResult code, const char* message) {
    cases.push_back({what, {good, p}, {}, code, message});
  };
  AtmoLightPoint p = good;
  p.position_m[1] = std::nan("");
  add("NaN position", p, ATMO_ERROR_NON_FINITE_VALUE, "lights[1]");
  p = good;
  p.position_m[0] = 3e9;
  add("position beyond 1e9 m", p, ATMO_ERROR_OUT_OF_RANGE, "lights[1].position_m[0] = 3000000000 is outside");
  p = good;
  p.intensity_cd = -1.0;
  add("negative intensity", p, ATMO_ERROR_OUT_OF_RANGE, "lights[1].intensity_cd = -1");
  p = good;
  p.color[2] = 100.0;
  add("colour too large", p, ATMO_ERROR_OUT_OF_RANGE, "lights[1].color[2] = 100");
  p = good;
  p.cone_inner_rad = 0.5;
  p.cone_outer_rad = 0.2;
  p.direction[1] = 1.0;
  add("inner beyond outer", p, ATMO_ERROR_OUT_OF_RANGE, "lights[1].cone");
  p = good;
  p.cone_inner_rad = 0.1;
  p.cone_outer_rad = 0.2;
  add("zero axis", p, ATMO_ERROR_INVALID_ARGUMENT, "lights[1].direction is the zero vector");
  for (LightCase& c : cases) c.s = lights_of(c.lights);
  {
    LightCase c{"undersized light_size", {good}, {}, ATMO_ERROR_STRUCT_TOO_SMALL, "light_size is 64"};
    c.s = lights_of(c.lights);
    c.s.light_size = 64;
    cases.push_back(c);
    LightCase n{"NULL array", {}, {}, ATMO_ERROR_INVALID_ARGUMENT, "lights is NULL with light_count 3"};
    n.s = lights_of({});
    n.s.light_count = 3;
    cases.push_back(n);
    LightCase m{"too many", {good}, {}, ATMO_ERROR_OUT_OF_RANGE, "light_count = 65537"};
    m.s = lights_of(m.lights);
    m.s.light_count = ATMO_LIGHTS_MAX + 1;  // rejected before the array is read
    cases.push_back(m);
    LightCase t{"NaN threshold", {good}, {}, ATMO_ERROR_NON_FINITE_VALUE, "glow_threshold_cd_m2 = nan"};
    t.s = lights_of(t.lights, std::nan(""));
    cases.push_back(t);
  }
  for (LightCase& c : cases) {
    c.s.lights = c.lights.empty() ? nullptr : c.lights.data();
    EXPECT_EQ(raw_set_lights(f, &c.s), c.code) << c.what;
    EXPECT_NE(f.context->last_error().find(c.message), std::string::npos) << c.what << ": " << f.context->last_error();
  }
  AtmoFogLighting fl = atmo::make<AtmoFogLighting>(ATMO_TYPE_FOG_LIGHTING);
  EXPECT_EQ(f.plugin->api().get_fog_lighting(f.view->handle(), &fl), ATMO_STATUS_NOTHING_TO_DRAW)
      << "a rejected set_lights changed the lights";

  // A larger light struct (a newer host): light_size strides over the tail.
  struct Grown {
    AtmoLightPoint point;
    double future[4];
  };
  std::vector<Grown> grown(2);
  grown[0].point = good;
  grown[1].point = atmo::omni_light(10.0, 120.0, 5.0, 1e4);
  for (Grown& g : grown)
    for (double& v : g.future) v = std::nan("");  // never read
  AtmoLightsState ls = lights_of({});
  ls.lights = &grown[0].point;
  ls.light_count = 2;
  ls.light_size = sizeof(Grown);
  EXPECT_EQ(raw_set_lights(f, &ls), ATMO_SUCCESS) << f.context->last_error();
  EXPECT_EQ(f.plugin->api().get_fog_lighting(f.view->handle(), &fl), ATMO_SUCCESS);
  EXPECT_EQ(fl.light_count, 2u);
}

TEST(FogPass, CallsOutOfOrderAreRefused) {
  Fixture f;
  f.context->set_fog(fog_of(200.0));
  const std::vector<AtmoLightPoint> one = {atmo::omni_light(0.0, 100.0, 5.0, 1e4)};
  f.context->set_lights(lights_of(one));
  AtmoFogLighting fl = atmo::make<AtmoFogLighting>(ATMO_TYPE_FOG_LIGHTING);
  const AtmoPluginApi& api = f.plugin->api();
  EXPECT_EQ(api.get_fog_lighting(f.view->handle(), &fl), ATMO_ERROR_CALL_OUT_OF_ORDER);
  EXPECT_NE(f.context->last_error().find("set_frame has not been called"), std::string::npos) << f.context->last_error();
  f.set_utc(kJulyNightUtc);
  EXPECT_EQ(api.get_fog_lighting(f.view->handle(), &fl), ATMO_ERROR_CALL_OUT_OF_ORDER);
  EXPECT_NE(f.context->last_error().find("set_view has not been called"), std::string::npos) << f.context->last_error();
  EXPECT_EQ(api.get_fog_lighting(f.view->handle(), nullptr), ATMO_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(api.get_fog_lighting(nullptr, &fl), ATMO_ERROR_INVALID_HANDLE);
  EXPECT_EQ(api.set_fog(nullptr, nullptr), ATMO_ERROR_INVALID_HANDLE);
  EXPECT_EQ(api.set_lights(nullptr, nullptr), ATMO_ERROR_INVALID_HANDLE);
  AtmoFogLighting small = fl;
  small.header.struct_size = 8;
  f.view->set(innsbruck_view(kEyeHeightM, 0.0, 0.0, kProjection));
  EXPECT_EQ(api.get_fog_lighting(f.view->handle(), &small), ATMO_ERROR_STRUCT_TOO_SMALL);
  EXPECT_EQ(api.get_fog_lighting(f.view->handle(), &fl), ATMO_SUCCESS);
}

// Where the model is fragile the pass stays finite and non-negative.
TEST(FogPass, FiniteWhereTheModelIsFragile) {
  Fixture f;
  struct Case {
    const char* what;
    double visibility_m, extinction_per_m, top_m, eye_height_m, pitch_deg;
    AtmoLightPoint light;
  };
  const Case cases[] = {
      {"light at the eye", 200.0, 0.0, 0.0, kEyeHeightM, 0.0, atmo::omni_light(0.0, 0.0, kEyeHeightM, 1e5)},
      {"light on the view axis", 200.0, 0.0, 0.0, kEyeHeightM, 0.0, atmo::omni_light(0.0, 300.0, kEyeHeightM, 1e5)},
      {"densest fog", 0.0, 1.0, 0.0, kEyeHeightM, 0.0, atmo::omni_light(0.0, 50.0, 3.0, 1e8)},
      {"thinnest fog", 100000.0, 0.0, 0.0, kEyeHeightM, 0.0, atmo::omni_light(0.0, 50.0, 3.0, 1e8)},
      {"light 1000 km away", 200.0, 0.0, 0.0, kEyeHeightM, 0.0, atmo::omni_light(0.0, 1e6, 3.0, 1e8)},
      {"eye above the fog top", 500.0, 0.0, 100.0, 800.0, -30.0, atmo::omni_light(0.0, 600.0, 3.0, 1e5)},
      {"top just at the eye", 500.0, 0.0, kEyeHeightM, kEyeHeightM, 10.0, atmo::omni_light(0.0, 100.0, 3.0, 1e5)},
  };
  for (const Case& c : cases) {
    for (uint32_t scattering : {uint32_t(ATMO_FOG_SCATTERING_SINGLE), uint32_t(ATMO_FOG_SCATTERING_AUTO)}) {
      AtmoFogState s = fog_of(c.visibility_m, scattering);
      s.extinction_per_m = c.extinction_per_m;
      s.top_height_m = c.top_m;
      f.context->set_fog(s);
      const std::vector<AtmoLightPoint> one = {c.light};
      f.context->set_lights(lights_of(one));
      set_night_view(f, c.eye_height_m, 0.0, c.pitch_deg);
      atmo::support::Image img;
      EXPECT_EQ(draw_glows(f, &img), ATMO_SUCCESS) << c.what;
      size_t negative = 0;
      for (float v : img.rgba) negative += v < 0.0f;
      EXPECT_EQ(atmo::support::count_nonfinite(img), 0u) << c.what << " scattering " << scattering;
      EXPECT_EQ(negative, 0u) << c.what << " scattering " << scattering;
      AtmoFogLighting fl = atmo::make<AtmoFogLighting>(ATMO_TYPE_FOG_LIGHTING);
      EXPECT_EQ(f.plugin->api().get_fog_lighting(f.view->handle(), &fl), ATMO_SUCCESS) << c.what;
      for (double v : fl.diffusion) EXPECT_TRUE(std::isfinite(v)) << c.what;
    }
  }
}

}  // namespace
