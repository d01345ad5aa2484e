// The host's surfaces lit through atmo_fog_lights.glsl, in a host shader that
// includes it (each pixel the ground point it sees, 2 m below the eye):
//   - against its twin: the include's loop replayed on the CPU with the twin's
//     terms over every texture the plugin filled, read back (the light texture,
//     the cluster grid and lists, the far field), so their layouts are checked;
//   - at scale, against the brute-force sum over every light (each with its
//     whole light, the diffusion term included, at the pixel's own point):
//     what the clusters (at most 12 lights a pixel, the rest in a far field at
//     the cluster's centre) lose or add, in fog and in clear air.
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "atmo_host_scene/fog_lighting_binding.h"
#include "atmo_support/image.h"
#include "atmo_support/image_metrics.h"
#include "core/fog/fog_twin.h"
#include "host_shader.h"
#include "plugin_gl_fixture.h"

namespace {

using namespace plugin_gl;
namespace twin = atmo::fog::twin;

constexpr double kEyeHeightM = 2.0;
// A 320 x 180 view, 40 degrees high, 12 degrees down (the fixture's target is too small for clusters of
// 1.25 degrees, the size they have at 1280 x 720 and 40 degrees).
constexpr int kW = 320, kH = 180;
const glm::dmat4 kProjection = glm::perspective(glm::radians(40.0), double(kW) / kH, 1.0, 1e5);
constexpr double kPitchDeg = -12.0;

const char* kVertex =
    "#version 330 core\nvoid main(){vec2 p=vec2((gl_VertexID<<1)&2,gl_VertexID&2);"
    "gl_Position=vec4(p*2.0-1.0,0.5,1.0);}\n";
// The unit ray through the fragment's pixel, relative to the eye (world axes), before either main.
const char* kPixelRay = R"(
uniform mat4 rel_from_clip;
uniform vec2 size;
out vec4 colour;
vec3 pixel_ray() {
  vec2 ndc = gl_FragCoord.xy / size * 2.0 - 1.0;
  vec4 a = rel_from_clip * vec4(ndc, -1.0, 1.0);
  vec4 b = rel_from_clip * vec4(ndc, 1.0, 1.0);
  return normalize(b.xyz / b.w - a.xyz / a.w);
}
)";

// The ground point (2 m below the eye) each pixel sees, relative to the eye.
const char* kFragmentMain = R"(
uniform vec3 kd;
uniform vec3 ks;
uniform float exponent;
uniform float eye_height;
void main() {
  vec3 dir = pixel_ray();
  if (dir.z > -1.0e-3) { colour = vec4(0.0); return; }
  vec3 p = dir * (-eye_height / dir.z);
  colour = vec4(atmo_fog_lights_surface(p, vec3(0.0, 0.0, 1.0), kd, ks, exponent), 1.0);
}
)";

// A translucent surface (ATMO_PASS_LIGHT_GLOWS drawn first): each pixel the point `distance` metres along its
// ray, its own light `own` (cd/m^2) through atmo_fog_translucent; alpha holds the transmittance.
const char* kTranslucentMain = R"(
uniform float distance;
uniform vec3 own;
void main() {
  vec4 f = atmo_fog_translucent(pixel_ray() * distance);
  colour = vec4(own * f.a + f.rgb, f.a);
}
)";

glm::dmat4 rel_from_clip() { return glm::inverse(kProjection * look(0.0, kPitchDeg)); }

// The ground point of window pixel (x, y) (GL order) relative to the eye, or false where it sees sky.
bool ground_point(int x, int y, glm::dvec3* p) {
  const glm::dvec2 ndc((x + 0.5) / kW * 2.0 - 1.0, (y + 0.5) / kH * 2.0 - 1.0);
  const glm::dmat4 m = rel_from_clip();
  const glm::dvec4 a = m * glm::dvec4(ndc, -1.0, 1.0), b = m * glm::dvec4(ndc, 1.0, 1.0);
  const glm::dvec3 dir = glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w);
  if (dir.z > -1e-3) return false;
  *p = dir * (-kEyeHeightM / dir.z);
  return true;
}

// Everything the include reads, read back from the plugin's textures.
struct Readback {
  std::vector<float> lights;  // the clusters' lights, 3 texels each, 1024 a row
  int light_width = 0;
  std::vector<uint32_t> grid;
  std::vector<float> far;  // RGBA, (tiles x, tiles y, 4 x slices)
  int fx = 0, fy = 0, fz = 0;

