#include "gl/renderer.h"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "gl/gl_state_guard.h"
#include "gl/shader_program.h"

namespace atmo::gl {

namespace {
constexpr int kUnitsUsed = kPassUnitsUsed;

// Appends the raw bytes of `v` to a cache key.
template <typename T>
void append_key(std::vector<unsigned char>* key, const T& v) {
  const auto* b = reinterpret_cast<const unsigned char*>(&v);
  key->insert(key->end(), b, b + sizeof(T));
}

// The clouds' shadow in a table's key, field by field: the struct has padding.
void append_cloud_shadow_key(std::vector<unsigned char>* key, const CloudShadowPass& s) {
  append_key(key, s.texture);
  append_key(key, s.version);
  append_key(key, s.uv_from_eye_enu);
  append_key(key, s.base_m);
  append_key(key, s.top_m);
}
}  // namespace

bool Renderer::init(ProcLoader loader, void* user, std::string* error) {
  if (initialised()) return true;
  int version = gladLoadGLUserPtr(loader, user);
  if (version == 0) {
    if (error) *error = "gl_init: could not load GL entry points through the host's proc-address function";
    return false;
  }
  if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 33) {
    if (error) *error = "gl_init: OpenGL 3.3 or later is required, the current context is " +
                        std::to_string(GLAD_VERSION_MAJOR(version)) + "." + std::to_string(GLAD_VERSION_MINOR(version));
    return false;
  }
  GlStateGuard guard(kUnitsUsed);  // first: it keeps the host's GL errors
  bool ok = build(&sky_view_builder_, "sky_view_lut.frag", SkyMethod::kLut, error) &&
            build(&aerial_volume_builder_, "aerial_volume_lut.frag", SkyMethod::kLut, error);
  for (int m = 0; ok && m < kMethods; ++m) {
    ok = build(&sky_[m], "sky.frag", static_cast<SkyMethod>(m), error) &&
         (m == static_cast<int>(SkyMethod::kAnalytic) ||
          build(&aerial_[m], "aerial_perspective.frag", static_cast<SkyMethod>(m), error));
  }
  if (!ok) {
    destroy();
    return false;
  }
  glGenVertexArrays(1, &vao_);
  glGenFramebuffers(1, &fbo_);
  create_pass_samplers(&linear_sampler_, &nearest_sampler_);
  glGenTextures(1, &transmittance_texture_);
  glGenTextures(1, &multiple_scattering_texture_);
  glGenTextures(1, &sky_view_texture_);
  glGenTextures(1, &aerial_inscatter_texture_);
  glGenTextures(1, &aerial_transmittance_texture_);
  glGenTextures(1, &moon_sky_view_texture_);
  std::string gl_error;
  if (!check_gl("creating objects", &gl_error)) {
    if (error) *error = "gl_init: " + gl_error;
    destroy();
    return false;
  }
  return true;
}

bool Renderer::build(Program* p, const char* fragment_path, SkyMethod method, std::string* error, int sky_variant) {
  const std::string defines = "#define ATMO_METHOD " + std::to_string(static_cast<int>(method)) + "\n" +
                              "#define ATMO_NIGHT_TERMS " + std::to_string(sky_variant & 7) + "\n" +
                              "#define ATMO_SKY_CLOUD_SHADOW " + std::to_string((sky_variant & kSkyCloudShadowBit) ? 1 : 0) +
                              "\n";
  p->program = build_program("fullscreen.vert", fragment_path, defines, error);
  if (!p->program) return false;
  p->pass = locate_pass_uniforms(p->program);
  p->aerial_grid = glGetUniformLocation(p->program, "u_aerial_grid");
  p->slice = glGetUniformLocation(p->program, "u_slice");
  p->sin_sun_elevation = glGetUniformLocation(p->program, "u_sin_sun_elevation");
  p->sky_cloud_loss = glGetUniformLocation(p->program, "u_sky_cloud_loss");
  p->sky_cloud_loss_size = glGetUniformLocation(p->program, "u_sky_cloud_loss_size");
  return true;
}

