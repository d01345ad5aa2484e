// Frame cost of the fog and the host's lights at 1280x720 (docs/measurements/
// fog_bench.md): ATMO_PASS_LIGHT_GLOWS (one full-screen fog pass, then one
// instanced rectangle per light whose glow can exceed the threshold) and the
// host's own surface shading through host_sdk/include/atmo/atmo_fog_lights.glsl
// (atmo_fog_lights_surface: a loop over every light), at 0, 1, 100 and 1000
// lights, against a trivial full-screen pass timed in the same run (as
// atmo_gpu_bench and atmo_clouds_bench: on a noisy machine, and on llvmpipe
// where "GPU" time is rasterisation on the CPU cores, only ratios carry over).
//
// The scene: night at Innsbruck (2024-11-20T22:00Z, the Sun 60 degrees down),
// fog of 200 m visibility (extinction ln(20) / 200 m = 0.015 /m) up to 150 m
// above the ground, the ground flat at 600 m. A runway of 3000 x 45 m runs north
// from its threshold 400 m north of the eye; the eye is on a 3 degree approach,
// 35 m above the ground, looking north 3 degrees down (60 degree vertical field
// of view). Exposure of a night scene (EV100 2: exposure_scale 1 / (1.2 * 4)),
// so the default glow threshold is 1 / (2000 * exposure) = 2.4e-3 cd/m^2.
// The host depth is that ground plane (the lower ~55 % of the image, 35 m below
// the eye, out to the far plane), so the passes' occlusion paths run.
//
// The lights (runway_lights): 1000 of them, in this order: 16 green threshold
// lights (10 000 cd), an approach lighting system of 30 bars of 5 white lights
// every 30 m before the threshold and a crossbar of 20 at 300 m (20 000 cd; 17
// bars are behind the eye, the nearest 20 m behind and 35 m below), 16 red end
// lights (5 000 cd), white edge lights every 30 m along both edges (10 000 cd),
// centreline lights every 15 m (5 000 cd), touchdown-zone barrettes of 3 on
// both sides every 30 m over the first 900 m (5 000 cd), and blue taxiway
// edge lights (omnidirectional, 50 cd) every 30 m on both sides of a taxiway
// 180 m east up to 1000 lights. N lights: every (1000 / N)-th of them (N = 1:
// the first threshold light, 400 m ahead), so each N spans the same layout.
// Omni: every light omnidirectional. Cone: the runway lights beamed as
// runway lights are (tools/atmo/render_command.cpp): inner 10, outer 25
// degrees, axis along the approach (towards the eye), 3 degrees up; the
// taxiway lights stay omnidirectional. Far: the omnidirectional layout
// moved 20 km north (on screen, just below the horizon; every light far below
// the threshold: what a cull that works draws nothing of).
//
// BM_FogGlows_*: the pass alone, wall time from a drained queue to glFinish
// (the GL timer query alongside: timer_query_ms), set_view called before each
// frame as a host does (so the plugin's frame of lights, with its glow bounds
// and rectangles, is made every frame: cpu_call_ms is the time render_pass
// takes to return, the CPU part). Counters from the renderer's FogDrawStats
// (what its "fog: ..." debug line prints): glows_drawn, covered_px (summed
// rectangle area, clipped to the screen), covered_screens (covered_px / the
// screen's pixels); from the plugin's frame of lights: culled_threshold
// (glow radius 0: below the threshold everywhere), hemisphere_glows (radius
// >= 90 degrees: the rectangle is the whole screen), subpixel_glows (radius
// under a pixel, 1.6e-3 rad), unseen_glows (radius > 0 but under the glow
// shader's floor of sin(gamma), min_sin = 4.5e-4 rad: then the bound's own
// core value, intensity-scaled Ghat(0, 0) / min_sin, is under the threshold,
// so no pixel of the glow can reach it; such a light is not culled, as the
// bound (core/fog/fog_model.cpp GlowBound::radius_rad) returns 0 only when its
// value underflows); glow_px (after the timed frames): the pixels
// where the glows together add more than the threshold (the frame less one
// with a threshold no glow reaches), against covered_px (the rectangles'
// summed area) the bound's tightness. glow_ms: the time over
// the fog-only pass's (lights:0, earlier in the run); ns_per_covered_px:
// glow_ms per covered pixel (a covered pixel of one light's rectangle).
//
// BM_SurfaceLights_*: the host's surface shading: a full-screen pass whose
// fragment shader pastes atmo_fog_lights.glsl (as tools/host_scene's
// terrain does) and calls atmo_fog_lights_surface once per pixel for a point
// of the ground plane under that pixel's ray (rays above the horizon are
// mirrored below it, so every pixel shades a ground point: the upper part of
// the image shades the ground again at the mirrored distances), normal up,
// kd = 0.3 / pi, ks = 0.03, exponent 16 (the terrain's), with the uniforms and
// textures get_fog_lighting gives. ns_per_px_light: time / (pixels * lights);
// in_range: the fraction of (pixel, light) pairs the loop does not skip by
// range (the light within its range of the point) and cone (> 0 towards the
// point), from the light texture read back and the same ground points on the
// CPU (every 8th pixel each way); ns_per_shaded_pair: the time over the
// 0-light pass's per (pixel, light) pair in range. get_fog_lighting_ms: the
// call's CPU time (the frame of lights, every light's surface range, the
// texture upload), made every frame after set_view. BM_SurfaceLights_Far:
// every light out of range, so the loop's cost per skipped light;
// BM_SurfaceSkipOnly_Far: the same loop reduced to its range test (the first
// texel fetch, the distance and `continue`, a trivial body): the cost of a
// skipped light when the skipped body is not run. range_mean_m / range_max_m:
// the lights' surface ranges (the light texture's fourth texel value).

