// renderer.h — the thin GL layer: owns the plugin's GL objects for one
// context and draws what the core computed. No physics here: every number a
// pass needs arrives in PassInputs, computed on the CPU in double precision;
// the shaders evaluate shaders/atmosphere/functions.glsl.
//
// Tables on the GPU (sizes in docs/SKY.md): the transmittance and multiple-
// scattering tables come from the CPU; the sky-view table (RGBA32F 2D) and the
// aerial-perspective volume (two RGBA32F 3D textures) are rendered here from
// them, only when their inputs changed (the sky view: air, altitude, sun; the
// volume: also the camera).
#pragma once

#include <glad/gl.h>
#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "core/night_sky/night_sky_twin.h"
#include "core/sky/preetham.h"
#include "core/atmosphere/shader_twin.h"
#include "core/sky/sky_view_table.h"

#include "gl/atmosphere_uniforms.h"
#include "gl/night_terms_uniforms.h"
#include "gl/pass_uniforms.h"

namespace atmo::gl {

// Matches the METHOD_* constants of shaders/atmosphere/pass_common.glsl.
enum class SkyMethod : int { kLut = 0, kAnalytic = 1, kMarch = 2 };

// Table sizes and march steps: the quality knobs of the LUT tier.
struct TableSizes {
  int sky_view_width = core::kSkyViewWidth, sky_view_height = core::kSkyViewHeight;
  int sky_view_steps = 32;
  int aerial_width = 32, aerial_height = 32, aerial_slices = 32;
  int aerial_steps = 16;
  int march_sky_steps = 32;     // the MARCH tier's per-pixel steps
  int march_aerial_steps = 16;
  bool operator==(const TableSizes& o) const {
    return sky_view_width == o.sky_view_width && sky_view_height == o.sky_view_height &&
           sky_view_steps == o.sky_view_steps && aerial_width == o.aerial_width && aerial_height == o.aerial_height &&
           aerial_slices == o.aerial_slices && aerial_steps == o.aerial_steps &&
           march_sky_steps == o.march_sky_steps && march_aerial_steps == o.march_aerial_steps;
  }
};

// The night sky's terms of the sky pass (sky_pixel.glsl; which are on:
// core/night_sky/night_plan.h). All off: the pass costs what it did without them.
struct NightTerms {
  // The sky lit by the Moon: a second sky-view table built with the Moon in
  // the Sun's place (core::night::moonlit_atmosphere), LUT and ANALYTIC only.
  bool moonlit_sky = false;
  bool moon_disc = false;   // the Moon's disc (night_sky/moon_disc.glsl)
  bool background = false;  // airglow, zodiacal light, Milky Way (night_sky/background.glsl)
  twin::AtmosphereParameters moonlit_atmosphere{};
  glm::vec3 moon_direction_enu{0.0f, 0.0f, 1.0f};  // apparent (refracted)
  twin::MoonDisc moon{};
  twin::NightBackground sky_background{};
  float pixel_angle_rad = 0.0f;  // angular size of a pixel at the image centre (the disc's edge ramp)
  // Bits of u_night_terms: 1 moonlit sky, 2 Moon disc, 4 background.
  int bits() const { return (moonlit_sky ? 1 : 0) | (moon_disc ? 2 : 0) | (background ? 4 : 0); }
};

// The clouds' shadow map as the sky passes use it (functions.glsl
// CloudShadowing): the texture (R16F; 0: no clouds, or not of the Sun), the
// map from a point relative to the eye (its ENU, m) to (u, v, height in the
// clouds' frame m), the clouds' lowest base and highest top in that height,
// and a version that changes with the map (the aerial volume is rebuilt).
struct CloudShadowPass {
  GLuint texture = 0;
  glm::mat4 uv_from_eye_enu{1.0f};
  float base_m = 0.0f, top_m = 0.0f;
  uint64_t version = 0;
};

struct PassInputs {
  twin::AtmosphereParameters atmosphere;
  glm::vec3 sun_direction_enu{0.0f, 0.0f, 1.0f};
  float eye_altitude_m = 0.0f;
  glm::mat3 enu_from_view{1.0f};
  glm::mat4 view_from_clip{1.0f};
  int viewport[4] = {0, 0, 1, 1};
  GLuint depth_texture = 0;
  int depth_origin[2] = {0, 0};  // the window pixel of the depth texture's texel (0, 0)
  int depth_convention = 0;
  float log_far_m = 1.0f;
  float log_coefficient = 1.0f;
  float exposure = 1.0f;
  int output_encoding = 0;
  SkyMethod method = SkyMethod::kLut;
  float aerial_range_m = 1.0e6f;             // distance the volume's last slice reaches
  twin::PreethamCoefficients preetham{};     // ANALYTIC only
  float analytic_weight = 0.0f;              // ANALYTIC only: Preetham's confidence
  TableSizes table_sizes;                    // the table sizes of this view
  NightTerms night;                          // the sky pass's night terms (and the point pass's sky under a star)
  CloudShadowPass cloud_shadow;              // the clouds' shadow on the sunlit air (texture 0: none)
};

// The tables the pass samples; names owned by the caller (the Renderer).
struct NightSkyTextures {
  // Always: the transmittance table (RGB32F, as Renderer::upload_tables).
  GLuint transmittance = 0;
  glm::vec2 transmittance_size{1.0f};
  // DISPLAY_SRGB only, to re-evaluate the sky under a source as sky.frag
  // does: the sky-view table of this frame (LUT, and ANALYTIC while
  // analytic_weight < 1) — the one Renderer::draw_sky built for the same
  // PassInputs — or the multiple-scattering table (MARCH).
  GLuint sky_view = 0;
  glm::vec2 sky_view_size{1.0f};
  GLuint multiple_scattering = 0;
  glm::vec2 multiple_scattering_size{1.0f};
  // DISPLAY_SRGB with PassInputs::night.moonlit_sky: the moonlit sky-view table
  // and the factor its texels take to the current Moon (moon_sky_scale below).
  GLuint moon_sky_view = 0;
  glm::vec3 moon_sky_scale{1.0f};
};

class Renderer {
 public:
  using ProcLoader = GLADapiproc (*)(void* user, const char* name);

