#include "gl/cloud_renderer.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "core/clouds/cloud_optics.h"
#include "gl/gl_state_guard.h"
#include "gl/renderer.h"
#include "gl/shader_program.h"

namespace atmo::gl {

namespace {
constexpr GLuint kCloudUnit = kPassUnitsUsed;  // the 3D atlas (march, bake), impostor colour (boards), the image (composite)
constexpr GLuint kImpostorDepthUnit = kPassUnitsUsed + 1;
constexpr int kUnitsUsed = kPassUnitsUsed + 3;  // the resolve: trace, its depth, the history
constexpr int kVec4PerInstance = 9;  // cloud_instance.glsl
constexpr int kMaxInstancesPerBatch = 64;
constexpr int kVec4PerBoard = 4;     // clouds_impostor.vert
constexpr int kMaxBoardsPerBatch = 64;

// The light's scale: impostors store radiance over it, so half floats hold
// noon and moonlight alike, and a slowly dimming light needs no re-render.
double light_scale(const clouds::CloudLight& l) {
  return std::max(l.illuminance_lux.g / M_PI + l.sky_radiance.g + l.ground_radiance.g, 1e-12);
}
}  // namespace

// A cloud in view this frame.
struct CloudRenderer::Item {
  double distance_m;
  size_t index;          // into the field's instances
  double direct_weight;  // the direct march's share, [0, 1]
};

bool CloudRenderer::init(std::string* error) {
  if (initialised()) return true;
  GlStateGuard guard(kUnitsUsed);
  march_.program = build_program("fullscreen.vert", "clouds_march.frag", "", error);
  if (march_.program) bake_.program = build_program("fullscreen.vert", "clouds_impostor_bake.frag", "", error);
  if (bake_.program) board_.program = build_program("clouds_impostor.vert", "clouds_impostor.frag", "", error);
  if (board_.program) composite_ = build_program("fullscreen.vert", "clouds_composite.frag", "", error);
  if (!composite_) {
    destroy();
    return false;
  }
  auto locate_cloud = [](GLuint program) {
    InstanceUniforms u;
    auto loc = [&](const char* name) { return glGetUniformLocation(program, name); };
    u.atlas = loc("u_cloud_atlas");
    u.atlas_size = loc("u_cloud_atlas_size");
    u.instances = loc("u_instances");
    u.instance_count = loc("u_instance_count");
    u.light_illuminance = loc("u_light_illuminance");
    u.sky_radiance = loc("u_sky_radiance");
    u.ground_radiance = loc("u_ground_radiance");
    u.step_voxels = loc("u_step_voxels");
    u.max_steps = loc("u_max_steps");
    u.octaves.locate(program);
    return u;
  };
  march_.pass = locate_pass_uniforms(march_.program);
  march_.cloud = locate_cloud(march_.program);
  march_.divisor = glGetUniformLocation(march_.program, "u_divisor");
  march_.full_viewport = glGetUniformLocation(march_.program, "u_full_viewport");
  bake_.cloud = locate_cloud(bake_.program);
  bake_.board_centre = glGetUniformLocation(bake_.program, "u_board_centre");
  bake_.board_right = glGetUniformLocation(bake_.program, "u_board_right");
  bake_.board_up = glGetUniformLocation(bake_.program, "u_board_up");
  bake_.radiance_scale = glGetUniformLocation(bake_.program, "u_radiance_scale");
  bake_.tile_texels = glGetUniformLocation(bake_.program, "u_tile_texels");
  board_.pass = locate_pass_uniforms(board_.program);
  board_.boards = glGetUniformLocation(board_.program, "u_boards");
  board_.clip_from_enu = glGetUniformLocation(board_.program, "u_clip_from_enu");
  board_.ndc_scale = glGetUniformLocation(board_.program, "u_ndc_scale");
  board_.colour = glGetUniformLocation(board_.program, "u_impostor_colour");
  board_.depth = glGetUniformLocation(board_.program, "u_impostor_depth");
  board_.divisor = glGetUniformLocation(board_.program, "u_divisor");
  board_.full_viewport = glGetUniformLocation(board_.program, "u_full_viewport");
  composite_clouds_ = glGetUniformLocation(composite_, "u_clouds");
  composite_viewport_ = glGetUniformLocation(composite_, "u_viewport");
  composite_encoding_ = glGetUniformLocation(composite_, "u_output_encoding");
  glGenVertexArrays(1, &vao_);
  glGenFramebuffers(1, &fbo_);
  glGenFramebuffers(1, &bake_fbo_);
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
  for (GLuint p : {march_.program, bake_.program, board_.program, composite_})
    if (p) glDeleteProgram(p);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  for (GLuint f : {fbo_, bake_fbo_})
    if (f) glDeleteFramebuffers(1, &f);
  for (GLuint t : {target_, atlas_, shadow_})
    if (t) glDeleteTextures(1, &t);
  for (GLuint s : {linear_sampler_, border_sampler_})
    if (s) glDeleteSamplers(1, &s);
  impostors_.destroy();
  layer_.destroy();
  temporal_.destroy();
  forget();
}

void CloudRenderer::forget() { *this = CloudRenderer{}; }

uint64_t CloudRenderer::impostor_hash() const {
  core::StateHasher h;
  h.add(static_cast<uint64_t>(impostor_of_.size()));
  for (const Impostor& im : impostor_of_) {
    h.add(im.baked);
    if (im.baked) h.add(im.baked_eye_m);
  }
  return h.value();
}

void CloudRenderer::hash_state(uint64_t frame, core::StateHasher* h) const {
  h->add(have_before_ && before_frame_ == frame ? impostors_before_update_ : impostor_hash());
}

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
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);  // a host's bound PBO would be read instead (restored by the guard)
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  for (size_t p = 0; p < protos.size(); ++p) {
    const clouds::DenseGrid& g = protos[p].density;
    const std::vector<float> texels = clouds::pack_cloud_texels(g, (*frame.depths)[p]);
    const glm::ivec3 o(atlas_offsets_[p]);
    glTexSubImage3D(GL_TEXTURE_3D, 0, o.x, o.y, o.z, g.nx, g.ny, g.nz, GL_RGBA, GL_FLOAT, texels.data());
  }
  atlas_bytes_ = static_cast<size_t>(size_x) * size_y * size_z * 8;
  phases_.clear();
  for (const clouds::CloudVolume& v : protos) phases_.push_back(clouds::phase_for_droplet(v.optics.droplet_diameter_um));
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

