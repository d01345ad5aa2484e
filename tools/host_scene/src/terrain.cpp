#include "atmo_host_scene/terrain.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <iterator>
#include <optional>

#include <glad/gl.h>

#include "atmo_host_scene/fog_lighting_binding.h"
#include "atmo_host_scene/gl_program.h"

namespace atmo::host_scene {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Runway decals float this far above the flat ground they lie on; depth writes
// are off for them, so they never fight with each other, only sit over terrain.
constexpr double kRunwayLiftM = 0.25;
constexpr double kLightHeightM = 0.5;
// Flat area around the runway (half sizes beyond the runway ends / axis) and
// the distance over which the hills blend in.
constexpr double kFlatBeyondEndsM = 1100.0;
constexpr double kFlatHalfWidthM = 250.0;
constexpr double kFlatBlendM = 1000.0;
constexpr double kCorridorHalfWidthM = 800.0;

const glm::vec3 kGrassAlbedo(0.10f, 0.15f, 0.06f);
const glm::vec3 kRockAlbedo(0.24f, 0.22f, 0.20f);
const glm::vec3 kAsphaltAlbedo(0.07f, 0.07f, 0.075f);
const glm::vec3 kPaintAlbedo(0.60f, 0.60f, 0.60f);

uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Deterministic lattice value in [0, 1).
double lattice(uint64_t seed, int64_t ix, int64_t iy, int octave) {
  uint64_t h = splitmix64(seed ^ 0x5851F42D4C957F2Dull);
  h = splitmix64(h ^ static_cast<uint64_t>(ix));
  h = splitmix64(h ^ static_cast<uint64_t>(iy));
  h = splitmix64(h ^ static_cast<uint64_t>(octave));
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

double fade(double t) { return t * t * (3.0 - 2.0 * t); }

double value_noise(uint64_t seed, double x, double y, int octave) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  const double tx = fade(x - fx), ty = fade(y - fy);
  const double a = lattice(seed, ix, iy, octave), b = lattice(seed, ix + 1, iy, octave);
  const double c = lattice(seed, ix, iy + 1, octave), d = lattice(seed, ix + 1, iy + 1, octave);
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

const char* kSurfaceVertex = R"(
layout(location = 0) in vec3 a_pos_hi;
layout(location = 1) in vec3 a_pos_lo;
layout(location = 2) in vec3 a_normal;
layout(location = 3) in vec3 a_albedo;
uniform mat4 u_clip_from_rel;  // projection * view rotation; positions are eye-relative
uniform vec3 u_eye_hi;
uniform vec3 u_eye_lo;
out vec3 v_normal;
out vec3 v_albedo;
out vec3 v_rel;
#ifdef LOG_DEPTH
out float v_w;
#endif
void main() {
  vec3 rel = (a_pos_hi - u_eye_hi) + (a_pos_lo - u_eye_lo);
  gl_Position = u_clip_from_rel * vec4(rel, 1.0);
  v_rel = rel;
  v_normal = a_normal;
  v_albedo = a_albedo;
#ifdef LOG_DEPTH
  v_w = gl_Position.w;  // = view-space distance along -z for a perspective matrix
#endif
}
)";

const char* kSurfaceFragment = R"(
in vec3 v_normal;
in vec3 v_albedo;
in vec3 v_rel;
#ifdef LOG_DEPTH
in float v_w;
uniform float u_log_c;
uniform float u_log_inv;  // 1 / log2(C * far + 1)
#endif
uniform vec3 u_sun_dir;
uniform vec3 u_sun_lux;
uniform vec3 u_sky_lux;
uniform float u_exposure;
layout(location = 0) out vec4 o_color;
void main() {
  vec3 n = normalize(v_normal);
  // Lambert: sun plus a hemispherical sky ambient (full when facing up).
  vec3 e = u_sun_lux * max(dot(n, u_sun_dir), 0.0) + u_sky_lux * (0.5 + 0.5 * n.z);
  vec3 radiance = v_albedo * (1.0 / 3.14159265) * e;
#ifdef FOG_LIGHTS
  // The plugin's lights in its fog (atmo_fog_lights.glsl): Lambertian albedo / pi plus a faint gloss.
  radiance += atmo_fog_lights_surface(v_rel, n, v_albedo * (1.0 / 3.14159265), vec3(0.03), 16.0);
#endif
  o_color = vec4(radiance * u_exposure, 1.0);
#ifdef LOG_DEPTH
  gl_FragDepth = log2(u_log_c * v_w + 1.0) * u_log_inv;
#endif
}
)";