#include <benchmark/benchmark.h>
#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "abi/objects.h"
#include "atmo/atmo.h"
#include "atmo/atmo.hpp"
#include "atmo_support/example_view.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"
#include "trivial_pass.h"

namespace {

constexpr int kWidth = 1280, kHeight = 720;
constexpr double kLatDeg = 47.26, kLonDeg = 11.35;
constexpr double kGroundM = 600.0;           // the flat ground's height above the ellipsoid
constexpr double kEyeAboveGroundM = 35.0;    // on a 3 degree path, 400 m before the threshold (+ 14 m)
constexpr double kThresholdNorthM = 400.0;   // the runway's threshold, north of the eye
constexpr double kPitchDeg = -3.0;
constexpr double kVerticalFovDeg = 60.0, kNearM = 1.0, kFarM = 1e5;
constexpr double kUtcPosixS = 1732140000.0;  // 2024-11-20T22:00:00Z (config/scenarios/runway_fog_night.json)
constexpr double kVisibilityM = 200.0;
constexpr double kFogTopAboveGroundM = 150.0;
const double kExposure = 1.0 / (1.2 * 4.0);  // EV100 2 (tools/scenario auto_exposure_ev100 at night)
constexpr int kLayoutLights = 1000;
constexpr double kFarShiftM = 20000.0;  // Far: the omnidirectional layout moved 20 km north
constexpr double kNoGlowThreshold = 1e30;  // cd/m^2: glow_px's reference frame without glows

void log_to_stderr(void*, int32_t severity, const char* message) {
  if (severity >= ATMO_LOG_WARNING) std::fprintf(stderr, "[atmo] %s\n", message);
}

void copy(const glm::dmat4& m, double out[16]) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c * 4 + r] = m[c][r];
}

// View space: x right, y up, -z forward; heading 0 = north, +pitch up.
glm::dmat4 view_from_world() {
  const double h = 0.0, p = glm::radians(kPitchDeg);
  const glm::dvec3 forward(std::sin(h) * std::cos(p), std::cos(h) * std::cos(p), std::sin(p));
  return glm::lookAt(glm::dvec3(0.0), forward, glm::dvec3(0, 0, 1));
}

glm::dmat4 clip_from_view() {
  return glm::perspective(glm::radians(kVerticalFovDeg), double(kWidth) / kHeight, kNearM, kFarM);
}

// The ground point (metres from the eye, ENU) under the ray through pixel centre (x, y) (y from the bottom);
// rays above the horizon mirrored below it; along the ray at most kFarM.
glm::dvec3 ground_point(double x, double y, const glm::dmat3& world_from_view, bool mirror, bool* hit) {
  const double ty = std::tan(glm::radians(kVerticalFovDeg / 2)), tx = ty * double(kWidth) / kHeight;
  const glm::dvec3 ray_view((2.0 * x / kWidth - 1.0) * tx, (2.0 * y / kHeight - 1.0) * ty, -1.0);
  glm::dvec3 d = world_from_view * ray_view;
  *hit = d.z < 0.0;
  if (mirror) d.z = -std::max(std::abs(d.z), 1e-4);
  if (d.z >= 0.0) return glm::dvec3(0.0);
  const double t = std::min(kEyeAboveGroundM / -d.z, kFarM / glm::length(d));
  return d * t;
}

// --- The lights -------------------------------------------------------------

enum Layout { kOmni = 0, kCone = 1, kFar = 2 };

