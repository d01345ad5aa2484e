// shaders/night_sky/moon_disc.glsl and shaders/night_sky/background.glsl
// compiled by the GL driver (llvmpipe here) against their C++ twins
// (plugin/core/night_sky/night_sky_twin.h). A tiny fragment shader includes
// both files (read from the source tree with the plugin's `#include "path"`
// convention, path relative to shaders/), reads a unit ENU direction per
// pixel from an RGB32F texture and writes moon_disc_radiance or
// night_background_radiance to an RGBA32F target; the twin evaluates the
// same float directions with the same float parameters.
//
// Proved: the GPU's value equals the twin's to 1e-4 relative (measured ~1e-5)
// where the Moon's radiance is well conditioned, to 2e-4 of the disc's peak in
// the limb's coverage ramp and elsewhere on the disc, and is the double core's
// for a direction within 0.02" of the pixel's (four phases and orientations);
// the background equals the twin to 1e-4 relative over the whole sphere for
// an eye on the ground, at 1.5 km and inside the airglow layer.
// Figures are printed with the prefix "[ night twin gl ]" and quoted in docs/NIGHT_SKY.md.
#include <glad/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"
#include "core/night_sky/night_sky_twin.h"
#include "core/night_sky/star_photometry.h"

namespace {

using atmo::support::HeadlessGl;
using atmo::support::Image;
using atmo::support::OffscreenTarget;
namespace night = atmo::core::night;
namespace twin = atmo::twin;

constexpr int kSize = 128;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// A shader file from the source tree with `#include "path"` lines expanded
// (each file once), as plugin/gl/shader_program.cpp does with the embedded copies.
bool expand(const std::string& path, std::vector<std::string>& seen, std::string& out, std::string* error) {
  if (std::find(seen.begin(), seen.end(), path) != seen.end()) return true;
  seen.push_back(path);
  std::ifstream file(std::string(ATMO_SOURCE_DIR) + "/shaders/" + path);
  if (!file) {
    *error = "cannot read shaders/" + path;
    return false;
  }
  std::string line;
  const std::string directive = "#include \"";
  while (std::getline(file, line)) {
    if (line.rfind(directive, 0) == 0) {
      const size_t end = line.find('"', directive.size());
      if (!expand(line.substr(directive.size(), end - directive.size()), seen, out, error)) return false;
    } else {
      out += line + "\n";
    }
  }
  return true;
}

const char* kVertex = R"(#version 330 core
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

const char* kFragment = R"(#version 330 core
#define ATMO_FN
#define IN(T) in T
#define OUT(T) out T
#include "night_sky/moon_disc.glsl"
#include "night_sky/background.glsl"
uniform sampler2D u_directions;  // RGB32F: a unit ENU direction per pixel
uniform int u_mode;              // 0: the Moon's disc, 1: the background
uniform float u_pixel_angle;
uniform MoonDisc u_moon;
uniform NightBackground u_background;
out vec4 out_color;
void main() {
  vec3 dir = texelFetch(u_directions, ivec2(gl_FragCoord.xy), 0).xyz;
  vec3 c = u_mode == 0 ? moon_disc_radiance(u_moon, dir, u_pixel_angle) : night_background_radiance(u_background, dir);
  out_color = vec4(c, 1.0);
}
)";

GLuint compile(GLenum stage, const std::string& source, std::string* error) {
  const GLuint s = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = GL_FALSE;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    *error = log;
    glDeleteShader(s);
    return 0;
  }
  return s;
}