const char* kPointVertex = R"(
layout(location = 0) in vec3 a_pos_hi;
layout(location = 1) in vec3 a_pos_lo;
layout(location = 2) in vec3 a_rgb_cd;
uniform mat4 u_clip_from_rel;
uniform vec3 u_eye_hi;
uniform vec3 u_eye_lo;
uniform float u_point_size;
uniform float u_radiance_scale;  // exposure / (pixel solid angle * point size^2)
out vec3 v_radiance;
#ifdef LOG_DEPTH
out float v_w;
#endif
void main() {
  vec3 rel = (a_pos_hi - u_eye_hi) + (a_pos_lo - u_eye_lo);
  gl_Position = u_clip_from_rel * vec4(rel, 1.0);
  gl_PointSize = u_point_size;
  // Illuminance at the eye I / d^2 spread over the point's solid angle.
  v_radiance = a_rgb_cd / max(dot(rel, rel), 1.0) * u_radiance_scale;
#ifdef LOG_DEPTH
  v_w = gl_Position.w;
#endif
}
)";

const char* kPointFragment = R"(
in vec3 v_radiance;
#ifdef LOG_DEPTH
in float v_w;
uniform float u_log_c;
uniform float u_log_inv;
#endif
layout(location = 0) out vec4 o_color;
void main() {
  o_color = vec4(v_radiance, 1.0);
#ifdef LOG_DEPTH
  gl_FragDepth = log2(u_log_c * v_w + 1.0) * u_log_inv;
#endif
}
)";

struct LightVertex {
  float position_hi[3];
  float position_lo[3];
  float rgb_cd[3];
};

void split(const glm::dvec3& p, float hi[3], float lo[3]) {
  for (int i = 0; i < 3; ++i) {
    hi[i] = static_cast<float>(p[i]);
    lo[i] = static_cast<float>(p[i] - static_cast<double>(hi[i]));
  }
}

// Saves and restores the GL state draw() changes.
class SavedState {
 public:
  SavedState() {
    glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao_);
    blend_ = glIsEnabled(GL_BLEND);
    glGetIntegerv(GL_BLEND_SRC_RGB, &blend_src_rgb_);
    glGetIntegerv(GL_BLEND_DST_RGB, &blend_dst_rgb_);
    glGetIntegerv(GL_BLEND_SRC_ALPHA, &blend_src_alpha_);
    glGetIntegerv(GL_BLEND_DST_ALPHA, &blend_dst_alpha_);
    glGetIntegerv(GL_BLEND_EQUATION_RGB, &blend_eq_rgb_);
    glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &blend_eq_alpha_);
    GLboolean mask = GL_TRUE;
    glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    depth_mask_ = mask;
    offset_fill_ = glIsEnabled(GL_POLYGON_OFFSET_FILL);
    glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &offset_factor_);
    glGetFloatv(GL_POLYGON_OFFSET_UNITS, &offset_units_);
    point_size_ = glIsEnabled(GL_PROGRAM_POINT_SIZE);
    cull_ = glIsEnabled(GL_CULL_FACE);
  }
  ~SavedState() {
    glUseProgram(static_cast<GLuint>(program_));
    glBindVertexArray(static_cast<GLuint>(vao_));
    set(GL_BLEND, blend_);
    glBlendFuncSeparate(static_cast<GLenum>(blend_src_rgb_), static_cast<GLenum>(blend_dst_rgb_),
                        static_cast<GLenum>(blend_src_alpha_), static_cast<GLenum>(blend_dst_alpha_));
    glBlendEquationSeparate(static_cast<GLenum>(blend_eq_rgb_), static_cast<GLenum>(blend_eq_alpha_));
    glDepthMask(depth_mask_ ? GL_TRUE : GL_FALSE);
    set(GL_POLYGON_OFFSET_FILL, offset_fill_);
    glPolygonOffset(offset_factor_, offset_units_);
    set(GL_PROGRAM_POINT_SIZE, point_size_);
    set(GL_CULL_FACE, cull_);
  }
  SavedState(const SavedState&) = delete;
  SavedState& operator=(const SavedState&) = delete;

 private:
  static void set(GLenum cap, GLboolean on) {
    if (on) {
      glEnable(cap);
    } else {
      glDisable(cap);
    }
  }
  GLint program_ = 0, vao_ = 0;
  GLboolean blend_ = GL_FALSE;
  GLint blend_src_rgb_ = 0, blend_dst_rgb_ = 0, blend_src_alpha_ = 0, blend_dst_alpha_ = 0;
  GLint blend_eq_rgb_ = 0, blend_eq_alpha_ = 0;
  GLboolean depth_mask_ = GL_TRUE;
  GLboolean offset_fill_ = GL_FALSE;
  GLfloat offset_factor_ = 0, offset_units_ = 0;
  GLboolean point_size_ = GL_FALSE;
  GLboolean cull_ = GL_FALSE;
};