void Renderer::destroy() {
  for (int m = 0; m < kMethods; ++m) {
    if (sky_[m].program) glDeleteProgram(sky_[m].program);
    for (Program& v : sky_variants_[m])
      if (v.program) glDeleteProgram(v.program);
    if (aerial_[m].program) glDeleteProgram(aerial_[m].program);
  }
  for (Program* p : {&sky_view_builder_, &aerial_volume_builder_, &sky_cloud_loss_builder_})
    if (p->program) glDeleteProgram(p->program);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  for (GLuint* t : {&transmittance_texture_, &multiple_scattering_texture_, &sky_view_texture_,
                    &aerial_inscatter_texture_, &aerial_transmittance_texture_, &moon_sky_view_texture_,
                    &sky_cloud_loss_texture_})
    if (*t) glDeleteTextures(1, t);
  if (linear_sampler_) glDeleteSamplers(1, &linear_sampler_);
  if (nearest_sampler_) glDeleteSamplers(1, &nearest_sampler_);
  forget();
}

void Renderer::forget() {
  for (int m = 0; m < kMethods; ++m) {
    sky_[m] = aerial_[m] = Program{};
    for (Program& v : sky_variants_[m]) v = Program{};
  }
  sky_view_builder_ = aerial_volume_builder_ = sky_cloud_loss_builder_ = Program{};
  sky_cloud_loss_texture_ = 0;
  sky_cloud_loss_key_.clear();
  vao_ = fbo_ = transmittance_texture_ = multiple_scattering_texture_ = 0;
  sky_view_texture_ = aerial_inscatter_texture_ = aerial_transmittance_texture_ = moon_sky_view_texture_ = 0;
  linear_sampler_ = nearest_sampler_ = 0;
  derived_allocated_ = false;
  sky_view_key_.clear();
  aerial_key_.clear();
  moon_sky_view_key_.clear();
}

void Renderer::use_table_sizes(const TableSizes& s) {
  if (s == settings_) return;
  settings_ = s;
  derived_allocated_ = false;
  sky_view_key_.clear();
  aerial_key_.clear();
  moon_sky_view_key_.clear();
}

void Renderer::upload_tables(const twin::Lut2D& transmittance, const twin::Lut2D& multiple_scattering) {
  GlStateGuard guard(1);
  glActiveTexture(GL_TEXTURE0);
  for (auto [texture, table] : {std::pair{transmittance_texture_, &transmittance},
                                std::pair{multiple_scattering_texture_, &multiple_scattering}}) {
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, table->width, table->height, 0, GL_RGB, GL_FLOAT, table->texels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  }
  transmittance_size_ = glm::vec2(transmittance.width, transmittance.height);
  multiple_scattering_size_ = glm::vec2(multiple_scattering.width, multiple_scattering.height);
  ++tables_version_;
}

void Renderer::allocate_derived_tables() {
  // Called inside a GlStateGuard (texture unit 0 is restored by it).
  glActiveTexture(GL_TEXTURE0);
  for (GLuint t : {sky_view_texture_, moon_sky_view_texture_}) {
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, settings_.sky_view_width, settings_.sky_view_height, 0, GL_RGBA,
                 GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  }
  GLint previous_3d = 0;
  glGetIntegerv(GL_TEXTURE_BINDING_3D, &previous_3d);
  for (GLuint t : {aerial_inscatter_texture_, aerial_transmittance_texture_}) {
    glBindTexture(GL_TEXTURE_3D, t);
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA32F, settings_.aerial_width, settings_.aerial_height,
                 settings_.aerial_slices, 0, GL_RGBA, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAX_LEVEL, 0);
  }
  glBindTexture(GL_TEXTURE_3D, static_cast<GLuint>(previous_3d));
  derived_allocated_ = true;
}

void Renderer::set_uniforms(const Program& p, const PassInputs& in, int steps) const {
  const PassTableSizes sizes{transmittance_size_, multiple_scattering_size_,
                             glm::vec2(settings_.sky_view_width, settings_.sky_view_height), moon_sky_scale_};
  set_pass_uniforms(p.pass, in, sizes, steps, in.night);
  glUniform2f(p.aerial_grid, static_cast<float>(settings_.aerial_width), static_cast<float>(settings_.aerial_height));
  glUniform1f(p.sin_sun_elevation, in.sun_direction_enu.z);
  glUniform1i(p.sky_cloud_loss, static_cast<GLint>(kSkyCloudLossUnit));
  glUniform2f(p.sky_cloud_loss_size, static_cast<float>(kSkyCloudLossWidth), static_cast<float>(kSkyCloudLossHeight));
}

