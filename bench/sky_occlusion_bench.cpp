// atmo_sky_occlusion_bench — the cost of sky occlusion by the host's objects
// (issue 21): an apron at noon, aircraft- and van-like sphere sets parked in
// rows in front of a camera 2 m up, every pixel of a full-screen host pass
// shaded through atmo_sky_occlusion.glsl (the ground plane below the horizon,
// the sky's pixels at a point 10 km along their ray, which still call the
// include). Each case prints the wall time to glFinish (median of the timed
// frames; the GL timer query's value alongside in the CSV) of
//   - the pair: the sky pass + the aerial-perspective pass, drawn in the same frames (the ratio base),
//   - the trivial full-screen pass (bench/trivial_pass.h),
//   - the host pass shaded from get_lighting's SH9 alone (what a host pays without occlusion),
//   - the host pass through the include: default flags (bounce, hybrid), ATMO_OCCLUSION_NO_BOUNCE,
//     ATMO_OCCLUSION_OPTIMAL_LINEAR (each with its own set_occluders),
//   - every pixel through the include compiled with ATMO_OCC_IMAGE: the plugin's image pass
//     (ATMO_PASS_SKY_OCCLUSION_IMAGE, an eighth, a quarter and a sixteenth across, and an eighth with
//     ATMO_PASS_SKY_OCCLUSION_NO_SUN) + the host pass reading it, the two
//     summed; its error against the include evaluated at every pixel: the sky's and the bounce's light
//     (p50/p95 of |image - exact| / the open sky, green, over the pixels where the objects change it by 1 % or
//     more) and the Sun's visibility (p50/p95 of |image - exact| over the pixels where either is below 0.99),
// and the CPU time a frame of set_occluder_poses (every object moves) and get_sky_occlusion.
// Sweeps: spheres an object {1 .. 128} at 16 objects; objects {1, 4, 16, 64} at 32 spheres.
//
//   atmo_sky_occlusion_bench [--size 1280x720] [--frames N] [--only SUBSTRING] [--csv FILE]
//                            [--include FILE]   (another atmo_sky_occlusion.glsl: time a variant of it)
//
// tools/sky_occlusion_cost_chart.py turns the CSV into docs/images/sky_occlusion_cost_by_spheres.png.
#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/sky_occlusion_binding.h"
#include "atmo_support/example_view.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"
#include "scale_options.h"
#include "trivial_pass.h"