void set_common_uniforms(GLuint program, const glm::mat4& clip_from_rel, const float eye_hi[3],
                         const float eye_lo[3], const ViewSetup& view) {
  glUniformMatrix4fv(glGetUniformLocation(program, "u_clip_from_rel"), 1, GL_FALSE, &clip_from_rel[0][0]);
  glUniform3fv(glGetUniformLocation(program, "u_eye_hi"), 1, eye_hi);
  glUniform3fv(glGetUniformLocation(program, "u_eye_lo"), 1, eye_lo);
  if (view.depth_convention == DepthConvention::Logarithmic) {
    const double c = kLogDepthCoefficient;
    glUniform1f(glGetUniformLocation(program, "u_log_c"), static_cast<float>(c));
    glUniform1f(glGetUniformLocation(program, "u_log_inv"),
                static_cast<float>(1.0 / std::log2(c * view.far_m + 1.0)));
  }
}

}  // namespace

double curvature_drop_m(double east_m, double north_m) {
  return (east_m * east_m + north_m * north_m) / (2.0 * kEarthRadiusM);
}

SceneLighting lighting_from_atmo(const AtmoLighting& lighting) {
  SceneLighting out;
  out.sun_direction_enu = glm::dvec3(lighting.sun_direction_enu[0], lighting.sun_direction_enu[1],
                                     lighting.sun_direction_enu[2]);
  const double len = glm::length(out.sun_direction_enu);
  out.sun_direction_enu = len > 0 ? out.sun_direction_enu / len : glm::dvec3(0, 0, 1);
  out.sun_illuminance_lux = glm::dvec3(lighting.sun_illuminance_lux[0], lighting.sun_illuminance_lux[1],
                                       lighting.sun_illuminance_lux[2]);
  // One directional light, as many hosts have: the Moon takes the Sun's place when it gives more light.
  const glm::dvec3 moon_lux(lighting.moon_illuminance_lux[0], lighting.moon_illuminance_lux[1],
                            lighting.moon_illuminance_lux[2]);
  const glm::dvec3 moon_dir(lighting.moon_direction_enu[0], lighting.moon_direction_enu[1],
                            lighting.moon_direction_enu[2]);
  if (moon_lux.y > out.sun_illuminance_lux.y && glm::length(moon_dir) > 0.0) {
    out.sun_direction_enu = glm::normalize(moon_dir);
    out.sun_illuminance_lux = moon_lux;
  }
  // The plugin's sky illuminance on a horizontal surface (the terrain's
  // ambient term), plus a floor of starlight-level light so night is not 0.
  out.sky_ambient_lux = glm::dvec3(lighting.sky_illuminance_horizontal_lux[0], lighting.sky_illuminance_horizontal_lux[1],
                                   lighting.sky_illuminance_horizontal_lux[2]) +
                        glm::dvec3(0.001);
  return out;
}

Terrain::Terrain(const TerrainOptions& options) : options_(options) {
  if (options_.kind == TerrainOptions::Kind::None) return;
  grid_ = std::max(options_.grid, 2);
  build_heights();
  build_mesh();
  build_runway();
  build_lights();
}