  // Loads GL through `loader` and creates programs and objects. Needs GL 3.3.
  bool init(ProcLoader loader, void* user, std::string* error);
  // Deletes GL objects (context current).
  void destroy();
  // Drops GL object names without calling GL (context lost).
  void forget();
  bool initialised() const { return sky_[0].program != 0; }

  // The aerial-perspective volume as the last aerial pass built it (0 names
  // before any), for the host's transparent objects.
  GLuint aerial_inscatter_texture() const { return aerial_key_.empty() ? 0 : aerial_inscatter_texture_; }
  GLuint aerial_transmittance_texture() const { return aerial_key_.empty() ? 0 : aerial_transmittance_texture_; }
  const TableSizes& table_sizes() const { return settings_; }

  // The tables the night pass samples for `in`: in DISPLAY_SRGB output the
  // point pass re-evaluates the sky under each source, so the sky-view table
  // is brought up to date for `in` as draw_sky would (no GL work when the sky
  // pass of this frame built it). False and *error on a GL error.
  bool night_sky_textures(const PassInputs& in, NightSkyTextures* out, std::string* error);

  // For another pass drawing with pass_common.glsl (the clouds): brings the
  // aerial-perspective volume up to date for `in` (LUT and ANALYTIC), binds
  // the tables on their units (call inside that pass's GlStateGuard) and sets
  // pass_common's uniforms of the program in use. False and *error on a GL error.
  bool prepare_pass_tables(const PassUniforms& uniforms, const PassInputs& in, std::string* error);
  // Uploads the transmittance and multiple-scattering tables (RGB32F).
  void upload_tables(const twin::Lut2D& transmittance, const twin::Lut2D& multiple_scattering);
  // Each returns false and sets *error on a GL error; state is restored either way.
  bool draw_sky(const PassInputs& in, std::string* error);
  bool draw_aerial_perspective(const PassInputs& in, std::string* error);

  // How many times each derived table was rendered (tests check the caching).
  static constexpr float kMoonSkyViewElevationStep = 1e-3f;  // 0.06° at the horizon
  static constexpr float kMoonSkyViewLightStep = 0.01f;

  struct Counters {
    uint64_t sky_view_builds = 0, aerial_volume_builds = 0, moon_sky_view_builds = 0, sky_cloud_loss_builds = 0;
  };
  const Counters& counters() const { return counters_; }