bool CloudRenderer::shadow_texture(const clouds::CloudShadowMap& map, uint64_t field_version, uint64_t shadow_version,
                                   GLuint* texture, std::string* error) {
  *texture = 0;
  if (map.size <= 0) return true;
  if (shadow_ && field_version == shadow_field_version_ && shadow_version == shadow_version_) {
    *texture = shadow_;
    return true;
  }
  GlStateGuard guard(1);
  if (!shadow_) glGenTextures(1, &shadow_);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, shadow_);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);  // a host's bound PBO would be read instead (restored by the guard)
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R16F, map.size, map.size, 0, GL_RED, GL_FLOAT, map.transmittance.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  shadow_field_version_ = field_version;
  shadow_version_ = shadow_version;
  *texture = shadow_;
  return check_gl("uploading the cloud shadow map", error);
}

void CloudRenderer::set_cloud_uniforms(const InstanceUniforms& u, const CloudFrameInputs& frame) const {
  glUniform1i(u.atlas, static_cast<GLint>(kCloudUnit));
  glUniform3fv(u.atlas_size, 1, glm::value_ptr(atlas_size_));
  glUniform3fv(u.light_illuminance, 1, glm::value_ptr(glm::vec3(frame.light.illuminance_lux)));
  glUniform3fv(u.sky_radiance, 1, glm::value_ptr(glm::vec3(frame.light.sky_radiance)));
  glUniform3fv(u.ground_radiance, 1, glm::value_ptr(glm::vec3(frame.light.ground_radiance)));
  glUniform1f(u.step_voxels, frame.step_voxels);
  glUniform1i(u.max_steps, 512);
  u.octaves.set(frame.octaves);
}