  explicit Readback(const AtmoFogLighting& fl) {
    auto size2d = [](GLuint t, int* w, int* h) {
      glBindTexture(GL_TEXTURE_2D, t);
      glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, w);
      glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, h);
    };
    int w = 0, h = 0;
    size2d(fl.light_texture, &w, &h);
    light_width = w;
    lights.resize(size_t(w) * h * 4);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, lights.data());
    size2d(fl.cluster_grid, &w, &h);
    grid.resize(size_t(w) * h * 2);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RG_INTEGER, GL_UNSIGNED_INT, grid.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindTexture(GL_TEXTURE_3D, fl.far_field);
    glGetTexLevelParameteriv(GL_TEXTURE_3D, 0, GL_TEXTURE_WIDTH, &fx);
    glGetTexLevelParameteriv(GL_TEXTURE_3D, 0, GL_TEXTURE_HEIGHT, &fy);
    glGetTexLevelParameteriv(GL_TEXTURE_3D, 0, GL_TEXTURE_DEPTH, &fz);
    far.resize(size_t(fx) * fy * fz * 4);
    glGetTexImage(GL_TEXTURE_3D, 0, GL_RGBA, GL_FLOAT, far.data());
    glBindTexture(GL_TEXTURE_3D, 0);
  }
  glm::vec4 light(size_t i, int k) const {
    return glm::make_vec4(&lights[((i / 1024) * size_t(light_width) + 3 * (i % 1024) + size_t(k)) * 4]);
  }
  // texture(sampler3D, uvw).rgb with GL_LINEAR and CLAMP_TO_EDGE.
  glm::vec3 far_at(glm::vec3 uvw) const {
    const glm::vec3 f = uvw * glm::vec3(fx, fy, fz) - 0.5f;
    const glm::ivec3 i0 = glm::ivec3(glm::floor(f));
    const glm::vec3 t = f - glm::vec3(i0);
    glm::vec3 sum(0.0f);
    for (int c = 0; c < 8; ++c) {
      const glm::ivec3 i = glm::clamp(i0 + glm::ivec3(c & 1, (c >> 1) & 1, c >> 2), glm::ivec3(0),
                                      glm::ivec3(fx - 1, fy - 1, fz - 1));
      const float w = (c & 1 ? t.x : 1.0f - t.x) * ((c >> 1) & 1 ? t.y : 1.0f - t.y) * (c >> 2 ? t.z : 1.0f - t.z);
      sum += w * glm::make_vec3(&far[((size_t(i.z) * fy + i.y) * fx + i.x) * 4]);
    }
    return sum;
  }
};