std::vector<AtmoLightPoint> runway_lights(Layout layout) {
  const bool cone = layout == kCone;
  std::vector<AtmoLightPoint> all;
  const double t = kThresholdNorthM, length = 3000.0, half_w = 22.5, height = 0.4;
  const double axis[3] = {0.0, -1.0, std::tan(glm::radians(3.0))};  // towards the approach, 3 deg up
  auto add = [&](double east, double north, double r, double g, double b, double cd, bool beamed) {
    AtmoLightPoint p{};
    p.position_m[0] = east;
    p.position_m[1] = north + (layout == kFar ? kFarShiftM : 0.0);
    p.position_m[2] = height;
    p.intensity_cd = cd;
    p.color[0] = r;
    p.color[1] = g;
    p.color[2] = b;
    if (cone && beamed) {
      for (int k = 0; k < 3; ++k) p.direction[k] = axis[k];
      p.cone_inner_rad = glm::radians(10.0);
      p.cone_outer_rad = glm::radians(25.0);
    }
    all.push_back(p);
  };
  for (int k = 0; k < 16; ++k) add(-half_w + k * (2 * half_w) / 15, t - 1.0, 0.10, 1.0, 0.25, 10000.0, true);
  for (int bar = 1; bar <= 30; ++bar)
    for (int k = 0; k < 5; ++k) add(k - 2.0, t - 30.0 * bar, 1.0, 0.93, 0.80, 20000.0, true);
  for (int k = 0; k < 20; ++k) add((k < 10 ? -1.0 : 1.0) * (3.0 + 1.5 * (k % 10)), t - 300.0, 1.0, 0.93, 0.80,
                                   20000.0, true);
  for (int k = 0; k < 16; ++k) add(-half_w + k * (2 * half_w) / 15, t + length + 1.0, 1.0, 0.05, 0.02, 5000.0, true);
  for (int k = 0; k <= 100; ++k) {
    add(-half_w - 1.5, t + 30.0 * k, 1.0, 0.93, 0.80, 10000.0, true);
    add(half_w + 1.5, t + 30.0 * k, 1.0, 0.93, 0.80, 10000.0, true);
  }
  for (int k = 0; k <= 200; ++k) add(0.0, t + 15.0 * k, 1.0, 0.93, 0.80, 5000.0, true);
  for (int k = 1; k <= 30; ++k)
    for (int s = -1; s <= 1; s += 2)
      for (int j = 0; j < 3; ++j) add(s * (9.0 + 1.5 * j), t + 30.0 * k, 1.0, 0.93, 0.80, 5000.0, true);
  for (int k = 0; all.size() < size_t(kLayoutLights); ++k) {
    add(180.0 - 12.0, t - 600.0 + 30.0 * k, 0.1, 0.2, 1.0, 50.0, false);
    if (all.size() < size_t(kLayoutLights)) add(180.0 + 12.0, t - 600.0 + 30.0 * k, 0.1, 0.2, 1.0, 50.0, false);
  }
  return all;
}

std::vector<AtmoLightPoint> pick(const std::vector<AtmoLightPoint>& all, size_t n) {
  std::vector<AtmoLightPoint> out;
  for (size_t i = 0; i < n; ++i) out.push_back(all[i * all.size() / n]);
  return out;
}

// --- The host's surface shader ---------------------------------------------

constexpr const char* kSurfaceFragmentHead = "#version 330 core\n";
constexpr const char* kSurfaceFragmentMain = R"(
uniform mat3 u_world_from_view;
uniform vec2 u_tan_half;     // tan of the half field of view, x and y
uniform vec2 u_size;
uniform float u_eye_height;  // above the ground plane, m
out vec4 o_color;
void main() {
  vec2 ndc = gl_FragCoord.xy / u_size * 2.0 - 1.0;
  vec3 d = u_world_from_view * vec3(ndc * u_tan_half, -1.0);
  d.z = -max(abs(d.z), 1.0e-4);  // rays above the horizon: the ground point of the mirrored ray
  vec3 p = d * min(u_eye_height / -d.z, 1.0e5 / length(d));
  vec3 L = atmo_fog_lights_surface(p, atmo_fog_up, vec3(0.3 / 3.14159265), vec3(0.03), 16.0);
  o_color = vec4(L, 1.0);
}
)";

// The loop's range test alone (BM_SurfaceSkipOnly): atmo_fog_lights_surface's first fetch, distance and
// `continue`, with a trivial body, and the same ground points.
constexpr const char* kSkipOnlyFunction = R"(
uniform sampler2D atmo_fog_surface_table;
uniform sampler2D atmo_fog_light_texture;
uniform vec4 atmo_fog_medium;
uniform vec4 atmo_fog_diffusion;
uniform vec3 atmo_fog_up;
uniform vec2 atmo_fog_surface_table_size;
uniform int atmo_fog_light_count;
vec3 atmo_fog_lights_surface(vec3 position_rel_eye_m, vec3 normal, vec3 kd, vec3 ks, float exponent) {
  vec3 sum = vec3(0.0);
  for (int i = 0; i < atmo_fog_light_count; ++i) {
    vec4 t0 = texelFetch(atmo_fog_light_texture, ivec2(0, i), 0);
    float d = length(t0.xyz - position_rel_eye_m);
    if (d > t0.w) continue;
    sum += kd * d;
  }
  return sum;
}
)";