void CloudRenderer::pack_instance(const CloudFrameInputs& frame, size_t index, float weight,
                                  std::vector<glm::vec4>* out) const {
  const clouds::CloudInstance& inst = frame.field->instances[index];
  const size_t pi = static_cast<size_t>(inst.prototype);
  const clouds::CloudVolume& v = frame.field->prototypes[pi];
  const glm::dmat3& M = frame.eye_enu_from_clouds;
  const glm::dmat3 axes = M * glm::mat3_cast(v.rotation);
  const glm::vec3 origin(M * (inst.origin_enu_m - frame.eye_in_clouds_m));
  const glm::vec3 centre(M * (v.centre_at(inst.origin_enu_m) - frame.eye_in_clouds_m));
  const glm::vec3 light_grid = clouds::grid_direction(v, frame.light.direction_enu);
  const glm::vec3 off = atlas_offsets_[pi];
  const clouds::twin::CloudPhase& ph = phases_[pi];
  out->push_back(glm::vec4(origin, v.voxel_size_m));
  out->push_back(glm::vec4(glm::vec3(axes[0]), v.optics.extinction_per_m));
  out->push_back(glm::vec4(glm::vec3(axes[1]), v.optics.albedo));
  out->push_back(glm::vec4(glm::vec3(axes[2]), off.x));
  out->push_back(glm::vec4(v.density.nx, v.density.ny, v.density.nz, off.y));
  out->push_back(glm::vec4(light_grid, off.z));
  out->push_back(glm::vec4(centre, static_cast<float>(v.bounding_radius_m())));
  out->push_back(glm::vec4(ph.g_hg, ph.g_draine, ph.alpha_draine, ph.w_draine));
  const clouds::ContinuingSides& s = (*frame.depths)[pi].sides;
  const int sides = (s.west ? 1 : 0) | (s.east ? 2 : 0) | (s.south ? 4 : 0) | (s.north ? 8 : 0);
  out->push_back(glm::vec4(weight, static_cast<float>(sides), 0.0f, 0.0f));
}

bool CloudRenderer::bake(const CloudFrameInputs& frame, size_t index, std::string* error) {
  Impostor& im = impostor_of_[index];
  const clouds::CloudInstance& inst = frame.field->instances[index];
  const clouds::CloudVolume& v = frame.field->prototypes[static_cast<size_t>(inst.prototype)];
  const glm::dvec3 centre = v.centre_at(inst.origin_enu_m);
  im.board = clouds::make_billboard(frame.eye_in_clouds_m, centre, v.bounding_radius_m());
  im.baked_eye_m = frame.eye_in_clouds_m;
  im.version = frame.version;
  im.baked = true;
  const int tile = impostors_.tile_texels();
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, bake_fbo_);
  glFramebufferTextureLayer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, impostors_.colour(im.slot), 0,
                            ImpostorAtlas::layer(im.slot));
  glFramebufferTextureLayer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, impostors_.depth(im.slot), 0,
                            ImpostorAtlas::layer(im.slot));
  const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(2, buffers);
  if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    if (error) *error = "the impostor framebuffer is incomplete";
    return false;
  }
  glViewport(0, 0, tile, tile);
  const glm::dmat3& M = frame.eye_enu_from_clouds;
  std::vector<glm::vec4> packed;
  pack_instance(frame, index, 1.0f, &packed);
  glUniform4fv(bake_.cloud.instances, static_cast<GLsizei>(packed.size()), glm::value_ptr(packed[0]));
  glUniform1i(bake_.cloud.instance_count, 1);
  glUniform4fv(bake_.board_centre, 1,
               glm::value_ptr(glm::vec4(glm::vec3(M * (centre - frame.eye_in_clouds_m)), im.board.half_size_m)));
  glUniform3fv(bake_.board_right, 1, glm::value_ptr(glm::vec3(M * im.board.right)));
  glUniform3fv(bake_.board_up, 1, glm::value_ptr(glm::vec3(M * im.board.up)));
  glUniform1f(bake_.radiance_scale, static_cast<float>(1.0 / light_scale(frame.light)));
  glUniform1f(bake_.tile_texels, static_cast<float>(tile));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  return true;
}