// atmo_fog_lights_surface replayed on the CPU: the twin's terms over the read-back textures.
glm::vec3 include_on_cpu(const AtmoFogLighting& fl, const Readback& rb, const atmo::fog::FogTable& table, glm::vec3 p,
                         glm::vec3 kd, glm::vec3 ks, float exponent) {
  const glm::vec3 normal(0.0f, 0.0f, 1.0f), up(fl.up_world[0], fl.up_world[1], fl.up_world[2]);
  const glm::vec3 mirror = glm::reflect(-glm::normalize(-p), normal);
  const glm::vec2 size(fl.surface_table_size[0], fl.surface_table_size[1]);
  glm::mat4 m;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m[c][r] = float(fl.cluster_from_position[c * 4 + r]);
  const glm::vec4 grid(fl.cluster_grid_size[0], fl.cluster_grid_size[1], fl.cluster_grid_size[2], 0.0);
  const glm::vec4 cell = twin::atmo_fog_cluster_of(m * glm::vec4(p, 1.0f), glm::length(p), grid,
                                                   glm::vec2(fl.cluster_range[0], fl.cluster_range[1]));
  const size_t g = size_t(cell.z * grid.y + cell.y) * size_t(grid.x) + size_t(cell.x);
  glm::vec3 sum(0.0f);
  for (uint32_t j = 0; j < rb.grid[2 * g + 1]; ++j) {
    const size_t i = rb.grid[2 * g] + j;
    const glm::vec4 t0 = rb.light(i, 0), t1 = rb.light(i, 1), t2 = rb.light(i, 2);
    const glm::vec3 to_light = glm::vec3(t0) - p;
    const float d = glm::length(to_light);
    if (d > t0.w) continue;
    const glm::vec3 l = to_light / std::max(d, 1e-3f);
    const float extent = glm::length(glm::vec3(t2)) - 1.0f;  // the axis's length: 1 + the entry's extent
    const bool both_ways = t2.w > 2.5f;
    const float cone = twin::atmo_fog_cone(glm::vec3(t2) / (1.0f + extent), t1.w, both_ways ? t2.w - 4.0f : t2.w,
                                           both_ways ? 2.0f : 1.0f, -l);
    if (cone <= 0.0f) continue;
    const float d_lit = std::max(d, extent);
    const float beta = float(fl.medium[0]) * twin::atmo_fog_inside_fraction(glm::dot(p, up), glm::dot(glm::vec3(t0), up),
                                                                           float(fl.medium[2]));
    const glm::vec2 terms = twin::atmo_fog_surface_terms_single(table, size, beta, float(fl.medium[1]), d_lit,
                                                                beta * d_lit,
                                                                glm::dot(normal, l), glm::dot(mirror, l), exponent);
    sum += glm::vec3(t1) * cone * (kd * terms.x + ks * terms.y);
  }
  glm::mat3 enu_from_world;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) enu_from_world[c][r] = float(fl.enu_from_world[c * 3 + r]);
  const glm::vec3 n = enu_from_world * normal;
  const glm::vec4 clip = m * glm::vec4(p, 1.0f);
  const glm::vec2 uv = clip.w > 1e-6f ? glm::clamp(glm::vec2(clip) / clip.w, -1.0f, 1.0f) * 0.5f + 0.5f
                                      : (glm::vec2(cell.x, cell.y) + 0.5f) / glm::vec2(grid);
  const float slices = grid.z, k = std::clamp(cell.w, 0.5f, slices - 0.5f);
  glm::vec3 e(0.0f);
  for (int axis = 0; axis < 3; ++axis) {
    const float face = float(2 * axis + (n[axis] < 0.0f ? 1 : 0));
    e += n[axis] * n[axis] * rb.far_at(glm::vec3(uv, (k + face * slices) / (6.0f * slices)));
  }
  return sum + kd * e;
}

struct Scene {
  Fixture f;
  std::unique_ptr<OffscreenTarget> target;
  glm::vec3 kd{0.3f / float(M_PI)}, ks{0.2f};
  float exponent = 24.0f;

  Scene() {
    std::string error;
    target = OffscreenTarget::create(kW, kH, &error);
    if (!target) throw std::runtime_error(error);
    f.set_utc(kJulyNightUtc);
    AtmoViewState vs = innsbruck_view(kEyeHeightM, 0.0, kPitchDeg, kProjection);
    vs.viewport[2] = kW;
    vs.viewport[3] = kH;
    vs.exposure_scale = 1.0 / (1.2 * 4.0);  // EV100 2: the threshold (1/2000 of white) is 2.4e-3 cd/m^2
    f.view->set(vs);
  }

  void set_lights(const std::vector<AtmoLightPoint>& lights) {
    f.context->set_lights(atmo::lights_state(0, lights, 47.26, 11.35, 0.0));
  }

  // The host shader's image (`main_source` after the include), and the AtmoFogLighting it was drawn with.
  atmo::support::Image draw(AtmoFogLighting* fl, const char* main_source = kFragmentMain, float distance = 0.0f,
                            glm::vec3 own = glm::vec3(0.0f)) {
    *fl = atmo::make<AtmoFogLighting>(ATMO_TYPE_FOG_LIGHTING);
    EXPECT_EQ(f.plugin->api().get_fog_lighting(f.view->handle(), fl), ATMO_SUCCESS) << f.context->last_error();
    const std::string include =
        read_text(std::string(ATMO_SOURCE_DIR) + "/host_sdk/include/atmo/atmo_fog_lights.glsl");
    const HostProgram host(kVertex, "#version 330 core\n" + include + kPixelRay + main_source);
    EXPECT_TRUE(host.linked());
    const GLuint program = host.id();
    glUseProgram(program);
    glUniform3fv(host.uniform("kd"), 1, &kd[0]);
    glUniform3fv(host.uniform("ks"), 1, &ks[0]);
    glUniform1f(host.uniform("exponent"), exponent);
    const glm::mat4 m(rel_from_clip());
    glUniformMatrix4fv(host.uniform("rel_from_clip"), 1, GL_FALSE, glm::value_ptr(m));
    glUniform1f(host.uniform("eye_height"), float(kEyeHeightM));
    glUniform2f(host.uniform("size"), float(kW), float(kH));
    glUniform1f(host.uniform("distance"), distance);
    glUniform3fv(host.uniform("own"), 1, &own[0]);
    atmo::support::Image img;
    {
      const atmo::host_scene::FogLightingBinding binding(program, *fl, 0);
      target->bind();
      glViewport(0, 0, kW, kH);
      glDisable(GL_BLEND);
      glDisable(GL_DEPTH_TEST);
      draw_full_screen_triangle();
      glFinish();
      img = target->read_color();
    }
    return img;
  }
};