glm::dvec3 Terrain::runway_to_enu(double along_m, double across_m, double up_m) const {
  const double h = glm::radians(options_.runway_heading_deg);
  const glm::dvec2 axis(std::sin(h), std::cos(h));
  const glm::dvec2 right(std::cos(h), -std::sin(h));
  const glm::dvec2 p = axis * along_m + right * across_m;
  return glm::dvec3(p, height_at(p.x, p.y) + up_m - curvature_drop_m(p.x, p.y));
}

double Terrain::raw_height(double east_m, double north_m) const {
  // fBm of value noise, 5 octaves from a quarter of the terrain size down.
  const double base = options_.size_m / 4.0;
  double sum = 0.0, amplitude = 1.0, total = 0.0, frequency = 1.0 / base;
  for (int octave = 0; octave < 5; ++octave) {
    sum += amplitude * value_noise(options_.seed, east_m * frequency, north_m * frequency, octave);
    total += amplitude;
    amplitude *= 0.5;
    frequency *= 2.0;
  }
  const double fbm = sum / total;  // [0, 1], mostly around 0.5
  const double hills = options_.relief_m * smoothstep(0.3, 0.8, fbm);

  // Flat runway area: hills fade in with the distance from its rectangle.
  const double h = glm::radians(options_.runway_heading_deg);
  const double along = east_m * std::sin(h) + north_m * std::cos(h);
  const double across = east_m * std::cos(h) - north_m * std::sin(h);
  const double dx = std::max(std::abs(along) - (0.5 * options_.runway_length_m + kFlatBeyondEndsM), 0.0);
  const double dy = std::max(std::abs(across) - kFlatHalfWidthM, 0.0);
  double height = hills * smoothstep(0.0, kFlatBlendM, std::hypot(dx, dy));
  // Approach corridors off both ends: hills stay below half the 3 degree glide
  // path, so an approach (and approach_path in the sample host) clears them.
  const double beyond = std::abs(along) - 0.5 * options_.runway_length_m;
  if (beyond > 0.0) {
    const double cap = 0.5 * std::tan(glm::radians(3.0)) * beyond;
    const double corridor = 1.0 - smoothstep(kCorridorHalfWidthM, kCorridorHalfWidthM + kFlatBlendM, std::abs(across));
    height += (std::min(height, cap) - height) * corridor;
  }
  return height;
}

void Terrain::build_heights() {
  const int n = grid_;
  const double step = options_.size_m / (n - 1);
  const double half = 0.5 * options_.size_m;
  heights_.resize(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      heights_[static_cast<size_t>(j) * n + i] = static_cast<float>(raw_height(-half + i * step, -half + j * step));
    }
  }
}

double Terrain::height_at(double east_m, double north_m) const {
  if (heights_.empty()) return 0.0;
  const int n = grid_;
  const double step = options_.size_m / (n - 1);
  const double x = (east_m + 0.5 * options_.size_m) / step;
  const double y = (north_m + 0.5 * options_.size_m) / step;
  if (x < 0 || y < 0 || x > n - 1 || y > n - 1) return 0.0;
  const int i = std::min(static_cast<int>(x), n - 2), j = std::min(static_cast<int>(y), n - 2);
  const double tx = x - i, ty = y - j;
  auto at = [&](int a, int b) { return static_cast<double>(heights_[static_cast<size_t>(b) * n + a]); };
  const double h0 = at(i, j) + (at(i + 1, j) - at(i, j)) * tx;
  const double h1 = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * tx;
  return h0 + (h1 - h0) * ty;
}

Terrain::Vertex Terrain::make_vertex(const glm::dvec3& p, const glm::dvec3& n, const glm::vec3& albedo) const {
  Vertex v{};
  split(p, v.position_hi, v.position_lo);
  for (int k = 0; k < 3; ++k) {
    v.normal[k] = static_cast<float>(n[k]);
    v.albedo[k] = albedo[k];
  }
  return v;
}