void CloudRenderer::draw_boards(const PassInputs& in, const CloudFrameInputs& frame, const std::vector<Item>& far,
                                int d) {
  const glm::mat4 view_from_enu(glm::transpose(in.enu_from_view));
  const glm::mat4 clip_from_enu = glm::inverse(in.view_from_clip) * view_from_enu;
  glUniformMatrix4fv(board_.clip_from_enu, 1, GL_FALSE, glm::value_ptr(clip_from_enu));
  const float used_w = static_cast<float>(in.viewport[2]) / d, used_h = static_cast<float>(in.viewport[3]) / d;
  glUniform2f(board_.ndc_scale, used_w / target_w_, used_h / target_h_);
  glUniform1i(board_.colour, static_cast<GLint>(kCloudUnit));
  glUniform1i(board_.depth, static_cast<GLint>(kImpostorDepthUnit));
  glBindSampler(kCloudUnit, linear_sampler_);
  glBindSampler(kImpostorDepthUnit, linear_sampler_);
  const glm::dmat3& M = frame.eye_enu_from_clouds;
  const float factor = static_cast<float>(light_scale(frame.light));
  std::vector<glm::vec4> packed;
  // Far to near; a batch ends where the chunk (texture) changes.
  size_t k = 0;
  while (k < far.size()) {
    const int chunk = ImpostorAtlas::chunk(impostor_of_[far[k].index].slot);
    packed.clear();
    int count = 0;
    for (; k < far.size() && count < kMaxBoardsPerBatch; ++k) {
      const Impostor& im = impostor_of_[far[k].index];
      if (ImpostorAtlas::chunk(im.slot) != chunk) break;
      packed.push_back(glm::vec4(glm::vec3(M * (im.board.centre_m - frame.eye_in_clouds_m)), im.board.half_size_m));
      packed.push_back(glm::vec4(glm::vec3(M * im.board.right), ImpostorAtlas::layer(im.slot)));
      packed.push_back(glm::vec4(glm::vec3(M * im.board.up), static_cast<float>(1.0 - far[k].direct_weight)));
      packed.push_back(glm::vec4(factor, 0.0f, 0.0f, 0.0f));
      ++count;
    }
    const int slot = impostor_of_[far[k - 1].index].slot;
    glActiveTexture(GL_TEXTURE0 + kCloudUnit);
    glBindTexture(GL_TEXTURE_2D_ARRAY, impostors_.colour(slot));
    glActiveTexture(GL_TEXTURE0 + kImpostorDepthUnit);
    glBindTexture(GL_TEXTURE_2D_ARRAY, impostors_.depth(slot));
    glUniform4fv(board_.boards, static_cast<GLsizei>(packed.size()), glm::value_ptr(packed[0]));
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, count);
    stats_.impostors_drawn += count;
  }
}