// skip_only: kSkipOnlyFunction instead of the SDK's include.
GLuint build_surface_program(bool skip_only, std::string* error) {
  std::string include = kSkipOnlyFunction;
  if (!skip_only) {
    std::ifstream in(ATMO_HOST_SDK_INCLUDE_DIR "/atmo/atmo_fog_lights.glsl");
    if (!in) {
      *error = "cannot read " ATMO_HOST_SDK_INCLUDE_DIR "/atmo/atmo_fog_lights.glsl";
      return 0;
    }
    include.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string fs = std::string(kSurfaceFragmentHead) + include + kSurfaceFragmentMain;
  GLuint vs_shader = glCreateShader(GL_VERTEX_SHADER), fs_shader = glCreateShader(GL_FRAGMENT_SHADER);
  const char* vs_src = bench_gl::kFullScreenVertex;
  const char* fs_src = fs.c_str();
  glShaderSource(vs_shader, 1, &vs_src, nullptr);
  glShaderSource(fs_shader, 1, &fs_src, nullptr);
  glCompileShader(vs_shader);
  glCompileShader(fs_shader);
  GLint ok = 0;
  glGetShaderiv(fs_shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(fs_shader, sizeof(log), nullptr, log);
    *error = std::string("surface shader: ") + log;
    return 0;
  }
  GLuint program = glCreateProgram();
  glAttachShader(program, vs_shader);
  glAttachShader(program, fs_shader);
  glLinkProgram(program);
  glDeleteShader(vs_shader);
  glDeleteShader(fs_shader);
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    *error = "surface program did not link";
    return 0;
  }
  return program;
}

// --- The host ----------------------------------------------------------------

struct World {
  std::unique_ptr<atmo::support::HeadlessGl> gl;
  std::unique_ptr<atmo::support::OffscreenTarget> target;
  AtmoPluginApi api{};
  AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  AtmoContext ctx = nullptr;
  AtmoView view = nullptr;
  AtmoViewState view_state{};
  GLuint ground_depth = 0, trivial_program = 0, surface_program = 0, skip_program = 0, vao = 0, query = 0;
  double trivial_ms = 0.0;   // BM_TrivialFullScreenPass's mean
  double fog_only_ms = 0.0;  // BM_FogGlows_Omni/lights:0's mean (the glow pass with no light)
  double surface_zero_ms = 0.0;  // BM_SurfaceLights_Omni/lights:0's mean
  int configured_layout = -1;
  size_t configured_n = size_t(-1);
  double configured_threshold = -1.0;

  World() {
    std::string error;
    gl = atmo::support::HeadlessGl::create(atmo::support::HeadlessGl::Profile::Core, &error);
    if (!gl) throw std::runtime_error("no headless GL context: " + error);
    target = atmo::support::OffscreenTarget::create(kWidth, kHeight, &error);
    if (!target) throw std::runtime_error("offscreen target: " + error);
    ground_depth = make_ground_depth();
    auto info = atmo::make<AtmoNegotiateInfo>(ATMO_TYPE_NEGOTIATE_INFO);
    info.min_interface_version = ATMO_INTERFACE_VERSION_1;
    info.max_interface_version = ATMO_INTERFACE_VERSION_CURRENT;
    info.host_name = "atmo fog bench";
    api.header = ATMO_HEADER(ATMO_TYPE_PLUGIN_API, AtmoPluginApi);
    check(atmo_negotiate(&info, &api), "atmo_negotiate");
    services.log = &log_to_stderr;
    services.gl_get_proc_address = &atmo::support::HeadlessGl::get_proc_address;
    auto create = atmo::make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
    create.services = &services;
    check(api.create_context(&create, &ctx), "create_context");
    check(api.gl_init(ctx), "gl_init");
    auto view_info = atmo::make<AtmoViewCreateInfo>(ATMO_TYPE_VIEW_CREATE_INFO);
    check(api.create_view(ctx, &view_info, &view), "create_view");
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = kUtcPosixS;
    check(api.set_frame(ctx, &frame), "set_frame");
    view_state = atmo::support::example_view_state(kWidth, kHeight, ground_depth, kGroundM + kEyeAboveGroundM);
    copy(view_from_world(), view_state.view_from_world);
    copy(clip_from_view(), view_state.clip_from_view);
    view_state.exposure_scale = kExposure;
    view_state.output_encoding = ATMO_OUTPUT_LINEAR_HDR;
    set_view();
    auto fog = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
    fog.visibility_m = kVisibilityM;
    fog.top_height_m = kGroundM + kFogTopAboveGroundM;
    check(api.set_fog(ctx, &fog), "set_fog");

    trivial_program = bench_gl::make_trivial_program();
    surface_program = build_surface_program(false, &error);
    if (!surface_program) throw std::runtime_error(error);
    skip_program = build_surface_program(true, &error);
    if (!skip_program) throw std::runtime_error(error);
    glGenVertexArrays(1, &vao);
    glGenQueries(1, &query);
  }
  ~World() {
    glDeleteQueries(1, &query);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(trivial_program);
    glDeleteProgram(surface_program);
    glDeleteProgram(skip_program);
    glDeleteTextures(1, &ground_depth);
    api.destroy_view(view);
    api.gl_shutdown(ctx);
    api.destroy_context(ctx);
  }

