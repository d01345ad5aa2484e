// The host GLSL include (host_sdk/include/atmo/atmo_aerial_perspective.glsl)
// gives a host's transparent surface the same haze the plugin's aerial pass
// puts on opaque geometry at the same distance: a host shader using the
// include and the textures from get_lighting must reproduce the pass.
#include <glad/gl.h>

#include <fstream>
#include <sstream>

#include "host_shader.h"
#include "plugin_gl_fixture.h"

using namespace plugin_gl;

namespace {

// A host transparent surface covering the screen at the host depth `depth`
// (standard convention): colour = include(surface colour, distance).
const char* kVertex =
    "#version 330 core\nvoid main(){vec2 p=vec2((gl_VertexID<<1)&2,gl_VertexID&2);"
    "gl_Position=vec4(p*2.0-1.0,0.5,1.0);}\n";
const char* kFragmentMain = R"(
uniform mat4 view_from_clip;
uniform float depth;
uniform vec3 surface;
out vec4 colour;
void main() {
  vec2 ndc = (gl_FragCoord.xy - atmo_viewport.xy) / atmo_viewport.zw * 2.0 - 1.0;
  vec4 p = view_from_clip * vec4(ndc, depth * 2.0 - 1.0, 1.0);
  colour = vec4(atmo_apply_aerial_perspective(surface, length(p.xyz / p.w)), 1.0);
}
)";

// As the include's header asks: linear filtering, clamped at the edges.
void set_linear_clamped(GLenum target) {
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTexParameteri(target, wrap, GL_CLAMP_TO_EDGE);
}

}  // namespace

TEST(HostAerialInclude, TransparentSurfaceMatchesThePluginsPass) {
  Fixture f;
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1718989800.0;  // low sun: coloured haze
  f.context->set_frame(frame);
  auto atm = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
  f.context->set_atmosphere(atm);

  const glm::dmat4 proj = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 10.0, 2e5);
  AtmoViewState vs = innsbruck_view(1500.0, 250.0, 3.0, proj);
  vs.exposure_scale = 1.0 / 4000.0;
  vs.depth_texture = f.target->depth_texture();
  f.view->set(vs);

  const glm::vec3 surface(0.3f, 0.5f, 0.2f);
  const std::string include = read_text(ATMO_SOURCE_DIR "/host_sdk/include/atmo/atmo_aerial_perspective.glsl");
  ASSERT_FALSE(include.empty());
  const HostProgram host(kVertex, "#version 330 core\n" + include + kFragmentMain);
  ASSERT_TRUE(host.linked());
  const GLuint program = host.id();

  for (float depth : {0.9f, 0.99f, 0.999f, 0.9999f}) {
    SCOPED_TRACE(depth);
    // Reference: the plugin's pass over an opaque surface of that colour at that depth.
    f.target->bind();
    f.target->clear(surface.r, surface.g, surface.b, 1.0f, depth);
    ASSERT_EQ(f.view->render(ATMO_PASS_AERIAL_PERSPECTIVE), ATMO_SUCCESS);
    atmo::support::Image expected = f.target->read_color();

    const AtmoLighting lighting = f.view->lighting();
    ASSERT_NE(lighting.aerial_inscatter_texture, 0u);
    ASSERT_NE(lighting.aerial_transmittance_texture, 0u);

    // The host's transparent surface at the same depth, through the include.
    f.target->bind();
    f.target->clear(0, 0, 0, 0, 1.0f);
    glUseProgram(program);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_3D, lighting.aerial_inscatter_texture);
    set_linear_clamped(GL_TEXTURE_3D);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_3D, lighting.aerial_transmittance_texture);
    set_linear_clamped(GL_TEXTURE_3D);
    glUniform1i(glGetUniformLocation(program, "atmo_aerial_inscatter"), 0);
    glUniform1i(glGetUniformLocation(program, "atmo_aerial_transmittance"), 1);
    glUniform1f(glGetUniformLocation(program, "atmo_aerial_range_m"), float(lighting.aerial_range_m));
    glUniform1i(glGetUniformLocation(program, "atmo_aerial_slices"), int(lighting.aerial_slices));
    glUniform4f(glGetUniformLocation(program, "atmo_viewport"), 0.0f, 0.0f, float(kWidth), float(kHeight));
    glUniform1f(glGetUniformLocation(program, "atmo_exposure"), float(vs.exposure_scale));
    glUniformMatrix4fv(glGetUniformLocation(program, "view_from_clip"), 1, GL_FALSE,
                       &glm::mat4(glm::inverse(proj))[0][0]);
    glUniform1f(glGetUniformLocation(program, "depth"), depth);
    glUniform3f(glGetUniformLocation(program, "surface"), surface.r, surface.g, surface.b);
    draw_full_screen_triangle();
    atmo::support::Image got = f.target->read_color();

    double worst = 0.0, change = 0.0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        for (int c = 0; c < 3; ++c) {
          worst = std::max(worst, double(std::abs(got.pixel(x, y)[c] - expected.pixel(x, y)[c])));
          change = std::max(change, double(std::abs(expected.pixel(x, y)[c] - surface[c])));
        }
    std::printf("[ include ] depth %.4f: haze changes the surface by up to %.3f; include vs pass: %.2e\n", depth,
                change, worst);
    EXPECT_GT(change, 1e-3);  // the comparison is not vacuous: the haze is visible
    EXPECT_LT(worst, 1e-4);
  }
}

