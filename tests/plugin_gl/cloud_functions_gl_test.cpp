// shaders/clouds/cloud_functions.glsl compiled by the GL driver (llvmpipe
// here) against its C++ twin (core/clouds/cloud_twin.h), the one text the
// CPU lighting reference and the GL passes share. A fragment shader built
// with the plugin's own build_program reads per-pixel inputs (optical depths
// towards the light, behind the point, up and down; the phase angle's cosine,
// the view's elevation, a step's optical thickness) from RGBA32F textures and
// writes the lighting model's terms; the twin evaluates the same float inputs.
// The CloudOctaves uniforms are set by name from clouds::kOctaveFloats, the
// list the cloud renderer sets them from, so a member missing from that list
// or renamed in the GLSL fails here.
//
// Proved (printed with the prefix "[ cloud twin gl ]"): every term equals the
// twin to 1e-4 relative (or 1e-6 absolute where a term is ~0) over 4096
// random inputs that span thin to very thick clouds and every view.
#include <glad/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "atmo_support/offscreen_target.h"
#include "core/clouds/cloud_optics.h"
#include "gl/shader_program.h"
#include "../support/gl_test_util.h"

namespace {

using atmo::support::Image;
using atmo::support::OffscreenTarget;
namespace clouds = atmo::clouds;
namespace twin = atmo::clouds::twin;

constexpr int kSize = 64;

// Mode 0: octaves (with the multiple share), diffusion, sky share, look-ahead
// share. Mode 1: the ambient radiance (rgb) and the multiple share.
const char* kHarnessMain = R"(
uniform sampler2D u_depths;  // tau_light, tau_back, tau_up, tau_down
uniform sampler2D u_view;    // cos_theta, mu, step_tau, unused
uniform int u_mode;
uniform CloudPhase u_phase;
uniform CloudOctaves u_octaves;
uniform vec3 u_sky;
uniform vec3 u_ground;
out vec4 out_color;
void main() {
  vec4 d = texelFetch(u_depths, ivec2(gl_FragCoord.xy), 0);
  vec4 v = texelFetch(u_view, ivec2(gl_FragCoord.xy), 0);
  float around = cloud_tau_around(d.x, d.y, d.z, d.w);
  float multiple = cloud_multiple_share(u_octaves, around);
  if (u_mode == 0) {
    out_color = vec4(cloud_light_octaves(u_phase, u_octaves, d.x, v.x, multiple),
                     cloud_light_diffusion(u_octaves, d.x, d.y, d.z, d.w, v.x),
                     cloud_sky_share(u_phase, u_octaves, d.z, d.w, around, v.y),
                     cloud_lookahead_share(u_octaves, v.z));
  } else {
    out_color = vec4(cloud_ambient(u_phase, u_octaves, u_sky, u_ground, d.z, d.w, around, v.y), multiple);
  }
}
)";

class CloudFunctionsGl : public GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    if (HasFatalFailure()) return;
    std::string error;
    target_ = OffscreenTarget::create(kSize, kSize, &error);
    ASSERT_NE(target_, nullptr) << error;
    program_ = atmo::gl::build_program("fullscreen.vert", "clouds/cloud_functions.glsl",
                                       "#define ATMO_FN\n#define IN(T) in T\n#define OUT(T) out T\n", &error,
                                       kHarnessMain);
    ASSERT_NE(program_, 0u) << error;
    glGenVertexArrays(1, &vao_);
    glGenTextures(2, textures_);
  }
  void TearDown() override {
    if (!gl_) return;
    glDeleteTextures(2, textures_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (program_) glDeleteProgram(program_);
    target_.reset();
    gl_.reset();
  }

  GLint loc(const std::string& name) const { return glGetUniformLocation(program_, name.c_str()); }

  // Sets u_phase and u_octaves; false (with the name) if one is not in the program.
  bool set_parameters(const twin::CloudPhase& ph, const twin::CloudOctaves& oc, std::string* missing) {
    glUseProgram(program_);
    const std::pair<const char*, float> phase[] = {
        {"g_hg", ph.g_hg}, {"g_draine", ph.g_draine}, {"alpha_draine", ph.alpha_draine}, {"w_draine", ph.w_draine}};
    for (const auto& [name, value] : phase) {
      const GLint l = loc(std::string("u_phase.") + name);
      if (l < 0) return *missing = std::string("u_phase.") + name, false;
      glUniform1f(l, value);
    }
    for (const clouds::OctaveFloat& f : clouds::kOctaveFloats) {
      const GLint l = loc(std::string("u_octaves.") + f.name);
      if (l < 0) return *missing = std::string("u_octaves.") + f.name, false;
      glUniform1f(l, oc.*f.field);
    }
    glUniform1i(loc("u_octaves.count"), oc.count);
    // up_grid is read by the march only (cloud_march.glsl), not these functions.
    return true;
  }

  Image draw(int mode, const std::vector<glm::vec4>& depths, const std::vector<glm::vec4>& view,
             const glm::vec3& sky, const glm::vec3& ground) {
    const std::vector<glm::vec4>* inputs[2] = {&depths, &view};
    for (int i = 0; i < 2; ++i) {
      glActiveTexture(GL_TEXTURE0 + i);
      glBindTexture(GL_TEXTURE_2D, textures_[i]);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, kSize, kSize, 0, GL_RGBA, GL_FLOAT, inputs[i]->data());
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    }
    target_->clear(0.0f, 0.0f, 0.0f, 0.0f);
    glUseProgram(program_);
    glUniform1i(loc("u_depths"), 0);
    glUniform1i(loc("u_view"), 1);
    glUniform1i(loc("u_mode"), mode);
    glUniform3f(loc("u_sky"), sky.x, sky.y, sky.z);
    glUniform3f(loc("u_ground"), ground.x, ground.y, ground.z);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glFinish();
    return target_->read_color();
  }

  std::unique_ptr<OffscreenTarget> target_;
  GLuint program_ = 0, vao_ = 0;
  GLuint textures_[2] = {0, 0};
};