class NightSkyShader : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    gl_ = HeadlessGl::create(HeadlessGl::Profile::Core, &error);
    ASSERT_NE(gl_, nullptr) << error;
    target_ = OffscreenTarget::create(kSize, kSize, &error);
    ASSERT_NE(target_, nullptr) << error;
    // The fragment shader with the includes expanded after its #version line.
    std::string fragment;
    std::vector<std::string> seen;
    std::istringstream lines(kFragment);
    std::string line;
    const std::string directive = "#include \"";
    while (std::getline(lines, line)) {
      if (line.rfind(directive, 0) == 0) {
        const size_t end = line.find('"', directive.size());
        ASSERT_TRUE(expand(line.substr(directive.size(), end - directive.size()), seen, fragment, &error)) << error;
      } else {
        fragment += line + "\n";
      }
    }
    const GLuint vs = compile(GL_VERTEX_SHADER, kVertex, &error);
    ASSERT_NE(vs, 0u) << error;
    const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, &error);
    ASSERT_NE(fs, 0u) << error;
    program_ = glCreateProgram();
    glAttachShader(program_, vs);
    glAttachShader(program_, fs);
    glLinkProgram(program_);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = GL_FALSE;
    glGetProgramiv(program_, GL_LINK_STATUS, &ok);
    ASSERT_EQ(ok, GL_TRUE);
    glGenVertexArrays(1, &vao_);
    glGenTextures(1, &directions_);
  }
  void TearDown() override {
    if (!gl_) return;
    if (directions_) glDeleteTextures(1, &directions_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (program_) glDeleteProgram(program_);
    target_.reset();
    gl_.reset();
  }

  GLint loc(const char* name) const { return glGetUniformLocation(program_, name); }
  void set(const char* name, float v) const { glUniform1f(loc(name), v); }
  void set(const char* name, const glm::vec3& v) const { glUniform3f(loc(name), v.x, v.y, v.z); }

  void set_moon(const twin::MoonDisc& m) const {
    set("u_moon.direction", m.direction);
    set("u_moon.angular_radius_rad", m.angular_radius_rad);
    set("u_moon.to_sun", m.to_sun);
    set("u_moon.sun_radiance", m.sun_radiance);
    set("u_moon.earthshine_radiance", m.earthshine_radiance);
  }
  void set_background(const twin::NightBackground& b) const {
    glUniformMatrix3fv(loc("u_background.icrs_from_enu"), 1, GL_FALSE, &b.icrs_from_enu[0][0]);
    set("u_background.sun_icrs", b.sun_icrs);
    set("u_background.eye_altitude_m", b.eye_altitude_m);
    set("u_background.planet_radius_m", b.planet_radius_m);
    set("u_background.airglow_zenith_cd_m2", b.airglow_zenith_cd_m2);
    set("u_background.airglow_layer_altitude_m", b.airglow_layer_altitude_m);
    set("u_background.airglow_layer_thickness_m", b.airglow_layer_thickness_m);
    set("u_background.zodiacal_cd_m2_per_unit", b.zodiacal_cd_m2_per_unit);
    set("u_background.starlight_pole_cd_m2", b.starlight_pole_cd_m2);
    set("u_background.starlight_plane_excess_cd_m2", b.starlight_plane_excess_cd_m2);
    set("u_background.starlight_width_sin_b", b.starlight_width_sin_b);
    set("u_background.starlight_longitude_contrast", b.starlight_longitude_contrast);
    set("u_background.diffuse_galactic_fraction", b.diffuse_galactic_fraction);
    set("u_background.cosmic_cd_m2", b.cosmic_cd_m2);
    set("u_background.airglow_rgb", b.airglow_rgb);
    set("u_background.zodiacal_rgb", b.zodiacal_rgb);
    set("u_background.starlight_rgb", b.starlight_rgb);
  }

  // Draws mode 0 (Moon) or 1 (background) for `dirs` (kSize x kSize, row 0 =
  // window row 0 = the bottom); returns the image as rows from the bottom.
  std::vector<glm::vec3> draw(int mode, const std::vector<glm::vec3>& dirs, float pixel_angle,
                              const twin::MoonDisc& moon, const twin::NightBackground& background) {
    glBindTexture(GL_TEXTURE_2D, directions_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, kSize, kSize, 0, GL_RGB, GL_FLOAT, dirs.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    target_->clear(0.0f, 0.0f, 0.0f, 0.0f);
    glUseProgram(program_);
    glUniform1i(loc("u_directions"), 0);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(loc("u_mode"), mode);
    set("u_pixel_angle", pixel_angle);
    set_moon(moon);
    set_background(background);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    const Image img = target_->read_color();
    std::vector<glm::vec3> out(dirs.size());
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const float* p = img.pixel(x, kSize - 1 - y);
        out[static_cast<size_t>(y) * kSize + x] = glm::vec3(p[0], p[1], p[2]);
      }
    return out;
  }

  std::unique_ptr<HeadlessGl> gl_;
  std::unique_ptr<OffscreenTarget> target_;
  GLuint program_ = 0, vao_ = 0, directions_ = 0;
};

