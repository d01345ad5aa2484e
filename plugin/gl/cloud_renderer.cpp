#include "gl/cloud_renderer.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_state_guard.h"
#include "gl/renderer.h"
#include "gl/shader_program.h"

namespace atmo::gl {

namespace {
constexpr GLuint kCloudUnit = kPassUnitsUsed;  // the atlas (march) or the low-res image (composite)
constexpr int kUnitsUsed = kPassUnitsUsed + 1;
constexpr int kVec4PerInstance = 7;  // clouds_march.frag's kFloatsPerInstance
constexpr int kMaxInstancesPerBatch = 64;
}  // namespace

bool CloudRenderer::init(std::string* error) {
  if (initialised()) return true;
  while (glGetError() != GL_NO_ERROR) {}
  GlStateGuard guard(kUnitsUsed);
  march_.program = build_program("fullscreen.vert", "clouds_march.frag", "", error);
  if (!march_.program) return false;
  composite_ = build_program("fullscreen.vert", "clouds_composite.frag", "", error);
  if (!composite_) {
    destroy();
    return false;
  }
  auto loc = [&](const char* name) { return glGetUniformLocation(march_.program, name); };
  march_.pass = locate_pass_uniforms(march_.program);
  march_.atlas = loc("u_cloud_atlas");
  march_.atlas_size = loc("u_cloud_atlas_size");
  march_.instances = loc("u_instances");
  march_.instance_count = loc("u_instance_count");
  march_.light_illuminance = loc("u_light_illuminance");
  march_.sky_radiance = loc("u_sky_radiance");
  march_.ground_radiance = loc("u_ground_radiance");
  march_.step_voxels = loc("u_step_voxels");
  march_.max_steps = loc("u_max_steps");
  march_.divisor = loc("u_divisor");
  march_.full_viewport = loc("u_full_viewport");
  const char* phase[4] = {"u_phase.g_hg", "u_phase.g_draine", "u_phase.alpha_draine", "u_phase.w_draine"};
  for (int i = 0; i < 4; ++i) march_.phase[i] = loc(phase[i]);
  const char* oct[5] = {"u_octaves.count", "u_octaves.extinction_scale", "u_octaves.scattering_scale",
                        "u_octaves.eccentricity_scale", "u_octaves.ambient_extinction"};
  for (int i = 0; i < 5; ++i) march_.octaves[i] = loc(oct[i]);
  composite_clouds_ = glGetUniformLocation(composite_, "u_clouds");
  composite_viewport_ = glGetUniformLocation(composite_, "u_viewport");
  glGenVertexArrays(1, &vao_);
  glGenFramebuffers(1, &fbo_);
  GLuint nearest = 0;
  create_pass_samplers(&linear_sampler_, &nearest);
  glDeleteSamplers(1, &nearest);
  // The atlas: linear, and 0 outside (a cloud fades to clear air at its border).
  glGenSamplers(1, &border_sampler_);
  glSamplerParameteri(border_sampler_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glSamplerParameteri(border_sampler_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glSamplerParameteri(border_sampler_, wrap, GL_CLAMP_TO_BORDER);
  const float zero[4] = {0, 0, 0, 0};
  glSamplerParameterfv(border_sampler_, GL_TEXTURE_BORDER_COLOR, zero);
  std::string gl_error;
  if (!check_gl("creating the cloud renderer's objects", &gl_error)) {
    if (error) *error = "cloud renderer: " + gl_error;
    destroy();
    return false;
  }
  return true;
}

void CloudRenderer::destroy() {
  if (march_.program) glDeleteProgram(march_.program);
  if (composite_) glDeleteProgram(composite_);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (target_) glDeleteTextures(1, &target_);
  if (atlas_) glDeleteTextures(1, &atlas_);
  if (linear_sampler_) glDeleteSamplers(1, &linear_sampler_);
  if (border_sampler_) glDeleteSamplers(1, &border_sampler_);
  forget();
}

void CloudRenderer::forget() { *this = CloudRenderer{}; }

bool CloudRenderer::upload_atlas(const CloudFrameInputs& frame, std::string* error) {
  const std::vector<clouds::CloudVolume>& protos = frame.field->prototypes;
  GLint max3d = 256;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
  // Stack the prototypes along z, one zero voxel between blocks; a new column
  // along x when z is full.
  atlas_offsets_.assign(protos.size(), glm::vec3(0.0f));
  int column_x = 0, column_w = 0, z = 1, size_y = 1, size_z = 1;
  for (size_t p = 0; p < protos.size(); ++p) {
    const clouds::DenseGrid& g = protos[p].density;
    if (g.nx + 2 > max3d || g.ny + 2 > max3d || g.nz + 2 > max3d) {
      if (error) *error = "cloud \"" + protos[p].name + "\": " + std::to_string(g.nx) + "x" + std::to_string(g.ny) + "x" +
                          std::to_string(g.nz) + " voxels exceed the GL 3D texture limit " + std::to_string(max3d);
      return false;
    }
    if (z + g.nz + 1 > max3d) {
      column_x += column_w + 1;
      column_w = 0;
      z = 1;
    }
    atlas_offsets_[p] = glm::vec3(column_x + 1, 1, z);
    column_w = std::max(column_w, g.nx + 1);
    size_y = std::max(size_y, g.ny + 2);
    z += g.nz + 1;
    size_z = std::max(size_z, z);
  }
  const int size_x = column_x + column_w + 1;
  if (size_x > max3d) {
    if (error) *error = "the clouds' prototypes do not fit one GL 3D texture (" + std::to_string(max3d) + "^3)";
    return false;
  }
  atlas_size_ = glm::vec3(size_x, size_y, size_z);
  if (atlas_) glDeleteTextures(1, &atlas_);
  glGenTextures(1, &atlas_);
  glActiveTexture(GL_TEXTURE0 + kCloudUnit);
  glBindTexture(GL_TEXTURE_3D, atlas_);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAX_LEVEL, 0);
  glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA16F, size_x, size_y, size_z, 0, GL_RGBA, GL_FLOAT, nullptr);
  // Zero everywhere first (the gaps), then each block.
  {
    const std::vector<float> zeros(static_cast<size_t>(size_x) * size_y * 4, 0.0f);
    for (int k = 0; k < size_z; ++k)
      glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, k, size_x, size_y, 1, GL_RGBA, GL_FLOAT, zeros.data());
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  for (size_t p = 0; p < protos.size(); ++p) {
    const clouds::DenseGrid& g = protos[p].density;
    const std::vector<float> texels = clouds::pack_cloud_texels(g, (*frame.depths)[p]);
    const glm::ivec3 o(atlas_offsets_[p]);
    glTexSubImage3D(GL_TEXTURE_3D, 0, o.x, o.y, o.z, g.nx, g.ny, g.nz, GL_RGBA, GL_FLOAT, texels.data());
  }
  atlas_bytes_ = static_cast<size_t>(size_x) * size_y * size_z * 8;
  uploaded_version_ = frame.version;
  return check_gl("uploading the cloud atlas", error);
}

bool CloudRenderer::ensure_target(int w, int h, std::string* error) {
  if (target_ && w == target_w_ && h == target_h_) return true;
  if (!target_) glGenTextures(1, &target_);
  glActiveTexture(GL_TEXTURE0 + kCloudUnit);
  glBindTexture(GL_TEXTURE_2D, target_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA16F, w, h, 0, GL_RGBA, GL_FLOAT, nullptr);
  target_w_ = w;
  target_h_ = h;
  return check_gl("allocating the cloud image", error);
}

bool CloudRenderer::draw(Renderer& renderer, const PassInputs& in, const CloudFrameInputs& frame, bool* drawn,
                         std::string* error) {
  *drawn = false;
  last_drawn_ = 0;
  if (!frame.field || frame.field->instances.empty()) return true;
  if (!init(error)) return false;
  while (glGetError() != GL_NO_ERROR) {}
  GlStateGuard guard(kUnitsUsed);
  guard.use_single_draw_buffer();
  if (uploaded_version_ != frame.version || !atlas_) {
    if (!upload_atlas(frame, error)) return false;
  }
  // The instances in view, in the eye's ENU axes, nearest first.
  const glm::dmat3 M = frame.eye_enu_from_clouds;
  const glm::dvec3 forward = glm::dmat3(in.enu_from_view) * glm::dvec3(0.0, 0.0, -1.0);
  struct Item {
    double distance;
    size_t index;
    glm::dvec3 centre;  // eye-relative, the eye's ENU axes
  };
  std::vector<Item> items;
  const std::vector<clouds::CloudVolume>& protos = frame.field->prototypes;
  for (size_t i = 0; i < frame.field->instances.size(); ++i) {
    const clouds::CloudInstance& inst = frame.field->instances[i];
    const clouds::CloudVolume& v = protos[static_cast<size_t>(inst.prototype)];
    const glm::dvec3 centre = M * (v.centre_at(inst.origin_enu_m) - frame.eye_in_clouds_m);
    const double r = v.bounding_radius_m();
    if (glm::dot(centre, forward) < -r) continue;  // wholly behind the camera
    items.push_back({glm::length(centre), i, centre});
  }
  if (items.empty()) return true;
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.distance < b.distance; });

  const int vw = in.viewport[2], vh = in.viewport[3];
  const int d = std::max(1, frame.divisor);
  const int w = (vw + d - 1) / d, h = (vh + d - 1) / d;
  if (!ensure_target(w, h, error)) return false;

  // March, far batch first, each over the nearer ones' background.
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target_, 0);
  const GLenum buffers[1] = {GL_COLOR_ATTACHMENT0};
  glDrawBuffers(1, buffers);
  glViewport(0, 0, w, h);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_DEPTH_TEST);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const float clear[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, clear);
  glUseProgram(march_.program);
  if (!renderer.prepare_pass_tables(march_.pass, in, error)) return false;
  glUseProgram(march_.program);  // the volume build may have used another program
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
  glViewport(0, 0, w, h);
  glUniform4f(march_.pass.viewport, 0.0f, 0.0f, static_cast<float>(vw) / d, static_cast<float>(vh) / d);
  glUniform4f(march_.full_viewport, static_cast<float>(in.viewport[0]), static_cast<float>(in.viewport[1]),
              static_cast<float>(vw), static_cast<float>(vh));
  glUniform1i(march_.divisor, d);
  glUniform1i(march_.atlas, static_cast<GLint>(kCloudUnit));
  glUniform3fv(march_.atlas_size, 1, glm::value_ptr(atlas_size_));
  glUniform3fv(march_.light_illuminance, 1, glm::value_ptr(glm::vec3(frame.light.illuminance_lux)));
  glUniform3fv(march_.sky_radiance, 1, glm::value_ptr(glm::vec3(frame.light.sky_radiance)));
  glUniform3fv(march_.ground_radiance, 1, glm::value_ptr(glm::vec3(frame.light.ground_radiance)));
  glUniform1f(march_.step_voxels, frame.step_voxels);
  glUniform1i(march_.max_steps, 512);
  glUniform1f(march_.phase[0], frame.phase.g_hg);
  glUniform1f(march_.phase[1], frame.phase.g_draine);
  glUniform1f(march_.phase[2], frame.phase.alpha_draine);
  glUniform1f(march_.phase[3], frame.phase.w_draine);
  glUniform1i(march_.octaves[0], frame.octaves.count);
  glUniform1f(march_.octaves[1], frame.octaves.extinction_scale);
  glUniform1f(march_.octaves[2], frame.octaves.scattering_scale);
  glUniform1f(march_.octaves[3], frame.octaves.eccentricity_scale);
  glUniform1f(march_.octaves[4], frame.octaves.ambient_extinction);
  glActiveTexture(GL_TEXTURE0 + kCloudUnit);
  glBindTexture(GL_TEXTURE_3D, atlas_);
  glBindSampler(kCloudUnit, border_sampler_);
  glEnablei(GL_BLEND, 0);
  set_blend_of_buffer0(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_FUNC_ADD, GL_FUNC_ADD);
  glBindVertexArray(vao_);
  std::vector<glm::vec4> packed;
  const int batches = (static_cast<int>(items.size()) + kMaxInstancesPerBatch - 1) / kMaxInstancesPerBatch;
  for (int b = batches - 1; b >= 0; --b) {
    const size_t begin = static_cast<size_t>(b) * kMaxInstancesPerBatch;
    const size_t end = std::min(items.size(), begin + kMaxInstancesPerBatch);
    packed.clear();
    for (size_t k = begin; k < end; ++k) {
      const clouds::CloudInstance& inst = frame.field->instances[items[k].index];
      const size_t pi = static_cast<size_t>(inst.prototype);
      const clouds::CloudVolume& v = protos[pi];
      const glm::dmat3 axes = M * glm::mat3_cast(v.rotation);
      const glm::vec3 origin(M * (inst.origin_enu_m - frame.eye_in_clouds_m));
      const glm::vec3 light_grid = clouds::grid_direction(v, frame.light.direction_enu);
      const glm::vec3 off = atlas_offsets_[pi];
      packed.push_back(glm::vec4(origin, v.voxel_size_m));
      packed.push_back(glm::vec4(glm::vec3(axes[0]), v.optics.extinction_per_m));
      packed.push_back(glm::vec4(glm::vec3(axes[1]), v.optics.albedo));
      packed.push_back(glm::vec4(glm::vec3(axes[2]), off.x));
      packed.push_back(glm::vec4(v.density.nx, v.density.ny, v.density.nz, off.y));
      packed.push_back(glm::vec4(light_grid, off.z));
      packed.push_back(glm::vec4(glm::vec3(items[k].centre), static_cast<float>(v.bounding_radius_m())));
    }
    glUniform4fv(march_.instances, static_cast<GLsizei>(packed.size()), glm::value_ptr(packed[0]));
    glUniform1i(march_.instance_count, static_cast<GLint>(end - begin));
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  last_drawn_ = static_cast<int>(items.size());

  // Composite over the host's frame.
  guard.restore_draw_framebuffer();
  glViewport(in.viewport[0], in.viewport[1], vw, vh);
  glUseProgram(composite_);
  glUniform1i(composite_clouds_, static_cast<GLint>(kCloudUnit));
  // The low-res image covers w * d >= vw pixels: scale uv to the part that maps the viewport.
  glUniform4f(composite_viewport_, static_cast<float>(in.viewport[0]), static_cast<float>(in.viewport[1]),
              static_cast<float>(w * d), static_cast<float>(h * d));
  glActiveTexture(GL_TEXTURE0 + kCloudUnit);
  glBindTexture(GL_TEXTURE_2D, target_);
  glBindSampler(kCloudUnit, linear_sampler_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  *drawn = true;
  return check_gl("drawing the clouds", error);
}

}  // namespace atmo::gl