AtmoFogState fog_of(double visibility_m) {
  AtmoFogState s = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
  s.visibility_m = visibility_m;
  return s;
}

// Three lights, one a cone, in fog with multiple scattering: the shader equals its replay on the CPU.
TEST(FogHostInclude, SurfaceShaderMatchesItsTwin) {
  for (const bool fog : {true, false}) {
    Scene s;
    if (fog) s.f.context->set_fog(fog_of(250.0));
    std::vector<AtmoLightPoint> lights = {atmo::omni_light(-20.0, 80.0, 0.5, 5e3), atmo::omni_light(25.0, 130.0, 6.0, 2e4),
                                          atmo::omni_light(0.0, 60.0, 0.3, 3e4)};
    lights[2].direction[1] = -1.0;
    lights[2].cone_inner_rad = glm::radians(10.0);
    lights[2].cone_outer_rad = glm::radians(40.0);
    s.set_lights(lights);
    AtmoFogLighting fl;
    const atmo::support::Image img = s.draw(&fl);
    ASSERT_EQ(fl.light_count, 3u);
    if (fog) {
      EXPECT_GT(fl.diffusion[3], 0.0) << "AUTO scattering turns the diffusion term on";
    }
    const Readback rb(fl);
    const atmo::fog::FogTable table =
        fog ? atmo::fog::build_surface_table(32, 32, 0.85) : atmo::fog::FogTable{2, 18, std::vector<float>(36, 0.0f)};
    double worst = 0.0, peak = 0.0;
    int lit = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        glm::dvec3 p;
        if (!ground_point(x, y, &p)) continue;
        const glm::vec3 want = include_on_cpu(fl, rb, table, glm::vec3(p), s.kd, s.ks, s.exponent);
        const float* got = img.pixel(x, kH - 1 - y);
        peak = std::max(peak, double(want.g));
        if (want.g > 1e-3f) ++lit;
        for (int c = 0; c < 3; ++c)
          worst = std::max(worst, double(std::abs(got[c] - want[c]) / std::max(want[c], 1e-3f)));
      }
    std::printf("%s: host include vs its twin: %d pixels above 1e-3 cd/m^2, peak %.3g cd/m^2, worst relative "
                "difference %.2e\n",
                fog ? "fog" : "clear air", lit, peak, worst);
    EXPECT_GT(lit, kW * kH / 8);
    EXPECT_LT(worst, 0.01);
  }
}

// A host built with the 136-byte AtmoFogLighting has an include from before the clusters, which reads the
// light texture in another layout: it is given no lights (and told once in the log), not wrong ones.
TEST(FogHostInclude, AnIncludeFromBeforeTheClustersGetsNoLights) {
  Scene s;
  s.set_lights({atmo::omni_light(0.0, 60.0, 5.0, 1e4)});
  AtmoFogLighting fl = atmo::make<AtmoFogLighting>(ATMO_TYPE_FOG_LIGHTING);
  fl.header.struct_size = 136;
  EXPECT_EQ(s.f.plugin->api().get_fog_lighting(s.f.view->handle(), &fl), ATMO_STATUS_NOTHING_TO_DRAW);
  EXPECT_EQ(fl.light_count, 0u);
  fl.header.struct_size = sizeof(AtmoFogLighting);
  EXPECT_EQ(s.f.plugin->api().get_fog_lighting(s.f.view->handle(), &fl), ATMO_SUCCESS);
  EXPECT_EQ(fl.light_count, 1u);
}