void Terrain::build_mesh() {
  const int n = grid_;
  const double step = options_.size_m / (n - 1);
  const double half = 0.5 * options_.size_m;
  // Final heights, curvature included, so normals follow the sphere too.
  auto z = [&](int i, int j) {
    i = std::clamp(i, 0, n - 1);
    j = std::clamp(j, 0, n - 1);
    const double x = -half + i * step, y = -half + j * step;
    return static_cast<double>(heights_[static_cast<size_t>(j) * n + i]) - curvature_drop_m(x, y);
  };
  terrain_vertices_.clear();
  terrain_vertices_.reserve(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = -half + i * step, y = -half + j * step;
      const double dzdx = (z(i + 1, j) - z(i - 1, j)) / ((std::min(i + 1, n - 1) - std::max(i - 1, 0)) * step);
      const double dzdy = (z(i, j + 1) - z(i, j - 1)) / ((std::min(j + 1, n - 1) - std::max(j - 1, 0)) * step);
      const glm::dvec3 normal = glm::normalize(glm::dvec3(-dzdx, -dzdy, 1.0));
      // Rock on steep slopes, grass elsewhere, with a little seeded variation.
      const float rock = static_cast<float>(smoothstep(0.12, 0.35, 1.0 - normal.z));
      const float jitter = static_cast<float>(0.85 + 0.3 * lattice(options_.seed + 7, i, j, 99));
      const glm::vec3 albedo = glm::mix(kGrassAlbedo, kRockAlbedo, rock) * jitter;
      terrain_vertices_.push_back(make_vertex(glm::dvec3(x, y, z(i, j)), normal, albedo));
    }
  }
  terrain_indices_.clear();
  terrain_indices_.reserve(static_cast<size_t>(n - 1) * (n - 1) * 6);
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = static_cast<uint32_t>(j * n + i), b = a + 1;
      const uint32_t c = a + static_cast<uint32_t>(n), d = c + 1;
      terrain_indices_.insert(terrain_indices_.end(), {a, b, d, a, d, c});  // counter-clockwise from above
    }
  }
}

void Terrain::add_runway_quad(double u0, double u1, double v0, double v1, double lift_m, const glm::vec3& albedo) {
  // Pieces of at most 100 m so the quad follows the curvature drop.
  const int pieces = std::max(1, static_cast<int>(std::ceil((u1 - u0) / 100.0)));
  for (int k = 0; k < pieces; ++k) {
    const double a = u0 + (u1 - u0) * k / pieces, b = u0 + (u1 - u0) * (k + 1) / pieces;
    const glm::dvec3 p00 = runway_to_enu(a, v0, lift_m), p10 = runway_to_enu(b, v0, lift_m);
    const glm::dvec3 p01 = runway_to_enu(a, v1, lift_m), p11 = runway_to_enu(b, v1, lift_m);
    const glm::dvec3 centre = 0.25 * (p00 + p10 + p01 + p11);
    // Up of the sphere at the quad (the ground under it is flat).
    const glm::dvec3 up = glm::normalize(glm::dvec3(-centre.x / kEarthRadiusM, -centre.y / kEarthRadiusM, 1.0));
    for (const glm::dvec3& p : {p00, p10, p11, p00, p11, p01}) runway_vertices_.push_back(make_vertex(p, up, albedo));
  }
}

void Terrain::build_runway() {
  const double half_l = 0.5 * options_.runway_length_m;
  const double half_w = 0.5 * options_.runway_width_m;
  runway_vertices_.clear();
  add_runway_quad(-half_l, half_l, -half_w, half_w, kRunwayLiftM, kAsphaltAlbedo);
  asphalt_vertex_count_ = runway_vertices_.size();

  // Markings (drawn after the asphalt with depth writes off: painter's order).
  for (double side : {-1.0, 1.0}) {
    // Edge lines.
    add_runway_quad(-half_l, half_l, side * half_w - (side > 0 ? 0.9 : 0.0),
                    side * half_w + (side < 0 ? 0.9 : 0.0), kRunwayLiftM, kPaintAlbedo);
    for (double end : {-1.0, 1.0}) {
      // Threshold bars: 6 per side of the axis, 30 m long, 6 m in from the end.
      const double u_start = end < 0 ? -half_l + 6.0 : half_l - 36.0;
      for (int k = 0; k < 6; ++k) {
        const double v0 = 3.0 + 3.0 * k, v1 = v0 + 1.5;
        add_runway_quad(u_start, u_start + 30.0, side * (side > 0 ? v0 : v1), side * (side > 0 ? v1 : v0),
                        kRunwayLiftM, kPaintAlbedo);
      }
      // Aiming-point blocks, 60 m long, 400 m from the end.
      const double a0 = end < 0 ? -half_l + 400.0 : half_l - 460.0;
      add_runway_quad(a0, a0 + 60.0, side > 0 ? 7.0 : -17.0, side > 0 ? 17.0 : -7.0, kRunwayLiftM, kPaintAlbedo);
    }
  }
  // Centreline: 30 m dashes, 20 m gaps, 0.9 m wide.
  for (double u = -half_l + 60.0; u + 30.0 <= half_l - 60.0; u += 50.0) {
    add_runway_quad(u, u + 30.0, -0.45, 0.45, kRunwayLiftM, kPaintAlbedo);
  }
}