namespace {

constexpr double kLatitude = 47.26, kLongitude = 11.35;
constexpr double kEyeHeightM = 2.0;
constexpr double kPitchDeg = -10.0;
constexpr double kVfovDeg = 50.0;
// 2024-07-03 11:18 UTC: local noon at Innsbruck, the Sun 66 degrees up in the south.
constexpr double kNoonUtc = 1.72e9 + 5520.0;

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Wall time of f() from a drained queue to glFinish, ms (llvmpipe rasterises late, so a timer query can miss
// it); the GL timer query's value in *query_ms.
struct Timer {
  GLuint query = 0;
  Timer() { glGenQueries(1, &query); }
  ~Timer() { glDeleteQueries(1, &query); }
  double operator()(const std::function<void()>& f, double* query_ms) {
    glFinish();
    const double t0 = now_ms();
    glBeginQuery(GL_TIME_ELAPSED, query);
    f();
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    const double ms = now_ms() - t0;
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    *query_ms = double(ns) * 1e-6;
    return ms;
  }
};

// ---- The host's objects ----

AtmoOccluderSphere sphere(double x, double y, double z, double r) { return {{x, y, z}, r}; }

// `n` spheres along a segment from a to b (the first and last at its ends), each of radius r, none below the
// ground (a coarse set's large spheres rest on it).
void segment(std::vector<AtmoOccluderSphere>* out, int n, glm::dvec3 a, glm::dvec3 b, double r) {
  for (int i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.5 : double(i) / (n - 1);
    const glm::dvec3 c = a + (b - a) * t;
    out->push_back(sphere(c.x, c.y, std::max(c.z, r), r));
  }
}

// An aircraft of k spheres (nose along +y, 32 m long, 30 m span): half on the fuselage, the rest on the wings
// (and a fin from 8 on); fewer spheres are larger, so the set still covers the aircraft's outline.
std::vector<AtmoOccluderSphere> aircraft(int k) {
  std::vector<AtmoOccluderSphere> s;
  if (k == 1) {
    s.push_back(sphere(0.0, 0.0, 8.0, 8.0));
    return s;
  }
  const int fin = k >= 8 ? std::max(1, k / 16) : 0;
  const int fuselage = std::max(1, (k - fin) / 2), wings = k - fin - fuselage;
  segment(&s, fuselage, {0.0, -15.0, 2.6}, {0.0, 15.0, 2.6}, std::max(1.9, 16.0 / fuselage));
  const int left = wings / 2, right = wings - left;
  const double wr = std::max(0.8, 14.0 / std::max(1, wings));
  if (left) segment(&s, left, {-2.5 - wr, 1.0, 2.0}, {-15.0 + wr, -3.0, 2.3}, wr);
  if (right) segment(&s, right, {2.5 + wr, 1.0, 2.0}, {15.0 - wr, -3.0, 2.3}, wr);
  if (fin) segment(&s, fin, {0.0, -14.0, 4.5}, {0.0, -15.5, 8.0}, 1.2);
  return s;
}

// A van of k spheres (6 m long): two rows along y, one from 1 to 3.
std::vector<AtmoOccluderSphere> van(int k) {
  std::vector<AtmoOccluderSphere> s;
  if (k < 4) {
    segment(&s, k, {0.0, -2.0, 1.3}, {0.0, 2.0, 1.3}, std::max(1.1, 3.2 / k));
    return s;
  }
  const int a = k / 2, b = k - a;
  const double r = std::max(0.5, 3.6 / a);
  segment(&s, a, {-0.6, -3.0 + r, 0.6 + r}, {-0.6, 3.0 - r, 0.6 + r}, r);
  segment(&s, b, {0.6, -3.0 + r, 0.6 + r}, {0.6, 3.0 - r, 0.6 + r}, r);
  return s;
}

struct Apron {
  std::vector<std::vector<AtmoOccluderSphere>> spheres;
  std::vector<AtmoOccluderObject> objects;
  std::vector<glm::dmat4> poses;  // world (ENU at the apron's origin) from object
  std::vector<double> heading_rad;
};

// n objects of k spheres on a grid in front of the eye, 34 m apart across and 38 m apart away from it, the
// nearest row 18 m ahead; aircraft and vans in turn, headings varied.
Apron apron(int n, int k) {
  Apron a;
  const int columns = std::max(1, int(std::ceil(std::sqrt(double(n)))));
  for (int i = 0; i < n; ++i) {
    const int row = i / columns, column = i % columns;
    const bool is_aircraft = (row + column) % 2 == 1 || n == 1;
    a.spheres.push_back(is_aircraft ? aircraft(k) : van(k));
    const double east = (column - 0.5 * (columns - 1)) * 34.0, north = 18.0 + 38.0 * row;
    const double heading = glm::radians(35.0 * i + 20.0);
    a.heading_rad.push_back(heading);
    a.poses.push_back(glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(east, north, 0.0)), -heading,
                                  glm::dvec3(0, 0, 1)));
  }
  for (int i = 0; i < n; ++i) {
    AtmoOccluderObject o{};
    o.spheres = a.spheres[i].data();
    o.sphere_count = uint32_t(a.spheres[i].size());
    o.sphere_size = sizeof(AtmoOccluderSphere);
    o.albedo[0] = o.albedo[1] = o.albedo[2] = 0.6;
    std::memcpy(o.world_from_object, glm::value_ptr(a.poses[i]), sizeof(o.world_from_object));
    a.objects.push_back(o);
  }
  return a;
}

AtmoOccludersState occluders_state(const Apron& a, uint32_t flags) {
  auto s = atmo::make<AtmoOccludersState>(ATMO_TYPE_OCCLUDERS_STATE);
  s.world_frame = ATMO_WORLD_ENU;
  s.object_size = sizeof(AtmoOccluderObject);
  s.world_origin_geodetic[0] = kLatitude;
  s.world_origin_geodetic[1] = kLongitude;
  s.objects = a.objects.data();
  s.object_count = uint32_t(a.objects.size());
  s.flags = flags;
  return s;
}

// ---- The host's passes ----

const char* kPixelRay = R"(
uniform mat4 rel_from_clip;
uniform vec2 size;
uniform float eye_height;
vec3 pixel_ray() {
  vec2 ndc = gl_FragCoord.xy / size * 2.0 - 1.0;
  vec4 a = rel_from_clip * vec4(ndc, -1.0, 1.0);
  vec4 b = rel_from_clip * vec4(ndc, 1.0, 1.0);
  return normalize(b.xyz / b.w - a.xyz / a.w);
}
// The ground point (world = ENU at the eye's foot, relative to the eye) or 10 km along a sky pixel's ray.
vec3 receiver(vec3 dir) { return dir.z < -1.0e-4 ? dir * (-eye_height / dir.z) : dir * 1.0e4; }
)";

