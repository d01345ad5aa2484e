// pass_uniforms.h — the uniforms every program compiling
// shaders/atmosphere/pass_common.glsl declares (and sky_pixel.glsl's night
// terms), looked up once after linking and set per draw from PassInputs; the
// texture units both renderers bind the tables on; their samplers. Shared by
// the sky and aerial passes (gl/renderer) and the night point pass
// (gl/night_renderer), so the two set the same uniforms the same way.
#pragma once

#include <glad/gl.h>
#include <glm/glm.hpp>

#include "gl/atmosphere_uniforms.h"
#include "gl/night_terms_uniforms.h"

namespace atmo::gl {

struct PassInputs;

// Texture units of the tables (pass_common.glsl's samplers).
constexpr GLuint kTransmittanceUnit = 0;
constexpr GLuint kDepthUnit = 1;
constexpr GLuint kMultipleScatteringUnit = 2;
constexpr GLuint kSkyViewUnit = 3;
constexpr GLuint kAerialInscatterUnit = 4;
constexpr GLuint kAerialTransmittanceUnit = 5;
static_assert(kMoonSkyViewUnit == 6, "the moonlit sky-view table follows the aerial volume's units");
constexpr GLuint kCloudShadowUnit = kMoonSkyViewUnit + 1;  // the clouds' shadow map (PassInputs::cloud_shadow)
// The sky's loss to the clouds' shadow, per direction (the sky pass's ATMO_SKY_CLOUD_SHADOW variant).
constexpr GLuint kSkyCloudLossUnit = kCloudShadowUnit + 1;
constexpr int kPassUnitsUsed = static_cast<int>(kSkyCloudLossUnit) + 1;

struct PassUniforms {
  // Locations (-1 where a program does not use a uniform).
  AtmosphereUniforms atmosphere;
  GLint transmittance = -1, transmittance_size = -1, multiple_scattering = -1, multiple_scattering_size = -1,
        depth = -1, has_depth = -1, depth_origin = -1, depth_convention = -1, log_far = -1, log_coefficient = -1, view_from_clip = -1,
        enu_from_view = -1, viewport = -1, eye_altitude = -1, sun_direction = -1, exposure = -1,
        output_encoding = -1, steps = -1, sky_view = -1, sky_view_size = -1, aerial_inscatter = -1,
        aerial_transmittance = -1, aerial_range = -1, aerial_slices = -1, analytic_weight = -1;
  GLint preetham[6] = {-1, -1, -1, -1, -1, -1};
  GLint cloud_shadow = -1, cloud_uv_from_eye = -1, cloud_base = -1, cloud_top = -1, cloud_enabled = -1;
  NightTermUniforms night;
};

PassUniforms locate_pass_uniforms(GLuint program);

// What the uniforms take besides PassInputs: the bound tables' sizes and the
// moonlit table's scale to the current Moon (the volume's slices come from in.table_sizes).
struct PassTableSizes {
  glm::vec2 transmittance{1.0f};
  glm::vec2 multiple_scattering{1.0f};
  glm::vec2 sky_view{1.0f};
  glm::vec3 moon_sky_scale{1.0f};
};

// The program must be in use. Samplers are set to the units above; `night`
// replaces in.night (the point pass clears terms it has no table for).
void set_pass_uniforms(const PassUniforms& u, const PassInputs& in, const PassTableSizes& sizes, int steps,
                       const NightTerms& night);

// The two samplers the passes sample with: linear, clamped to the edge (the
// tables, 2D and 3D), and nearest without comparison (the host's depth).
void create_pass_samplers(GLuint* linear, GLuint* nearest);

}  // namespace atmo::gl