void Terrain::build_lights() {
  const double half_l = 0.5 * options_.runway_length_m;
  const double half_w = 0.5 * options_.runway_width_m;
  const double threshold = -half_l;  // approach end
  const glm::vec3 white(1.0f, 0.93f, 0.80f), green(0.10f, 1.0f, 0.25f), red(1.0f, 0.05f, 0.02f);
  auto add = [&](double u, double v, const glm::vec3& color, float cd) {
    lights_.push_back(LightPoint{runway_to_enu(u, v, kLightHeightM), color, cd});
  };
  lights_.clear();
  for (int bar = 1; bar <= kApproachBars; ++bar) {
    for (int k = 0; k < kApproachBarLights; ++k) {
      add(threshold - bar * kApproachBarSpacingM, k - 0.5 * (kApproachBarLights - 1), white, 20000.0f);
    }
  }
  for (int k = 0; k < kCrossbarLights; ++k) {
    const int half = kCrossbarLights / 2;
    const double offset = 3.0 + 1.5 * (k % half);
    add(threshold - 300.0, k < half ? -offset : offset, white, 20000.0f);
  }
  for (int k = 0; k < kThresholdLights; ++k) {
    const double v = -half_w + k * (2.0 * half_w) / (kThresholdLights - 1);
    add(threshold - 1.0, v, green, 10000.0f);
    add(half_l + 1.0, v, red, 5000.0f);
  }
  const int edge = static_cast<int>(std::floor(options_.runway_length_m / kEdgeLightSpacingM + 1e-9)) + 1;
  for (int k = 0; k < edge; ++k) {
    const double u = -half_l + k * kEdgeLightSpacingM;
    add(u, -half_w - 1.5, white, 10000.0f);
    add(u, half_w + 1.5, white, 10000.0f);
  }
}

AtmoLightsState lights_state_enu(const Geodetic& origin, const std::vector<AtmoLightPoint>& points,
                                 double glow_threshold_cd_m2) {
  AtmoLightsState s{};
  s.header.type = ATMO_TYPE_LIGHTS_STATE;
  s.header.struct_size = sizeof(s);
  s.world_frame = ATMO_WORLD_ENU;
  s.light_size = sizeof(AtmoLightPoint);
  s.world_origin_geodetic[0] = origin.latitude_deg;
  s.world_origin_geodetic[1] = origin.longitude_deg;
  s.world_origin_geodetic[2] = origin.height_m;
  s.lights = points.empty() ? nullptr : points.data();
  s.light_count = static_cast<uint32_t>(points.size());
  s.glow_threshold_cd_m2 = glow_threshold_cd_m2;
  return s;
}

std::vector<AtmoLightPoint> Terrain::atmo_light_points() const {
  const double h = glm::radians(options_.runway_heading_deg);
  const glm::dvec3 axis(-std::sin(h), -std::cos(h), std::tan(glm::radians(3.0)));
  std::vector<AtmoLightPoint> points;
  points.reserve(lights_.size());
  for (const LightPoint& l : lights_) {
    AtmoLightPoint p{};
    for (int k = 0; k < 3; ++k) {
      p.position_m[k] = l.position_enu_m[k];
      p.color[k] = l.color[k];
      p.direction[k] = axis[k];
    }
    p.intensity_cd = l.intensity_cd;
    p.cone_inner_rad = glm::radians(10.0);
    p.cone_outer_rad = glm::radians(25.0);
    points.push_back(p);
  }
  return points;
}