// The ground through the include.
const char* kOccludedMain = R"(
uniform vec3 sun_world;
uniform vec3 sun_lux;
out vec4 colour;
void main() {
  vec3 p = receiver(pixel_ray());
  vec3 n = vec3(0.0, 0.0, 1.0);
  AtmoSkyOcclusion o = atmo_sky_occlusion(p, n);
  vec3 albedo = vec3(0.25) + 0.05 * sin(0.3 * p.xyx);
  colour = vec4(albedo / 3.14159265 * (o.sky_lux + o.bounce_lux + sun_lux * max(dot(n, sun_world), 0.0) * o.sun_visibility), 1.0);
}
)";

// What the include returns, for its error (untimed): r the Sun's visibility, g the sky's and the bounce's green
// light, b the open sky's green (SH9), lux.
const char* kAnswerMain = R"(
out vec4 colour;
void main() {
  vec3 p = receiver(pixel_ray());
  vec3 n = vec3(0.0, 0.0, 1.0);
  AtmoSkyOcclusion o = atmo_sky_occlusion(p, n);
  AtmoOccSh y = atmo_occ_basis(n);
  vec3 open = atmo_occ_sky_sh9[0] * y.a.x + atmo_occ_sky_sh9[1] * y.a.y + atmo_occ_sky_sh9[2] * y.a.z +
              atmo_occ_sky_sh9[3] * y.a.w + atmo_occ_sky_sh9[4] * y.b.x + atmo_occ_sky_sh9[5] * y.b.y +
              atmo_occ_sky_sh9[6] * y.b.z + atmo_occ_sky_sh9[7] * y.b.w + atmo_occ_sky_sh9[8] * y.c.x;
  colour = vec4(o.sun_visibility, o.sky_lux.g + o.bounce_lux.g, max(open.g, 0.0), 1.0);
}
)";

// The same ground from the sky's SH9 alone (no occlusion): what the host pays anyway.
const char* kPlainMain = R"(
uniform vec3 sun_world;
uniform vec3 sun_lux;
uniform vec3 sky_sh9[9];
out vec4 colour;
void main() {
  vec3 p = receiver(pixel_ray());
  vec3 n = vec3(0.0, 0.0, 1.0);
  float y[9] = float[9](0.282095, 0.488603 * n.y, 0.488603 * n.z, 0.488603 * n.x, 1.092548 * n.x * n.y,
                        1.092548 * n.y * n.z, 0.315392 * (3.0 * n.z * n.z - 1.0), 1.092548 * n.x * n.z,
                        0.546274 * (n.x * n.x - n.y * n.y));
  vec3 sky = vec3(0.0);
  for (int k = 0; k < 9; ++k) sky += y[k] * sky_sh9[k];
  vec3 albedo = vec3(0.25) + 0.05 * sin(0.3 * p.xyx);
  colour = vec4(albedo / 3.14159265 * (max(sky, vec3(0.0)) + sun_lux * max(dot(n, sun_world), 0.0)), 1.0);
}
)";

// The ground's depth for the aerial-perspective pass (untimed).
const char* kDepthMain = R"(
uniform mat4 clip_from_rel;
out vec4 colour;
void main() {
  vec3 dir = pixel_ray();
  if (dir.z >= -1.0e-4) {
    gl_FragDepth = 1.0;
  } else {
    vec4 c = clip_from_rel * vec4(receiver(dir), 1.0);
    gl_FragDepth = clamp(c.z / c.w * 0.5 + 0.5, 0.0, 1.0);
  }
  colour = vec4(0.0);
}
)";

GLuint program_of(const std::string& fragment) {
  GLuint vs = glCreateShader(GL_VERTEX_SHADER), fs = glCreateShader(GL_FRAGMENT_SHADER);
  const char* v = bench_gl::kFullScreenVertex;
  const char* f = fragment.c_str();
  glShaderSource(vs, 1, &v, nullptr);
  glShaderSource(fs, 1, &f, nullptr);
  glCompileShader(vs);
  glCompileShader(fs);
  GLint ok = 0;
  glGetShaderiv(fs, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(fs, sizeof log, nullptr, log);
    std::fprintf(stderr, "host shader: %s\n", log);
  }
  GLuint p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    std::fprintf(stderr, "host program: %s\n", log);
  }
  glDeleteShader(vs);
  glDeleteShader(fs);
  return p;
}

// The include's inputs as its header's "HOST USE" says (textures on units first..first + 4).

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Mode {
  const char* name;
  uint32_t flags;
};
const Mode kModes[] = {{"default", 0u},
                       {"no bounce", ATMO_OCCLUSION_NO_BOUNCE},
                       {"optimal linear", ATMO_OCCLUSION_OPTIMAL_LINEAR}};

struct Case {
  int objects, spheres;
  std::string sweeps;  // "spheres", "objects" or both ("spheres+objects")
};

}  // namespace