void Renderer::bind_textures(GLuint depth_texture, GLuint cloud_shadow_texture) const {
  auto bind = [](GLuint unit, GLenum target, GLuint texture, GLuint sampler) {
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(target, texture);
    glBindSampler(unit, sampler);
  };
  bind(kTransmittanceUnit, GL_TEXTURE_2D, transmittance_texture_, linear_sampler_);
  bind(kDepthUnit, GL_TEXTURE_2D, depth_texture, nearest_sampler_);
  bind(kMultipleScatteringUnit, GL_TEXTURE_2D, multiple_scattering_texture_, linear_sampler_);
  bind(kSkyViewUnit, GL_TEXTURE_2D, sky_view_texture_, linear_sampler_);
  bind(kAerialInscatterUnit, GL_TEXTURE_3D, aerial_inscatter_texture_, linear_sampler_);
  bind(kAerialTransmittanceUnit, GL_TEXTURE_3D, aerial_transmittance_texture_, linear_sampler_);
  bind(kMoonSkyViewUnit, GL_TEXTURE_2D, moon_sky_view_texture_, linear_sampler_);
  bind(kCloudShadowUnit, GL_TEXTURE_2D, cloud_shadow_texture, linear_sampler_);
  bind(kSkyCloudLossUnit, GL_TEXTURE_2D, sky_cloud_loss_texture_, linear_sampler_);
}

void Renderer::render_2d_table(const Program& builder, const PassInputs& in, int steps, GLuint texture, int width,
                               int height, GLuint cloud_shadow_texture) {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, 0, 0);
  const GLenum buffers[1] = {GL_COLOR_ATTACHMENT0};
  glDrawBuffers(1, buffers);
  glDisablei(GL_BLEND, 0);
  glViewport(0, 0, width, height);
  glUseProgram(builder.program);
  set_uniforms(builder, in, steps);
  bind_textures(0, cloud_shadow_texture);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

void Renderer::render_sky_view(const PassInputs& in, GLuint texture) {
  GlStateGuard guard(kUnitsUsed);
  if (!derived_allocated_) allocate_derived_tables();
  render_2d_table(sky_view_builder_, in, settings_.sky_view_steps, texture, settings_.sky_view_width,
                  settings_.sky_view_height, 0);
}

bool Renderer::ensure_sky_view(const PassInputs& in, std::string* error) {
  std::vector<unsigned char> key;
  append_key(&key, tables_version_);
  append_key(&key, in.atmosphere);
  append_key(&key, in.eye_altitude_m);
  append_key(&key, in.sun_direction_enu.z);
  if (derived_allocated_ && key == sky_view_key_) return true;
  render_sky_view(in, sky_view_texture_);
  if (!check_gl("building the sky-view table", error)) return false;
  sky_view_key_ = std::move(key);
  ++counters_.sky_view_builds;
  return true;
}

bool Renderer::ensure_sky_cloud_loss(const PassInputs& in, std::string* error) {
  std::vector<unsigned char> key;
  append_key(&key, tables_version_);
  append_key(&key, in.atmosphere);
  append_key(&key, in.eye_altitude_m);
  append_key(&key, in.sun_direction_enu);
  append_cloud_shadow_key(&key, in.cloud_shadow);
  if (sky_cloud_loss_texture_ && key == sky_cloud_loss_key_) return true;
  GlStateGuard guard(kUnitsUsed);
  if (!sky_cloud_loss_builder_.program &&
      !build(&sky_cloud_loss_builder_, "sky_cloud_loss_lut.frag", SkyMethod::kLut, error))
    return false;
  if (!sky_cloud_loss_texture_) {
    glGenTextures(1, &sky_cloud_loss_texture_);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, sky_cloud_loss_texture_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, kSkyCloudLossWidth, kSkyCloudLossHeight, 0, GL_RGBA, GL_FLOAT,
                 nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  }
  render_2d_table(sky_cloud_loss_builder_, in, 0, sky_cloud_loss_texture_, kSkyCloudLossWidth, kSkyCloudLossHeight,
                  in.cloud_shadow.texture);
  if (!check_gl("building the sky's cloud-shadow table", error)) return false;
  sky_cloud_loss_key_ = std::move(key);
  ++counters_.sky_cloud_loss_builds;
  return true;
}