// The clouds' shadow map through get_cloud_shadows and the host include
// (host_sdk/include/atmo/atmo_cloud_shadow.glsl): no clouds, no map; with
// clouds a map with shadows in it; its matrix slides a point along the
// light; the include, drawn by a host program over a grid of ground points,
// returns the bilinear lookup of the map at the matrix's (u, v) computed here
// in double precision.
TEST(HostCloudShadowInclude, MatchesTheMapAtTheMatrixUv) {
  plugin_gl::Fixture f;
  const AtmoPluginApi& api = f.plugin->api();
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1.72e9;  // the Sun ~50 degrees up
  f.context->set_frame(frame);
  const glm::dmat4 proj = glm::perspective(glm::radians(60.0), double(plugin_gl::kWidth) / plugin_gl::kHeight, 1.0, 1e5);
  f.view->set(plugin_gl::innsbruck_view(500.0, 0.0, 10.0, proj));
  AtmoCloudShadows m = atmo::make<AtmoCloudShadows>(ATMO_TYPE_CLOUD_SHADOWS);
  EXPECT_EQ(api.get_cloud_shadows(f.view->handle(), &m), ATMO_STATUS_NOTHING_TO_DRAW);
  EXPECT_EQ(m.texture, 0u);
  AtmoCloudShadows small = m;
  small.header.struct_size = 16;
  EXPECT_EQ(api.get_cloud_shadows(f.view->handle(), &small), ATMO_ERROR_STRUCT_TOO_SMALL);

  const AtmoCloudLayer layer = cumulus();
  const AtmoCloudsState s = clouds_at_innsbruck(&layer, 1);
  ASSERT_EQ(f.context->set_clouds(s), ATMO_SUCCESS);
  ASSERT_EQ(api.get_cloud_shadows(f.view->handle(), &m), ATMO_SUCCESS) << f.context->last_error();
  ASSERT_NE(m.texture, 0u);
  ASSERT_EQ(m.size, 256u);
  const int n = static_cast<int>(m.size);
  std::vector<float> map(static_cast<size_t>(n) * n);
  glBindTexture(GL_TEXTURE_2D, m.texture);
  glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, map.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  float lo = 1.0f, hi = 0.0f;
  for (float t : map) {
    ASSERT_TRUE(std::isfinite(t));
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  std::printf("[ shadow ] %dx%d texels of %.1f m, transmittance %.3g .. %.3g\n", n, n, m.texel_m, lo, hi);
  EXPECT_LT(lo, 0.1f);  // there are shadows
  EXPECT_LE(hi, 1.0f);
  EXPECT_GE(lo, 0.0f);

  glm::dmat4 uv_from_world;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) uv_from_world[c][r] = m.uv_from_world[c * 4 + r];
  const glm::dvec3 light(m.light_direction_world[0], m.light_direction_world[1], m.light_direction_world[2]);
  EXPECT_NEAR(glm::length(light), 1.0, 1e-9);
  const glm::dvec3 p(100.0, 200.0, 0.0);
  const glm::dvec4 a = uv_from_world * glm::dvec4(p, 1.0), b = uv_from_world * glm::dvec4(p + light * 1500.0, 1.0);
  EXPECT_NEAR(a.x, b.x, 1e-9);
  EXPECT_NEAR(a.y, b.y, 1e-9);

  // A host program: each pixel a ground point of a 6 km square, through the include.
  const std::string include = read_text(ATMO_SOURCE_DIR "/host_sdk/include/atmo/atmo_cloud_shadow.glsl");
  ASSERT_FALSE(include.empty());
  const HostProgram host(kVertex, "#version 330 core\n" + include + R"(
uniform sampler2D shadow_map;
uniform mat4 uv_from_world;
uniform vec2 size;
out vec4 colour;
void main() {
  vec3 world = vec3(-3000.0 + gl_FragCoord.x / size.x * 6000.0, -3000.0 + gl_FragCoord.y / size.y * 6000.0, 0.0);
  colour = vec4(atmo_cloud_shadow(shadow_map, uv_from_world, world), 0.0, 0.0, 1.0);
})");
  ASSERT_TRUE(host.linked());
  const GLuint program = host.id();
  f.target->bind();
  glUseProgram(program);
  glm::mat4 uvf(uv_from_world);
  glUniformMatrix4fv(glGetUniformLocation(program, "uv_from_world"), 1, GL_FALSE, &uvf[0][0]);
  glUniform2f(glGetUniformLocation(program, "size"), plugin_gl::kWidth, plugin_gl::kHeight);
  glUniform1i(glGetUniformLocation(program, "shadow_map"), 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, m.texture);
  draw_full_screen_triangle();
  glFinish();
  const atmo::support::Image got = f.target->read_color();
  double worst = 0.0;
  int shadowed = 0;
  for (int y = 0; y < plugin_gl::kHeight; ++y)
    for (int x = 0; x < plugin_gl::kWidth; ++x) {
      const glm::dvec3 w(-3000.0 + (x + 0.5) / plugin_gl::kWidth * 6000.0,
                         -3000.0 + (y + 0.5) / plugin_gl::kHeight * 6000.0, 0.0);
      const glm::dvec4 uv = uv_from_world * glm::dvec4(w, 1.0);
      double expected = 1.0;
      if (uv.x >= 0.0 && uv.y >= 0.0 && uv.x <= 1.0 && uv.y <= 1.0) {
        const double fx = uv.x * n - 0.5, fy = uv.y * n - 0.5;
        const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
        auto at = [&](int i, int j) {
          return double(map[static_cast<size_t>(std::clamp(j, 0, n - 1)) * n + std::clamp(i, 0, n - 1)]);
        };
        const double ax = fx - x0, ay = fy - y0;
        expected = (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
                   ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
      }
      worst = std::max(worst, std::abs(got.pixel(x, plugin_gl::kHeight - 1 - y)[0] - expected));  // row 0 is the top
      if (expected < 0.5) ++shadowed;
    }
  std::printf("[ shadow ] include vs the map at the matrix's uv: worst %.2e over %d points (%d in shadow)\n", worst,
              plugin_gl::kWidth * plugin_gl::kHeight, shadowed);
  EXPECT_GT(shadowed, 0);
  EXPECT_LT(worst, 5e-3);
}