int main(int argc, char** argv) {
  int width = 1280, height = 720;
  bench_scale::CommonOptions common;
  common.frames = 3;
  std::string include_path = std::string(ATMO_SOURCE_DIR) + "/host_sdk/include/atmo/atmo_sky_occlusion.glsl";
  for (int i = 1; i < argc; ++i) {
    if (common.take(argc, argv, &i)) continue;
    const std::string a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : "";
    if (a == "--size" && std::sscanf(v, "%dx%d", &width, &height) == 2) {
      ++i;
    } else if (a == "--include" && *v) {
      include_path = v;
      ++i;
    } else {
      std::fprintf(stderr, "atmo_sky_occlusion_bench: unknown option %s\n", a.c_str());
      return 2;
    }
  }

  std::string error;
  auto gl = atmo::support::HeadlessGl::create(atmo::support::HeadlessGl::Profile::Core, &error);
  if (!gl) {
    std::fprintf(stderr, "no headless GL context: %s\n", error.c_str());
    return 1;
  }
  auto target = atmo::support::OffscreenTarget::create(width, height, &error);
  if (!target) {
    std::fprintf(stderr, "offscreen target: %s\n", error.c_str());
    return 1;
  }
  atmo::Plugin plugin(ATMO_PLUGIN_PATH, "atmo sky occlusion bench");
  if (!plugin.api().get_sky_occlusion) {
    std::fprintf(stderr, "the plugin has no sky occlusion (an older plugin)\n");
    return 1;
  }
  AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  services.gl_get_proc_address = &atmo::support::HeadlessGl::get_proc_address;
  services.log = [](void*, int32_t severity, const char* message) {
    if (severity >= ATMO_LOG_WARNING) std::fprintf(stderr, "[atmo] %s\n", message);
  };
  atmo::Context context(plugin, &services);
  context.gl_init();
  atmo::View view(context, 0);
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = kNoonUtc;
  context.set_frame(frame);

  // The camera 2 m above the apron's origin, looking north across it, 10 degrees down (the sky a third of the frame).
  const double aspect = double(width) / height;
  const glm::dmat4 projection = glm::perspective(glm::radians(kVfovDeg), aspect, 0.5, 1e5);
  const double pitch = glm::radians(kPitchDeg);
  const glm::dmat4 view_rotation =
      glm::lookAt(glm::dvec3(0.0), glm::dvec3(0.0, std::cos(pitch), std::sin(pitch)), glm::dvec3(0, 0, 1));
  AtmoViewState vs = atmo::support::example_view_state(width, height, target->depth_texture(), kEyeHeightM);
  std::memcpy(vs.view_from_world, glm::value_ptr(view_rotation), sizeof(vs.view_from_world));
  std::memcpy(vs.clip_from_view, glm::value_ptr(projection), sizeof(vs.clip_from_view));
  vs.exposure_scale = 1e-4;
  view.set(vs);
  const AtmoLighting lighting = view.lighting();

  // The host's programs.
  const std::string include = read_text(include_path);
  if (include.empty()) {
    std::fprintf(stderr, "cannot read %s\n", include_path.c_str());
    return 1;
  }
  const std::string head = "#version 400 core\n";
  const GLuint occluded = program_of(head + include + kPixelRay + kOccludedMain);
  // A host that never draws the bounce compiles it out (ATMO_OCC_NO_BOUNCE), as the "no bounce" mode does.
  const GLuint occluded_no_bounce =
      program_of(head + "#define ATMO_OCC_NO_BOUNCE\n" + include + kPixelRay + kOccludedMain);
  // Every pixel through the include reading the plugin's image (ATMO_PASS_SKY_OCCLUSION_IMAGE).
  const GLuint occluded_image = program_of(head + "#define ATMO_OCC_IMAGE\n" + include + kPixelRay + kOccludedMain);
  const GLuint answer = program_of(head + include + kPixelRay + kAnswerMain);
  const GLuint answer_image = program_of(head + "#define ATMO_OCC_IMAGE\n" + include + kPixelRay + kAnswerMain);
  const GLuint plain = program_of(head + kPixelRay + kPlainMain);
  const GLuint depth = program_of(head + kPixelRay + kDepthMain);
  const GLuint trivial = bench_gl::make_trivial_program();
  GLuint vao = 0;
  glGenVertexArrays(1, &vao);
  const glm::mat4 rel_from_clip(glm::inverse(projection * view_rotation));
  const glm::mat4 clip_from_rel(projection * view_rotation);
  const glm::vec3 sun_world(lighting.sun_direction_enu[0], lighting.sun_direction_enu[1], lighting.sun_direction_enu[2]);
  const glm::vec3 sun_lux(lighting.sun_illuminance_lux[0], lighting.sun_illuminance_lux[1], lighting.sun_illuminance_lux[2]);
  float sky_sh9[27];
  for (int k = 0; k < 9; ++k)
    for (int c = 0; c < 3; ++c) sky_sh9[3 * k + c] = float(lighting.sky_irradiance_sh9[k][c]);
  for (GLuint p : {occluded, occluded_no_bounce, occluded_image, answer, answer_image, plain, depth}) {
    glUseProgram(p);
    glUniformMatrix4fv(glGetUniformLocation(p, "rel_from_clip"), 1, GL_FALSE, glm::value_ptr(rel_from_clip));
    glUniformMatrix4fv(glGetUniformLocation(p, "clip_from_rel"), 1, GL_FALSE, glm::value_ptr(clip_from_rel));
    glUniform2f(glGetUniformLocation(p, "size"), float(width), float(height));
    glUniform1f(glGetUniformLocation(p, "eye_height"), float(kEyeHeightM));
    glUniform3fv(glGetUniformLocation(p, "sun_world"), 1, glm::value_ptr(sun_world));
    glUniform3fv(glGetUniformLocation(p, "sun_lux"), 1, glm::value_ptr(sun_lux));
    glUniform3fv(glGetUniformLocation(p, "sky_sh9"), 9, sky_sh9);
  }
  glUseProgram(0);
  auto full_screen = [&](GLuint program) {
    glUseProgram(program);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
  };

  std::vector<Case> cases;
  for (int k : {1, 2, 4, 8, 16, 32, 64, 128}) cases.push_back({16, k, k == 32 ? "spheres+objects" : "spheres"});
  for (int n : {1, 4, 64}) cases.push_back({n, 32, "objects"});

  std::FILE* csv = common.csv_path.empty() ? nullptr : std::fopen(common.csv_path.c_str(), "w");
  if (csv)
    std::fprintf(csv, "sweep,objects,spheres_per_object,mode,pair_ms,pair_spread,trivial_ms,plain_ms,include_ms,ratio_to_pair,"
                      "added_ratio_to_pair,pair_query_ms,include_query_ms,longest_tile_list,poses_cpu_ms,"
                      "get_sky_occlusion_cpu_ms,cpu_ms,pass_ratio_to_pair,pass_quarter_ratio_to_pair,"
                      "pass_eighth_ratio_to_pair,quarter_error_p50,quarter_error_p95,eighth_error_p50,eighth_error_p95,"
                      "no_sun_quarter_error_p50,no_sun_quarter_error_p95,no_sun_eighth_error_p50,no_sun_eighth_error_p95,"
                      "image_eighth_pass_ratio,image_eighth_host_ratio,image_eighth_ratio_to_pair,image_quarter_ratio_to_pair,"
                      "image_eighth_sky_error_p50,image_eighth_sky_error_p95,image_quarter_sky_error_p50,image_quarter_sky_error_p95,"
                      "image_eighth_sun_error_p50,image_eighth_sun_error_p95,image_quarter_sun_error_p50,"
                      "image_quarter_sun_error_p95,image_sixteenth_ratio_to_pair,image_sixteenth_sky_error_p50,"
                      "image_sixteenth_sky_error_p95,image_sixteenth_sun_error_p50,image_sixteenth_sun_error_p95,"
                      "image_eighth_no_sun_ratio_to_pair\n");
  std::printf("== %dx%d, %s, %d timed frames a case (wall time to glFinish, median) ==\n", width, height,
              gl->renderer().c_str(), common.frames);
  // x_pair: the include pass / the pair, median of the frames' ratios (each frame's pair timed before and after
  // the others); added_x: (include pass - the same pass from the SH9 alone) / the pair; spread: the slowest pair
  // of the case / its fastest (above ~1.2 the machine was shared); tiles: the longest tile list; pass_x, pass4_x,
  // pass8_x: ATMO_PASS_SKY_OCCLUSION over the ground (NORMAL_UP) at every pixel, a quarter and an eighth across,
  // / the pair; err4, err8: the 95th percentile of |factor - every pixel's factor| (green) over the pixels whose
  // every-pixel factor differs from 1 by 1 % or more; img8_x, img4_x: every pixel through the include with
  // ATMO_OCC_IMAGE (the image pass an eighth / a quarter across + the host pass) / the pair; ierr8: p95 of its
  // sky + bounce error / the open sky; isun8: p95 of its Sun's visibility's error.
  std::printf("%-8s %-8s %-15s %8s %7s %8s %8s %10s %8s %8s %6s %9s %9s %7s %7s %7s %7s %7s %7s %7s %7s %7s %7s %7s\n", "objects",
              "spheres", "mode", "pair_ms", "spread", "triv_ms", "plain_ms", "include_ms", "x_pair", "added_x", "tiles",
              "poses_ms", "get_ms", "pass_x", "pass4_x", "pass8_x", "err4", "err8", "img8_x", "img4_x", "img16_x", "ierr8",
              "ierr16", "isun8");
  Timer timer;
  for (const Case& c : cases) {
    const std::string name = std::to_string(c.objects) + " objects x " + std::to_string(c.spheres) + " spheres";
    if (common.skips(name)) continue;
    for (const Mode& mode : kModes) {
      Apron a = apron(c.objects, c.spheres);
      const AtmoOccludersState state = occluders_state(a, mode.flags);
      const AtmoResult r = plugin.api().set_occluders(context.handle(), &state);
      if (r != ATMO_SUCCESS) {
        std::fprintf(stderr, "set_occluders: %s\n", context.last_error().c_str());
        return 1;
      }
      std::vector<double> pair, pair_extremes, triv, plain_ms, inc, ratio, added, pair_q, inc_q, poses_cpu, get_cpu;
      std::vector<double> pass_ratio[3], error_p50[6], error_p95[6];
      std::vector<double> image_ratio[4], image_pass_ratio, image_host_ratio, image_p50[3], image_p95[3];
      std::vector<double> image_sun_p50[3], image_sun_p95[3];
      std::vector<double> moved(16 * a.poses.size());
      uint32_t longest = 0;
      for (int f = -1; f < common.frames; ++f) {  // frame -1 warms up (programs, tables)
        // Every object taxis 0.5 m along its heading.
        for (size_t i = 0; i < a.poses.size(); ++i) {
          a.poses[i] = glm::translate(a.poses[i], glm::dvec3(0.0, 0.5, 0.0));
          std::memcpy(&moved[16 * i], glm::value_ptr(a.poses[i]), 16 * sizeof(double));
        }
        auto poses = atmo::make<AtmoOccluderPoses>(ATMO_TYPE_OCCLUDER_POSES);
        poses.first = 0;
        poses.count = uint32_t(a.poses.size());
        poses.world_from_object = moved.data();
        const double t0 = now_ms();
        const AtmoResult pr = plugin.api().set_occluder_poses(context.handle(), &poses);
        const double t1 = now_ms();
        AtmoSkyOcclusion occ = atmo::make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
        const AtmoResult gr = plugin.api().get_sky_occlusion(view.handle(), &occ);
        const double t2 = now_ms();
        if (pr != ATMO_SUCCESS || gr != ATMO_SUCCESS) {
          std::fprintf(stderr, "set_occluder_poses / get_sky_occlusion: %s\n", context.last_error().c_str());
          return 1;
        }
        longest = occ.longest_tile_list;
        const GLuint shading = (mode.flags & ATMO_OCCLUSION_NO_BOUNCE) ? occluded_no_bounce : occluded;
        glUseProgram(shading);
        const atmo::host_scene::SkyOcclusionBinding binding(shading, occ, 0);  // as a host binds them
        glUseProgram(0);

        target->bind();
        glClearColor(0, 0, 0, 1);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        // The ground's depth (untimed), for the aerial-perspective pass.
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_ALWAYS);
        glDepthMask(GL_TRUE);
        full_screen(depth);
        glDisable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        double pq = 0.0, pq2 = 0.0, iq = 0.0, unused = 0.0;
        auto the_pair = [&] {
          view.render(ATMO_PASS_SKY);
          view.render(ATMO_PASS_AERIAL_PERSPECTIVE);
        };
        // The pair before and after the others: a frame's ratios use their mean (the machine may be shared).
        const double pair_before = timer(the_pair, &pq);
        const double trivial_ms = timer([&] { full_screen(trivial); }, &unused);
        const double p_ms = timer([&] { full_screen(plain); }, &unused);
        const double include_ms = timer([&] { full_screen(shading); }, &iq);
        // Every pixel through the include reading the plugin's image, an eighth (i = 0), a quarter (1) and a
        // sixteenth (2) across:
        // the image pass + the host pass, against the include at every pixel (once a frame, the default mode).
        const bool image_error = f >= 0 && mode.flags == 0;
        const size_t pixels = static_cast<size_t>(width) * height;
        std::vector<float> exact_rgba(image_error ? pixels * 4 : 0), image_rgba(exact_rgba.size());
        if (image_error) {
          glUseProgram(answer);
          const atmo::host_scene::SkyOcclusionBinding answer_binding(answer, occ, 0);
          full_screen(answer);
          glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, exact_rgba.data());
        }
        double image_ms[4] = {0.0, 0.0, 0.0, 0.0}, image_pass_ms = 0.0, image_host_ms = 0.0;
        for (int i = 0; i < 4; ++i) {
          // 3: an eighth across without the Sun's visibility (the host's shadow maps give the Sun's shadow).
          const uint32_t resolution[4] = {ATMO_PASS_SKY_OCCLUSION_EIGHTH_RES, ATMO_PASS_SKY_OCCLUSION_QUARTER_RES,
                                          ATMO_PASS_SKY_OCCLUSION_SIXTEENTH_RES,
                                          ATMO_PASS_SKY_OCCLUSION_EIGHTH_RES | ATMO_PASS_SKY_OCCLUSION_NO_SUN};
          const uint32_t flags = ATMO_PASS_SKY_OCCLUSION_IMAGE | ATMO_PASS_SKY_OCCLUSION_NORMAL_UP | resolution[i];
          const double pass_ms = timer([&] { view.render(ATMO_PASS_SKY_OCCLUSION, flags); }, &unused);
          AtmoSkyOcclusion with_image = atmo::make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
          if (plugin.api().get_sky_occlusion(view.handle(), &with_image) != ATMO_SUCCESS || !with_image.image[0]) {
            std::fprintf(stderr, "get_sky_occlusion after the image pass: no image (%s)\n", context.last_error().c_str());
            return 1;
          }
          target->bind();
          glUseProgram(occluded_image);
          const atmo::host_scene::SkyOcclusionBinding image_binding(occluded_image, with_image, 5);
          const double host_ms = timer([&] { full_screen(occluded_image); }, &unused);
          image_ms[i] = pass_ms + host_ms;
          if (i == 0) {
            image_pass_ms = pass_ms;
            image_host_ms = host_ms;
          }
          if (!image_error || i == 3) continue;
          {
            glUseProgram(answer_image);
            const atmo::host_scene::SkyOcclusionBinding answer_binding(answer_image, with_image, 5);
            full_screen(answer_image);
          }
          glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, image_rgba.data());
          std::vector<double> sky_diff, sun_diff;
          for (size_t k = 0; k < pixels * 4; k += 4) {
            const double open = exact_rgba[k + 2];
            if (open > 0.0 && std::abs(exact_rgba[k + 1] - open) >= 0.01 * open)
              sky_diff.push_back(std::abs(double(image_rgba[k + 1]) - exact_rgba[k + 1]) / open);
            if (exact_rgba[k] < 0.99f || image_rgba[k] < 0.99f)
              sun_diff.push_back(std::abs(double(image_rgba[k]) - exact_rgba[k]));
          }
          for (auto* v : {&sky_diff, &sun_diff}) std::sort(v->begin(), v->end());
          if (!sky_diff.empty()) {
            image_p50[i].push_back(sky_diff[sky_diff.size() / 2]);
            image_p95[i].push_back(sky_diff[sky_diff.size() * 95 / 100]);
          }
          if (!sun_diff.empty()) {
            image_sun_p50[i].push_back(sun_diff[sun_diff.size() / 2]);
            image_sun_p95[i].push_back(sun_diff[sun_diff.size() * 95 / 100]);
          }
        }
        // The plugin's pass over the ground (terrain: NORMAL_UP) at every pixel, a quarter and an eighth across,
        // on a colour of 1 (the framebuffer then holds the factor): its cost, and its factors against every pixel's.
        // The error again with ATMO_PASS_SKY_OCCLUSION_NO_SUN (the Sun's shadow left to the host's maps): r 3..5.
        double pass_ms[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        std::vector<float> full_factor, factor(static_cast<size_t>(width) * height * 4);
        for (int r = 0; r < 6; ++r) {
          if (r >= 3 && (f < 0 || mode.flags != 0)) break;
          const uint32_t resolution[3] = {0u, ATMO_PASS_SKY_OCCLUSION_QUARTER_RES, ATMO_PASS_SKY_OCCLUSION_EIGHTH_RES};
          const uint32_t flags = ATMO_PASS_SKY_OCCLUSION_NORMAL_UP | resolution[r % 3] |
                                 (r >= 3 ? uint32_t(ATMO_PASS_SKY_OCCLUSION_NO_SUN) : 0u);
          glClearColor(1, 1, 1, 1);
          glClear(GL_COLOR_BUFFER_BIT);
          pass_ms[r] = timer([&] { view.render(ATMO_PASS_SKY_OCCLUSION, flags); }, &unused);
          if (f < 0 || mode.flags != 0) continue;  // the error once a frame, in the default mode
          glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, factor.data());
          if (r % 3 == 0) {
            full_factor = factor;
            continue;
          }
          std::vector<double> diff;
          for (size_t k = 0; k < factor.size(); k += 4)
            if (std::abs(full_factor[k + 1] - 1.0f) > 0.01f)  // the pixels the objects change (by 1 % or more)
              diff.push_back(std::abs(factor[k + 1] - full_factor[k + 1]));
          std::sort(diff.begin(), diff.end());
          if (!diff.empty()) {
            error_p50[r].push_back(diff[diff.size() / 2]);
            error_p95[r].push_back(diff[diff.size() * 95 / 100]);
          }
        }
        const double pair_after = timer(the_pair, &pq2);
        glDepthMask(GL_TRUE);
        if (f < 0) continue;
        const double pair_ms = 0.5 * (pair_before + pair_after);
        pair.push_back(pair_ms);
        pair_extremes.push_back(pair_before);
        pair_extremes.push_back(pair_after);
        triv.push_back(trivial_ms);
        plain_ms.push_back(p_ms);
        inc.push_back(include_ms);
        ratio.push_back(include_ms / pair_ms);
        added.push_back((include_ms - p_ms) / pair_ms);
        pair_q.push_back(0.5 * (pq + pq2));
        inc_q.push_back(iq);
        poses_cpu.push_back(t1 - t0);
        get_cpu.push_back(t2 - t1);
        for (int r = 0; r < 3; ++r) pass_ratio[r].push_back(pass_ms[r] / pair_ms);  // with the Sun
        for (int i = 0; i < 4; ++i) image_ratio[i].push_back(image_ms[i] / pair_ms);
        image_pass_ratio.push_back(image_pass_ms / pair_ms);
        image_host_ratio.push_back(image_host_ms / pair_ms);
      }
      for (int i = 0; i < 8; ++i) {
        glActiveTexture(GL_TEXTURE0 + i);
        glBindTexture(GL_TEXTURE_2D, 0);
      }
      glActiveTexture(GL_TEXTURE0);
      if (const GLenum e = glGetError(); e != GL_NO_ERROR) std::fprintf(stderr, "GL error 0x%x\n", e);
      const double p = median(pair), t = median(triv), pl = median(plain_ms), in = median(inc);
      const double x = median(ratio), ax = median(added);
      const double spread = *std::max_element(pair_extremes.begin(), pair_extremes.end()) /
                            *std::min_element(pair_extremes.begin(), pair_extremes.end());
      const double pc = median(poses_cpu), gc = median(get_cpu);
      auto med = [&](std::vector<double>& v) { return v.empty() ? 0.0 : median(v); };
      const double px[3] = {med(pass_ratio[0]), med(pass_ratio[1]), med(pass_ratio[2])};
      std::printf("%-8d %-8d %-15s %8.1f %7.2f %8.1f %8.1f %10.1f %8.2f %8.2f %6u %9.3f %9.3f %7.2f %7.2f %7.2f %7.4f "
                  "%7.4f %7.2f %7.2f %7.2f %7.4f %7.4f %7.4f\n",
                  c.objects, c.spheres, mode.name, p, spread, t, pl, in, x, ax, longest, pc, gc, px[0], px[1], px[2],
                  med(error_p95[1]), med(error_p95[2]), med(image_ratio[0]), med(image_ratio[1]), med(image_ratio[2]),
                  med(image_p95[0]), med(image_p95[2]), med(image_sun_p95[0]));
      std::fflush(stdout);
      if (csv) {
        std::stringstream sweeps(c.sweeps);
        for (std::string sweep; std::getline(sweeps, sweep, '+');)
          std::fprintf(csv,
                       "%s,%d,%d,%s,%.2f,%.3f,%.2f,%.2f,%.2f,%.4f,%.4f,%.2f,%.2f,%u,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.5f,"
                       "%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%.5f,%.5f,%.5f,%.5f,%.4f\n",
                       sweep.c_str(), c.objects, c.spheres, mode.name, p, spread, t, pl, in, x, ax, median(pair_q),
                       median(inc_q), longest, pc, gc, pc + gc, px[0], px[1], px[2], med(error_p50[1]),
                       med(error_p95[1]), med(error_p50[2]), med(error_p95[2]), med(error_p50[4]), med(error_p95[4]),
                       med(error_p50[5]), med(error_p95[5]), med(image_pass_ratio), med(image_host_ratio),
                       med(image_ratio[0]), med(image_ratio[1]), med(image_p50[0]), med(image_p95[0]), med(image_p50[1]),
                       med(image_p95[1]), med(image_sun_p50[0]), med(image_sun_p95[0]), med(image_sun_p50[1]),
                       med(image_sun_p95[1]), med(image_ratio[2]), med(image_p50[2]), med(image_p95[2]),
                       med(image_sun_p50[2]), med(image_sun_p95[2]), med(image_ratio[3]));
        std::fflush(csv);
      }
    }
  }
  if (csv) std::fclose(csv);
  glDeleteVertexArrays(1, &vao);
  for (GLuint p : {occluded, occluded_no_bounce, occluded_image, answer, answer_image, plain, depth, trivial})
    glDeleteProgram(p);
  return 0;
}