bool Renderer::ensure_moon_sky_view(const PassInputs& in, std::string* error) {
  const NightTerms& night = in.night;
  if (!night.moonlit_sky) return true;
  twin::AtmosphereParameters air = night.moonlit_atmosphere;
  const glm::vec3 light = air.sun_illuminance_lux;
  air.sun_illuminance_lux = glm::vec3(0.0f);  // the key is the air without the light, which is compared apart
  std::vector<unsigned char> key;
  append_key(&key, tables_version_);
  append_key(&key, air);
  append_key(&key, in.eye_altitude_m);
  const float sin_elevation = night.moon_direction_enu.z;
  const glm::vec3 built = moon_sky_view_light_;
  const bool light_close = glm::all(glm::lessThanEqual(glm::abs(light - built), kMoonSkyViewLightStep * built));
  if (derived_allocated_ && key == moon_sky_view_key_ && light_close &&
      std::abs(sin_elevation - moon_sky_view_sin_elevation_) <= kMoonSkyViewElevationStep) {
    moon_sky_scale_ = glm::vec3(built.x > 0.0f ? light.x / built.x : 0.0f, built.y > 0.0f ? light.y / built.y : 0.0f,
                                built.z > 0.0f ? light.z / built.z : 0.0f);
    return true;
  }
  PassInputs moonlit = in;
  moonlit.atmosphere = night.moonlit_atmosphere;
  moonlit.sun_direction_enu = night.moon_direction_enu;
  moonlit.night = NightTerms{};
  moon_sky_scale_ = glm::vec3(1.0f);
  render_sky_view(moonlit, moon_sky_view_texture_);
  if (!check_gl("building the moonlit sky-view table", error)) return false;
  moon_sky_view_key_ = std::move(key);
  moon_sky_view_sin_elevation_ = sin_elevation;
  moon_sky_view_light_ = light;
  ++counters_.moon_sky_view_builds;
  return true;
}

bool Renderer::ensure_aerial_volume(const PassInputs& in, std::string* error) {
  std::vector<unsigned char> key;
  append_key(&key, tables_version_);
  append_key(&key, in.atmosphere);
  append_key(&key, in.eye_altitude_m);
  append_key(&key, in.sun_direction_enu);
  append_key(&key, in.enu_from_view);
  append_key(&key, in.view_from_clip);
  append_key(&key, in.depth_convention);
  append_key(&key, in.aerial_range_m);
  append_cloud_shadow_key(&key, in.cloud_shadow);
  if (derived_allocated_ && key == aerial_key_) return true;
  {
    GlStateGuard guard(kUnitsUsed);
    if (!derived_allocated_) allocate_derived_tables();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, buffers);
    glDisablei(GL_BLEND, 0);  // the guard restores both buffers' blend enables
    glDisablei(GL_BLEND, 1);
    glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glViewport(0, 0, settings_.aerial_width, settings_.aerial_height);
    glUseProgram(aerial_volume_builder_.program);
    set_uniforms(aerial_volume_builder_, in, settings_.aerial_steps);
    bind_textures(0, in.cloud_shadow.texture);
    glBindVertexArray(vao_);
    for (int k = 0; k < settings_.aerial_slices; ++k) {
      glFramebufferTextureLayer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, aerial_inscatter_texture_, 0, k);
      glFramebufferTextureLayer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, aerial_transmittance_texture_, 0, k);
      glUniform1i(aerial_volume_builder_.slice, k);
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
  }
  if (!check_gl("building the aerial-perspective volume", error)) return false;
  aerial_key_ = std::move(key);
  ++counters_.aerial_volume_builds;
  return true;
}

