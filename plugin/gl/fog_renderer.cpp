#include "gl/fog_renderer.h"

#include <algorithm>
#include <cmath>

#include "gl/gl_state_guard.h"
#include "gl/shader_program.h"

namespace atmo::gl {

namespace {

constexpr GLuint kAirlightUnit = kPassUnitsUsed;  // after the sky passes' units
constexpr int kUnitsUsed = static_cast<int>(kAirlightUnit) + 1;
constexpr int kInstanceFloats = 20;  // rect, light, intensity, axis, cone lobes

// Under a GlStateGuard, whose baseline unbinds any host PBO and sets tight unpacking.
void upload_r32f(GLuint* texture, const fog::FogTable& t) {
  if (!*texture) glGenTextures(1, texture);
  glBindTexture(GL_TEXTURE_2D, *texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, t.width, t.height, 0, GL_RED, GL_FLOAT, t.texels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

// The NDC rectangle that holds the cone of half-angle `radius` about `towards`
// (ENU, unit); the whole viewport when the cone reaches behind the camera.
glm::vec4 glow_rectangle(const glm::dmat4& clip_from_enu, const glm::dvec3& towards, double radius) {
  const glm::vec4 whole(-1.0f, -1.0f, 1.0f, 1.0f);
  if (radius >= 0.5 * M_PI) return whole;
  const glm::dvec3 a = std::abs(towards.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(towards, a)), v = glm::cross(towards, u);
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  const double c = std::cos(radius), s = std::sin(radius) / std::cos(M_PI / 16.0);  // the 16-gon contains the circle
  for (int k = 0; k < 16; ++k) {
    const double t = k * (2.0 * M_PI / 16.0);
    const glm::dvec3 d = c * towards + s * (std::cos(t) * u + std::sin(t) * v);
    const glm::dvec4 p = clip_from_enu * glm::dvec4(d, 0.0);
    if (p.w <= 1e-9) return whole;
    for (int i = 0; i < 2; ++i) {
      lo[i] = std::min(lo[i], p[i] / p.w);
      hi[i] = std::max(hi[i], p[i] / p.w);
    }
  }
  return glm::vec4(std::max(lo[0], -1.0), std::max(lo[1], -1.0), std::min(hi[0], 1.0), std::min(hi[1], 1.0));
}

}  // namespace

void FogRenderer::forget() {
  medium_program_ = glow_program_ = 0;
  airlight_table_ = surface_table_ = light_texture_ = 0;
  cluster_grid_ = cluster_lists_ = far_field_ = 0;
  vao_ = instance_buffer_ = 0;
  linear_sampler_ = nearest_sampler_ = 0;
  tables_version_ = 0;
}

void FogRenderer::destroy() {
  for (GLuint p : {medium_program_, glow_program_})
    if (p) glDeleteProgram(p);
  for (GLuint t : {airlight_table_, surface_table_, light_texture_, cluster_grid_, cluster_lists_, far_field_})
    if (t) glDeleteTextures(1, &t);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (instance_buffer_) glDeleteBuffers(1, &instance_buffer_);
  for (GLuint s : {linear_sampler_, nearest_sampler_})
    if (s) glDeleteSamplers(1, &s);
  forget();
}

bool FogRenderer::build_programs(std::string* error) {
  if (medium_program_) return true;
  medium_program_ = build_program("fullscreen.vert", "fog_medium.frag", "", error);
  if (!medium_program_) return false;
  glow_program_ = build_program("fog_glow.vert", "fog_glow.frag", "", error);
  if (!glow_program_) return false;
  medium_pass_ = locate_pass_uniforms(medium_program_);
  glow_pass_ = locate_pass_uniforms(glow_program_);
  medium_fog_ = glGetUniformLocation(medium_program_, "u_fog");
  medium_ambient_ = glGetUniformLocation(medium_program_, "u_fog_ambient");
  medium_fluence_ = glGetUniformLocation(medium_program_, "u_fog_fluence");
  medium_flux_ = glGetUniformLocation(medium_program_, "u_fog_flux");
  glow_table_ = glGetUniformLocation(glow_program_, "u_fog_airlight");
  glow_table_size_ = glGetUniformLocation(glow_program_, "u_fog_airlight_size");
  glow_top_ = glGetUniformLocation(glow_program_, "u_fog_top");
  glow_min_sin_ = glGetUniformLocation(glow_program_, "u_min_sin");
  create_pass_samplers(&linear_sampler_, &nearest_sampler_);
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &instance_buffer_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, instance_buffer_);
  for (GLuint a = 0; a < 5; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, 4, GL_FLOAT, GL_FALSE, kInstanceFloats * sizeof(float),
                          reinterpret_cast<const void*>(static_cast<uintptr_t>(a * 4 * sizeof(float))));
    glVertexAttribDivisor(a, 1);
  }
  return check_gl("building the fog programs", error);
}

bool FogRenderer::upload_tables(const fog::FogTable& airlight, const fog::FogTable& surface, uint64_t version,
                                std::string* error) {
  if (version == tables_version_ && airlight_table_) return true;
  GlStateGuard guard(1);
  glActiveTexture(GL_TEXTURE0);
  upload_r32f(&airlight_table_, airlight);
  upload_r32f(&surface_table_, surface);
  airlight_size_ = static_cast<float>(airlight.width);
  tables_version_ = version;
  return check_gl("uploading the fog tables", error);
}

bool FogRenderer::draw(const Renderer&, const PassInputs& in, const FogDrawInputs& fog, std::string* error) {
  GlStateGuard guard(kUnitsUsed);  // first: building the programs binds the glows' VAO and buffer
  if (!build_programs(error)) return false;
  const fog::FogFrame& frame = *fog.frame;
  // The glows' rectangles and instance data.
  const glm::dmat4 clip_from_view = glm::inverse(glm::dmat4(in.view_from_clip));
  const glm::dmat4 clip_from_enu = clip_from_view * glm::dmat4(glm::transpose(glm::dmat3(in.enu_from_view)));
  instances_.clear();
  stats_ = FogDrawStats{};
  stats_.lights = static_cast<int>(frame.lights.size());
  const double half_w = 0.5 * in.viewport[2], half_h = 0.5 * in.viewport[3];
  for (const fog::FrameLight& l : frame.lights) {
    // Below the threshold beyond min_sin: the shader floors sin(gamma) there, so no pixel can show it.
    if (l.glow_radius_rad <= fog.min_sin) continue;
    const double d = glm::length(glm::dvec3(l.position_enu_m));
    if (d <= 0.0) continue;
    const glm::vec4 r = glow_rectangle(clip_from_enu, glm::dvec3(l.position_enu_m) / d, l.glow_radius_rad);
    if (r.x >= r.z || r.y >= r.w) continue;  // off screen
    const float rect[4] = {r.x, r.y, r.z, r.w};
    instances_.insert(instances_.end(), rect, rect + 4);
    instances_.insert(instances_.end(), {l.position_enu_m.x, l.position_enu_m.y, l.position_enu_m.z, l.beta_per_m});
    const glm::vec3 i = l.intensity_cd * fog.albedo;
    instances_.insert(instances_.end(), {i.x, i.y, i.z, l.cos_inner});
    instances_.insert(instances_.end(), {l.axis_enu.x, l.axis_enu.y, l.axis_enu.z, l.cos_outer});
    instances_.insert(instances_.end(), {l.lobes, 0.0f, 0.0f, 0.0f});
    ++stats_.glows_drawn;
    stats_.covered_pixels += (r.z - r.x) * half_w * (r.w - r.y) * half_h;
  }

  guard.use_single_draw_buffer();
  glViewport(in.viewport[0], in.viewport[1], in.viewport[2], in.viewport[3]);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glActiveTexture(GL_TEXTURE0 + kDepthUnit);
  glBindTexture(GL_TEXTURE_2D, in.depth_texture);
  glBindSampler(kDepthUnit, nearest_sampler_);
  glActiveTexture(GL_TEXTURE0 + kAirlightUnit);
  glBindTexture(GL_TEXTURE_2D, airlight_table_);
  glBindSampler(kAirlightUnit, linear_sampler_);
  glBindVertexArray(vao_);

  // The fog over the frame: colour * transmittance + its own light.
  glUseProgram(medium_program_);
  set_pass_uniforms(medium_pass_, in, PassTableSizes{}, 1, NightTerms{});
  glUniform4f(medium_fog_, fog.extinction_per_m, fog.albedo, frame.top_above_eye_m, 0.0f);
  glUniform3f(medium_ambient_, fog.ambient_cd_m2.x, fog.ambient_cd_m2.y, fog.ambient_cd_m2.z);
  glUniform3f(medium_fluence_, frame.fluence.x, frame.fluence.y, frame.fluence.z);
  glUniformMatrix3fv(medium_flux_, 1, GL_FALSE, &frame.flux_towards_lights[0][0]);
  glEnablei(GL_BLEND, 0);
  set_blend_of_buffer0(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE, GL_FUNC_ADD, GL_FUNC_ADD);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  // The glows, added.
  if (stats_.glows_drawn > 0) {
    glUseProgram(glow_program_);
    set_pass_uniforms(glow_pass_, in, PassTableSizes{}, 1, NightTerms{});
    glUniform1i(glow_table_, static_cast<GLint>(kAirlightUnit));
    glUniform1f(glow_table_size_, airlight_size_);
    glUniform1f(glow_top_, frame.top_above_eye_m);
    glUniform1f(glow_min_sin_, fog.min_sin);
    glBindBuffer(GL_ARRAY_BUFFER, instance_buffer_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(instances_.size() * sizeof(float)), instances_.data(),
                 GL_STREAM_DRAW);
    set_blend_of_buffer0(GL_ONE, GL_ONE, GL_ZERO, GL_ONE, GL_FUNC_ADD, GL_FUNC_ADD);
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, stats_.glows_drawn);
  }
  return check_gl("drawing the fog and glows", error);
}