  void check(AtmoResult r, const char* what) const {
    if (r < 0)
      throw std::runtime_error(std::string(what) + ": " + api.result_string(r) + ": " + (ctx ? api.last_error(ctx) : ""));
  }

  // The host depth: the flat ground 35 m below the eye (standard depth, the far plane where no ground).
  static GLuint make_ground_depth() {
    const glm::dmat3 world_from_view = glm::transpose(glm::dmat3(view_from_world()));
    const glm::dmat4 clip = clip_from_view();
    std::vector<float> depth(size_t(kWidth) * kHeight, 1.0f);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        bool hit = false;
        const glm::dvec3 p = ground_point(x + 0.5, y + 0.5, world_from_view, false, &hit);
        if (!hit || glm::length(p) >= 0.999 * kFarM) continue;
        const glm::dvec4 c = clip * glm::dvec4(glm::transpose(world_from_view) * p, 1.0);
        depth[size_t(y) * kWidth + x] = float(0.5 * c.z / c.w + 0.5);
      }
    return atmo::support::make_depth_texture(kWidth, kHeight, depth);
  }

  void set_view() { check(api.set_view(view, &view_state), "set_view"); }

  // threshold 0: the default (1/2000 of the view's white).
  void set_lights(Layout layout, size_t n, double threshold = 0.0) {
    if (configured_layout == int(layout) && configured_n == n && configured_threshold == threshold) return;
    const std::vector<AtmoLightPoint> lights = pick(runway_lights(layout), n);
    auto s = atmo::make<AtmoLightsState>(ATMO_TYPE_LIGHTS_STATE);
    s.world_frame = ATMO_WORLD_ENU;
    s.light_size = sizeof(AtmoLightPoint);
    s.world_origin_geodetic[0] = kLatDeg;
    s.world_origin_geodetic[1] = kLonDeg;
    s.world_origin_geodetic[2] = kGroundM;
    s.lights = lights.empty() ? nullptr : lights.data();
    s.light_count = uint32_t(lights.size());
    s.glow_threshold_cd_m2 = threshold;
    check(api.set_lights(ctx, &s), "set_lights");
    configured_layout = int(layout);
    configured_n = n;
    configured_threshold = threshold;
  }

  void clear_target() {
    target->bind();
    glClearColor(0.001f, 0.001f, 0.002f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
  }

  // Wall time of draw() from a drained queue to glFinish, ms; the timer query in *query_ms; the time draw()
  // took to return in *call_ms.
  template <typename F>
  double finished_ms(F&& draw, double* query_ms, double* call_ms) {
    glFinish();
    const auto start = std::chrono::steady_clock::now();
    glBeginQuery(GL_TIME_ELAPSED, query);
    draw();
    const auto returned = std::chrono::steady_clock::now();
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    const auto end = std::chrono::steady_clock::now();
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    if (query_ms) *query_ms = double(ns) * 1e-6;
    if (call_ms) *call_ms = std::chrono::duration<double, std::milli>(returned - start).count();
    return std::chrono::duration<double, std::milli>(end - start).count();
  }

  double trivial_pass_ms(double* query_ms) {
    target->bind();
    return finished_ms(
        [&] {
          glBindVertexArray(vao);
          glUseProgram(trivial_program);
          glDrawArrays(GL_TRIANGLES, 0, 3);
          glUseProgram(0);
        },
        query_ms, nullptr);
  }

  // The median of 3 trivial passes: the ratio base timed between a benchmark's frames (the same load).
  double trivial_pass_median_ms() {
    double t[3];
    for (double& x : t) x = trivial_pass_ms(nullptr);
    std::sort(t, t + 3);
    return t[1];
  }

  double glow_pass_ms(double* query_ms, double* call_ms) {
    set_view();  // as a host does every frame
    clear_target();
    return finished_ms(
        [&] {
          auto info = atmo::make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO);
          info.pass = ATMO_PASS_LIGHT_GLOWS;
          check(api.render_pass(view, &info), "render_pass(ATMO_PASS_LIGHT_GLOWS)");
        },
        query_ms, call_ms);
  }

  // get_fog_lighting after set_view (its CPU time in *call_ms), then the host's surface pass timed.
  double surface_pass_ms(double* query_ms, double* call_ms, AtmoFogLighting* out, bool skip_only = false) {
    set_view();
    auto fog = atmo::make<AtmoFogLighting>(ATMO_TYPE_FOG_LIGHTING);
    const auto start = std::chrono::steady_clock::now();
    check(api.get_fog_lighting(view, &fog), "get_fog_lighting");
    *call_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (out) *out = fog;
    clear_target();
    const GLuint p = skip_only ? skip_program : surface_program;
    glUseProgram(p);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, fog.surface_table);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, fog.light_texture);
    glUniform1i(glGetUniformLocation(p, "atmo_fog_surface_table"), 0);
    glUniform1i(glGetUniformLocation(p, "atmo_fog_light_texture"), 1);
    glUniform4f(glGetUniformLocation(p, "atmo_fog_medium"), float(fog.medium[0]), float(fog.medium[1]),
                float(fog.medium[2]), float(fog.medium[3]));
    glUniform4f(glGetUniformLocation(p, "atmo_fog_diffusion"), float(fog.diffusion[0]), float(fog.diffusion[1]),
                float(fog.diffusion[2]), float(fog.diffusion[3]));
    // 0 lights: the plugin fills nothing; the loop does not run, but the normal (atmo_fog_up) must be set.
    const bool lit = fog.light_count > 0;
    glUniform3f(glGetUniformLocation(p, "atmo_fog_up"), lit ? float(fog.up_world[0]) : 0.0f,
                lit ? float(fog.up_world[1]) : 0.0f, lit ? float(fog.up_world[2]) : 1.0f);
    glUniform2f(glGetUniformLocation(p, "atmo_fog_surface_table_size"), float(fog.surface_table_size[0]),
                float(fog.surface_table_size[1]));
    glUniform1i(glGetUniformLocation(p, "atmo_fog_light_count"), GLint(fog.light_count));
    const glm::mat3 world_from_view(glm::transpose(glm::dmat3(view_from_world())));
    glUniformMatrix3fv(glGetUniformLocation(p, "u_world_from_view"), 1, GL_FALSE, &world_from_view[0][0]);
    const double ty = std::tan(glm::radians(kVerticalFovDeg / 2)), tx = ty * double(kWidth) / kHeight;
    glUniform2f(glGetUniformLocation(p, "u_tan_half"), float(tx), float(ty));
    glUniform2f(glGetUniformLocation(p, "u_size"), float(kWidth), float(kHeight));
    glUniform1f(glGetUniformLocation(p, "u_eye_height"), float(kEyeAboveGroundM));
    glBindVertexArray(vao);
    const double ms = finished_ms([&] { glDrawArrays(GL_TRIANGLES, 0, 3); }, query_ms, nullptr);
    glUseProgram(0);
    return ms;
  }

  // The fraction of (pixel, light) pairs atmo_fog_lights_surface does not skip (in range, cone > 0), on a
  // grid of every 8th pixel each way, from the light texture of `fog`; the lights' mean and largest range.
  double in_range_fraction(const AtmoFogLighting& fog, double* mean_range_m, double* max_range_m) {
    *mean_range_m = *max_range_m = 0.0;
    if (fog.light_count == 0) return 0.0;
    std::vector<float> t(size_t(fog.light_count) * 16);
    glBindTexture(GL_TEXTURE_2D, fog.light_texture);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, t.data());
    for (uint32_t i = 0; i < fog.light_count; ++i) {
      *mean_range_m += t[size_t(i) * 16 + 3] / double(fog.light_count);
      *max_range_m = std::max(*max_range_m, double(t[size_t(i) * 16 + 3]));
    }
    const glm::dmat3 world_from_view = glm::transpose(glm::dmat3(view_from_world()));
    double pairs = 0.0, shaded = 0.0;
    for (int y = 4; y < kHeight; y += 8)
      for (int x = 4; x < kWidth; x += 8) {
        bool hit = false;
        const glm::dvec3 p = ground_point(x + 0.5, y + 0.5, world_from_view, true, &hit);
        for (uint32_t i = 0; i < fog.light_count; ++i) {
          const float* l = &t[size_t(i) * 16];
          pairs += 1.0;
          const glm::dvec3 to_light = glm::dvec3(l[0], l[1], l[2]) - p;
          const double d = glm::length(to_light);
          if (d > l[3]) continue;
          if (l[11] >= -1.5) {  // a cone: smoothstep(cos_outer, cos_inner, axis . (point - light) / d) > 0
            const double c = -glm::dot(glm::dvec3(l[8], l[9], l[10]), to_light) / std::max(d, 1e-3);
            if (c <= l[11]) continue;
          }
          shaded += 1.0;
        }
      }
    return shaded / pairs;
  }
};