// A host's light as the twin's functions take it: relative to the eye (the world is ENU at the lights'
// origin, the eye 2 m above it), its cone (cos_outer < -1.5: omnidirectional).
struct EyeLight {
  glm::vec3 position, axis;
  float cos_inner, cos_outer;
};
EyeLight eye_light(const AtmoLightPoint& light) {
  const bool cone_light = light.cone_outer_rad > 0.0;
  return {glm::vec3(light.position_m[0], light.position_m[1], light.position_m[2] - kEyeHeightM),
          cone_light ? glm::normalize(glm::vec3(light.direction[0], light.direction[1], light.direction[2]))
                     : glm::vec3(0.0f, 0.0f, 1.0f),
          cone_light ? std::cos(float(light.cone_inner_rad)) : -2.0f,
          cone_light ? std::cos(float(light.cone_outer_rad)) : -2.0f};
}

// The brute-force sum over every light at the pixel's own point: each light's whole light (direct, single
// scattered, diffusion; atmo_fog_surface_terms) with no range, no list and no far field.
glm::vec3 every_light(const AtmoFogLighting& fl, const std::vector<AtmoLightPoint>& lights,
                      const atmo::fog::FogTable& table, glm::vec3 p, glm::vec3 kd, glm::vec3 ks, float exponent) {
  const glm::vec3 normal(0.0f, 0.0f, 1.0f), up(fl.up_world[0], fl.up_world[1], fl.up_world[2]);
  const glm::vec3 mirror = glm::reflect(-glm::normalize(-p), normal);
  const glm::vec2 size(fl.surface_table_size[0], fl.surface_table_size[1]);
  const glm::vec4 diffusion(fl.diffusion[0], fl.diffusion[1], fl.diffusion[2], fl.diffusion[3]);
  glm::vec3 sum(0.0f);
  for (const AtmoLightPoint& light : lights) {
    const EyeLight eye = eye_light(light);
    const glm::vec3 position = eye.position, axis = eye.axis;
    const float ci = eye.cos_inner, co = eye.cos_outer;
    const bool cone_light = co > -1.5f;
    const glm::vec3 intensity = float(light.intensity_cd) * glm::vec3(light.color[0], light.color[1], light.color[2]);
    const glm::vec3 to_light = position - p;
    const float d = glm::length(to_light);
    const glm::vec3 l = to_light / std::max(d, 1e-3f);
    const float cone = twin::atmo_fog_cone(axis, ci, co, 1.0f, -l);
    const float beta = float(fl.medium[0]) * twin::atmo_fog_inside_fraction(glm::dot(p, up), glm::dot(position, up),
                                                                           float(fl.medium[2]));
    const glm::vec2 single = twin::atmo_fog_surface_terms_single(table, size, beta, float(fl.medium[1]), d, beta * d,
                                                                 glm::dot(normal, l), glm::dot(mirror, l), exponent);
    sum += intensity * cone * (kd * single.x + ks * single.y);
    // The diffusion term with the cone's mean (the power), as the plugin's far field takes it.
    const glm::vec2 all = twin::atmo_fog_surface_terms(table, size, beta, float(fl.medium[1]), diffusion, d, beta * d,
                                                       glm::dot(normal, l), glm::dot(mirror, l), exponent);
    const float mean = cone_light ? (2.0f - ci - co) / 4.0f : 1.0f;
    sum += intensity * mean * (kd * (all.x - single.x));
  }
  return sum;
}