bool Terrain::gl_init(std::string* error) {
  if (gl_ready_) return true;
  if (options_.kind == TerrainOptions::Kind::None) {
    gl_ready_ = true;
    return true;
  }
  // The host SDK's fog include, pasted after the defines (as a host without #include does).
  std::string fog_include;
  {
    std::ifstream in(ATMO_HOST_SDK_INCLUDE_DIR "/atmo/atmo_fog_lights.glsl");
    if (!in) {
      *error = "cannot read " ATMO_HOST_SDK_INCLUDE_DIR "/atmo/atmo_fog_lights.glsl";
      return false;
    }
    fog_include.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  for (int variant = 0; variant < 2; ++variant) {
    const std::string defines = variant == 1 ? "#define LOG_DEPTH 1\n" : "";
    fog_program_[variant] = build_program(kSurfaceVertex, kSurfaceFragment, defines + "#define FOG_LIGHTS 1\n" + fog_include,
                                          "host_scene terrain in fog", error);
    if (!fog_program_[variant]) {
      gl_shutdown();
      return false;
    }
    surface_program_[variant] =
        build_program(kSurfaceVertex, kSurfaceFragment, defines, "host_scene terrain", error);
    point_program_[variant] = surface_program_[variant]
                                  ? build_program(kPointVertex, kPointFragment, defines,
                                                          "host_scene light points", error)
                                  : 0;
    if (!point_program_[variant]) {
      gl_shutdown();
      return false;
    }
  }

  GLint old_vao = 0, old_array = 0;
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &old_vao);
  glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &old_array);

  auto surface_layout = [](GLuint vao, GLuint vbo, const std::vector<Vertex>& vertices) {
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(),
                 GL_STATIC_DRAW);
    const size_t offsets[4] = {offsetof(Vertex, position_hi), offsetof(Vertex, position_lo),
                               offsetof(Vertex, normal), offsetof(Vertex, albedo)};
    for (GLuint k = 0; k < 4; ++k) {
      glEnableVertexAttribArray(k);
      glVertexAttribPointer(k, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<const void*>(offsets[k]));
    }
  };

  glGenVertexArrays(1, &terrain_vao_);
  glGenBuffers(1, &terrain_vbo_);
  glGenBuffers(1, &terrain_ibo_);
  surface_layout(terrain_vao_, terrain_vbo_, terrain_vertices_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, terrain_ibo_);  // recorded in the VAO
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(terrain_indices_.size() * sizeof(uint32_t)),
               terrain_indices_.data(), GL_STATIC_DRAW);

  glGenVertexArrays(1, &runway_vao_);
  glGenBuffers(1, &runway_vbo_);
  surface_layout(runway_vao_, runway_vbo_, runway_vertices_);

  std::vector<LightVertex> lights;
  lights.reserve(lights_.size());
  for (const LightPoint& l : lights_) {
    LightVertex v{};
    split(l.position_enu_m, v.position_hi, v.position_lo);
    for (int k = 0; k < 3; ++k) v.rgb_cd[k] = l.color[k] * l.intensity_cd;
    lights.push_back(v);
  }
  glGenVertexArrays(1, &light_vao_);
  glGenBuffers(1, &light_vbo_);
  glBindVertexArray(light_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, light_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lights.size() * sizeof(LightVertex)), lights.data(),
               GL_STATIC_DRAW);
  const size_t offsets[3] = {offsetof(LightVertex, position_hi), offsetof(LightVertex, position_lo),
                             offsetof(LightVertex, rgb_cd)};
  for (GLuint k = 0; k < 3; ++k) {
    glEnableVertexAttribArray(k);
    glVertexAttribPointer(k, 3, GL_FLOAT, GL_FALSE, sizeof(LightVertex), reinterpret_cast<const void*>(offsets[k]));
  }

  glBindVertexArray(static_cast<GLuint>(old_vao));
  glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(old_array));
  gl_ready_ = true;
  return true;
}