World& world() {
  static World w;
  return w;
}

// Sums over the timed iterations of one pass (`pass(&query_ms, &call_ms)` returns its wall ms), with a
// trivial pass timed after each one, outside the timing, as the ratio's base.
struct LoopTotals {
  double total_ms = 0.0, query_ms = 0.0, call_ms = 0.0, trivial_ms = 0.0;
};
template <typename Pass>
LoopTotals timed_loop(benchmark::State& state, World& w, Pass pass) {
  LoopTotals t;
  for (auto _ : state) {
    double query_ms = 0.0, call_ms = 0.0;
    const double ms = pass(&query_ms, &call_ms);
    t.total_ms += ms;
    t.query_ms += query_ms;
    t.call_ms += call_ms;
    state.SetIterationTime(ms * 1e-3);
    state.PauseTiming();
    t.trivial_ms += w.trivial_pass_median_ms();
    state.ResumeTiming();
  }
  return t;
}

void BM_TrivialFullScreenPass(benchmark::State& state) {
  World& w = world();
  double total_ms = 0.0, query_total_ms = 0.0;
  for (auto _ : state) {
    double query_ms = 0.0;
    const double ms = w.trivial_pass_ms(&query_ms);
    total_ms += ms;
    query_total_ms += query_ms;
    state.SetIterationTime(ms * 1e-3);
  }
  const double it = std::max<double>(1.0, double(state.iterations()));
  w.trivial_ms = total_ms / it;
  state.counters["timer_query_ms"] = query_total_ms / it;
}