bool FogRenderer::upload_host_lights(const fog::FogFrame& frame, const lights::LightClusters& clusters,
                                     const glm::dmat3& world_from_enu, std::string* error) {
  // The lights: 256 a row of 4 texels each.
  constexpr size_t kLightsPerRow = 256;
  // The frame's lights, then the clusters' merged lights.
  const size_t n = frame.lights.size() + clusters.merged.size();
  const GLsizei light_rows = static_cast<GLsizei>(std::max<size_t>(1, (n + kLightsPerRow - 1) / kLightsPerRow));
  std::vector<float> texels(static_cast<size_t>(light_rows) * kLightsPerRow * 16, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    const bool own = i < frame.lights.size();
    const fog::FrameLight& l = own ? frame.lights[i] : clusters.merged[i - frame.lights.size()];
    const float range = own ? clusters.range_m[i] : clusters.merged_range_m[i - frame.lights.size()];
    const glm::vec3 p(world_from_enu * glm::dvec3(l.position_enu_m));
    const glm::vec3 axis(world_from_enu * glm::dvec3(l.axis_enu));
    const float t[16] = {p.x, p.y, p.z, range, l.intensity_cd.x, l.intensity_cd.y, l.intensity_cd.z,
                         l.cos_inner, axis.x, axis.y, axis.z, l.cos_outer, l.lobes, 0.0f, 0.0f, 0.0f};
    std::copy(t, t + 16, texels.begin() + static_cast<std::ptrdiff_t>(i * 16));
  }
  // The clusters: (first, count) per cluster, rows of tiles, slices stacked; the lists 4096 a row.
  const lights::ClusterGrid& g = clusters.grid;
  const GLsizei grid_w = g.tiles_x, grid_h = g.tiles_y * lights::ClusterGrid::kSlices;
  std::vector<uint32_t> grid(static_cast<size_t>(grid_w) * grid_h * 2);
  for (size_t f = 0; f < clusters.offset.size(); ++f) {
    grid[2 * f] = clusters.offset[f];
    grid[2 * f + 1] = clusters.count[f];
  }
  constexpr size_t kEntriesPerRow = 4096;
  const GLsizei list_rows =
      static_cast<GLsizei>(std::max<size_t>(1, (clusters.lists.size() + kEntriesPerRow - 1) / kEntriesPerRow));
  std::vector<uint32_t> lists(static_cast<size_t>(list_rows) * kEntriesPerRow, 0u);
  std::copy(clusters.lists.begin(), clusters.lists.end(), lists.begin());
  // The far field: the six faces (ENU at the eye), each a stack of the slices.
  const int slices = lights::ClusterGrid::kSlices, per_slice = g.tiles_x * g.tiles_y;
  constexpr int kFaces = lights::LightClusters::kFaces;
  std::vector<float> far(static_cast<size_t>(per_slice) * slices * kFaces * 4, 0.0f);
  for (int face = 0; face < kFaces; ++face)
    for (int f = 0; f < per_slice * slices; ++f) {
      const glm::vec3& e = clusters.far[face][static_cast<size_t>(f)];
      float* texel = &far[(static_cast<size_t>(face) * per_slice * slices + static_cast<size_t>(f)) * 4];
      texel[0] = e.x;
      texel[1] = e.y;
      texel[2] = e.z;
    }
  GlStateGuard guard(1);
  glActiveTexture(GL_TEXTURE0);
  const auto texture_2d = [](GLuint* name, GLint format, GLsizei w, GLsizei h, GLenum layout, GLenum type,
                             const void* data) {
    if (!*name) glGenTextures(1, name);
    glBindTexture(GL_TEXTURE_2D, *name);  // unpacking: the guard's baseline
    glTexImage2D(GL_TEXTURE_2D, 0, format, w, h, 0, layout, type, data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  };
  texture_2d(&light_texture_, GL_RGBA32F, static_cast<GLsizei>(4 * kLightsPerRow), light_rows, GL_RGBA, GL_FLOAT,
             texels.data());
  texture_2d(&cluster_grid_, GL_RG32UI, grid_w, grid_h, GL_RG_INTEGER, GL_UNSIGNED_INT, grid.data());
  texture_2d(&cluster_lists_, GL_R32UI, static_cast<GLsizei>(kEntriesPerRow), list_rows, GL_RED_INTEGER,
             GL_UNSIGNED_INT, lists.data());
  if (!far_field_) glGenTextures(1, &far_field_);
  glBindTexture(GL_TEXTURE_3D, far_field_);
  glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA32F, g.tiles_x, g.tiles_y, kFaces * slices, 0, GL_RGBA, GL_FLOAT, far.data());
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTexParameteri(GL_TEXTURE_3D, wrap, GL_CLAMP_TO_EDGE);
  return check_gl("uploading the host's lights", error);
}

}  // namespace atmo::gl