void Terrain::gl_shutdown() {
  for (int variant = 0; variant < 2; ++variant) {
    if (surface_program_[variant]) glDeleteProgram(surface_program_[variant]);
    if (point_program_[variant]) glDeleteProgram(point_program_[variant]);
    if (fog_program_[variant]) glDeleteProgram(fog_program_[variant]);
    surface_program_[variant] = point_program_[variant] = fog_program_[variant] = 0;
  }
  for (unsigned* vao : {&terrain_vao_, &runway_vao_, &light_vao_}) {
    if (*vao) glDeleteVertexArrays(1, vao);
    *vao = 0;
  }
  for (unsigned* buffer : {&terrain_vbo_, &terrain_ibo_, &runway_vbo_, &light_vbo_}) {
    if (*buffer) glDeleteBuffers(1, buffer);
    *buffer = 0;
  }
  gl_ready_ = false;
}

void Terrain::draw(const ViewSetup& view, const SceneLighting& lighting, const AtmoFogLighting* fog) const {
  if (!gl_ready_ || options_.kind == TerrainOptions::Kind::None) return;
  const SavedState saved;

  // Eye-relative rendering: only the view's rotation goes to the GPU.
  const glm::dmat4 rotation(glm::dmat3(view_from_enu(view)));
  const glm::mat4 clip_from_rel(clip_from_view(view) * rotation);
  float eye_hi[3], eye_lo[3];
  split(view.pose.position_enu_m, eye_hi, eye_lo);
  const int variant = view.depth_convention == DepthConvention::Logarithmic ? 1 : 0;
  const glm::vec3 sun_dir(lighting.sun_direction_enu);
  const glm::vec3 sun_lux(lighting.sun_illuminance_lux);
  const glm::vec3 sky_lux(lighting.sky_ambient_lux);

  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);

  const bool fogged = fog && fog->light_count > 0;
  const GLuint surface = fogged ? fog_program_[variant] : surface_program_[variant];
  glUseProgram(surface);
  set_common_uniforms(surface, clip_from_rel, eye_hi, eye_lo, view);
  // atmo_fog_lights.glsl's inputs, as its header says (units 0-7, restored when it goes).
  std::optional<FogLightingBinding> fog_binding;
  if (fogged) fog_binding.emplace(surface, *fog, 0);
  glUniform3fv(glGetUniformLocation(surface, "u_sun_dir"), 1, &sun_dir[0]);
  glUniform3fv(glGetUniformLocation(surface, "u_sun_lux"), 1, &sun_lux[0]);
  glUniform3fv(glGetUniformLocation(surface, "u_sky_lux"), 1, &sky_lux[0]);
  glUniform1f(glGetUniformLocation(surface, "u_exposure"), static_cast<float>(view.exposure_scale));
  glBindVertexArray(terrain_vao_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(terrain_indices_.size()), GL_UNSIGNED_INT, nullptr);

  // Runway decals: no depth writes; a polygon offset towards the eye (sign
  // depends on the convention; log depth comes from the shader, the lift suffices).
  glDepthMask(GL_FALSE);
  if (view.depth_convention != DepthConvention::Logarithmic) {
    const float sign = view.depth_convention == DepthConvention::Reversed ? 1.0f : -1.0f;
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(sign * 1.0f, sign * 4.0f);
  }
  glBindVertexArray(runway_vao_);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(runway_vertices_.size()));
  glDisable(GL_POLYGON_OFFSET_FILL);
  fog_binding.reset();

  if (!options_.draw_light_points) return;
  // Light points: additive, tested against depth but not writing it.
  const double pixel_angle = 2.0 * std::tan(0.5 * view.vfov_rad) / std::max(view.viewport[3], 1);
  const double point_size = 2.0;
  const double radiance_scale = view.exposure_scale / (pixel_angle * pixel_angle * point_size * point_size);
  const GLuint points = point_program_[variant];
  glUseProgram(points);
  set_common_uniforms(points, clip_from_rel, eye_hi, eye_lo, view);
  glUniform1f(glGetUniformLocation(points, "u_point_size"), static_cast<float>(point_size));
  glUniform1f(glGetUniformLocation(points, "u_radiance_scale"), static_cast<float>(radiance_scale));
  glEnable(GL_PROGRAM_POINT_SIZE);
  glEnable(GL_BLEND);
  glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
  glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ZERO, GL_ONE);
  glBindVertexArray(light_vao_);
  glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(lights_.size()));
}

}  // namespace atmo::host_scene