double max_abs(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

glm::dvec3 perpendicular(const glm::dvec3& u) {
  const glm::dvec3 a = std::abs(u.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(u, a));
}

// The core's radiance (double) in direction `dir` for a Moon of centre `c`,
// angular radius `alpha`, Moon -> Sun `to_sun`; 0 off the disc (hard edge).
glm::dvec3 core_moon(const night::MoonDiscLighting& l, const glm::dvec3& c, double alpha, const glm::dvec3& to_sun,
                     const glm::dvec3& dir) {
  return night::moon_disc_radiance_toward(l, c, alpha, to_sun, dir);
}

// The smallest angle (arcsec, of a ladder) within which some direction around
// `dir` gives the core's luminance `value` (to 1e-5 of it): the backward error.
double backward_error_arcsec(double value, const night::MoonDiscLighting& l, const glm::dvec3& c, double alpha,
                             const glm::dvec3& to_sun, const glm::dvec3& dir, double peak) {
  const glm::dvec3 e1 = perpendicular(dir), e2 = glm::cross(dir, e1);
  const double at = night::rgb_luminance(core_moon(l, c, alpha, to_sun, dir));
  double lo = at, hi = at;
  const double tol = 1e-5 * value + 1e-7 * peak;
  if (std::abs(value - at) <= tol) return 0.0;
  for (double arcsec : {0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0}) {
    const double delta = arcsec * kDeg / 3600.0;
    for (int k = 0; k < 16; ++k) {
      const double a = k * kPi / 8.0;
      const double v =
          night::rgb_luminance(core_moon(l, c, alpha, to_sun, dir + delta * (std::cos(a) * e1 + std::sin(a) * e2)));
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    if (value >= lo - tol && value <= hi + tol) return arcsec;
  }
  return 1e9;
}

TEST_F(NightSkyShader, MoonDiscOnTheGpuEqualsTheTwin) {
  const twin::NightBackground unused = night::make_night_background(glm::dmat3(1.0), glm::dvec3(1, 0, 0), 0.0, 6371000.0);
  // Pixels: well conditioned (disc radius <= 0.99, sunlit term >= 0.1 of its
  // peak): relative difference; the limb's ramp (one pixel about the limb) and
  // the rest of the disc (the last 1 % of the radius, the terminator): the
  // difference over the disc's peak (near the limb, mu = sqrt(1 - rho^2), and
  // the terminator, mu0 -> 0, a relative figure measures only the float
  // rounding's amplification). And against the double core, on the disc
  // outside the ramp, the backward error: the GPU's value is the core's for a
  // direction within that angle of the pixel's.
  double worst_rel = 0.0, worst_ramp = 0.0, worst_rest = 0.0, worst_backward = 0.0;
  int compared = 0, conditioned = 0, ramp = 0;
  const double phases_deg[] = {10.0, 60.0, 100.0, 160.0};
  for (int k = 0; k < 4; ++k) {
    const double phase = phases_deg[k] * kDeg, distance = 362000e3 + 11000e3 * k;
    const double alpha = std::asin(night::kMoonRadiusM / distance);
    const glm::dvec3 c = glm::normalize(glm::dvec3(0.4 - 0.3 * k, 0.7, 0.3 + 0.2 * k));
    const glm::dvec3 right = perpendicular(c), up = glm::cross(c, right);
    const double psi = 0.7 + 1.9 * k;
    const glm::dvec3 to_sun = std::cos(phase) * (-c) + std::sin(phase) * (std::cos(psi) * right + std::sin(psi) * up);
    const night::MoonDiscLighting lighting = night::moon_disc_lighting(phase, distance, 1.0);
    const twin::MoonDisc m = night::make_moon_disc(c, alpha, to_sun, lighting);
    // A gnomonic grid 1.2 radii across each way; the ramp one grid step wide.
    const double step = 2.4 * std::tan(alpha) / kSize;
    std::vector<glm::vec3> dirs(kSize * kSize);
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        dirs[static_cast<size_t>(y) * kSize + x] =
            glm::vec3(glm::normalize(c + ((x + 0.5) * step - 1.2 * std::tan(alpha)) * right +
                                     ((y + 0.5) * step - 1.2 * std::tan(alpha)) * up));
    const std::vector<glm::vec3> gpu = draw(0, dirs, static_cast<float>(step), m, unused);
    const double earthshine = night::rgb_luminance(glm::dvec3(m.earthshine_radiance));
    const double sun_peak = night::rgb_luminance(glm::dvec3(m.sun_radiance));
    const double peak = sun_peak + earthshine;
    const glm::dvec3 cf(m.direction), sf(m.to_sun);
    for (size_t i = 0; i < dirs.size(); ++i) {
      const glm::dvec3 d(dirs[i]);
      const glm::dvec3 cpu(twin::moon_disc_radiance(m, dirs[i], static_cast<float>(step)));
      const glm::dvec3 g(gpu[i]);
      ASSERT_TRUE(std::isfinite(g.x) && std::isfinite(g.y) && std::isfinite(g.z)) << i;
      const double e = max_abs(g - cpu);
      const double theta = std::acos(std::min(glm::dot(glm::normalize(d), glm::normalize(cf)), 1.0));
      const double rho = std::sin(theta) / std::sin(alpha);
      const double sunlit = (night::rgb_luminance(cpu) - earthshine) / sun_peak;
      if (std::abs(theta - alpha) <= 0.5 * step + 1e-6) {
        worst_ramp = std::max(worst_ramp, e / peak);
        ++ramp;
      } else if (rho <= 0.99 && sunlit >= 0.1) {
        worst_rel = std::max(worst_rel, e / max_abs(cpu));
        ++conditioned;
      } else if (theta < alpha) {
        worst_rest = std::max(worst_rest, e / peak);
      }
      if (theta < alpha - 0.5 * step - 1e-6)
        worst_backward = std::max(worst_backward,
                                  backward_error_arcsec(night::rgb_luminance(g), lighting, cf, alpha, sf, d, peak));
      ++compared;
    }
  }
  std::printf("[ night twin gl ] Moon disc on %s vs the C++ twin, %d pixels (4 phases 10-160 deg, limb ramp 1 px = "
              "radius/53): relative difference where well conditioned (%d px) worst %.2e; |difference| / peak in the "
              "ramp (%d px) %.2e, elsewhere on the disc %.2e; GPU vs the double core, backward error on the disc "
              "%.3f\"\n",
              gl_->renderer().c_str(), compared, conditioned, worst_rel, ramp, worst_ramp, worst_rest, worst_backward);
  EXPECT_LT(worst_rel, 1e-4);
  EXPECT_LT(worst_ramp, 2e-4);
  EXPECT_LT(worst_rest, 1e-4);
  EXPECT_LE(worst_backward, 0.02);
}

TEST_F(NightSkyShader, BackgroundOnTheGpuEqualsTheTwin) {
  const twin::MoonDisc unused{};
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 1.0);
  double worst = 0.0, median_sum = 0.0;
  int compared = 0, skipped = 0;
  const double altitudes[] = {0.0, 1500.0, 90000.0};
  for (int k = 0; k < 3; ++k) {
    // A rotation ICRS <- ENU (east, north, up columns) and the Sun on the ecliptic, 25° below the horizon-ish.
    const glm::dvec3 up = glm::normalize(glm::dvec3(0.3 + k, -0.5, 0.8));
    const glm::dvec3 east = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), up));
    const glm::dmat3 icrs_from_enu(east, glm::cross(up, east), up);
    const double lambda = 1.0 + 2.1 * k;
    const double eps = night::kObliquityJ2000Rad;
    const glm::dvec3 sun(std::cos(lambda), std::sin(lambda) * std::cos(eps), std::sin(lambda) * std::sin(eps));
    const twin::NightBackground b = night::make_night_background(icrs_from_enu, sun, altitudes[k], 6371000.0);
    std::vector<glm::vec3> dirs(kSize * kSize);
    for (auto& d : dirs) {
      glm::dvec3 v(n(rng), n(rng), n(rng));
      d = glm::vec3(glm::normalize(v));
    }
    const std::vector<glm::vec3> gpu = draw(1, dirs, 0.0f, unused, b);
    std::vector<double> rel;
    for (size_t i = 0; i < dirs.size(); ++i) {
      const glm::dvec3 cpu(twin::night_background_radiance(b, dirs[i]));
      const glm::dvec3 g(gpu[i]);
      ASSERT_TRUE(std::isfinite(g.x) && std::isfinite(g.y) && std::isfinite(g.z)) << i;
      // Rays within 1 m of grazing the ground or a shell of the airglow layer:
      // the slant factor jumps there, so either side is right.
      const double mu = dirs[i].z, r0 = 6371000.0 + altitudes[k];
      const double tangent = r0 * std::sqrt(std::max(1.0 - mu * mu, 0.0));
      bool edge = false;
      for (double rho : {6371000.0, 6371000.0 + 85000.0, 6371000.0 + 95000.0})
        if (mu <= 0.0 && std::abs(tangent - rho) < 1.0) edge = true;
      if (edge) {
        ++skipped;
        continue;
      }
      rel.push_back(max_abs(g - cpu) / max_abs(cpu));
      ++compared;
    }
    std::nth_element(rel.begin(), rel.begin() + rel.size() / 2, rel.end());
    median_sum += rel[rel.size() / 2];
    worst = std::max(worst, *std::max_element(rel.begin(), rel.end()));
  }
  std::printf("[ night twin gl ] background on %s vs the C++ twin, %d random directions (eye at 0, 1.5 and 90 km): "
              "worst relative %.2e, mean of the medians %.2e (%d grazing rays skipped)\n",
              gl_->renderer().c_str(), compared, worst, median_sum / 3.0, skipped);
  EXPECT_LT(worst, 1e-4);
}

}  // namespace