bool Renderer::draw(const Program& p, const PassInputs& in, int steps, bool dual_source_blend, std::string* error,
                    const int* scissor) {
  {
    GlStateGuard guard(kUnitsUsed);
    guard.use_single_draw_buffer();
    glUseProgram(p.program);
    set_uniforms(p, in, steps);
    bind_textures(in.depth_texture, in.cloud_shadow.texture);
    glViewport(in.viewport[0], in.viewport[1], in.viewport[2], in.viewport[3]);
    GLint scissor_box[4] = {0, 0, 0, 0};  // the guard restores the enable, not the box
    if (scissor) {
      glGetIntegerv(GL_SCISSOR_BOX, scissor_box);
      glEnable(GL_SCISSOR_TEST);
      glScissor(scissor[0], scissor[1], scissor[2], scissor[3]);
    }
    if (dual_source_blend) {
      glEnablei(GL_BLEND, 0);
      set_blend_of_buffer0(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE, GL_FUNC_ADD, GL_FUNC_ADD);
    } else {
      glDisablei(GL_BLEND, 0);
    }
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    if (scissor) glScissor(scissor_box[0], scissor_box[1], scissor_box[2], scissor_box[3]);
  }
  return check_gl("drawing", error);
}

bool Renderer::moon_disc_window_box(const PassInputs& in, int box[4]) const {
  const twin::MoonDisc& moon = in.night.moon;
  const glm::dvec3 c = glm::normalize(glm::dvec3(moon.direction));
  const glm::dmat3 view_from_enu = glm::transpose(glm::dmat3(in.enu_from_view));
  const glm::dmat4 clip_from_view = glm::inverse(glm::dmat4(in.view_from_clip));
  // The disc's outline, widened by the limb's one-pixel ramp and a pixel more.
  const double r = static_cast<double>(moon.angular_radius_rad) + 2.0 * static_cast<double>(in.night.pixel_angle_rad);
  const glm::dvec3 a = std::abs(c.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(c, a)), v = glm::cross(c, u);
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  int behind = 0;
  for (int k = 0; k < 16; ++k) {
    const double t = k * (2.0 * 3.14159265358979323846 / 16.0);
    // A polygon of 16 sides circumscribing the circle: its vertices are r / cos(pi / 16) away.
    const double rr = r / std::cos(3.14159265358979323846 / 16.0);
    const glm::dvec3 p = c * std::cos(rr) + (u * std::cos(t) + v * std::sin(t)) * std::sin(rr);
    const glm::dvec4 clip = clip_from_view * glm::dvec4(view_from_enu * p, 0.0);
    if (!(clip.w > 1e-9)) {
      ++behind;
      continue;
    }
    for (int i = 0; i < 2; ++i) {
      const double window = in.viewport[i] + (clip[i] / clip.w * 0.5 + 0.5) * in.viewport[i + 2];
      lo[i] = std::min(lo[i], window);
      hi[i] = std::max(hi[i], window);
    }
  }
  if (behind == 16) {  // wholly behind the camera: nothing of the disc to draw
    box[0] = box[1] = box[2] = box[3] = 0;
    return true;
  }
  if (behind > 0) return false;  // across the camera's plane: no box (drawn whole)
  for (int i = 0; i < 2; ++i) {
    const double x0 = std::max(std::floor(lo[i]) - 1.0, double(in.viewport[i]));
    const double x1 = std::min(std::ceil(hi[i]) + 1.0, double(in.viewport[i] + in.viewport[i + 2]));
    box[i] = static_cast<int>(x0);
    box[i + 2] = std::max(static_cast<int>(x1 - x0), 0);
  }
  return true;
}