// |gpu - cpu| relative to |cpu|, or absolute below `floor`.
double difference(double gpu, double cpu, double floor) {
  return std::abs(gpu - cpu) / std::max(std::abs(cpu), floor);
}

}  // namespace

TEST_F(CloudFunctionsGl, EveryTermMatchesTheCppTwin) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  // Optical depths from 0 to ~60, denser near 0 where the terms change fastest.
  auto depth = [&] { return unit(rng) < 0.1f ? 0.0f : 60.0f * unit(rng) * unit(rng); };
  std::vector<glm::vec4> depths(kSize * kSize), view(kSize * kSize);
  for (size_t i = 0; i < depths.size(); ++i) {
    depths[i] = glm::vec4(depth(), depth(), depth(), depth());
    view[i] = glm::vec4(2.0f * unit(rng) - 1.0f, 2.0f * unit(rng) - 1.0f, 3.0f * unit(rng), 0.0f);
  }
  const glm::vec3 sky(4000.0f, 5000.0f, 7000.0f), ground(900.0f, 800.0f, 600.0f);  // cd/m^2

  const twin::CloudPhase ph = clouds::phase_for_droplet(20.0f);
  for (const twin::CloudOctaves& oc : {clouds::default_octaves(), clouds::single_scattering_octaves()}) {
    SCOPED_TRACE(oc.count == 1 ? "single scattering" : "default octaves");
    std::string missing;
    ASSERT_TRUE(set_parameters(ph, oc, &missing)) << missing << " is not a uniform of the harness";
    const Image terms = draw(0, depths, view, sky, ground);
    const Image ambient = draw(1, depths, view, sky, ground);
    const char* names[6] = {"octaves", "diffusion", "sky share", "look-ahead share", "ambient", "multiple share"};
    double worst[6] = {0, 0, 0, 0, 0, 0};
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const size_t i = static_cast<size_t>(y) * kSize + x;
        const glm::vec4 d = depths[i], v = view[i];
        const float around = twin::cloud_tau_around(d.x, d.y, d.z, d.w);
        const float multiple = twin::cloud_multiple_share(oc, around);
        const double cpu[6] = {twin::cloud_light_octaves(ph, oc, d.x, v.x, multiple),
                               twin::cloud_light_diffusion(oc, d.x, d.y, d.z, d.w, v.x),
                               twin::cloud_sky_share(ph, oc, d.z, d.w, around, v.y),
                               twin::cloud_lookahead_share(oc, v.z),
                               twin::cloud_ambient(ph, oc, sky, ground, d.z, d.w, around, v.y).g,
                               multiple};
        const float* t = terms.pixel(x, kSize - 1 - y);  // read_color's row 0 is the top
        const float* a = ambient.pixel(x, kSize - 1 - y);
        const double gpu[6] = {t[0], t[1], t[2], t[3], a[1], a[3]};
        const double floor[6] = {1e-2, 1e-2, 1e-2, 1e-2, 10.0, 1e-2};  // 1e-4 of these is the absolute floor
        for (int k = 0; k < 6; ++k) {
          ASSERT_TRUE(std::isfinite(gpu[k])) << names[k] << " at " << x << "," << y;
          worst[k] = std::max(worst[k], difference(gpu[k], cpu[k], floor[k]));
        }
      }
    for (int k = 0; k < 6; ++k) {
      std::printf("[ cloud twin gl ] %s, %s: worst |gpu - cpu| / |cpu| %.2e\n",
                  oc.count == 1 ? "single scattering" : "default", names[k], worst[k]);
      EXPECT_LE(worst[k], 1e-4) << names[k];
    }
  }
}