 private:
  struct Program {
    GLuint program = 0;
    PassUniforms pass;  // pass_common.glsl's uniforms, looked up once after linking
    GLint aerial_grid = -1, slice = -1, sin_sun_elevation = -1;  // the table builders' own
    GLint sky_cloud_loss = -1, sky_cloud_loss_size = -1;  // the sky cloud-loss table (builder, sky variant)
  };
  // The sky's loss to the clouds' shadow (sky_cloud_loss_lut.frag), rebuilt when the eye, the Sun, the air or
  // the map changes: a table per view direction, so the sky pass pays one fetch for it.
  bool ensure_sky_cloud_loss(const PassInputs& in, std::string* error);
  static constexpr int kSkyCloudLossWidth = 128, kSkyCloudLossHeight = 64;
  // sky_variant (sky.frag only): bits 0-2 sky_pixel.glsl's ATMO_NIGHT_TERMS, kSkyCloudShadowBit its
  // ATMO_SKY_CLOUD_SHADOW.
  bool build(Program* p, const char* fragment_path, SkyMethod method, std::string* error, int sky_variant = 0);
  void set_uniforms(const Program& p, const PassInputs& in, int steps) const;
  void bind_textures(GLuint depth_texture, GLuint cloud_shadow_texture) const;
  // scissor: x, y, width, height in window pixels, or null for the whole viewport.
  bool draw(const Program& p, const PassInputs& in, int steps, bool dual_source_blend, std::string* error,
            const int* scissor = nullptr);
  // The window-space box (x, y, width, height, within the viewport) that holds the Moon's disc of
  // in.night (empty when the disc is off screen or wholly behind the camera); false when the disc
  // straddles the camera's plane (then it is drawn with the whole sky).
  bool moon_disc_window_box(const PassInputs& in, int box[4]) const;
  bool ensure_sky_view(const PassInputs& in, std::string* error);
  // The moonlit sky-view table for in.night (only when in.night.moonlit_sky):
  // rebuilt when the Moon's elevation sine moved by more than
  // kMoonSkyViewElevationStep or its light by more than kMoonSkyViewLightStep
  // (relative) since the last build, or the air or altitude changed; between
  // builds the table is scaled to the current light (moon_sky_scale_).
  bool ensure_moon_sky_view(const PassInputs& in, std::string* error);
  // Renders the sky-view table of `in` (its sun and air) into `texture`.
  void render_sky_view(const PassInputs& in, GLuint texture);
  // One full-screen draw of `builder` into a 2D table (width x height texels), inside the caller's GlStateGuard.
  void render_2d_table(const Program& builder, const PassInputs& in, int steps, GLuint texture, int width, int height,
                       GLuint cloud_shadow_texture);
  bool ensure_aerial_volume(const PassInputs& in, std::string* error);
  void allocate_derived_tables();
  // Table sizes; reallocates and invalidates the derived tables when they change.
  void use_table_sizes(const TableSizes& s);

  static constexpr int kMethods = 3;
  // One variant per SkyMethod (indexed by its value); the analytic tier's
  // aerial perspective uses the LUT variant.
  // sky_: the sky pass without night terms or cloud shadow (built by init); sky_variants_[m][bits]: with
  // exactly the night terms `bits & 7` (NightTerms::bits()) and the clouds' shadow if `bits &
  // kSkyCloudShadowBit`, built the first time a frame needs it, so a frame pays only for what it draws.
  static constexpr int kSkyCloudShadowBit = 8;
  static constexpr int kSkyVariants = 16;
  Program sky_[kMethods], sky_variants_[kMethods][kSkyVariants], aerial_[kMethods], sky_view_builder_,
      sky_cloud_loss_builder_,
      aerial_volume_builder_;
  GLuint vao_ = 0, fbo_ = 0;
  GLuint transmittance_texture_ = 0, multiple_scattering_texture_ = 0;
  GLuint sky_view_texture_ = 0, aerial_inscatter_texture_ = 0, aerial_transmittance_texture_ = 0;
  GLuint moon_sky_view_texture_ = 0;
  GLuint linear_sampler_ = 0, nearest_sampler_ = 0;
  glm::vec2 transmittance_size_{1.0f}, multiple_scattering_size_{1.0f};
  TableSizes settings_;
  bool derived_allocated_ = false;
  uint64_t tables_version_ = 0;  // bumps on every upload: derived tables depend on it
  // The inputs each derived table was last built from (bytes compared).
  std::vector<unsigned char> sky_view_key_, aerial_key_, sky_cloud_loss_key_;
  GLuint sky_cloud_loss_texture_ = 0;
  // The moonlit table: what it was built for (key without the Moon), the Moon's elevation sine and light.
  std::vector<unsigned char> moon_sky_view_key_;
  float moon_sky_view_sin_elevation_ = 0.0f;
  glm::vec3 moon_sky_view_light_{0.0f};
  glm::vec3 moon_sky_scale_{1.0f};
  Counters counters_;
};

}  // namespace atmo::gl