bool Renderer::draw_sky(const PassInputs& in, std::string* error) {
  GlStateGuard guard(kUnitsUsed);  // the tables' lazy updates are inside it too
  use_table_sizes(in.table_sizes);
  const bool needs_sky_view = in.method == SkyMethod::kLut ||
                              (in.method == SkyMethod::kAnalytic && in.analytic_weight < 1.0f);
  if (needs_sky_view && !ensure_sky_view(in, error)) return false;
  if (!ensure_moon_sky_view(in, error)) return false;
  // The clouds' shadow on the sky's rays: with a map of the Sun and the eye below the clouds' tops (from
  // above, the clouds hide the air they shadow).
  const glm::vec4 eye_in_clouds = in.cloud_shadow.uv_from_eye_enu * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  const bool cloud_shadow = in.cloud_shadow.texture != 0 && eye_in_clouds.z < in.cloud_shadow.top_m;
  if (cloud_shadow && !ensure_sky_cloud_loss(in, error)) return false;
  const int m = static_cast<int>(in.method), bits = in.night.bits() | (cloud_shadow ? kSkyCloudShadowBit : 0);
  auto variant = [&](int b) -> const Program* {
    if (b == 0) return &sky_[m];
    if (sky_variants_[m][b].program == 0) {
      GlStateGuard guard(kUnitsUsed);
      if (!build(&sky_variants_[m][b], "sky.frag", in.method, error, b)) return nullptr;
    }
    return &sky_variants_[m][b];
  };
  // The Moon's disc covers a few pixels: the whole sky is drawn without it and only the disc's box with it
  // (llvmpipe would run the disc's code for every pixel); a disc reaching behind the camera is drawn whole.
  int box[4];
  const bool boxed = (bits & 2) != 0 && moon_disc_window_box(in, box);
  const Program* whole = variant(boxed ? (bits & ~2) : bits);
  if (!whole || !draw(*whole, in, settings_.march_sky_steps, false, error)) return false;
  if (!boxed || box[2] == 0 || box[3] == 0) return true;
  const Program* disc = variant(bits);
  return disc && draw(*disc, in, settings_.march_sky_steps, false, error, box);
}

bool Renderer::night_sky_textures(const PassInputs& in, NightSkyTextures* out, std::string* error) {
  GlStateGuard guard(kUnitsUsed);
  use_table_sizes(in.table_sizes);
  const bool needs_sky_view = in.output_encoding == 1 &&
                              (in.method == SkyMethod::kLut ||
                               (in.method == SkyMethod::kAnalytic && in.analytic_weight < 1.0f));
  if (needs_sky_view && !ensure_sky_view(in, error)) return false;
  const bool needs_moon_sky_view = in.output_encoding == 1 && in.night.moonlit_sky;
  if (needs_moon_sky_view && !ensure_moon_sky_view(in, error)) return false;
  out->moon_sky_view = needs_moon_sky_view ? moon_sky_view_texture_ : 0;
  out->moon_sky_scale = moon_sky_scale_;
  out->transmittance = transmittance_texture_;
  out->transmittance_size = transmittance_size_;
  out->sky_view = needs_sky_view ? sky_view_texture_ : 0;
  out->sky_view_size = glm::vec2(settings_.sky_view_width, settings_.sky_view_height);
  out->multiple_scattering = multiple_scattering_texture_;
  out->multiple_scattering_size = multiple_scattering_size_;
  return true;
}

bool Renderer::prepare_pass_tables(const PassUniforms& uniforms, const PassInputs& in, std::string* error) {
  use_table_sizes(in.table_sizes);
  if (in.method != SkyMethod::kMarch && !ensure_aerial_volume(in, error)) return false;
  const PassTableSizes sizes{transmittance_size_, multiple_scattering_size_,
                             glm::vec2(settings_.sky_view_width, settings_.sky_view_height), moon_sky_scale_};
  set_pass_uniforms(uniforms, in, sizes, settings_.march_aerial_steps, NightTerms{});
  bind_textures(in.depth_texture, in.cloud_shadow.texture);
  return true;
}

bool Renderer::draw_aerial_perspective(const PassInputs& in, std::string* error) {
  GlStateGuard guard(kUnitsUsed);
  use_table_sizes(in.table_sizes);
  if (in.method != SkyMethod::kMarch && !ensure_aerial_volume(in, error)) return false;
  const SkyMethod variant = in.method == SkyMethod::kMarch ? SkyMethod::kMarch : SkyMethod::kLut;
  return draw(aerial_[static_cast<int>(variant)], in, settings_.march_aerial_steps, true, error);
}

}  // namespace atmo::gl