void CloudRenderer::march(const CloudFrameInputs& frame, const std::vector<Item>& near) {
  glActiveTexture(GL_TEXTURE0 + kCloudUnit);
  glBindTexture(GL_TEXTURE_3D, atlas_);
  glBindSampler(kCloudUnit, border_sampler_);
  set_cloud_uniforms(march_.cloud, frame);
  std::vector<glm::vec4> packed;
  // Far batch first, each over the nearer ones' background; near to far inside a batch.
  const int batches = (static_cast<int>(near.size()) + kMaxInstancesPerBatch - 1) / kMaxInstancesPerBatch;
  for (int b = batches - 1; b >= 0; --b) {
    const size_t begin = static_cast<size_t>(b) * kMaxInstancesPerBatch;
    const size_t end = std::min(near.size(), begin + kMaxInstancesPerBatch);
    packed.clear();
    for (size_t k = begin; k < end; ++k)
      pack_instance(frame, near[k].index, static_cast<float>(near[k].direct_weight), &packed);
    glUniform4fv(march_.cloud.instances, static_cast<GLsizei>(packed.size()), glm::value_ptr(packed[0]));
    glUniform1i(march_.cloud.instance_count, static_cast<GLint>(end - begin));
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  stats_.marched = static_cast<int>(near.size());
}

bool CloudRenderer::draw(Renderer& renderer, const PassInputs& in, const CloudFrameInputs& frame, bool* drawn,
                         std::string* error) {
  *drawn = false;
  stats_ = CloudDrawStats{};
  if (!frame.field || frame.field->instances.empty()) return true;
  GlStateGuard guard(kUnitsUsed);
  if (!init(error)) return false;
  guard.use_single_draw_buffer();
  const std::vector<clouds::CloudInstance>& instances = frame.field->instances;
  if (!have_before_ || before_frame_ != frame.host_frame) {  // the state hash's view of this frame
    impostors_before_update_ = impostor_hash();
    before_frame_ = frame.host_frame;
    have_before_ = true;
  }
  if (!frame.layer && (frame.field_version != impostor_field_version_ || impostor_of_.size() != instances.size() ||
                       impostors_.tile_texels() != frame.impostors.tile_texels)) {  // (the layer march has none)
    impostors_.reset(frame.impostors.tile_texels);
    impostor_of_.assign(instances.size(), Impostor{});
    impostor_field_version_ = frame.field_version;
    impostors_updated_once_ = false;
  }
  const int vw = in.viewport[2], vh = in.viewport[3];
  const int d = std::max(1, frame.divisor);
  const int w = (vw + d - 1) / d, h = (vh + d - 1) / d;
  if (frame.layer) {
    if (!frame.clipmap || frame.clipmap->levels.empty()) return true;
    if (!layer_.init(error) || !layer_.upload(*frame.clipmap, frame.clipmap_version, error)) return false;
    if (frame.temporal && !temporal_.init(error)) return false;
    stats_.in_view = static_cast<int>(instances.size());
    set_draw_state();  // blending off: the march writes every pixel of the image
    CloudTemporal::Plan plan;
    clouds::TemporalView now = frame.temporal_view;  // with this draw's eye and image
    now.eye_in_clouds_m = frame.eye_in_clouds_m;
    now.eye_enu_from_clouds = frame.eye_enu_from_clouds;
    now.width = w;
    now.height = h;
    if (frame.temporal) {
      plan = temporal_.plan(frame.view_key, now);
      if (!temporal_.begin_trace(fbo_, plan, error)) return false;
    } else if (!begin_image(w, h, error)) {
      return false;
    }
    const clouds::twin::CloudLayerMarch march = clouds::make_layer_march(
        *frame.clipmap, frame.eye_in_clouds_m, frame.light, frame.step_voxels, frame.layer_max_steps);
    if (!use_pass_program(renderer, in, layer_.program(), layer_.pass(), layer_.divisor_uniform(),
                          layer_.full_viewport_uniform(), frame.temporal ? plan.trace_w : w,
                          frame.temporal ? plan.trace_h : h, d, error))
      return false;
    layer_.use(march, frame.octaves, glm::mat3(glm::transpose(frame.eye_enu_from_clouds)), frame.temporal ? 2 : 1,
               plan.offset, kCloudUnit, linear_sampler_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    GLuint image = target_;
    if (frame.temporal && !temporal_.resolve(fbo_, plan, now, in.view_from_clip, in.enu_from_view,
                                             in.depth_convention, kCloudUnit, linear_sampler_, &image, error))
      return false;
    composite(in, guard, image, w, h, d);
    *drawn = true;
    return check_gl("drawing the clouds (layer march)", error);
  }
  if (uploaded_version_ != frame.version || !atlas_) {
    if (!upload_atlas(frame, error)) return false;
  }
  // Impostors: the context's, brought up to date once a host frame for every cloud, in view or not (whether a
  // view sees a cloud must not decide when it is made: other channels do see it).
  if (!frame.direct_only) {
    if (!update_impostors(frame, error)) return false;
    stats_.impostors_created = impostor_stats_.impostors_created;
    stats_.impostors_updated = impostor_stats_.impostors_updated;
    stats_.impostors_stale = impostor_stats_.impostors_stale;
    impostor_stats_ = CloudDrawStats{};  // counted once, by the draw that made them
  }

  // The view frustum's side planes and pixel density, in view space.
  const glm::dmat4 view_from_clip(in.view_from_clip);
  auto view_dir = [&](double x, double y) {
    const glm::dvec4 p = view_from_clip * glm::dvec4(x, y, 0.5, 1.0);
    return glm::normalize(glm::dvec3(p) / p.w);
  };
  const glm::dvec3 axis = view_dir(0.0, 0.0);
  const glm::dvec3 corner[4] = {view_dir(-1, -1), view_dir(1, -1), view_dir(1, 1), view_dir(-1, 1)};
  glm::dvec3 planes[4];
  for (int i = 0; i < 4; ++i) {
    planes[i] = glm::normalize(glm::cross(corner[i], corner[(i + 1) % 4]));
    if (glm::dot(planes[i], axis) > 0.0) planes[i] = -planes[i];  // outward
  }
  const double half_fov = std::acos(std::clamp(glm::dot(axis, view_dir(0.0, 1.0)), -1.0, 1.0));
  const double pixels_per_radian = 0.5 * static_cast<double>(vh) / d / std::max(1e-6, std::tan(half_fov));
  const glm::dmat3 view_from_enu = glm::transpose(glm::dmat3(in.enu_from_view));
  const glm::dmat3 view_from_clouds = view_from_enu * frame.eye_enu_from_clouds;

  // Which clouds are in view, and how each is drawn.
  std::vector<Item> far, near;
  for (size_t i = 0; i < instances.size(); ++i) {
    const clouds::CloudVolume& v = frame.field->prototypes[static_cast<size_t>(instances[i].prototype)];
    const glm::dvec3 rel = v.centre_at(instances[i].origin_enu_m) - frame.eye_in_clouds_m;
    const double r = v.bounding_radius_m();
    const glm::dvec3 c = view_from_clouds * rel;
    bool outside = false;
    for (const glm::dvec3& p : planes) outside = outside || glm::dot(p, c) > r;
    if (outside) continue;
    ++stats_.in_view;
    const double distance = glm::length(rel);
    const double weight =
        frame.direct_only ? 1.0
                          : clouds::direct_march_weight(
                                clouds::direct_march_need(distance, r, pixels_per_radian, frame.impostors),
                                frame.impostors);
    if (weight > 0.0) near.push_back({distance, i, weight});
    if (weight < 1.0) far.push_back({distance, i, weight});
  }
  if (near.empty() && far.empty()) return true;

  // A cloud without an impostor (over the atlas's cap) is marched.
  for (size_t k = 0; k < far.size(); ++k) {
    const Impostor& im = impostor_of_[far[k].index];
    if (im.slot >= 0 && im.baked) continue;
    near.push_back({far[k].distance_m, far[k].index, 1.0});
    far.erase(far.begin() + static_cast<std::ptrdiff_t>(k--));
  }
  std::sort(far.begin(), far.end(), [](const Item& a, const Item& b) { return a.distance_m > b.distance_m; });
  std::sort(near.begin(), near.end(), [](const Item& a, const Item& b) { return a.distance_m < b.distance_m; });

  set_draw_state();

  // The image: impostors far to near, then the direct march over them.
  if (!begin_image(w, h, error)) return false;
  glEnablei(GL_BLEND, 0);
  set_blend_of_buffer0(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_FUNC_ADD, GL_FUNC_ADD);
  if (!far.empty()) {
    if (!use_pass_program(renderer, in, board_.program, board_.pass, board_.divisor, board_.full_viewport, w, h, d,
                          error))
      return false;
    draw_boards(in, frame, far, d);
  }
  if (!near.empty()) {
    if (!use_pass_program(renderer, in, march_.program, march_.pass, march_.divisor, march_.full_viewport, w, h, d,
                          error))
      return false;
    march(frame, near);
  }

  composite(in, guard, target_, w, h, d);
  *drawn = true;
  return check_gl("drawing the clouds", error);
}

bool CloudRenderer::update_impostors(const CloudFrameInputs& frame, std::string* error) {
  if (impostors_updated_once_ && frame.host_frame == impostor_frame_ && frame.version == impostor_light_version_ &&
      frame.impostor_eye_in_clouds_m == impostor_eye_m_)
    return true;
  impostors_updated_once_ = true;
  impostor_frame_ = frame.host_frame;
  impostor_light_version_ = frame.version;
  impostor_eye_m_ = frame.impostor_eye_in_clouds_m;
  impostor_stats_ = CloudDrawStats{};
  // Baked from the reference eye, in its axes: the same texels whichever view draws first.
  CloudFrameInputs ref = frame;
  ref.eye_in_clouds_m = frame.impostor_eye_in_clouds_m;
  ref.eye_enu_from_clouds = frame.impostor_eye_enu_from_clouds;
  // New ones now, stale ones within the budget (largest change first), over every cloud.
  std::vector<size_t> to_bake, stale_items;
  std::vector<double> staleness;
  const std::vector<clouds::CloudInstance>& instances = frame.field->instances;
  for (size_t i = 0; i < instances.size(); ++i) {
    Impostor& im = impostor_of_[i];
    if (im.slot < 0) {
      std::string alloc_error;
      im.slot = impostors_.allocate(&alloc_error);
      if (im.slot < 0) {  // over the cap: the direct march draws it
        if (!alloc_error.empty() && error) *error = alloc_error;
        continue;
      }
    }
    if (!im.baked) {
      to_bake.push_back(i);
      ++impostor_stats_.impostors_created;
      continue;
    }
    const clouds::CloudVolume& v = frame.field->prototypes[static_cast<size_t>(instances[i].prototype)];
    const double change = clouds::impostor_view_change_rad(im.baked_eye_m, ref.eye_in_clouds_m, im.board.centre_m,
                                                           v.bounding_radius_m()) /
                          frame.impostors.angle_threshold_rad;
    const double st = im.version != frame.version ? 1.0 + change : change;
    if (st >= 1.0) {
      stale_items.push_back(i);
      staleness.push_back(st);
    }
  }
  const std::vector<size_t> chosen = clouds::choose_impostor_updates(staleness, frame.impostors);
  for (size_t c : chosen) to_bake.push_back(stale_items[c]);
  impostor_stats_.impostors_updated = static_cast<int>(chosen.size());
  impostor_stats_.impostors_stale = static_cast<int>(staleness.size() - chosen.size());
  if (to_bake.empty()) return true;
  set_draw_state();
  glActiveTexture(GL_TEXTURE0 + kCloudUnit);
  glBindTexture(GL_TEXTURE_3D, atlas_);
  glBindSampler(kCloudUnit, border_sampler_);
  glUseProgram(bake_.program);
  set_cloud_uniforms(bake_.cloud, ref);
  for (size_t index : to_bake)
    if (!bake(ref, index, error)) return false;
  return true;
}

void CloudRenderer::set_draw_state() const {
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_DEPTH_TEST);
  glDisablei(GL_BLEND, 0);  // the buffers the guard restores (glDisable would switch off all eight)
  glDisablei(GL_BLEND, 1);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindVertexArray(vao_);
}

bool CloudRenderer::begin_image(int w, int h, std::string* error) {
  if (!ensure_target(w, h, error)) return false;
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target_, 0);
  const GLenum buffers[1] = {GL_COLOR_ATTACHMENT0};
  glDrawBuffers(1, buffers);
  glViewport(0, 0, w, h);
  const float clear[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, clear);
  return true;
}