// Pixels where the glows add more than the threshold (1/2000 of white: 5e-4 in the exposed linear output):
// the pass with the lights, less the pass with the same lights and a threshold no glow reaches (the fog pass
// and its diffusion term unchanged).
double glow_pixels(World& w, Layout layout, size_t n) {
  w.set_lights(layout, n, kNoGlowThreshold);
  w.glow_pass_ms(nullptr, nullptr);
  const atmo::support::Image without = w.target->read_color();
  w.set_lights(layout, n);
  w.glow_pass_ms(nullptr, nullptr);
  const atmo::support::Image with = w.target->read_color();
  double count = 0.0;
  for (size_t i = 0; i < with.pixel_count(); ++i) {
    float d = 0.0f;
    for (int c = 0; c < 3; ++c) d = std::max(d, with.rgba[i * 4 + c] - without.rgba[i * 4 + c]);
    count += d > 5e-4f;
  }
  return count;
}

void run_glows(benchmark::State& state, Layout layout) {
  World& w = world();
  const size_t n = size_t(state.range(0));
  try {
    w.set_lights(layout, n);
    for (int i = 0; i < 2; ++i) w.glow_pass_ms(nullptr, nullptr);  // programs, tables, the sky lighting
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const auto [total_ms, query_total_ms, call_total_ms, trivial_total_ms] =
      timed_loop(state, w, [&](double* query_ms, double* call_ms) { return w.glow_pass_ms(query_ms, call_ms); });
  const double it = std::max<double>(1.0, double(state.iterations()));
  const double mean_ms = total_ms / it;
  if (n == 0 && layout == kOmni) w.fog_only_ms = mean_ms;
  const atmo::gl::FogDrawStats& st = w.ctx->fog_renderer.last_stats();
  int culled = 0, hemisphere = 0, subpixel = 0, unseen = 0;
  const double tan_half = std::tan(glm::radians(kVerticalFovDeg / 2));
  const double pixel_rad = 2.0 * tan_half / kHeight;
  const double min_sin = atmo::fog::glow_min_sin(tan_half, kHeight);  // FogDrawInputs::min_sin as the glow pass sets it
  if (w.view->fog_frame)
    for (const atmo::fog::FrameLight& l : w.view->fog_frame->lights) {
      culled += l.glow_radius_rad <= 0.0f;
      hemisphere += l.glow_radius_rad >= 0.5 * M_PI;
      subpixel += l.glow_radius_rad > 0.0f && l.glow_radius_rad < pixel_rad;
      unseen += l.glow_radius_rad > 0.0f && l.glow_radius_rad < min_sin;
    }
  state.counters["lights"] = double(st.lights);
  state.counters["glows_drawn"] = double(st.glows_drawn);
  state.counters["culled_threshold"] = culled;
  state.counters["hemisphere_glows"] = hemisphere;
  state.counters["subpixel_glows"] = subpixel;
  state.counters["unseen_glows"] = unseen;
  state.counters["covered_px"] = st.covered_pixels;
  const double covered = st.covered_pixels;
  state.counters["covered_screens"] = covered / (double(kWidth) * kHeight);
  if (n > 0) state.counters["glow_px"] = glow_pixels(w, layout, n);
  state.counters["timer_query_ms"] = query_total_ms / it;
  state.counters["cpu_call_ms"] = call_total_ms / it;
  state.counters["trivial_ms"] = trivial_total_ms / it;
  if (trivial_total_ms > 0.0) state.counters["x_trivial"] = total_ms / trivial_total_ms;
  if (w.trivial_ms > 0.0) state.counters["x_trivial_bm"] = mean_ms / w.trivial_ms;
  if (n > 0 && w.fog_only_ms > 0.0) {
    const double glow_ms = mean_ms - w.fog_only_ms;
    state.counters["glow_ms"] = glow_ms;
    if (covered > 0.0) state.counters["ns_per_covered_px"] = glow_ms * 1e6 / covered;
    state.counters["us_per_light"] = glow_ms * 1e3 / double(n);
  }
}

void run_surface(benchmark::State& state, Layout layout, bool skip_only = false) {
  World& w = world();
  const size_t n = size_t(state.range(0));
  AtmoFogLighting fog{};
  try {
    w.set_lights(layout, n);
    double q = 0.0, c = 0.0;
    w.surface_pass_ms(&q, &c, &fog, skip_only);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const auto [total_ms, query_total_ms, call_total_ms, trivial_total_ms] =
      timed_loop(state, w, [&](double* query_ms, double* call_ms) { return w.surface_pass_ms(query_ms, call_ms, nullptr, skip_only); });
  const double it = std::max<double>(1.0, double(state.iterations()));
  const double mean_ms = total_ms / it, pixels = double(kWidth) * kHeight;
  if (n == 0 && layout == kOmni && !skip_only) w.surface_zero_ms = mean_ms;
  state.counters["lights"] = double(fog.light_count);
  state.counters["timer_query_ms"] = query_total_ms / it;
  state.counters["get_fog_lighting_ms"] = call_total_ms / it;
  state.counters["trivial_ms"] = trivial_total_ms / it;
  if (trivial_total_ms > 0.0) state.counters["x_trivial"] = total_ms / trivial_total_ms;
  if (w.trivial_ms > 0.0) state.counters["x_trivial_bm"] = mean_ms / w.trivial_ms;
  if (n > 0) {
    double mean_range = 0.0, max_range = 0.0;
    const double in_range = w.in_range_fraction(fog, &mean_range, &max_range);
    state.counters["in_range"] = in_range;
    state.counters["range_mean_m"] = mean_range;
    state.counters["range_max_m"] = max_range;
    state.counters["ns_per_px_light"] = mean_ms * 1e6 / (pixels * double(n));
    if (w.surface_zero_ms > 0.0) {
      const double extra_ms = mean_ms - w.surface_zero_ms;
      state.counters["ns_per_px_light_extra"] = extra_ms * 1e6 / (pixels * double(n));
      if (in_range > 0.0) state.counters["ns_per_shaded_pair"] = extra_ms * 1e6 / (pixels * double(n) * in_range);
    }
  }
}

void BM_FogGlows_Omni(benchmark::State& s) { run_glows(s, kOmni); }
void BM_FogGlows_Cone(benchmark::State& s) { run_glows(s, kCone); }
void BM_FogGlows_Far(benchmark::State& s) { run_glows(s, kFar); }
void BM_SurfaceLights_Omni(benchmark::State& s) { run_surface(s, kOmni); }
void BM_SurfaceLights_Cone(benchmark::State& s) { run_surface(s, kCone); }
void BM_SurfaceLights_Far(benchmark::State& s) { run_surface(s, kFar); }
void BM_SurfaceSkipOnly_Far(benchmark::State& s) { run_surface(s, kFar, true); }

#define ATMO_FOG_BENCH(name) \
  BENCHMARK(name)->UseManualTime()->Unit(benchmark::kMillisecond)->ArgNames({"lights"})
// (No ArgNames here: with names but no arguments Google Benchmark drops the benchmark.)
BENCHMARK(BM_TrivialFullScreenPass)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(1.0);
// lights:0 first: the fog-only time the others' glow_ms subtract.
ATMO_FOG_BENCH(BM_FogGlows_Omni)->Arg(0)->Arg(1)->Arg(100)->Arg(1000)->MinTime(1.0);
ATMO_FOG_BENCH(BM_FogGlows_Cone)->Arg(1)->Arg(100)->Arg(1000)->MinTime(1.0);
ATMO_FOG_BENCH(BM_FogGlows_Far)->Arg(1000)->MinTime(1.0);
// lights:0 first: the base the others' ns_per_px_light_extra subtract.
ATMO_FOG_BENCH(BM_SurfaceLights_Omni)->Arg(0)->Arg(1)->Arg(100)->MinTime(1.0);
// About 20 s a frame on llvmpipe: two frames.
ATMO_FOG_BENCH(BM_SurfaceLights_Omni)->Arg(1000)->Iterations(2);
ATMO_FOG_BENCH(BM_SurfaceLights_Cone)->Arg(1)->Arg(100)->MinTime(1.0);
ATMO_FOG_BENCH(BM_SurfaceLights_Cone)->Arg(1000)->Iterations(2);
// Every light out of range: the loop's cost per skipped light.
ATMO_FOG_BENCH(BM_SurfaceLights_Far)->Arg(100)->MinTime(1.0);
ATMO_FOG_BENCH(BM_SurfaceLights_Far)->Arg(1000)->Iterations(2);
// The same, with the loop's range test alone (kSkipOnlyFunction): what a skipped light costs when the
// light's body is not executed.
ATMO_FOG_BENCH(BM_SurfaceSkipOnly_Far)->Arg(1000)->MinTime(1.0);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  World& w = world();  // the context first, so the report can name the renderer
  benchmark::AddCustomContext("gl_renderer", w.gl->renderer());
  benchmark::AddCustomContext("gl_version", w.gl->version());
  benchmark::AddCustomContext("size", std::to_string(kWidth) + "x" + std::to_string(kHeight));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