// A town's lights, 1 200 of them over 1.2 x 0.8 km ahead of the eye (1 250 a square kilometre) (street lights cut off upwards, windows,
// car headlights): the clustered shading against every light's whole light at each pixel's point, in RVR
// 550 m fog with multiple scattering and in clear air, at EV100 2 (threshold 2.4e-3 cd/m^2).
TEST(FogHostInclude, SurfacesAtScaleAgainstEveryLight) {
  std::vector<AtmoLightPoint> lights;
  uint64_t state = 7;
  auto uniform = [&]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) * 0x1.0p-53;
  };
  for (int i = 0; i < 1200; ++i) {
    const double east = -600.0 + 1200.0 * uniform(), north = 20.0 + 800.0 * uniform();
    const int kind = i % 4;
    if (kind == 0) {  // a street light: 9 m up, cut off upwards
      AtmoLightPoint l = atmo::omni_light(east, north, 9.0, 2500.0);
      l.direction[2] = -1.0;
      l.cone_inner_rad = glm::radians(55.0);
      l.cone_outer_rad = glm::radians(85.0);
      lights.push_back(l);
    } else if (kind == 1) {  // a headlight along a street
      AtmoLightPoint l = atmo::omni_light(east, north, 0.7, 10000.0);
      l.direction[0] = uniform() < 0.5 ? 1.0 : -1.0;
      l.direction[2] = -0.03;
      l.cone_inner_rad = glm::radians(10.0);
      l.cone_outer_rad = glm::radians(30.0);
      lights.push_back(l);
    } else {  // a window
      lights.push_back(atmo::omni_light(east, north, 3.0 + 20.0 * uniform(), 20.0 + 130.0 * uniform()));
    }
  }
  // Diffuse surfaces (the clusters' claim), then with a Phong lobe (ks 0.2, n 24): glints of lights in the
  // mirror direction beyond a cluster's list are smeared by the merging (measured, not bounded).
  for (const bool fog : {true, false})
    for (const bool specular : {false, true}) {
    Scene s;
    if (!specular) s.ks = glm::vec3(0.0f);
    if (fog) s.f.context->set_fog(fog_of(550.0));
    s.set_lights(lights);
    AtmoFogLighting fl;
    const atmo::support::Image img = s.draw(&fl);
    const atmo::fog::FogTable table =
        fog ? atmo::fog::build_surface_table(32, 32, 0.85) : atmo::fog::FogTable{2, 18, std::vector<float>(36, 0.0f)};
    std::vector<double> errors;
    double sum_got = 0.0, sum_want = 0.0, peak = 0.0;
    std::vector<std::pair<double, double>> pixels;  // (want, got) luminance
    // Every third pixel each way: the brute force is 1 200 lights a pixel.
    for (int y = 1; y < kH; y += 3)
      for (int x = 1; x < kW; x += 3) {
        glm::dvec3 p;
        if (!ground_point(x, y, &p)) continue;
        const glm::vec3 want = every_light(fl, lights, table, glm::vec3(p), s.kd, s.ks, s.exponent);
        const float* got = img.pixel(x, kH - 1 - y);
        const double w = atmo::support::luminance(&want[0]), g = atmo::support::luminance(got);
        pixels.push_back({w, g});
        peak = std::max(peak, w);
      }
    for (const auto& [w, g] : pixels) {
      sum_got += g;
      sum_want += w;
      if (w > 0.01 * peak) errors.push_back(std::abs(g - w) / w);
    }
    std::sort(errors.begin(), errors.end());
    const double median = errors[errors.size() / 2], p95 = errors[errors.size() * 95 / 100], worst = errors.back();
    std::printf("%s, %s, 1 200 lights: clustered against every light, %zu pixels above 1 %% of the peak (%.3g "
                "cd/m^2): relative error median %.3f, 95th percentile %.3f, worst %.3f; the image's total %.4f of every "
                "light's\n",
                fog ? "RVR 550 m fog" : "clear air", specular ? "diffuse + Phong" : "diffuse", errors.size(), peak,
                median, p95, worst, sum_got / sum_want);
    EXPECT_GT(errors.size(), 200u);
    if (!specular) {  // measured: fog 0.008 / 0.028 / 0.989, clear air 0.010 / 0.034 / 0.990
      EXPECT_LT(median, 0.045);
      EXPECT_LT(p95, 0.09);
      EXPECT_NEAR(sum_got / sum_want, 1.0, 0.02);
    }
  }
}