// Each program takes pass_common's uniforms from the renderer (which may
// build the aerial volume with its own program and framebuffer first).
bool CloudRenderer::use_pass_program(Renderer& renderer, const PassInputs& in, GLuint program, const PassUniforms& pass,
                                     GLint divisor, GLint full_viewport, int w, int h, int d, std::string* error) {
  glUseProgram(program);
  if (!renderer.prepare_pass_tables(pass, in, error)) return false;
  glUseProgram(program);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
  glViewport(0, 0, w, h);
  glBindVertexArray(vao_);
  glUniform4f(pass.viewport, 0.0f, 0.0f, static_cast<float>(in.viewport[2]) / d, static_cast<float>(in.viewport[3]) / d);
  glUniform4f(full_viewport, static_cast<float>(in.viewport[0]), static_cast<float>(in.viewport[1]),
              static_cast<float>(in.viewport[2]), static_cast<float>(in.viewport[3]));
  glUniform1i(divisor, d);
  return true;
}

// The image over the host's frame.
void CloudRenderer::composite(const PassInputs& in, GlStateGuard& guard, GLuint image, int w, int h, int d) {
  guard.restore_draw_framebuffer();
  glEnablei(GL_BLEND, 0);  // premultiplied
  set_blend_of_buffer0(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_FUNC_ADD, GL_FUNC_ADD);
  glViewport(in.viewport[0], in.viewport[1], in.viewport[2], in.viewport[3]);
  glUseProgram(composite_);
  glUniform1i(composite_clouds_, static_cast<GLint>(kCloudUnit));
  glUniform1i(composite_encoding_, in.output_encoding);
  // The low-res image covers w * d >= vw pixels: scale uv to the part that maps the viewport.
  glUniform4f(composite_viewport_, static_cast<float>(in.viewport[0]), static_cast<float>(in.viewport[1]),
              static_cast<float>(w * d), static_cast<float>(h * d));
  glActiveTexture(GL_TEXTURE0 + kCloudUnit);
  glBindTexture(GL_TEXTURE_2D, image);
  glBindSampler(kCloudUnit, linear_sampler_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace atmo::gl