// Translucent surfaces (atmo_fog_translucent): a surface 120 m along every ray, drawn after the glow pass, in
// RVR 300 m fog: its own light through the fog plus the fog's light in front of it, against the brute force
// (the fog's transmittance, the medium's light, and every light's whole glow up to the surface by the twin,
// which no list or tile limits): exact for a few lights (each in its tile's list), within what the merging
// loses for many.
TEST(FogHostInclude, TranslucentSurfacesGetTheFogAndGlowsInFrontOfThem) {
  const double visibility = 300.0;
  const float distance = 120.0f;
  const glm::vec3 own(0.5f, 0.4f, 0.3f);
  for (const int count : {3, 400}) {
    Scene s;
    s.f.context->set_fog(fog_of(visibility));
    std::vector<AtmoLightPoint> lights;
    uint64_t state = 5;
    auto uniform = [&]() {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      return double(state >> 11) * 0x1.0p-53;
    };
    if (count == 3) {
      lights = {atmo::omni_light(-15.0, 60.0, 4.0, 4e3), atmo::omni_light(20.0, 200.0, 8.0, 2e4),
                atmo::omni_light(0.0, 90.0, 1.0, 3e4)};
      lights[2].direction[1] = -1.0;  // a beam towards the eye
      lights[2].cone_inner_rad = glm::radians(10.0);
      lights[2].cone_outer_rad = glm::radians(30.0);
    } else {
      for (int i = 0; i < count; ++i)
        lights.push_back(atmo::omni_light(-150.0 + 300.0 * uniform(), 30.0 + 400.0 * uniform(), 1.0 + 15.0 * uniform(),
                                          200.0 + 5000.0 * uniform()));
    }
    s.set_lights(lights);
    // The glow pass fills the glow textures the include reads.
    s.target->bind();
    glViewport(0, 0, kW, kH);
    ASSERT_EQ(s.f.view->render(ATMO_PASS_LIGHT_GLOWS), ATMO_SUCCESS) << s.f.context->last_error();
    AtmoFogLighting fl;
    const atmo::support::Image img = s.draw(&fl, kTranslucentMain, distance, own);
    ASSERT_GT(fl.glow_grid[0], 0.0);
    ASSERT_NE(fl.glow_entries, 0u);
    const atmo::fog::FogTable table = atmo::fog::build_airlight_table(int(fl.glow_grid[2]), 0.85);
    glm::mat3 flux, enu_from_world;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) {
        flux[c][r] = float(fl.flux[c * 3 + r]);
        enu_from_world[c][r] = float(fl.enu_from_world[c * 3 + r]);
      }
    const float beta = float(fl.medium[0]), albedo = float(fl.medium[1]);
    std::vector<double> errors;
    double sum_got = 0.0, sum_want = 0.0, worst_t = 0.0;
    for (int y = 1; y < kH; y += 2)
      for (int x = 1; x < kW; x += 2) {
        const glm::dvec2 ndc((x + 0.5) / kW * 2.0 - 1.0, (y + 0.5) / kH * 2.0 - 1.0);
        const glm::dmat4 m = rel_from_clip();
        const glm::dvec4 a = m * glm::dvec4(ndc, -1.0, 1.0), b = m * glm::dvec4(ndc, 1.0, 1.0);
        const glm::vec3 dir = enu_from_world * glm::vec3(glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w));
        const float t = twin::atmo_fog_transmittance(beta, distance);
        glm::vec3 want = own * t + twin::atmo_fog_medium_light(t, glm::vec3(fl.ambient[0], fl.ambient[1], fl.ambient[2]),
                                                               glm::vec3(fl.fluence[0], fl.fluence[1], fl.fluence[2]),
                                                               flux, dir);
        for (const AtmoLightPoint& light : lights) {
          const EyeLight l = eye_light(light);
          want += albedo * float(light.intensity_cd) *
                  twin::atmo_fog_glow(table, float(fl.glow_grid[2]), beta, l.position, dir, l.axis, l.cos_inner,
                                      l.cos_outer, 1.0f, distance, float(fl.glow_grid[3]));
        }
        const float* got = img.pixel(x, kH - 1 - y);
        worst_t = std::max(worst_t, double(std::abs(got[3] - t)));
        const double w = atmo::support::luminance(&want[0]), g = atmo::support::luminance(got);
        errors.push_back(std::abs(g - w) / w);
        sum_got += g;
        sum_want += w;
      }
    std::sort(errors.begin(), errors.end());
    const double median = errors[errors.size() / 2], p95 = errors[errors.size() * 95 / 100], worst = errors.back();
    std::printf("%d lights, a translucent surface at %.0f m in RVR %.0f m fog (T %.3f): against the brute force, "
                "relative error median %.4f, 95th percentile %.4f, worst %.3f, total %.4f; transmittance off by "
                "%.1e at worst\n",
                count, distance, visibility, twin::atmo_fog_transmittance(beta, distance), median, p95, worst,
                sum_got / sum_want, worst_t);
    EXPECT_LT(worst_t, 1e-5);
    if (count == 3) {  // every light exact in its tile's list
      EXPECT_LT(worst, 0.01);
    } else {  // the tiles' merged glows (docs/FOG.md "Glows at scale")
      EXPECT_LT(median, 0.05);
      EXPECT_NEAR(sum_got / sum_want, 1.0, 0.05);
    }
  }
}

}  // namespace
